// Mesh -> narrow-band signed distance grid (geometry/implicit/distance_grid.h), one thread: time and peak heap per mesh
// and voxel size, and in bench_grid_openvdb the same conversion by OpenVDB's meshToLevelSet (one TBB thread), timed in
// turn round by round (process CPU time, so that other load on the machine does not count), with the values of the two
// grids compared at every node inside both narrow bands. Peak memory is the peak of live heap bytes during the
// conversion, counted by the global operator new of bench/support/peak_memory.cpp (what OpenVDB allocates through TBB's
// scalable allocator is not counted; its grid's own memUsage is printed too). Ours is a dense grid of doubles (the
// level_set node's form), OpenVDB's a sparse tree of floats. Bench only, never linked into the service.
//
// Usage: bench_grid [--quick] [--rounds N] [--band W] [--only NAME]   (quick: the coarser voxel size only; rounds:
// fastest of N, default 3; band: voxels, default 3; only: the meshes whose name starts with NAME)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <memory>
#include <numbers>
#include <utility>
#include <string>
#include <vector>

#include "geometry/implicit/distance_grid.h"
#include "geometry/io/bez.h"
#include "geometry/mesh/triangulate.h"
#include "geometry/surfaces/bezier_patch.h"
#include "geometry/spatial/closest_point.h"
#include "geometry/spatial/winding_number.h"
#include "bench/support/bench_data.h"
#include "bench/support/peak_memory.h"
#if SURFACED_BENCH_OPENVDB
#include "bench/grid_peers.h"
#endif

namespace {

using namespace surfaced;

int g_rounds = 3;
//! --only: run the meshes whose name starts with this
std::string g_only;

using Timing = bench::Measurement;

//! One run of `step`: its CPU time (the process's, all threads: both sides run on one, and other processes sharing the
//! machine do not count) and the live-heap peak above the start, in MiB.
Timing time_once(const std::function<void()>& step) { return bench::measure(step, bench::Clock::ProcessCpu); }

//! The Utah teapot (the built-in patch sample), 32 segments per patch side: 65,536 triangles, open (no lid rim
//! seal, the spout and handle ends open and running into the body), so signs take the open-surface path.
PolygonMesh teapot() {
    auto read = read_bez(patch_sample_text("teapot"));
    if (!read) return {};
    TessellationOptions options;
    options.segments = 32;
    auto tessellated = tessellate_patches(read->patches, options);
    return tessellated ? std::move(tessellated->mesh) : PolygonMesh{};
}

void run(const std::string& name, const PolygonMesh& input, int cells, int band) {
    if (name.compare(0, g_only.size(), g_only) != 0) return;
    const PolygonMesh mesh = input.is_triangle_mesh() ? input : triangulate(input);
    const Box3 box = mesh.bounds();
    const Vec3 extent = box.max - box.min;
    const double h = std::max({extent.x, extent.y, extent.z}) / cells;
    implicit::DistanceGridOptions options;
    options.voxel_size = h;
    options.band = band;
    options.max_nodes = std::uint64_t{1} << 31;
    implicit::DistanceGridStats stats;
    implicit::LevelSetGrid grid;
    auto ours_step = [&] { grid = std::move(implicit::mesh_distance_grid(mesh, options, &stats).value()); };
    Timing ours;
#if SURFACED_BENCH_OPENVDB
    // OpenVDB's voxel (i, j, k) at our node (i, j, k): the mesh moved by minus our grid's origin
    const Box3 bounds = implicit::default_distance_grid_bounds(box, h, band);
    std::vector<float> positions;
    for (const Vec3& p : mesh.positions)
        for (int a = 0; a < 3; ++a) positions.push_back(static_cast<float>(p[a] - bounds.min[a]));
    std::vector<unsigned> triangles(mesh.face_indices.begin(), mesh.face_indices.end());
    std::unique_ptr<bench::OpenVdbLevelSet> vdb;
    Timing theirs;
    for (int r = 0; r < g_rounds; ++r) {
        const Timing a = time_once(ours_step);
        if (a.seconds < ours.seconds) ours = a;
        vdb.reset();
        const Timing b =
            time_once([&] { vdb = std::make_unique<bench::OpenVdbLevelSet>(positions, triangles, h, band); });
        if (b.seconds < theirs.seconds) theirs = b;
    }
#else
    for (int r = 0; r < g_rounds; ++r) {
        const Timing a = time_once(ours_step);
        if (a.seconds < ours.seconds) ours = a;
    }
#endif
    std::printf("| %s | %zu | %.4g (%d cells) | %zux%zux%zu | %llu | %.1f | %.0f | %llu |", name.c_str(),
                mesh.face_count(), h, cells, grid.dims[0], grid.dims[1], grid.dims[2],
                static_cast<unsigned long long>(stats.band_nodes), ours.seconds * 1e3, ours.peak_mib,
                static_cast<unsigned long long>(stats.winding_queries));
#if SURFACED_BENCH_OPENVDB
    // every node inside both bands: the largest difference where the signs agree (and within one voxel of the
    // surface), the signs that differ; then 8 nodes against brute force (the minimum distance over every triangle,
    // the sign of the exact winding-number sum): where the signs differ, else where the values differ most
    const double limit = band * h;
    double max_difference = 0, near_difference = 0;
    std::size_t compared = 0, signs = 0, ours_only = 0;
    std::vector<std::pair<double, std::size_t>> worst;
    for (std::size_t k = 0; k < grid.dims[2]; ++k)
        for (std::size_t j = 0; j < grid.dims[1]; ++j)
            for (std::size_t i = 0; i < grid.dims[0]; ++i) {
                const std::size_t node = i + grid.dims[0] * (j + grid.dims[1] * k);
                const double a = grid.values[node];
                const double b = vdb->value(static_cast<int>(i), static_cast<int>(j), static_cast<int>(k));
                const bool in_a = std::abs(a) < limit * (1 - 1e-6), in_b = std::abs(b) < limit * (1 - 1e-6);
                ours_only += in_a && !in_b;
                if (!in_a || !in_b) continue;
                ++compared;
                const double difference = std::abs(a - b);
                const bool flipped = (a < 0) != (b < 0) && std::abs(a) > 1e-6 * h;
                signs += flipped;
                if (!flipped) {
                    max_difference = std::max(max_difference, difference);
                    if (std::abs(a) <= h) near_difference = std::max(near_difference, difference);
                }
                // a flipped sign goes first (its difference counted as above any other), then the largest
                worst.emplace_back(flipped ? 1e300 : difference, node);
                if (worst.size() > 64) {
                    std::nth_element(worst.begin(), worst.begin() + 8, worst.end(), std::greater<>());
                    worst.resize(8);
                }
            }
    std::sort(worst.begin(), worst.end(), std::greater<>());
    worst.resize(std::min<std::size_t>(worst.size(), 8));
    double ours_vs_brute = 0, vdb_vs_brute = 0;
    std::size_t ours_wrong_sign = 0, vdb_wrong_sign = 0;
    for (const auto& [difference, node] : worst) {
        const std::size_t i = node % grid.dims[0], j = (node / grid.dims[0]) % grid.dims[1],
                          k = node / (grid.dims[0] * grid.dims[1]);
        const Vec3 p = grid.origin + Vec3{static_cast<double>(i), static_cast<double>(j), static_cast<double>(k)} * h;
        double best = 1e300;
        for (std::size_t f = 0; f < mesh.face_count(); ++f) {
            const auto t = mesh.face(f);
            const Vec3 q =
                triangle_closest_point(p, mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]).point;
            best = std::min(best, norm(q - p));
        }
        double angles = 0;  // the exact winding number's sign: inside where w >= 1/2
        for (std::size_t f = 0; f < mesh.face_count(); ++f) {
            const auto t = mesh.face(f);
            angles += triangle_solid_angle(p, mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]);
        }
        const bool inside = angles / (4 * std::numbers::pi) >= 0.5;
        const double b = vdb->value(static_cast<int>(i), static_cast<int>(j), static_cast<int>(k));
        if (best > 1e-6 * h) {
            ours_wrong_sign += (grid.values[node] < 0) != inside;
            vdb_wrong_sign += (b < 0) != inside;
        }
        ours_vs_brute = std::max(ours_vs_brute, std::abs(std::abs(grid.values[node]) - best));
        vdb_vs_brute = std::max(vdb_vs_brute, std::abs(std::abs(b) - best));
    }
    std::printf(
        " %.1f | %.0f (grid %.0f) | %llu | **%.2f** | %.2g h (%.2g h within h) | %.2g h, %zu / %.2g h, %zu "
        "| %zu of %zu | %zu |\n",
        theirs.seconds * 1e3, theirs.peak_mib, static_cast<double>(vdb->memory_bytes()) / (1024.0 * 1024.0),
        static_cast<unsigned long long>(vdb->active_voxels()), ours.seconds / theirs.seconds, max_difference / h,
        near_difference / h, ours_vs_brute / h, ours_wrong_sign, vdb_vs_brute / h, vdb_wrong_sign, signs, compared,
        ours_only);
#else
    std::printf("\n");
#endif
    std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
    bool quick = false;
    int band = 3;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--quick") == 0) quick = true;
        if (std::strcmp(argv[i], "--rounds") == 0 && i + 1 < argc) g_rounds = std::max(1, std::atoi(argv[++i]));
        if (std::strcmp(argv[i], "--band") == 0 && i + 1 < argc) band = std::max(1, std::atoi(argv[++i]));
        if (std::strcmp(argv[i], "--only") == 0 && i + 1 < argc) g_only = argv[++i];
    }
#if SURFACED_BENCH_OPENVDB
    std::printf("OpenVDB %s, one thread; band %d voxels; fastest of %d\n\n", bench::openvdb_version().c_str(), band,
                g_rounds);
    std::printf(
        "| mesh | triangles | voxel size | grid | band nodes | ours ms | ours peak MiB | winding queries | "
        "OpenVDB ms | OpenVDB peak MiB | OpenVDB active voxels | ours / OpenVDB | max difference | "
        "vs brute force at 8 nodes (signs differ, else the largest difference): ours, wrong signs / OpenVDB, wrong "
        "signs | signs differ | ours in band, "
        "OpenVDB not |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
#else
    std::printf("one thread; band %d voxels; fastest of %d\n\n", band, g_rounds);
    std::printf("| mesh | triangles | voxel size | grid | band nodes | ours ms | ours peak MiB | winding queries |\n");
    std::printf("|---|---|---|---|---|---|---|---|\n");
#endif
    const PolygonMesh bunny = bench::read_bunny();
    const PolygonMesh sphere = bench::icosphere(6);
    const PolygonMesh pot = teapot();
    std::vector<int> resolutions = {128};
    if (!quick) resolutions.push_back(256);
    for (const int cells : resolutions) {
        if (bunny.face_count() > 0) run("bunny", bunny, cells, band);
        run("sphere", sphere, cells, band);
        if (pot.face_count() > 0) run("teapot (open)", pot, cells, band);
    }
    return 0;
}
