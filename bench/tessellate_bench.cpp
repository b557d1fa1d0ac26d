// Bézier patch tessellation (geometry/surfaces/bezier_patch.h) on the Utah teapot (the built-in sample, 32 bicubic
// patches): time per call (best of several), patches/s, triangles/s, triangles, the guaranteed bound and the
// measured maximum deviation, by tolerance and by fixed segment count; and our segment counts (per patch from each
// patch's own net, made equal along shared edges) against one uniform Wang-style count for all patches at the same
// tolerance (the smallest n for which the same second-derivative bound holds on every patch with n x n segments).
// Single thread.
//
//   build/bench/bench_tessellate [--quick]     (--quick: tolerances down to 1e-3, segments up to 16, fewer runs)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "geometry/io/bez.h"
#include "geometry/surfaces/bezier_patch.h"

namespace {

using namespace surfaced;

struct Run {
    double ms = 1e300;  //!< best of the runs
    std::size_t triangles = 0;
    double bound = 0;
    double measured = 0;
};

//! Max distance between each triangle (linear in its corners' parameters) and the exact surface at the same
//! parameters, at the points of a barycentric grid with `samples` steps per side (the test suite's measure).
double measured_max_deviation(const PatchSet& set, const PatchTessellation& t, int samples) {
    const PolygonMesh& mesh = t.mesh;
    double worst = 0;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const BezierPatch& patch = set.patches[t.face_patches[f]];
        const auto face = mesh.face(f);
        const std::size_t base = mesh.face_offsets[f];
        const Vec2 uv0 = mesh.uvs[mesh.uv_indices[base]], uv1 = mesh.uvs[mesh.uv_indices[base + 1]],
                   uv2 = mesh.uvs[mesh.uv_indices[base + 2]];
        for (int a = 0; a <= samples; ++a)
            for (int b = 0; a + b <= samples; ++b) {
                const double l1 = static_cast<double>(a) / samples, l2 = static_cast<double>(b) / samples;
                const double l0 = 1 - l1 - l2;
                const Vec3 linear =
                    l0 * mesh.positions[face[0]] + l1 * mesh.positions[face[1]] + l2 * mesh.positions[face[2]];
                const Vec3 exact =
                    evaluate(patch, l0 * uv0.x + l1 * uv1.x + l2 * uv2.x, l0 * uv0.y + l1 * uv1.y + l2 * uv2.y);
                worst = std::max(worst, norm(linear - exact));
            }
    }
    return worst;
}

Run measure(const PatchSet& set, const TessellationOptions& options, int repeats, bool measure_deviation) {
    Run best;
    for (int r = 0; r < repeats; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        auto result = tessellate_patches(set.patches, options);
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        if (!result) {
            std::fprintf(stderr, "tessellation failed: %s\n", result.error().message.c_str());
            std::exit(1);
        }
        best.ms = std::min(best.ms, ms);
        best.triangles = result->mesh.face_count();
        best.bound = result->plan.error_bound;
        if (measure_deviation && r == 0) best.measured = measured_max_deviation(set, *result, 4);
    }
    return best;
}

//! The smallest n such that tessellation_error_bound(patch, n, n) <= tolerance for every patch.
int uniform_wang_count(const PatchSet& set, double tolerance) {
    int n = 1;
    for (const BezierPatch& patch : set.patches)
        while (tessellation_error_bound(patch, n, n) > tolerance) ++n;
    return n;
}

int repeats_for(std::size_t triangles, bool quick) {
    const int base = quick ? 3 : 9;
    return triangles > 1'000'000 ? 1 : triangles > 100'000 ? std::max(1, base / 3) : base;
}

}  // namespace

int main(int argc, char** argv) {
    const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
    auto read = read_bez(patch_sample_text("teapot"));
    if (!read) {
        std::fprintf(stderr, "teapot: %s\n", read.error().message.c_str());
        return 1;
    }
    const PatchSet set = std::move(read.value());
    const double patches = static_cast<double>(set.patches.size());

    std::vector<double> tolerances = {1e-1, 1e-2, 1e-3};
    if (!quick) tolerances.push_back(1e-4);
    std::vector<int> segment_counts = {4, 8, 16};
    if (!quick) segment_counts.push_back(32);

    std::printf("teapot: %zu bicubic patches, single thread, best of N calls\n\n", set.patches.size());
    std::printf(
        "| input | triangles | ms per call (best) | patches/s | triangles/s | bound | measured max deviation |\n");
    std::printf("|---|---:|---:|---:|---:|---:|---:|\n");
    const auto row = [&](const char* kind, double value, const Run& run) {
        std::printf("| %s %g | %zu | %.3f | %.0f | %.3g | %.3g | %.3g |\n", kind, value, run.triangles, run.ms,
                    patches / (run.ms / 1000), static_cast<double>(run.triangles) / (run.ms / 1000), run.bound,
                    run.measured);
        std::fflush(stdout);
    };
    for (double tolerance : tolerances) {
        TessellationOptions options;
        options.tolerance = tolerance;
        options.max_segments = 4096;
        auto plan = plan_tessellation(set.patches, options);
        if (!plan) {
            std::fprintf(stderr, "plan: %s\n", plan.error().message.c_str());
            return 1;
        }
        row("tolerance", tolerance, measure(set, options, repeats_for(plan->triangles, quick), true));
    }
    for (int segments : segment_counts) {
        TessellationOptions options;
        options.segments = segments;
        const std::uint64_t triangles = 2ull * static_cast<std::uint64_t>(segments * segments) * set.patches.size();
        row("segments", segments, measure(set, options, repeats_for(triangles, quick), true));
    }

    std::printf(
        "\n| tolerance | ours: triangles | ours: segments per patch (min..max) | uniform Wang n | uniform "
        "triangles (32 x 2 n^2) | ratio ours / uniform |\n");
    std::printf("|---:|---:|---:|---:|---:|---:|\n");
    for (double tolerance : tolerances) {
        TessellationOptions options;
        options.tolerance = tolerance;
        options.max_segments = 4096;
        auto plan = plan_tessellation(set.patches, options);
        if (!plan) return 1;
        int lo = 1 << 30, hi = 0;
        for (const PatchSegments& s : plan->segments) {
            lo = std::min({lo, s.nu, s.nv});
            hi = std::max({hi, s.nu, s.nv});
        }
        const int n = uniform_wang_count(set, tolerance);
        const double uniform = 2.0 * n * n * patches;
        std::printf("| %g | %llu | %d..%d | %d | %.0f | %.3f |\n", tolerance,
                    static_cast<unsigned long long>(plan->triangles), lo, hi, n, uniform,
                    static_cast<double>(plan->triangles) / uniform);
    }
    return 0;
}
