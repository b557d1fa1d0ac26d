// simplify_qem against two peers on the same triangles, at 10% and 1% of the faces: meshoptimizer's meshopt_simplify
// (Debian libmeshoptimizer-dev) and, in bench_simplify_cgal, CGAL's edge_collapse with GarlandHeckbert_plane_policies
// (Debian libcgal-dev, compiled in cgal_peer.cpp only). Bench only, never linked into the service. Prints a Markdown
// table: time, faces reached, symmetric Hausdorff and two-sided RMS distance to the input (mesh_distance, the same
// sampling for all three), the invariants we promise (non-manifold edges, duplicate faces), and the ratios we hold
// ourselves to (time ours/meshopt <= 2, ours/CGAL <= 0.1; Hausdorff ours/meshopt <= 1; RMS ours/CGAL <= 1).
// Four rows per mesh and target: ours as by default, and with volume restoration (SimplifyOptions::restore_volume),
// each on one thread and with SimplifyOptions::threads = 2 (meshoptimizer and CGAL: one thread).
//
// Usage: bench_simplify[_cgal] [--quick]   (--quick skips the 1M-triangle meshes)
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <meshoptimizer.h>

#ifdef SURFACED_BENCH_CGAL
#include "bench/cgal_peer.h"
#endif

#include "bench/support/bench_data.h"
#include "geometry/core/block_pool.h"
#include "geometry/io/mesh_io.h"
#include "geometry/mesh/shapes.h"
#include "geometry/mesh/triangulate.h"
#include "geometry/simplify/mesh_distance.h"
#include "geometry/simplify/qem.h"
#include "geometry/subdivision/subdivide.h"

namespace {

using namespace surfaced;
using bench::icosphere;
using Clock = std::chrono::steady_clock;

//! Shared machines change speed between seconds, so the peers run in turn, and each one's fastest run is the
//! measurement. Meshes with fewer triangles than kRepeatBelow: kSmallRounds rounds
//! (CGAL, at about a second a run, kCgalSmallRounds); larger ones kLargeRounds (CGAL once, 15-20 s a run).
constexpr std::size_t kRepeatBelow = 500'000;
constexpr int kSmallRounds = 15;
constexpr int kCgalSmallRounds = 5;
constexpr int kLargeRounds = 3;
//! Our second row per mesh and target: SimplifyOptions::restore_volume.
constexpr double kRestoreVolume = 0.5;

//! Our runs take their large arrays from one pool for the process, with the service's limit
//! (api/operations/simplify.cpp), so that the bench times simplifications as the service runs them: on memory that
//! earlier runs faulted in.
BlockPool& block_pool() {
    static BlockPool pool(std::size_t{64} << 20);
    return pool;
}

struct Row {
    bool ran = false;
    std::size_t faces = 0;
    double seconds = 0, hausdorff = 0, rms = 0;
    std::size_t non_manifold = 0, duplicates = 0;
};

//! Edges used by more than two faces, and faces on the same vertex set as another.
void invariants(const PolygonMesh& mesh, Row& row) {
    std::vector<std::uint64_t> edges, faces;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        auto t = mesh.face(f);
        std::array<Index, 3> key{t[0], t[1], t[2]};
        std::sort(key.begin(), key.end());
        faces.push_back((std::uint64_t{key[0]} << 42) ^ (std::uint64_t{key[1]} << 21) ^ key[2]);
        for (int j = 0; j < 3; ++j) {
            const Index a = t[j], b = t[(j + 1) % 3];
            edges.push_back((std::uint64_t{std::min(a, b)} << 32) | std::max(a, b));
        }
    }
    std::sort(edges.begin(), edges.end());
    for (std::size_t i = 0; i < edges.size();) {
        std::size_t j = i;
        while (j < edges.size() && edges[j] == edges[i]) ++j;
        row.non_manifold += j - i > 2;
        i = j;
    }
    std::sort(faces.begin(), faces.end());
    for (std::size_t i = 1; i < faces.size(); ++i) row.duplicates += faces[i] == faces[i - 1];
}

void measure(const PolygonMesh& input, const PolygonMesh& output, Row& row) {
    row.ran = true;
    const MeshDistance d = mesh_distance(input, output);
    row.hausdorff = d.hausdorff;
    row.rms = d.rms;
    row.faces = output.face_count();
    invariants(output, row);
}

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

//! One simplifier on one mesh and target: run() simplifies once and returns the seconds it took; finish() measures
//! the last output (the runs are deterministic: every run gives the same output).
struct Peer {
    virtual ~Peer() = default;
    virtual double run() = 0;
    virtual Row finish() = 0;
};

struct Ours final : Peer {
    Ours(const PolygonMesh& mesh, std::size_t faces, double restore_volume, int threads) : input(mesh) {
        options.target_faces = faces;
        options.restore_volume = restore_volume;
        options.threads = threads;
        options.block_pool = &block_pool();
    }
    double run() override {
        const auto start = Clock::now();
        result = simplify_qem(input, options);
        return seconds_since(start);
    }
    Row finish() override {
        Row row;
        if (!result) {
            std::fprintf(stderr, "simplify_qem failed: %s\n", result.error().message.c_str());
            return row;
        }
        measure(input, result->mesh, row);
        return row;
    }
    const PolygonMesh& input;
    SimplifyOptions options;
    Result<SimplifyResult> result = make_error(ErrorCode::InvalidArgument, "not run");
};

struct Meshopt final : Peer {
    Meshopt(const PolygonMesh& mesh, std::size_t faces)
        : input(mesh),
          target(faces),
          indices(input.face_indices.begin(), input.face_indices.end()),
          out(indices.size()) {
        positions.reserve(3 * input.vertex_count());
        for (const Vec3& p : input.positions) {
            positions.push_back(static_cast<float>(p.x));
            positions.push_back(static_cast<float>(p.y));
            positions.push_back(static_cast<float>(p.z));
        }
    }
    double run() override {
        const auto start = Clock::now();
        float error = 0;
        // target_error 1 (relative): no error limit, stop at the count, as simplify_qem does with target_faces alone
        count = meshopt_simplify(out.data(), indices.data(), indices.size(), positions.data(), input.vertex_count(),
                                 3 * sizeof(float), 3 * target, 1.0f, 0, &error);
        return seconds_since(start);
    }
    Row finish() override {
        // meshopt keeps the original vertex buffer; drop unused vertices so that every vertex sampled is on the
        // surface
        PolygonMesh mesh;
        std::vector<Index> remap(input.vertex_count(), kInvalidIndex);
        for (std::size_t i = 0; i < count; ++i) {
            const Index v = out[i];
            if (remap[v] == kInvalidIndex) {
                remap[v] = static_cast<Index>(mesh.positions.size());
                mesh.positions.push_back(input.positions[v]);
            }
            mesh.face_indices.push_back(remap[v]);
            if (i % 3 == 2) mesh.face_offsets.push_back(static_cast<Index>(mesh.face_indices.size()));
        }
        Row row;
        measure(input, mesh, row);
        return row;
    }
    const PolygonMesh& input;
    std::size_t target;
    std::vector<float> positions;
    std::vector<unsigned int> indices, out;
    std::size_t count = 0;
};

#ifdef SURFACED_BENCH_CGAL
struct Cgal final : Peer {
    Cgal(const PolygonMesh& mesh, std::size_t faces)
        : input(mesh), target(faces), triangles(input.face_indices.begin(), input.face_indices.end()) {
        positions.reserve(3 * input.vertex_count());
        for (const Vec3& p : input.positions) positions.insert(positions.end(), {p.x, p.y, p.z});
    }
    double run() override {
        result = bench::cgal_simplify(positions, triangles, target);
        return result.seconds;
    }
    Row finish() override {
        Row row;
        if (!result.error.empty() || result.rejected_faces > 0) {
            std::fprintf(stderr, "CGAL failed: %s (%zu input faces rejected)\n", result.error.c_str(),
                         result.rejected_faces);
            return row;
        }
        PolygonMesh mesh;
        for (std::size_t i = 0; i + 2 < result.positions.size(); i += 3)
            mesh.positions.push_back({result.positions[i], result.positions[i + 1], result.positions[i + 2]});
        for (std::size_t i = 0; i < result.triangles.size(); ++i) {
            mesh.face_indices.push_back(result.triangles[i]);
            if (i % 3 == 2) mesh.face_offsets.push_back(static_cast<Index>(mesh.face_indices.size()));
        }
        measure(input, mesh, row);
        return row;
    }
    const PolygonMesh& input;
    std::size_t target;
    std::vector<double> positions;
    std::vector<unsigned> triangles;
    bench::CgalSimplifyResult result;
};
#endif

//! Runs the peers in turn, round after round (so that each ratio compares runs made under the same load on this
//! shared machine), peer i in rounds[i] of them, and keeps each peer's fastest run.
std::vector<Row> race(const std::vector<Peer*>& peers, const std::vector<int>& rounds) {
    std::vector<double> best(peers.size(), 1e300);
    const int most = *std::max_element(rounds.begin(), rounds.end());
    for (int round = 0; round < most; ++round)
        for (std::size_t i = 0; i < peers.size(); ++i)
            if (round < rounds[i]) best[i] = std::min(best[i], peers[i]->run());
    std::vector<Row> rows;
    for (std::size_t i = 0; i < peers.size(); ++i) {
        rows.push_back(peers[i]->finish());
        rows.back().seconds = best[i];
    }
    return rows;
}

// "a / b / c" with printf format `format` per value, "-" for a peer that did not run
template <typename Get>
std::string triple(const Row& a, const Row& b, const Row& c, const char* format, Get get) {
    std::string text;
    for (const Row* row : {&a, &b, &c}) {
        if (!text.empty()) text += " / ";
        char buffer[64];
        if (row->ran) {
            std::snprintf(buffer, sizeof buffer, format, get(*row));
            text += buffer;
        } else {
            text += "-";
        }
    }
    return text;
}

std::string ratio(const Row& a, const Row& b, double Row::*field) {
    if (!a.ran || !b.ran || b.*field <= 0) return "-";
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.2f", a.*field / b.*field);
    return buffer;
}

void run(const std::string& name, const PolygonMesh& mesh) {
    const double diagonal = mesh.bounds().diagonal();
    for (double fraction : {0.1, 0.01}) {
        const auto target = static_cast<std::size_t>(fraction * static_cast<double>(mesh.face_count()));
        const bool small = mesh.face_count() < kRepeatBelow;
        // ours four times: plain Garland-Heckbert (the default) and with volume restoration, on one thread and with
        // threads = 2
        Ours ours(mesh, target, 0.0, 1), restoring(mesh, target, kRestoreVolume, 1);
        Ours ours2(mesh, target, 0.0, 2), restoring2(mesh, target, kRestoreVolume, 2);
        Meshopt meshopt(mesh, target);
        const int rounds_each = small ? kSmallRounds : kLargeRounds;
        std::vector<Peer*> peers{&ours, &restoring, &ours2, &restoring2, &meshopt};
        std::vector<int> rounds{rounds_each, rounds_each, rounds_each, rounds_each, rounds_each};
#ifdef SURFACED_BENCH_CGAL
        Cgal cgal(mesh, target);
        peers.push_back(&cgal);
        rounds.push_back(small ? kCgalSmallRounds : 1);
#endif
        const std::vector<Row> rows = race(peers, rounds);
        const Row& b = rows[4];
        const Row c = rows.size() > 5 ? rows[5] : Row{};
        auto relative = [diagonal](double Row::*field) {
            return [diagonal, field](const Row& r) { return r.*field / diagonal; };
        };
        for (int variant = 0; variant < 4; ++variant) {
            const Row& a = rows[static_cast<std::size_t>(variant)];
            std::printf("| %s | %zu | %g%% | %s | %d | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n",
                        name.c_str(), mesh.face_count(), fraction * 100, variant % 2 == 0 ? "0" : "0.5",
                        variant < 2 ? 1 : 2, triple(a, b, c, "%zu", [](const Row& r) { return r.faces; }).c_str(),
                        triple(a, b, c, "%.3f", [](const Row& r) { return r.seconds; }).c_str(),
                        ratio(a, b, &Row::seconds).c_str(), ratio(a, c, &Row::seconds).c_str(),
                        triple(a, b, c, "%.2e", relative(&Row::hausdorff)).c_str(),
                        ratio(a, b, &Row::hausdorff).c_str(), triple(a, b, c, "%.2e", relative(&Row::rms)).c_str(),
                        ratio(a, c, &Row::rms).c_str(),
                        triple(a, b, c, "%zu", [](const Row& r) { return r.non_manifold; }).c_str(),
                        triple(a, b, c, "%zu", [](const Row& r) { return r.duplicates; }).c_str());
        }
        std::fflush(stdout);
    }
}

}  // namespace

int main(int argc, char** argv) {
    const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
#ifdef SURFACED_BENCH_CGAL
    const std::string cgal_name = "CGAL " + bench::cgal_version() + " (Garland-Heckbert plane policies)";
#else
    const std::string cgal_name = "CGAL (not built: bench_simplify_cgal)";
#endif
    std::printf(
        "ours / meshoptimizer %d.%d / %s; errors relative to the bounding-box diagonal; time in seconds, the "
        "peers on one thread (ours also with threads = 2) in turn, fastest of %d runs below %zu triangles (CGAL %d), "
        "else of %d (CGAL 1)\n\n",
        MESHOPTIMIZER_VERSION / 1000, MESHOPTIMIZER_VERSION % 1000 / 10, cgal_name.c_str(), kSmallRounds, kRepeatBelow,
        kCgalSmallRounds, kLargeRounds);
    std::printf(
        "| mesh | triangles | target | our restore_volume | our threads | faces | time | time ours/meshopt | "
        "time ours/CGAL | Hausdorff | Hausdorff ours/meshopt | RMS | RMS ours/CGAL | non-manifold edges | "
        "duplicate faces |\n");
    std::printf("|---|---:|---:|---:|---:|---|---|---:|---:|---|---:|---|---:|---|---|\n");
    const PolygonMesh bunny = bench::read_bunny();
    if (bunny.face_count() > 0) run("bunny", bunny);
    run("icosphere 6", icosphere(6));
    if (!quick) {
        run("icosphere 8", icosphere(8));
        run("torus 1024x512", triangulate(shapes::torus(1024, 512)));
    }
    return 0;
}
