// Mesh repair against the simplification it precedes, in one run: on the bunny after two Loop levels (1.1M triangles;
// an icosphere of 1.3M when tests/data/bunny is missing), clean, with one duplicate face appended, and as a soup (every
// triangle with its own three vertices, as STL stores it), it times needs_repair (audit_mesh), validate +
// check_manifold (the manifold rules /simplify and /remesh apply before running), repair_mesh, simplify_qem on the mesh
// as sent (what `repair: auto` tries first: on broken input, the time until it refuses) and simplify_qem to 1% on the
// repaired mesh, and prints the ratios we hold repair to (repair / simplify <= 0.1; the check on clean input as well).
// Peak memory is the peak of live heap bytes during the call, counted by the global operator new of
// bench/support/peak_memory.cpp (the aligned one too: BlockVector's blocks), minus what was live before it. Bench only,
// never linked into the service.
//
// Usage: bench_repair [--rounds N] [--repair-only] [--cpu]   (rounds: each step's fastest of N runs, the steps in turn,
// default 3; --repair-only: needs_repair and repair_mesh alone, for profiling; --cpu: the thread's CPU time instead of
// wall time)
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "geometry/core/block_pool.h"
#include "geometry/repair/repair.h"
#include "geometry/simplify/qem.h"
#include "geometry/subdivision/subdivide.h"
#include "bench/support/bench_data.h"
#include "bench/support/peak_memory.h"

namespace {

using namespace surfaced;

//! simplify_qem takes its large arrays from one pool for the process, with the service's limit
//! (api/operations/simplify.cpp), so that it is timed as the service runs it.
BlockPool& block_pool() {
    static BlockPool pool(std::size_t{64} << 20);
    return pool;
}

//! One step's fastest run and the peak heap of its last run.
using Timing = bench::Measurement;

//! Wall time, or with --cpu the thread's CPU time (steadier than wall time on a machine other work preempts us on).
bool g_cpu_time = false;

void time_once(const std::function<void()>& step, Timing& t) {
    bench::keep_fastest(t, bench::measure(step, g_cpu_time ? bench::Clock::ThreadCpu : bench::Clock::Wall));
}

Result<SimplifyResult> simplify(const PolygonMesh& mesh) {
    SimplifyOptions options;
    options.ratio = 0.01;
    options.block_pool = &block_pool();
    return simplify_qem(mesh, options);
}

PolygonMesh with_duplicate_face(const PolygonMesh& mesh) {
    PolygonMesh out = mesh;
    const auto face = mesh.face(mesh.face_count() / 2);
    out.add_face({face[0], face[1], face[2]});
    return out;
}

PolygonMesh soup(const PolygonMesh& mesh) {
    PolygonMesh out;
    out.positions.reserve(mesh.face_indices.size());
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const auto face = mesh.face(f);
        const auto first = static_cast<Index>(out.positions.size());
        for (Index v : face) out.positions.push_back(mesh.positions[v]);
        out.add_face({first, first + 1, first + 2});
    }
    return out;
}

std::string report_text(const RepairReport& r) {
    std::string text;
    auto add = [&](const char* name, std::size_t n) {
        if (n == 0) return;
        if (!text.empty()) text += ", ";
        text += name + std::string("=") + std::to_string(n);
    };
    add("welded", r.welded);
    add("degenerate", r.degenerate);
    add("duplicate", r.duplicate);
    add("flipped", r.flipped);
    add("nonmanifold_split", r.nonmanifold_split);
    add("unreferenced", r.unreferenced);
    return text.empty() ? "nothing" : text;
}

bool g_repair_only = false;

void run(const std::string& name, const PolygonMesh& mesh, int rounds) {
    Timing audit, manifold, repair, first_try, simplified;
    bool needs = false, is_manifold = false;
    RepairResult repaired;
    std::string first_outcome;
    for (int round = 0; round < rounds; ++round) {
        time_once([&] { needs = needs_repair(mesh); }, audit);
        // the shared manifold check /simplify and /remesh run before the operation (repair none and auto alike)
        time_once([&] { is_manifold = validate(mesh).ok() && check_manifold(mesh).ok(); }, manifold);
        time_once(
            [&] {
                auto result = repair_mesh(mesh);
                if (!result) {
                    std::fprintf(stderr, "repair_mesh failed: %s\n", result.error().message.c_str());
                    std::exit(1);
                }
                repaired = std::move(result.value());
            },
            repair);
        // what `repair: auto` runs first; on clean input that is the simplification itself (the next column)
        if (g_repair_only) continue;
        if (needs)
            time_once(
                [&] {
                    auto result = simplify(mesh);
                    first_outcome = result ? "accepted" : "refused";
                },
                first_try);
        time_once(
            [&] {
                auto result = simplify(repaired.mesh);
                if (!result) {
                    std::fprintf(stderr, "simplify_qem failed: %s\n", result.error().message.c_str());
                    std::exit(1);
                }
            },
            simplified);
    }
    if (g_repair_only) {
        std::printf("| %s | %zu / %zu | %s | %.3f | %s | %.3f | %.3f | %s | - | - | - | - | - | %.0f | - |\n",
                    name.c_str(), mesh.vertex_count(), mesh.face_count(), needs ? "yes" : "no", audit.seconds,
                    is_manifold ? "yes" : "no", manifold.seconds, repair.seconds, report_text(repaired.report).c_str(),
                    repair.peak_mib);
        std::fflush(stdout);
        return;
    }
    char first[64] = "-";
    if (needs) std::snprintf(first, sizeof first, "%.3f (%s)", first_try.seconds, first_outcome.c_str());
    std::printf(
        "| %s | %zu / %zu | %s | %.3f | %s | %.3f | %.3f | %s | %s | %.3f | %.3f | %.3f | %.3f | %.0f | %.0f |\n",
        name.c_str(), mesh.vertex_count(), mesh.face_count(), needs ? "yes" : "no", audit.seconds,
        is_manifold ? "yes" : "no", manifold.seconds, repair.seconds, report_text(repaired.report).c_str(), first,
        simplified.seconds, audit.seconds / simplified.seconds, manifold.seconds / simplified.seconds,
        repair.seconds / simplified.seconds, repair.peak_mib, simplified.peak_mib);
    std::fflush(stdout);
}

PolygonMesh large_mesh(std::string& name) {
    SubdivisionOptions options;
    options.scheme = SubdivisionScheme::Loop;
    const PolygonMesh bunny = bench::read_bunny();
    if (bunny.face_count() > 0) {
        options.levels = 2;
        name = "bunny, Loop 2";
        return subdivide(bunny, options).value();
    }
    std::fprintf(stderr, "icosphere 8 instead of the bunny\n");
    name = "icosphere 8";
    return bench::icosphere(8);
}

}  // namespace

int main(int argc, char** argv) {
    int rounds = 3;
    for (int i = 1; i + 1 < argc; ++i)
        if (std::strcmp(argv[i], "--rounds") == 0) rounds = std::max(1, std::atoi(argv[i + 1]));
    for (int i = 1; i < argc; ++i)
        if (std::strcmp(argv[i], "--repair-only") == 0)
            g_repair_only = true;
        else if (std::strcmp(argv[i], "--cpu") == 0)
            g_cpu_time = true;
    std::string name;
    const PolygonMesh clean = large_mesh(name);
    std::printf(
        "%s in seconds, one thread, each step's fastest of %d runs (the steps in turn); simplify: simplify_qem to "
        "1%% "
        "of the repaired mesh's faces; first try: simplify_qem on the mesh as sent (what repair auto runs first); "
        "peak: live heap during the call\n\n",
        g_cpu_time ? "CPU time" : "time", rounds);
    std::printf(
        "| input | vertices / faces | needs_repair | needs_repair time | manifold | check_manifold time | "
        "repair_mesh time | repairs | first try | simplify time | needs_repair / simplify | check_manifold / simplify "
        "| repair / simplify | repair peak MiB | simplify peak MiB |\n");
    std::printf("|---|---:|---|---:|---|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|\n");
    run(name + ", clean", clean, rounds);
    run(name + ", one duplicate face", with_duplicate_face(clean), rounds);
    run(name + ", soup", soup(clean), rounds);
    return 0;
}
