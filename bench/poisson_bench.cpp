// Screened Poisson reconstruction (geometry/reconstruct/poisson.h) by depth, on clouds sampled from a sphere, a torus
// and the bunny (area-uniform, with the faces' normals), and in bench_poisson_cgal CGAL 5.5's Poisson reconstruction on
// the same clouds: CPU time, peak heap, triangles, and Hausdorff / RMS distance to the mesh the cloud was sampled from
// (geometry/simplify/mesh_distance.h, 100k samples a side), one thread each. Peak memory is the peak of live heap bytes
// during the call, counted by the global operator new of bench/support/peak_memory.cpp (CGAL's and Eigen's allocations
// included). Bench only, never linked into the service.
//
// The scale table: 1,000,000 points sampled from the sphere and the bunny at depths 9 and 10 (ours only; CPU and wall
// time, peak heap against estimate_poisson's prediction, the time of each phase).
//
// Usage: bench_poisson [--quick] [--scale] [--points N] [--no-fit]
//                      [--scale-depth D] [--threads T] [--levels] [--tolerance E] [--iterations N]
//   quick: depths 6 and 7 only, no CGAL, no scale table; scale: the scale table only (scale-depth: at depth D only);
//   no-fit: the scale table without PoissonOptions::fit_to_samples;
//   points: per cloud, 50000; threads: PoissonOptions::threads of the scale table (1); levels: each scale row's
//   cells, unknowns and solver iterations per level, on stderr; tolerance, iterations: the scale table's
//   PoissonOptions::tolerance and max_iterations (the defaults)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "geometry/mesh/shapes.h"
#include "geometry/mesh/triangulate.h"
#include "geometry/pointcloud/sampling.h"
#include "geometry/reconstruct/poisson.h"
#include "geometry/simplify/mesh_distance.h"
#include "bench/support/bench_data.h"
#include "bench/support/peak_memory.h"
#if SURFACED_BENCH_CGAL
#include "bench/poisson_peer.h"
#endif

namespace {

using namespace surfaced;

struct Timing {
    double seconds = 0;  //!< CPU, all threads
    double wall = 0;
    double peak_mib = 0;
};

Timing time_once(const std::function<void()>& step) {
    const bench::HeapPeak peak;
    const bench::Stopwatch cpu(bench::Clock::ProcessCpu), wall(bench::Clock::Wall);
    step();
    Timing t;
    t.seconds = cpu.seconds();
    t.wall = wall.seconds();
    t.peak_mib = peak.mib();
    return t;
}

void print_row(const char* shape, const char* method, std::size_t points, const Timing& t, std::size_t triangles,
               const MeshDistance& d, double diagonal) {
    std::printf("| %s | %zu | %s | %.2f | %.0f | %zu | %.2e | %.2e | %.3f%% |\n", shape, points, method, t.seconds,
                t.peak_mib, triangles, d.hausdorff, d.rms, 100.0 * d.rms / diagonal);
    std::fflush(stdout);
}

void run(const char* shape, const PolygonMesh& truth, std::size_t points, const std::vector<int>& depths,
         [[maybe_unused]] bool with_cgal) {
    MeshSamplingOptions so;
    so.count = points;
    const Result<PointCloud> cloud = sample_mesh(truth, so);
    if (!cloud) {
        std::fprintf(stderr, "%s: sampling failed: %s\n", shape, cloud.error().message.c_str());
        return;
    }
    const double diagonal = truth.bounds().diagonal();
    MeshDistanceOptions mo;
    mo.samples = 100'000;
    // the defaults by depth, then from depth 7 the iso-surface as meshed (without the fit to the samples)
    std::vector<std::pair<int, bool>> runs;
    for (const int depth : depths) runs.emplace_back(depth, true);
    for (const int depth : depths)
        if (depth >= 7) runs.emplace_back(depth, false);
    for (const auto& [depth, fit] : runs) {
        PoissonOptions options;
        options.depth = depth;
        options.fit_to_samples = fit;
        Result<PoissonResult> result = make_error(ErrorCode::Internal, "not run");
        const Timing t = time_once([&] { result = reconstruct_poisson(*cloud, options); });
        if (!result) {
            std::fprintf(stderr, "%s depth %d: %s\n", shape, depth, result.error().message.c_str());
            continue;
        }
        char method[64];
        std::snprintf(method, sizeof method, "ours, depth %d%s", depth, fit ? "" : ", not fitted");
        print_row(shape, method, points, t, result->mesh.face_count(), mesh_distance(result->mesh, truth, mo),
                  diagonal);
    }
#if SURFACED_BENCH_CGAL
    if (!with_cgal) return;
    std::vector<double> xyz, normals;
    for (std::size_t i = 0; i < cloud->size(); ++i) {
        xyz.insert(xyz.end(), {cloud->positions[i].x, cloud->positions[i].y, cloud->positions[i].z});
        normals.insert(normals.end(), {cloud->normals[i].x, cloud->normals[i].y, cloud->normals[i].z});
    }
    // CGAL's default criteria, then a finer surface mesh (smaller Delaunay balls and distance bound)
    const double criteria[][2] = {{30.0, 0.375}, {1.0, 0.25}};
    for (const auto& c : criteria) {
        bench::CgalPoissonResult peer;
        const Timing t = time_once([&] { peer = bench::cgal_poisson(xyz, normals, c[0], c[1]); });
        if (!peer.error.empty()) {
            std::fprintf(stderr, "%s CGAL: %s\n", shape, peer.error.c_str());
            continue;
        }
        PolygonMesh mesh;
        for (std::size_t i = 0; i + 2 < peer.positions.size(); i += 3)
            mesh.positions.push_back({peer.positions[i], peer.positions[i + 1], peer.positions[i + 2]});
        for (std::size_t i = 0; i + 2 < peer.triangles.size(); i += 3)
            mesh.add_face({static_cast<Index>(peer.triangles[i]), static_cast<Index>(peer.triangles[i + 1]),
                           static_cast<Index>(peer.triangles[i + 2])});
        char method[96];
        std::snprintf(method, sizeof method, "CGAL, radius %g, distance %g", c[0], c[1]);
        print_row(shape, method, points, t, mesh.face_count(), mesh_distance(mesh, truth, mo), diagonal);
    }
#endif
}

int g_threads = 1;
bool g_levels = false;
double g_tolerance = PoissonOptions{}.tolerance;
int g_iterations = PoissonOptions{}.max_iterations;
bool g_fit = true;

//! 1M points at depths 9 and 10: time, memory and accuracy at scale.
void run_scale(const char* shape, const PolygonMesh& truth, const std::vector<int>& depths) {
    MeshSamplingOptions so;
    so.count = 1'000'000;
    const Result<PointCloud> cloud = sample_mesh(truth, so);
    if (!cloud) return;
    MeshDistanceOptions mo;
    mo.samples = 100'000;
    for (const int depth : depths) {
        PoissonOptions options;
        options.depth = depth;
        options.threads = g_threads;
        options.tolerance = g_tolerance;
        options.max_iterations = g_iterations;
        options.fit_to_samples = g_fit;
        Result<PoissonResult> result = make_error(ErrorCode::Internal, "not run");
        const Timing t = time_once([&] { result = reconstruct_poisson(*cloud, options); });
        if (!result) {
            std::fprintf(stderr, "%s depth %d: %s\n", shape, depth, result.error().message.c_str());
            continue;
        }
        const PoissonStats& s = result->stats;
        const MeshDistance d = mesh_distance(result->mesh, truth, mo);
        const double estimate_mib =
            static_cast<double>(estimate_poisson(cloud->size(), options).bytes) / (1024.0 * 1024.0);
        std::printf(
            "| %s | %zu | %d | %.1f | %.1f | %.1f / %.1f / %.1f / %.1f / %.1f | %.0f | %.0f | %zu | %.2e | %.3f%% |\n",
            shape, cloud->size(), depth, t.seconds, t.wall, s.seconds_octree, s.seconds_system, s.seconds_solve,
            s.seconds_extract, s.seconds_fit, t.peak_mib, estimate_mib, result->mesh.face_count(), d.rms,
            100.0 * d.rms / truth.bounds().diagonal());
        std::fflush(stdout);
        if (g_levels)
            for (std::size_t l = 0; l < s.dofs.size(); ++l)
                std::fprintf(stderr, "  level %zu: %zu cells, %zu unknowns, %d iterations, residual %.1e\n", l + 2,
                             s.cells[l], s.dofs[l], s.iterations[l], s.residuals[l]);
    }
}

}  // namespace

int main(int argc, char** argv) {
    bool quick = false, scale_only = false;
    std::vector<int> scale_depths{9, 10};
    std::size_t points = 50'000;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--quick") == 0) quick = true;
        if (std::strcmp(argv[i], "--scale") == 0) scale_only = true;
        if (std::strcmp(argv[i], "--levels") == 0) g_levels = true;
        if (std::strcmp(argv[i], "--no-fit") == 0) g_fit = false;
        if (std::strcmp(argv[i], "--tolerance") == 0 && i + 1 < argc) g_tolerance = std::atof(argv[++i]);
        if (std::strcmp(argv[i], "--iterations") == 0 && i + 1 < argc) g_iterations = std::atoi(argv[++i]);
        if (std::strcmp(argv[i], "--threads") == 0 && i + 1 < argc) g_threads = std::atoi(argv[++i]);
        if (std::strcmp(argv[i], "--scale-depth") == 0 && i + 1 < argc) {
            scale_only = true;
            scale_depths = {std::atoi(argv[++i])};
        }
        if (std::strcmp(argv[i], "--points") == 0 && i + 1 < argc) points = std::strtoull(argv[++i], nullptr, 10);
    }
    const PolygonMesh bunny = bench::read_bunny();
    if (!scale_only) {
        const std::vector<int> depths = quick ? std::vector<int>{6, 7} : std::vector<int>{6, 7, 8};
        std::printf("| shape | points | method | CPU s | peak MiB | triangles | Hausdorff | RMS | RMS / diagonal |\n");
        std::printf("|---|---|---|---|---|---|---|---|---|\n");
        run("sphere", bench::icosphere(6), points, depths, !quick);
        run("torus", triangulate(shapes::torus(512, 256, 1.0, 0.4)), points, depths, !quick);
        if (bunny.face_count() > 0) run("bunny", bunny, points, depths, !quick);
    }
    if (quick) return 0;
    std::printf(
        "\n| shape | points | depth | CPU s | wall s | octree / system / solve / extract s | peak MiB | "
        "estimate MiB | triangles | RMS | RMS / diagonal |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
    run_scale("sphere", bench::icosphere(6), scale_depths);
    if (bunny.face_count() > 0) run_scale("bunny", bunny, scale_depths);
    return 0;
}
