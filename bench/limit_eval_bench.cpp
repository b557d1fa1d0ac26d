// Limit surface evaluation at (face, u, v): ours (LimitSurfaceEvaluator) vs OpenSubdiv's Bfr::Surface on the same
// random points, position and first derivatives, one thread; Catmull-Clark rows, then Loop rows ("loop ...", the
// triangle meshes of the same shapes where they have them). Points are grouped by face, as a tessellator would ask
// for them.
//
// Bfr's side is what a user of Bfr does: a RefinerSurfaceFactory over the Far::TopologyRefiner (approximation levels
// at their maximum, 10, as in the accuracy test), then per face InitVertexSurface + PreparePatchPoints once and
// Evaluate per point. Two Bfr columns: per face set-up included ("bfr"), and evaluation alone ("bfr eval only").
// Ours: the evaluator is created once per mesh (its set-up time is printed apart). "ours": evaluate(face, u, v) per
// point, no per-face state kept between calls; "ours/face": face_surface(face) once per face (the patches of its
// regular sub-faces to 6 levels, set-up included), then evaluate(u, v) per point, as Bfr is used. "ours/face" and
// Bfr run in alternation, five rounds each: their columns are the medians, and "o/f:bfr" is the median of the rounds'
// ratios of the two rates (above 1: ours/face is faster).
//
// Usage: bench_limit_eval [--quick]
#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "geometry/mesh/shapes.h"
#include "geometry/mesh/triangulate.h"
#include "geometry/subdivision/limit_evaluation.h"

namespace {

using namespace surfaced;
using namespace OpenSubdiv;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

//! Rounds of the prepared and Bfr timings per mesh.
constexpr int kRounds = 5;

double median(std::vector<double> values) {
    std::sort(values.begin(), values.end());
    const std::size_t n = values.size();
    return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

std::unique_ptr<Far::TopologyRefiner> make_refiner(const PolygonMesh& mesh, bool loop) {
    using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
    std::vector<int> sizes(mesh.face_count());
    for (std::size_t f = 0; f < mesh.face_count(); ++f) sizes[f] = static_cast<int>(mesh.face_size(f));
    std::vector<int> indices(mesh.face_indices.begin(), mesh.face_indices.end());
    std::vector<int> pairs;
    std::vector<float> weights;
    for (const Crease& c : mesh.tags.creases) {
        pairs.push_back(static_cast<int>(c.v0));
        pairs.push_back(static_cast<int>(c.v1));
        weights.push_back(static_cast<float>(c.sharpness));
    }
    Far::TopologyDescriptor desc;
    desc.numVertices = static_cast<int>(mesh.vertex_count());
    desc.numFaces = static_cast<int>(mesh.face_count());
    desc.numVertsPerFace = sizes.data();
    desc.vertIndicesPerFace = indices.data();
    desc.numCreases = static_cast<int>(weights.size());
    desc.creaseVertexIndexPairs = pairs.data();
    desc.creaseWeights = weights.data();
    Sdc::Options sdc;
    sdc.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
    return std::unique_ptr<Far::TopologyRefiner>(
        Factory::Create(desc, Factory::Options(loop ? Sdc::SCHEME_LOOP : Sdc::SCHEME_CATMARK, sdc)));
}

struct Point {
    std::size_t face;
    double u, v;
};

int subface_columns(std::size_t n) {
    return n < 10 ? 2 + (n > 4 ? 1 : 0) : 1 + static_cast<int>(std::sqrt(static_cast<float>(n - 1)));
}

std::vector<Point> random_points(const PolygonMesh& mesh, std::size_t count, std::uint64_t seed, bool loop) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<Point> points;
    for (std::size_t i = 0; i < count; ++i) {
        const std::size_t f = rng() % mesh.face_count(), n = mesh.face_size(f);
        if (loop) {  // the unit triangle
            double u = unit(rng), v = unit(rng);
            if (u + v > 1.0) {
                u = 1.0 - u;
                v = 1.0 - v;
            }
            points.push_back({f, u, v});
        } else if (n == 4) {
            points.push_back({f, unit(rng), unit(rng)});
        } else {
            const int columns = subface_columns(n), sub = static_cast<int>(rng() % n);
            points.push_back({f, sub % columns + 0.5 * unit(rng), sub / columns + 0.5 * unit(rng)});
        }
    }
    std::stable_sort(points.begin(), points.end(), [](const Point& a, const Point& b) { return a.face < b.face; });
    return points;
}

void run(const char* name, const PolygonMesh& mesh, std::size_t count, bool loop = false) {
    const std::vector<Point> points = random_points(mesh, count, 12345, loop);

    SubdivisionOptions subdivision;
    if (loop) subdivision.scheme = SubdivisionScheme::Loop;
    auto t0 = Clock::now();
    auto evaluator = LimitSurfaceEvaluator::create(mesh, subdivision);
    const double setup = seconds_since(t0);
    if (!evaluator) {
        std::printf("%-26s create failed: %s\n", name, evaluator.error().message.c_str());
        return;
    }
    double checksum = 0;
    t0 = Clock::now();
    for (const Point& p : points) {
        auto s = evaluator->evaluate(p.face, p.u, p.v);
        checksum += s->position.x + s->du.y + s->dv.z;
    }
    const double ours = seconds_since(t0);

    std::unique_ptr<Far::TopologyRefiner> refiner = make_refiner(mesh, loop);
    Bfr::SurfaceFactory::Options options;
    options.SetApproxLevelSmooth(10);
    options.SetApproxLevelSharp(10);
    Bfr::RefinerSurfaceFactory<> factory(*refiner, options);
    std::vector<double> mesh_points;
    for (const Vec3& p : mesh.positions) mesh_points.insert(mesh_points.end(), {p.x, p.y, p.z});
    Bfr::Surface<double> surface;
    std::vector<double> patch;

    // prepared per face, as Bfr is used: face_surface once per face, then evaluate per point
    double prepared_checksum = 0;
    auto run_prepared = [&] {
        prepared_checksum = 0;
        const auto start = Clock::now();
        for (std::size_t i = 0; i < points.size();) {
            const std::size_t f = points[i].face;
            auto prepared = evaluator->face_surface(f);
            for (; i < points.size() && points[i].face == f; ++i) {
                auto s = prepared->evaluate(points[i].u, points[i].v);
                prepared_checksum += s->position.x + s->du.y + s->dv.z;
            }
        }
        return seconds_since(start);
    };
    double bfr_checksum = 0, eval_only = 0;
    auto run_bfr = [&] {
        bfr_checksum = 0;
        eval_only = 0;
        const auto start = Clock::now();
        for (std::size_t i = 0; i < points.size();) {
            const std::size_t f = points[i].face;
            factory.InitVertexSurface(static_cast<int>(f), &surface);
            patch.resize(3 * static_cast<std::size_t>(surface.GetNumPatchPoints()));
            surface.PreparePatchPoints(mesh_points.data(), 3, patch.data(), 3);
            const auto e0 = Clock::now();
            for (; i < points.size() && points[i].face == f; ++i) {
                const double uv[2] = {points[i].u, points[i].v};
                double P[3], du[3], dv[3];
                surface.Evaluate(uv, patch.data(), 3, P, du, dv);
                bfr_checksum += P[0] + du[1] + dv[2];
            }
            eval_only += seconds_since(e0);
        }
        return seconds_since(start);
    };
    // the shared machine's load changes within seconds: the two run in alternation, kRounds times (each goes first
    // in every other round), and the medians are reported, with the median of the rounds' ratios
    std::vector<double> prepared_times, bfr_times, eval_times, ratios;
    for (int round = 0; round < kRounds; ++round) {
        double a, b;
        if (round % 2 == 0) {
            a = run_prepared();
            b = run_bfr();
        } else {
            b = run_bfr();
            a = run_prepared();
        }
        prepared_times.push_back(a);
        bfr_times.push_back(b);
        eval_times.push_back(eval_only);
        ratios.push_back(b / a);
    }
    const double prepared = median(prepared_times), bfr = median(bfr_times), bfr_eval = median(eval_times);

    // Bfr at its default approximation levels (smooth 2, sharp 6: Gregory end caps around extraordinary vertices)
    // against ours (exact): the largest position and first-derivative differences over the points, relative to the
    // bounding-box diagonal
    Bfr::RefinerSurfaceFactory<> default_factory(*refiner, Bfr::SurfaceFactory::Options{});
    Vec3 lo = mesh.positions[0], hi = mesh.positions[0];
    for (const Vec3& q : mesh.positions)
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::min(lo[k], q[k]);
            hi[k] = std::max(hi[k], q[k]);
        }
    const double diagonal = norm(hi - lo);
    double default_position = 0, default_derivative = 0;
    for (std::size_t i = 0; i < points.size();) {
        const std::size_t f = points[i].face;
        default_factory.InitVertexSurface(static_cast<int>(f), &surface);
        patch.resize(3 * static_cast<std::size_t>(surface.GetNumPatchPoints()));
        surface.PreparePatchPoints(mesh_points.data(), 3, patch.data(), 3);
        for (; i < points.size() && points[i].face == f; ++i) {
            const double uv[2] = {points[i].u, points[i].v};
            double P[3], du[3], dv[3];
            surface.Evaluate(uv, patch.data(), 3, P, du, dv);
            auto exact = evaluator->evaluate(f, points[i].u, points[i].v);
            if (!exact || !exact->exact) continue;  // within 2^-24 of an extraordinary vertex
            default_position = std::max(default_position, norm(Vec3{P[0], P[1], P[2]} - exact->position));
            default_derivative = std::max({default_derivative, norm(Vec3{du[0], du[1], du[2]} - exact->du),
                                           norm(Vec3{dv[0], dv[1], dv[2]} - exact->dv)});
        }
    }
    const double per_face = static_cast<double>(count) / static_cast<double>(mesh.face_count());
    std::printf("%-26s %6zu %8.0f %8.3f %10.3g %10.3g %10.3g %10.3g %7.2f   %.1e %.1e   %.1e %.1e\n", name,
                mesh.face_count(), per_face, setup * 1e3, count / ours, count / prepared, count / bfr, count / bfr_eval,
                median(ratios), std::abs(checksum - bfr_checksum) / std::max(1.0, std::abs(checksum)),
                std::abs(checksum - prepared_checksum) / std::max(1.0, std::abs(checksum)), default_position / diagonal,
                default_derivative / diagonal);
}

}  // namespace

int main(int argc, char** argv) {
    const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
    const std::size_t count = quick ? 20000 : 200000;
    std::printf("%zu random points per mesh, position + du + dv, one thread; points/s\n", count);
    std::printf("%-26s %6s %8s %8s %10s %10s %10s %10s %7s   %s   %s\n", "mesh", "faces", "pts/face", "setup ms",
                "ours", "ours/face", "bfr", "bfr eval", "o/f:bfr", "checksum diff (bfr, ours/face)",
                "bfr at default levels vs exact: max |dP|, |dD| / diagonal");
    run("torus 32x24 (regular)", shapes::torus(32, 24), count);
    run("irregular_torus", shapes::irregular_torus(), count);
    run("cube (valence 3)", shapes::cube(), count);
    run("mixed_polygons", shapes::mixed_polygons(), count);
    PolygonMesh creased = shapes::cube();
    for (auto [a, b] : {std::pair<Index, Index>{4, 5}, {5, 6}, {6, 7}, {7, 4}})
        creased.tags.creases.push_back({a, b, 2.5});
    run("cube, creases 2.5", creased, count);
    PolygonMesh grid = shapes::grid(16, 16);
    run("grid 16x16 (boundary)", grid, count);
    // Loop: the triangle meshes of the same shapes where they have them
    run("loop torus 32x24 (reg.)", triangulate(shapes::torus(32, 24)), count, true);
    run("loop irregular_torus", triangulate(shapes::irregular_torus()), count, true);
    run("loop icosahedron (val. 5)", shapes::icosahedron(), count, true);
    PolygonMesh loop_creased = triangulate(shapes::cube());
    for (auto [a, b] : {std::pair<Index, Index>{4, 5}, {5, 6}, {6, 7}, {7, 4}})
        loop_creased.tags.creases.push_back({a, b, 2.5});
    run("loop cube, creases 2.5", loop_creased, count, true);
    run("loop grid 16x16 (bound.)", shapes::grid(16, 16, true), count, true);
    return 0;
}
