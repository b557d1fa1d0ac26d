// Trimmed NURBS surfaces (geometry/surfaces/trimmed_surface.h): the unit NURBS sphere (9 x 5 rational quadratic net,
// 8 Bézier patches) with a circular hole (an exact rational quadratic circle in (u, v)), by tolerance: time per call
// (best of several), triangles, the guaranteed bound and the measured deviation in both directions, the smallest
// angle. Built as bench_trim_occt it also meshes the same face with OpenCASCADE's BRepMesh at linear deflection =
// tolerance and measures its mesh the same way. Single thread.
//
// Measured deviation: the larger of (a) the largest distance from points of the mesh (a barycentric grid in every
// triangle) to the sphere and (b) the largest distance from 400 x 400 samples of the exact trimmed surface (u, v
// outside the hole) to the mesh (closest point on a BVH).
//
//   build/bench/bench_trim [--quick]    build/bench/bench_trim_occt [--quick]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <vector>

#include "geometry/spatial/bvh.h"
#include "geometry/spatial/closest_point.h"
#include "geometry/surfaces/trimmed_surface.h"
#ifdef SURFACED_BENCH_OCCT
#include "bench/trim_peers.h"
#endif

namespace {

using namespace surfaced;

constexpr double kCenterU = 0.3, kCenterV = 0.5, kRadius = 0.12;

TrimmedSurface sphere_with_hole() {
    const double h = std::sqrt(0.5);
    const double cx[9] = {1, 1, 0, -1, -1, -1, 0, 1, 1}, cy[9] = {0, 1, 1, 1, 0, -1, -1, -1, 0};
    const double cw[9] = {1, h, 1, h, 1, h, 1, h, 1};
    const std::vector<double> circle_knots{0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1};
    TrimmedSurface t;
    BSplineSurface& s = t.surface;
    s.degree_u = s.degree_v = 2;
    s.count_u = 9;
    s.count_v = 5;
    s.knots_u = circle_knots;
    s.knots_v = {0, 0, 0, 0.5, 0.5, 1, 1, 1};
    const double radius[5] = {0, 1, 1, 1, 0}, height[5] = {-1, -1, 0, 1, 1}, pw[5] = {1, h, 1, h, 1};
    for (int j = 0; j < 5; ++j)
        for (int i = 0; i < 9; ++i) {
            s.points.push_back({radius[j] * cx[i], radius[j] * cy[i], height[j]});
            s.weights.push_back(cw[i] * pw[j]);
        }
    TrimCurve c;
    c.degree = 2;
    c.knots = circle_knots;
    for (int i = 0; i < 9; ++i) {
        c.points.push_back({kCenterU + kRadius * cx[8 - i], kCenterV + kRadius * cy[8 - i]});  // clockwise: a hole
        c.weights.push_back(cw[8 - i]);
    }
    t.holes.push_back(TrimLoop{{c}});
    return t;
}

struct Measures {
    double deviation = 0;         //!< max of both directions
    double min_angle = 180;       //!< over all triangles (the sphere's poles included)
    double min_angle_trim = 180;  //!< over triangles with a corner on the hole's open edges
};

Measures measure(const BSplineSurface& s, const PolygonMesh& mesh) {
    Measures m;
    std::map<std::pair<Index, Index>, int> edge_uses;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const auto face = mesh.face(f);
        for (std::size_t k = 0; k < 3; ++k)
            ++edge_uses[{std::min(face[k], face[(k + 1) % 3]), std::max(face[k], face[(k + 1) % 3])}];
    }
    std::vector<char> open(mesh.positions.size(), 0);
    for (const auto& [edge, uses] : edge_uses)
        if (uses == 1) open[edge.first] = open[edge.second] = 1;
    // BRepMesh leaves the sphere's seam (y = 0, x >= 0) and its poles open: those are not the hole
    for (std::size_t v = 0; v < open.size(); ++v) {
        const Vec3& p = mesh.positions[v];
        if ((std::fabs(p.y) < 1e-9 && p.x > -1e-9) || std::fabs(p.z) > 1 - 1e-9) open[v] = 0;
    }
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const auto face = mesh.face(f);
        const Vec3 a = mesh.positions[face[0]], b = mesh.positions[face[1]], c = mesh.positions[face[2]];
        for (int i = 0; i <= 6; ++i)
            for (int j = 0; i + j <= 6; ++j)
                m.deviation = std::max(m.deviation, std::fabs(norm(a + (i / 6.0) * (b - a) + (j / 6.0) * (c - a)) - 1));
        for (int k = 0; k < 3; ++k) {
            const Vec3 o = mesh.positions[face[static_cast<std::size_t>(k)]];
            const Vec3 p = mesh.positions[face[static_cast<std::size_t>((k + 1) % 3)]] - o;
            const Vec3 q = mesh.positions[face[static_cast<std::size_t>((k + 2) % 3)]] - o;
            const double angle = std::atan2(norm(cross(p, q)), dot(p, q)) * 180 / 3.14159265358979;
            m.min_angle = std::min(m.min_angle, angle);
            if (open[face[0]] || open[face[1]] || open[face[2]]) m.min_angle_trim = std::min(m.min_angle_trim, angle);
        }
    }
    auto bvh = build_bvh(mesh);
    if (!bvh) return m;
    constexpr int n = 400;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const double u = static_cast<double>(i) / n, v = static_cast<double>(j) / n;
            if (std::hypot(u - kCenterU, v - kCenterV) <= kRadius) continue;
            const auto hit = closest_point(*bvh, *evaluate(s, u, v));
            if (hit) m.deviation = std::max(m.deviation, hit->distance);
        }
    return m;
}

}  // namespace

int main(int argc, char** argv) {
    const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
    const TrimmedSurface trimmed = sphere_with_hole();
    std::vector<double> tolerances{1e-2, 3e-3, 1e-3, 3e-4};
    if (!quick) tolerances.push_back(1e-4);
    std::printf("unit NURBS sphere with a circular hole (exact rational trim), single thread, best of N calls\n\n");
#ifdef SURFACED_BENCH_OCCT
    std::printf(
        "| tolerance | ours: triangles | ms | guaranteed bound | measured deviation | min angle (at the hole) | "
        "BRepMesh: triangles | ms | measured deviation | min angle (at the hole) | triangles ours / BRepMesh |\n");
    std::printf("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
#else
    std::printf(
        "| tolerance | triangles | ms per call | triangles/s | guaranteed bound | measured deviation | min angle (at "
        "the hole) |\n");
    std::printf("|---:|---:|---:|---:|---:|---:|---:|\n");
#endif
    for (const double tolerance : tolerances) {
        const int runs = tolerance < 5e-4 ? 3 : 7;
        TrimmedTessellationOptions options;
        options.tolerance = tolerance;
        double best = 1e300;
        TrimmedTessellation result;
        for (int r = 0; r < runs; ++r) {
            const auto t0 = std::chrono::steady_clock::now();
            auto t = tessellate(trimmed, options);
            const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
            if (!t) {
                std::fprintf(stderr, "tessellation failed: %s\n", t.error().message.c_str());
                return 1;
            }
            best = std::min(best, ms);
            result = std::move(t.value());
        }
        const Measures ours = measure(trimmed.surface, result.mesh);
#ifdef SURFACED_BENCH_OCCT
        const bench::PeerMesh peer = bench::occt_mesh(trimmed, tolerance, runs);
        if (!peer.error.empty()) {
            std::fprintf(stderr, "BRepMesh: %s\n", peer.error.c_str());
            return 1;
        }
        const Measures theirs = measure(trimmed.surface, peer.mesh);
        std::printf("| %g | %zu | %.2f | %.3g | %.3g | %.1f (%.1f) | %zu | %.2f | %.3g | %.1f (%.1f) | %.2f |\n",
                    tolerance, result.mesh.face_count(), best, result.bound, ours.deviation, ours.min_angle,
                    ours.min_angle_trim, peer.mesh.face_count(), peer.ms, theirs.deviation, theirs.min_angle,
                    theirs.min_angle_trim,
                    static_cast<double>(result.mesh.face_count()) / static_cast<double>(peer.mesh.face_count()));
#else
        std::printf("| %g | %zu | %.2f | %.2f M | %.3g | %.3g | %.1f (%.1f) |\n", tolerance, result.mesh.face_count(),
                    best, static_cast<double>(result.mesh.face_count()) / best / 1e3, result.bound, ours.deviation,
                    ours.min_angle, ours.min_angle_trim);
#endif
    }
    return 0;
}
