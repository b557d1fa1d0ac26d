// Tolerance-driven tessellation of the Catmull-Clark limit surface: the output vertices against OpenSubdiv's
// Bfr::Surface at their (face, u, v), dense exact limit samples against the output triangles (distance <= the
// tolerance), and the mesh invariants (watertight where the input is closed, no T-junctions, Euler characteristic,
// creases kept), over built-in and OpenSubdiv regression shapes.
#include <gtest/gtest.h>

#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/far/topologyRefiner.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "geometry/io/mesh_io.h"
#include "geometry/mesh/shapes.h"
#include "geometry/spatial/bvh.h"
#include "geometry/spatial/closest_point.h"
#include "geometry/subdivision/subdivide.h"
#include "geometry/subdivision/adaptive_tessellation.h"
#include "geometry/subdivision/limit_evaluation.h"
#include "geometry/subdivision/tessellation_bounds.h"
#include "geometry/subdivision/tessellation_strips.h"
#include "tests/support/opensubdiv_shapes.h"
#include "tests/support/mesh_asserts.h"
#include "tests/support/osd_reference.h"

namespace surfaced {
namespace {

namespace fs = std::filesystem;
using namespace OpenSubdiv;

using testing::load_opensubdiv_shape;

int subface_columns(std::size_t n) {
    return n < 10 ? 2 + (n > 4 ? 1 : 0) : 1 + static_cast<int>(std::sqrt(static_cast<float>(n - 1)));
}

struct Case {
    std::string name;
    PolygonMesh mesh;
};

//! Shapes with smooth regions, extraordinary vertices of valence 3 to 6, N-gons, boundaries, semi-sharp and
//! infinitely sharp creases and corners (no holes, no faces using a vertex twice).
std::vector<Case> cases() {
    std::vector<Case> out;
    out.push_back({"cube", shapes::cube()});
    out.push_back({"torus", shapes::torus(8, 6)});
    out.push_back({"irregular_torus", shapes::irregular_torus()});
    out.push_back({"mixed_polygons", shapes::mixed_polygons()});
    out.push_back({"grid", shapes::grid(4, 3)});
    for (const char* name :
         {"catmark_cube", "catmark_gregory_test1", "catmark_edgecorner", "catmark_cube_creases0",
          "catmark_cube_creases1", "catmark_cube_corner3", "catmark_cubes_semisharp", "catmark_inf_crease0",
          "catmark_pyramid_creases1", "catmark_nonquads", "catmark_torus_creases0", "catmark_dart_edgecorner"})
        out.push_back({name, load_opensubdiv_shape(name)});
    return out;
}

double diagonal(const PolygonMesh& mesh) {
    const Box3 box = mesh.bounds();
    return norm(box.max - box.min);
}

//! Bfr::Surface of every face, at its deepest approximation.
class BfrReference {
public:
    BfrReference(const PolygonMesh& mesh, const SubdivisionOptions& options)
        : refiner_(testing::make_refiner(mesh, options)) {
        for (const Vec3& p : mesh.positions) points_.insert(points_.end(), {p.x, p.y, p.z});
        Bfr::SurfaceFactory::Options fo;
        fo.SetApproxLevelSmooth(10);
        fo.SetApproxLevelSharp(10);
        factory_ = std::make_unique<Bfr::RefinerSurfaceFactory<>>(*refiner_, fo);
    }
    Vec3 position(std::size_t face, double u, double v) {
        Bfr::Surface<double> surface;
        EXPECT_TRUE(factory_->InitVertexSurface(static_cast<int>(face), &surface));
        std::vector<double> patch(3 * static_cast<std::size_t>(surface.GetNumPatchPoints()));
        surface.PreparePatchPoints(points_.data(), 3, patch.data(), 3);
        const double uv[2] = {u, v};
        double p[3];
        surface.Evaluate(uv, patch.data(), 3, p);
        return {p[0], p[1], p[2]};
    }

private:
    std::unique_ptr<Far::TopologyRefiner> refiner_;
    std::unique_ptr<Bfr::RefinerSurfaceFactory<>> factory_;
    std::vector<double> points_;
};

//! Undirected edge -> directed uses.
std::map<std::pair<Index, Index>, std::vector<std::pair<Index, Index>>> edge_uses(const PolygonMesh& mesh) {
    std::map<std::pair<Index, Index>, std::vector<std::pair<Index, Index>>> uses;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const auto fv = mesh.face(f);
        for (std::size_t k = 0; k < fv.size(); ++k) {
            const Index a = fv[k], b = fv[(k + 1) % fv.size()];
            uses[std::minmax(a, b)].emplace_back(a, b);
        }
    }
    return uses;
}

long euler(const PolygonMesh& mesh) {
    std::vector<bool> used(mesh.vertex_count(), false);
    long v = 0;
    for (Index i : mesh.face_indices)
        if (!used[i]) {
            used[i] = true;
            ++v;
        }
    return v - static_cast<long>(edge_uses(mesh).size()) + static_cast<long>(mesh.face_count());
}

//! Max distance from exact limit samples (a 9 x 9 grid per quad domain, per N-gon sub-face) to the triangles.
double sampled_distance(const LimitSurfaceEvaluator& evaluator, const PolygonMesh& base, const PolygonMesh& out) {
    auto bvh = build_bvh(out);
    EXPECT_TRUE(bvh.ok());
    if (!bvh.ok()) return 1e300;
    double worst = 0;
    constexpr int kSteps = 9;
    for (std::size_t f = 0; f < base.face_count(); ++f) {
        const std::size_t n = base.face_size(f);
        const std::size_t domains = n == 4 ? 1 : n;
        for (std::size_t d = 0; d < domains; ++d)
            for (int j = 0; j <= kSteps; ++j)
                for (int i = 0; i <= kSteps; ++i) {
                    // off the grid lines of any power-of-two rate: (i + 0.37) / (kSteps + 0.74)
                    const double s = (i + 0.37) / (kSteps + 0.74), t = (j + 0.61) / (kSteps + 1.22);
                    double u = s, v = t;
                    if (n != 4) {
                        const int columns = subface_columns(n);
                        u = double(d % std::size_t(columns)) + 0.5 * s;
                        v = double(d / std::size_t(columns)) + 0.5 * t;
                    }
                    auto sample = evaluator.evaluate(f, u, v);
                    EXPECT_TRUE(sample.ok());
                    if (!sample.ok()) continue;
                    auto closest = closest_point(*bvh, sample->position);
                    EXPECT_TRUE(closest.has_value());
                    if (closest) worst = std::max(worst, closest->distance);
                }
    }
    return worst;
}

TEST(AdaptiveTessellation, WithinToleranceWatertightOnTheLimit) {
    for (const Case& c : cases()) {
        SCOPED_TRACE(c.name);
        ASSERT_GT(c.mesh.face_count(), 0u);
        const SubdivisionOptions sub;
        auto evaluator = LimitSurfaceEvaluator::create(c.mesh, sub);
        ASSERT_TRUE(evaluator.ok()) << evaluator.error().message;
        const bool closed = [&] {
            for (const auto& [edge, uses] : edge_uses(c.mesh))
                if (uses.size() != 2) return false;
            return true;
        }();
        BfrReference bfr(c.mesh, sub);
        for (double relative : {1e-2, 3e-3}) {
            SCOPED_TRACE(relative);
            LimitTessellationOptions options;
            options.tolerance = relative * diagonal(c.mesh);
            options.straddle = 0;  // every vertex on the limit surface, checked against Far and Bfr below
            auto plan = plan_limit_tessellation(*evaluator, c.mesh, options);
            ASSERT_TRUE(plan.ok()) << plan.error().message;
            // the prediction is made before any vertex is evaluated: exact for the grids, an upper bound once the
            // vertices the tolerance does not need are removed
            options.decimate = false;
            auto grids = tessellate_limit(*evaluator, c.mesh, options);
            ASSERT_TRUE(grids.ok()) << grids.error().message;
            EXPECT_EQ(predict_triangles(*plan), grids->mesh.face_count());
            EXPECT_EQ(plan->vertices, grids->mesh.vertex_count());
            EXPECT_EQ(grids->removed_vertices, 0u);
            options.decimate = true;
            auto result = tessellate_limit(*evaluator, c.mesh, options);
            ASSERT_TRUE(result.ok()) << result.error().message;
            const PolygonMesh& out = result->mesh;
            EXPECT_LE(out.face_count(), predict_triangles(*plan));
            EXPECT_EQ(plan->vertices - result->removed_vertices, out.vertex_count());
            // a removed vertex takes two triangles with it on a closed surface (the Euler characteristic is kept)
            if (closed) {
                EXPECT_EQ(predict_triangles(*plan) - 2 * result->removed_vertices, out.face_count());
            }
            ASSERT_TRUE(validate(out).ok());
            EXPECT_TRUE(out.is_triangle_mesh());
            EXPECT_LE(result->achieved_error, options.tolerance);

            ASSERT_EQ(result->sites.size(), out.vertex_count());
            // base vertices against Far's limit masks (exact at level 0 without semi-sharp tags), other vertices
            // against Bfr (whose approximation at some crease corners is off by up to 1e-2 of the shape)
            bool semi_sharp = false;
            for (const auto& crease : c.mesh.tags.creases) semi_sharp |= crease.sharpness > 0 && crease.sharpness < 10;
            for (const auto& corner : c.mesh.tags.corners) semi_sharp |= corner.sharpness > 0 && corner.sharpness < 10;
            const auto far = testing::osd_limit(c.mesh, sub, 0, c.mesh.vertex_count());
            // darts (one sharp edge at a vertex): the smooth limit mask is not the limit there; Far's limit at a
            // finer level converges to ours (catmark_inf_crease0's dart moves by 0.0126 from level 0 to 5)
            std::vector<int> sharp_edges(c.mesh.vertex_count(), 0);
            for (const auto& [edge, uses] : edge_uses(c.mesh)) {
                bool sharp = uses.size() != 2;
                for (const auto& crease : c.mesh.tags.creases)
                    sharp |= crease.sharpness > 0 &&
                             std::minmax(crease.v0, crease.v1) == std::minmax(edge.first, edge.second);
                if (sharp) ++sharp_edges[edge.first], ++sharp_edges[edge.second];
            }
            const bool darts = std::count(sharp_edges.begin(), sharp_edges.end(), 1) > 0;
            const auto far3 = darts ? testing::osd_limit(c.mesh, sub, 3, c.mesh.vertex_count()) : far;
            const auto far5 = darts ? testing::osd_limit(c.mesh, sub, 5, c.mesh.vertex_count()) : far;
            std::size_t darts_checked = 0;
            for (std::size_t i = 0; i < out.vertex_count(); ++i) {
                const LimitSite& site = result->sites[i];
                const bool corner =
                    c.mesh.face_size(site.face) == 4 && (site.u == 0 || site.u == 1) && (site.v == 0 || site.v == 1);
                if (corner) {
                    const Index bv =
                        c.mesh.face(site.face)[site.u == 0 ? (site.v == 0 ? 0 : 3) : (site.v == 0 ? 1 : 2)];
                    if (semi_sharp) {
                    } else if (sharp_edges[bv] == 1 && c.mesh.tags.corners.empty()) {
                        const double d3 = norm(out.positions[i] - far3.positions[bv]);
                        const double d5 = norm(out.positions[i] - far5.positions[bv]);
                        EXPECT_LT(d5, 0.35 * d3) << "dart " << i;
                        EXPECT_LT(d5, 1e-4 * diagonal(c.mesh)) << "dart " << i;
                        ++darts_checked;
                    } else {
                        EXPECT_LT(norm(out.positions[i] - far.positions[bv]), 1e-9) << "vertex " << i;
                    }
                } else if (i % 7 == 0) {
                    const Vec3 reference = bfr.position(site.face, site.u, site.v);
                    EXPECT_LT(norm(out.positions[i] - reference), 1e-6 * diagonal(c.mesh))
                        << "vertex " << i << " face " << site.face << " (" << site.u << ", " << site.v << ")";
                }
            }
            if (c.name == "catmark_inf_crease0") {
                EXPECT_GT(darts_checked, 0u);
            }
            // dense exact samples are within the tolerance of the triangles
            const double distance = sampled_distance(*evaluator, c.mesh, out);
            EXPECT_LE(distance, options.tolerance);

            // watertight where the input is closed (every edge used twice, in opposite directions: no crack and
            // no T-junction), never more than two uses, Euler characteristic kept
            for (const auto& [edge, uses] : edge_uses(out)) {
                ASSERT_LE(uses.size(), 2u);
                if (closed) {
                    ASSERT_EQ(uses.size(), 2u);
                    EXPECT_EQ(uses[0].first, uses[1].second);
                }
            }
            EXPECT_EQ(euler(out), euler(c.mesh));
            // exact unit normals
            for (const Vec3& nrm : out.normals) EXPECT_NEAR(norm(nrm), 1.0, 1e-9);
        }
    }
}

// Rates from measured distances (guaranteed false): dense exact samples still within the tolerance on these shapes
// (the measurement's safety factor at work; no guarantee), the mesh invariants as with bounds.
TEST(AdaptiveTessellation, MeasuredRatesStayWithinToleranceOnTheseShapes) {
    for (const char* name : {"catmark_cube", "catmark_cube_creases1", "catmark_torus_creases0", "catmark_nonquads",
                             "catmark_gregory_test1"}) {
        SCOPED_TRACE(name);
        const PolygonMesh mesh = load_opensubdiv_shape(name);
        auto evaluator = LimitSurfaceEvaluator::create(mesh, {});
        ASSERT_TRUE(evaluator.ok());
        for (double relative : {1e-2, 3e-3}) {
            LimitTessellationOptions options;
            options.tolerance = relative * diagonal(mesh);
            options.guaranteed = false;
            auto measured = tessellate_limit(*evaluator, mesh, options);
            ASSERT_TRUE(measured.ok()) << measured.error().message;
            EXPECT_EQ(measured->plan.error_bound, 0.0);
            EXPECT_LE(measured->achieved_error, options.tolerance / kSampledSafety);
            EXPECT_LE(sampled_distance(*evaluator, mesh, measured->mesh), options.tolerance);
            for (const auto& [edge, uses] : edge_uses(measured->mesh)) ASSERT_LE(uses.size(), 2u);
            EXPECT_EQ(euler(measured->mesh), euler(mesh));
        }
    }
}

TEST(AdaptiveTessellation, FinerToleranceMoreTrianglesSmallerError) {
    const PolygonMesh mesh = load_opensubdiv_shape("catmark_cube_creases1");
    auto evaluator = LimitSurfaceEvaluator::create(mesh, {});
    ASSERT_TRUE(evaluator.ok());
    std::size_t previous = 0;
    for (double tolerance : {1e-1, 3e-2, 1e-2, 3e-3}) {
        LimitTessellationOptions options;
        options.tolerance = tolerance;
        auto result = tessellate_limit(*evaluator, mesh, options);
        ASSERT_TRUE(result.ok());
        EXPECT_GT(result->mesh.face_count(), previous);
        previous = result->mesh.face_count();
        EXPECT_LE(sampled_distance(*evaluator, mesh, result->mesh), tolerance);
    }
}

// A cube whose top face's four edges are infinitely sharp: the crease is the uniform cubic B-spline of the top
// square, in the plane z = 0.5, so every output vertex evaluated on one of those edges has z = 0.5 exactly.
// Vertices moved off the surface towards its convex side (straddle): the distance both ways stays within the
// tolerance (dense exact samples to the triangles; points of the triangles to a fine uniform limit mesh), each vertex
// is up to straddle x tolerance from its limit point along the normal there (none on saddles and C0 features), the mesh
// invariants hold, and shapes that curve one way take fewer triangles than with every vertex on the surface.
TEST(AdaptiveTessellation, StraddledVerticesStayWithinTolerance) {
    for (const Case& c : cases()) {
        SCOPED_TRACE(c.name);
        const SubdivisionOptions sub;
        auto evaluator = LimitSurfaceEvaluator::create(c.mesh, sub);
        ASSERT_TRUE(evaluator.ok()) << evaluator.error().message;
        LimitTessellationOptions options;
        options.tolerance = 3e-3 * diagonal(c.mesh);
        options.straddle = 0;
        auto on_surface = tessellate_limit(*evaluator, c.mesh, options);
        ASSERT_TRUE(on_surface.ok()) << on_surface.error().message;
        options.straddle = kDefaultStraddle;
        auto result = tessellate_limit(*evaluator, c.mesh, options);
        ASSERT_TRUE(result.ok()) << result.error().message;
        const PolygonMesh& out = result->mesh;
        ASSERT_TRUE(validate(out).ok());
        EXPECT_LE(result->achieved_error, options.tolerance);
        EXPECT_LE(sampled_distance(*evaluator, c.mesh, out), options.tolerance);
        EXPECT_EQ(euler(out), euler(c.mesh));
        // watertight where the input is closed: no crack and no T-junction
        const auto input_edges = edge_uses(c.mesh);
        const bool closed = std::all_of(input_edges.begin(), input_edges.end(),
                                        [](const auto& entry) { return entry.second.size() == 2; });
        for (const auto& [edge, uses] : edge_uses(out)) {
            ASSERT_LE(uses.size(), 2u);
            if (closed) {
                ASSERT_EQ(uses.size(), 2u);
                EXPECT_EQ(uses[0].first, uses[1].second);
            }
        }
        if (c.name == "catmark_torus_creases0" || c.name == "torus" || c.name == "catmark_cube") {
            EXPECT_LT(double(out.face_count()), 0.9 * double(on_surface->mesh.face_count()));
        }
        // each vertex: up to straddle x tolerance from the limit at its site along the normal there (all of it where
        // the surface curves one way)
        const double lift = options.straddle * options.tolerance;
        std::size_t moved = 0, whole = 0;
        for (std::size_t i = 0; i < out.vertex_count(); ++i) {
            const LimitSite& site = result->sites[i];
            auto limit = evaluator->evaluate(site.face, site.u, site.v);
            ASSERT_TRUE(limit.ok());
            const Vec3 offset = out.positions[i] - limit->position;
            EXPECT_LE(norm(offset), lift * (1 + 1e-12)) << "vertex " << i;
            EXPECT_LE(norm(cross(offset, limit->normal)), 1e-12 * diagonal(c.mesh)) << "vertex " << i;
            moved += norm(offset) > 1e-12 * diagonal(c.mesh);
            whole += norm(offset) > lift * (1 - 1e-9);
        }
        if (c.name == "cube") {
            EXPECT_GT(whole, out.vertex_count() / 2);
        }
        // the torus's outer half curves one way, its inner half is a saddle
        if (c.name == "torus") {
            EXPECT_GT(moved, out.vertex_count() / 4);
            EXPECT_LT(moved, 3 * out.vertex_count() / 4);
        }
        // points of the triangles (corners, edge midpoints, centroids) are near the limit surface: within the
        // tolerance of a uniform limit mesh fine enough to be within 2% of it (level 5 is not, next to
        // catmark_cube_creases1's creases of sharpness 5)
        SubdivisionOptions fine = sub;
        fine.levels = 6;
        fine.limit_surface = true;
        auto dense = subdivide(c.mesh, fine);
        ASSERT_TRUE(dense.ok());
        auto bvh = build_bvh(*dense);
        ASSERT_TRUE(bvh.ok());
        const auto reverse = [&](const PolygonMesh& m) -> double {
            double worst = 0;
            for (std::size_t f = 0; f < m.face_count(); ++f) {
                const auto fv = m.face(f);
                const Vec3 &a = m.positions[fv[0]], &b = m.positions[fv[1]], &d = m.positions[fv[2]];
                for (const Vec3& p : {a, (a + b) * 0.5, (b + d) * 0.5, (d + a) * 0.5, (a + b + d) * (1.0 / 3)}) {
                    auto closest = closest_point(*bvh, p);
                    if (!closest) return 1e300;
                    worst = std::max(worst, closest->distance);
                }
            }
            return worst;
        };
        // the guarantee is one-sided (the surface to the triangles' planes); the other way is measured, with every
        // vertex on the surface and with straddled vertices
        EXPECT_LE(reverse(on_surface->mesh), 1.02 * options.tolerance);
        EXPECT_LE(reverse(out), 1.02 * options.tolerance);
    }
}

// Every closed Catmull-Clark regression shape (every edge used twice; none with hole tags, whose holes open it),
// with the defaults (straddled vertices) at 1e-2 of its diagonal: dense exact samples within the tolerance of the
// triangles, watertight (every edge used twice, in opposite directions: no crack, no T-junction), the Euler
// characteristic kept, every vertex near an independent limit mesh. catmark_val2_back2back (pairs of flat faces glued
// back to back) folds onto itself along its rim, where the rim's chords lie in the triangles' plane: its folds are
// bounded as open boundaries; its corners (valence 2) are where the surface converges, not the mesh's vertices.
TEST(AdaptiveTessellation, EveryClosedRegressionShapeWithinToleranceAndWatertight) {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(fs::path(SURFACED_TEST_DATA_DIR) / "opensubdiv-shapes")) {
        const std::string file = entry.path().filename().string();
        if (file.rfind("catmark_", 0) == 0 && entry.path().extension() == ".obj") names.push_back(entry.path().stem());
    }
    std::sort(names.begin(), names.end());
    std::size_t checked = 0;
    for (const std::string& name : names) {
        const PolygonMesh mesh = load_opensubdiv_shape(name);
        if (mesh.face_count() == 0 || !mesh.tags.holes.empty()) continue;
        const auto uses = edge_uses(mesh);
        if (!std::all_of(uses.begin(), uses.end(), [](const auto& entry) { return entry.second.size() == 2; }))
            continue;
        SCOPED_TRACE(name);
        auto evaluator = LimitSurfaceEvaluator::create(mesh, {});
        ASSERT_TRUE(evaluator.ok()) << evaluator.error().message;
        LimitTessellationOptions options;
        options.tolerance = 1e-2 * diagonal(mesh);
        auto result = tessellate_limit(*evaluator, mesh, options);
        ASSERT_TRUE(result.ok()) << result.error().message;
        const PolygonMesh& out = result->mesh;
        ASSERT_TRUE(validate(out).ok());
        EXPECT_LE(result->achieved_error, options.tolerance);
        EXPECT_LE(sampled_distance(*evaluator, mesh, out), options.tolerance);
        for (const auto& [edge, edge_faces] : edge_uses(out)) {
            ASSERT_EQ(edge_faces.size(), 2u);
            EXPECT_EQ(edge_faces[0].first, edge_faces[1].second);
        }
        EXPECT_EQ(euler(out), euler(mesh));
        // the other way: every vertex (up to 0.45 of the tolerance off the surface) near an independent limit
        // mesh (uniform level 4 with limit masks: within a few thousandths of the diagonal of the surface)
        SubdivisionOptions fine;
        fine.levels = 4;
        fine.limit_surface = true;
        auto dense = subdivide(mesh, fine);
        ASSERT_TRUE(dense.ok());
        auto bvh = build_bvh(*dense);
        ASSERT_TRUE(bvh.ok());
        double worst = 0;
        for (const Vec3& p : out.positions) {
            auto closest = closest_point(*bvh, p);
            ASSERT_TRUE(closest.has_value());
            worst = std::max(worst, closest->distance);
        }
        EXPECT_LE(worst, options.tolerance);
        ++checked;
    }
    EXPECT_GE(checked, 27u);
}

TEST(AdaptiveTessellation, InfinitelySharpCreasesStayOnTheCrease) {
    PolygonMesh mesh = shapes::cube();
    std::vector<Index> top;
    for (Index v = 0; v < mesh.vertex_count(); ++v)
        if (mesh.positions[v].z > 0) top.push_back(v);
    ASSERT_EQ(top.size(), 4u);
    for (const auto& [edge, uses] : edge_uses(mesh))
        if (mesh.positions[edge.first].z > 0 && mesh.positions[edge.second].z > 0)
            mesh.tags.creases.push_back({edge.first, edge.second, 10.0});
    ASSERT_EQ(mesh.tags.creases.size(), 4u);
    auto evaluator = LimitSurfaceEvaluator::create(mesh, {});
    ASSERT_TRUE(evaluator.ok());
    for (double straddle : {0.0, 0.45}) {
        SCOPED_TRACE(straddle);
        LimitTessellationOptions options;
        options.tolerance = 1e-3;
        options.straddle = straddle;  // vertices on the crease stay on it when the rest move off the surface
        auto result = tessellate_limit(*evaluator, mesh, options);
        ASSERT_TRUE(result.ok()) << result.error().message;
        std::size_t on_crease = 0;
        for (std::size_t i = 0; i < result->sites.size(); ++i) {
            const LimitSite& s = result->sites[i];
            if (s.u != 0 && s.u != 1 && s.v != 0 && s.v != 1) continue;  // not on a base edge
            const auto fv = mesh.face(s.face);
            // the base edge the site is on
            const std::size_t k = s.v == 0 ? 0 : s.u == 1 ? 1 : s.v == 1 ? 2 : 3;
            const bool crease = mesh.positions[fv[k]].z > 0 && mesh.positions[fv[(k + 1) % 4]].z > 0;
            if (!crease) continue;
            ++on_crease;
            EXPECT_NEAR(result->mesh.positions[i].z, 0.5, 1e-12) << "vertex " << i;
        }
        EXPECT_GT(on_crease, 4u * 4u);
        // the surface below the crease is curved: some vertex is far from the cube's faces
        double inside = 0;
        for (const Vec3& p : result->mesh.positions)
            inside = std::max(inside, 0.5 - std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}));
        EXPECT_GT(inside, 0.05);
    }
}

TEST(AdaptiveTessellation, UvsAreBilinearInTheFaceParameter) {
    PolygonMesh mesh = shapes::torus(6, 4);
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        static constexpr Vec2 kCorners[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
        for (int k = 0; k < 4; ++k) {
            mesh.uv_indices.push_back(Index(mesh.uvs.size()));
            mesh.uvs.push_back({double(f) + kCorners[k].x, kCorners[k].y});
        }
    }
    auto evaluator = LimitSurfaceEvaluator::create(mesh, {});
    ASSERT_TRUE(evaluator.ok());
    LimitTessellationOptions options;
    options.tolerance = 1e-2;
    auto result = tessellate_limit(*evaluator, mesh, options);
    ASSERT_TRUE(result.ok());
    const PolygonMesh& out = result->mesh;
    ASSERT_TRUE(out.has_uvs());
    ASSERT_EQ(out.uv_indices.size(), out.face_indices.size());
    // the corner UVs (f + u, v) of face f are bilinear in (u, v): each output corner's UV is (f + u, v) of its site
    // when the site is on that face
    std::size_t checked = 0;
    for (std::size_t t = 0; t < out.face_count(); ++t)
        for (std::size_t k = 0; k < 3; ++k) {
            const Index vtx = out.face_indices[3 * t + k];
            const LimitSite& s = result->sites[vtx];
            if (s.face != result->face_of_triangle[t]) continue;
            const Vec2 uv = out.uvs[out.uv_indices[3 * t + k]];
            EXPECT_NEAR(uv.x, s.face + s.u, 1e-12);
            EXPECT_NEAR(uv.y, s.v, 1e-12);
            ++checked;
        }
    EXPECT_GT(checked, out.face_count());
}

TEST(AdaptiveTessellation, BudgetsAndBadOptions) {
    const PolygonMesh mesh = shapes::cube();
    auto evaluator = LimitSurfaceEvaluator::create(mesh, {});
    ASSERT_TRUE(evaluator.ok());
    LimitTessellationOptions options;
    options.tolerance = 1e-3;
    auto plan = plan_limit_tessellation(*evaluator, mesh, options);
    ASSERT_TRUE(plan.ok());
    options.max_triangles = plan->triangles - 1;
    auto over = tessellate_limit(*evaluator, mesh, options);
    ASSERT_FALSE(over.ok());
    EXPECT_EQ(over.error().code, ErrorCode::BudgetExceeded);
    options.max_triangles = plan->triangles;
    EXPECT_TRUE(tessellate_limit(*evaluator, mesh, options).ok());

    options.max_triangles = 0;
    options.max_segments = 2;
    auto segments = tessellate_limit(*evaluator, mesh, options);
    ASSERT_FALSE(segments.ok());
    EXPECT_EQ(segments.error().code, ErrorCode::BudgetExceeded);

    options.max_segments = 256;
    for (double bad : {0.0, -1.0, std::nan("")}) {
        options.tolerance = bad;
        auto result = tessellate_limit(*evaluator, mesh, options);
        ASSERT_FALSE(result.ok());
        EXPECT_EQ(result.error().code, ErrorCode::InvalidArgument);
    }
    options.tolerance = 1e-3;
    for (double bad : {-0.1, 1.0, std::nan("")}) {
        options.straddle = bad;
        auto result = tessellate_limit(*evaluator, mesh, options);
        ASSERT_FALSE(result.ok());
        EXPECT_EQ(result.error().code, ErrorCode::InvalidArgument);
    }
}

// On a shape with uneven curvature and creases the edge rates differ between faces, so transition strips are used,
// and the adaptive output is smaller than the uniform grid that has every face at the largest rate.
TEST(AdaptiveTessellation, RatesFollowCurvature) {
    const PolygonMesh mesh = load_opensubdiv_shape("catmark_torus_creases0");
    auto evaluator = LimitSurfaceEvaluator::create(mesh, {});
    ASSERT_TRUE(evaluator.ok());
    LimitTessellationOptions options;
    options.tolerance = 1e-2;
    auto plan = plan_limit_tessellation(*evaluator, mesh, options);
    ASSERT_TRUE(plan.ok());
    const auto [lo, hi] = std::minmax_element(plan->edge_rates.begin(), plan->edge_rates.end());
    EXPECT_LT(*lo, *hi);
    int top = 0;
    for (const auto& d : plan->domains) top = std::max({top, d.nu, d.nv});
    EXPECT_LT(plan->triangles, 2u * std::uint64_t(top) * std::uint64_t(top) * mesh.face_count());
}

// The semi-sharp creases (sharpness 4.7) bend the surface within a band about 2^-4.7 of a face wide: the grids of the
// faces along them are graded, fine next to the crease and coarse away from it, and so are the points along the
// edges that run into the crease (the same points for both faces on an edge: watertight, no T-junction); the output
// stays within the tolerance of dense exact samples.
TEST(AdaptiveTessellation, GridsAreGradedTowardsSemiSharpCreases) {
    const PolygonMesh mesh = load_opensubdiv_shape("catmark_torus_creases0");
    auto evaluator = LimitSurfaceEvaluator::create(mesh, {});
    ASSERT_TRUE(evaluator.ok());
    LimitTessellationOptions options;
    options.tolerance = 1e-3 * diagonal(mesh);
    auto result = tessellate_limit(*evaluator, mesh, options);
    ASSERT_TRUE(result.ok()) << result.error().message;
    double widest_ratio = 0;
    for (const auto& d : result->plan.domains)
        for (const std::vector<double>* lines : {&d.s_lines, &d.t_lines}) {
            if (lines->empty()) continue;
            ASSERT_EQ(lines->size(), std::size_t(lines == &d.s_lines ? d.nu : d.nv) + 1);
            EXPECT_EQ(lines->front(), 0.0);
            EXPECT_EQ(lines->back(), 1.0);
            double finest = 1, coarsest = 0;
            for (std::size_t i = 0; i + 1 < lines->size(); ++i) {
                const double step = (*lines)[i + 1] - (*lines)[i];
                ASSERT_GT(step, 0.0);
                finest = std::min(finest, step);
                coarsest = std::max(coarsest, step);
            }
            widest_ratio = std::max(widest_ratio, coarsest / finest);
        }
    EXPECT_GT(widest_ratio, 4.0);
    double widest_side = 0;
    for (const auto& d : result->plan.domains)
        for (int k = 0; k < 4; ++k) {
            const auto& lines = d.side_lines[std::size_t(k)];
            if (lines.empty()) continue;
            ASSERT_EQ(lines.size(), std::size_t(d.side[k]) + 1);
            EXPECT_EQ(lines.front(), 0.0);
            EXPECT_EQ(lines.back(), 1.0);
            double finest = 1, coarsest = 0;
            for (std::size_t i = 0; i + 1 < lines.size(); ++i) {
                ASSERT_GT(lines[i + 1], lines[i]);
                finest = std::min(finest, lines[i + 1] - lines[i]);
                coarsest = std::max(coarsest, lines[i + 1] - lines[i]);
            }
            widest_side = std::max(widest_side, coarsest / finest);
        }
    EXPECT_GT(widest_side, 4.0);
    // a grid's lines span its face: where the crease band needs them and the rest of the face does not, vertices
    // are removed
    EXPECT_GT(result->removed_vertices, 0u);
    EXPECT_LT(result->mesh.face_count(), result->plan.triangles);
    EXPECT_LE(result->achieved_error, options.tolerance);
    EXPECT_LE(sampled_distance(*evaluator, mesh, result->mesh), options.tolerance);
    for (const auto& [edge, uses] : edge_uses(result->mesh)) {
        ASSERT_EQ(uses.size(), 2u);
        EXPECT_EQ(uses[0].first, uses[1].second);
    }
}

// A saddle patch z = a x^2 - b y^2 (control points on it): the bounds keep the signs of z_ss and z_tt apart, and the
// triangle's bound is then the exact largest interpolation error (one direction's curvature per side), below the
// bound from the magnitudes alone (both directions added).
TEST(AdaptiveTessellation, SignedBoundsOnASaddleAreExact) {
    using namespace tessellation_detail;
    const double a = 0.3, b = 0.2;
    std::array<Vec3, 16> points{};
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) points[std::size_t(4 * r + c)] = {double(c), double(r), a * c * c - b * r * r};
    const PatchData patch = patch_data(points);
    const SignedBounds sb = signed_in_box(patch, {0, 0, 1}, 0.0, 1.0, 0.0, 1.0);
    // z_ss = 2a throughout and z_tt = -2b: from above z_ss <= 2a, z_tt <= -2b; from below -z_ss <= -2a, -z_tt <= 2b
    EXPECT_NEAR(sb.up.uu, 2 * a, 1e-12);
    EXPECT_NEAR(sb.up.vv, -2 * b, 1e-12);
    EXPECT_NEAR(sb.down.uu, -2 * a, 1e-12);
    EXPECT_NEAR(sb.down.vv, 2 * b, 1e-12);
    EXPECT_NEAR(sb.up.uv, 0.0, 1e-12);
    const Bounds magnitude = along_in_box(patch, {0, 0, 1}, 0.0, 1.0, 0.0, 1.0);
    EXPECT_NEAR(magnitude.uu, 2 * a, 1e-12);
    EXPECT_NEAR(magnitude.vv, 2 * b, 1e-12);
    // the interpolation error of z over triangles with corners p_i, sampled densely (z's linear part cancels)
    const auto z = [&](double s, double t) { return a * s * s - b * t * t; };
    for (const double h : {0.5, 0.25}) {
        SCOPED_TRACE(h);
        const P2 p0{0.25, 0.25}, p1{0.25 + h, 0.25}, p2{0.25 + h, 0.25 + 0.5 * h};
        double largest = 0;
        constexpr int kSteps = 200;
        for (int i = 0; i <= kSteps; ++i)
            for (int j = 0; i + j <= kSteps; ++j) {
                const double l1 = double(i) / kSteps, l2 = double(j) / kSteps, l0 = 1 - l1 - l2;
                const double s = l0 * p0.s + l1 * p1.s + l2 * p2.s, t = l0 * p0.t + l1 * p1.t + l2 * p2.t;
                const double linear = l0 * z(p0.s, p0.t) + l1 * z(p1.s, p1.t) + l2 * z(p2.s, p2.t);
                largest = std::max(largest, std::abs(linear - z(s, t)));
            }
        Bounds dominant;
        const double bound = triangle_bound(sb, p0, p1, p2, &dominant);
        EXPECT_GE(bound, largest * (1 - 1e-12));
        EXPECT_NEAR(bound, largest, 1e-3 * largest);
        EXPECT_NEAR(dominant.uu, 2 * a, 1e-12);  // the s side: its edge along s is the longer
        EXPECT_LT(bound, 0.9 * triangle_bound(magnitude, p0, p1, p2));
    }
    // convex with a small mixed term (z = 0.3 s^2 + 0.2 t^2 + 0.05 s t): z lies below its chords, nothing above them
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c)
            points[std::size_t(4 * r + c)] = {double(c), double(r), 0.3 * c * c + 0.2 * r * r + 0.05 * r * c};
    const SignedBounds convex = signed_in_box(patch_data(points), {0, 0, 1}, 0.0, 1.0, 0.0, 1.0);
    EXPECT_NEAR(convex.down.uu, -0.6, 1e-12);
    EXPECT_NEAR(convex.down.uv, 0.05, 1e-12);
    const P2 q0{0.1, 0.1}, q1{0.6, 0.1}, q2{0.6, 0.4};
    EXPECT_EQ(triangle_bound(convex.down, q0, q1, q2), 0.0);
    EXPECT_GT(triangle_bound(convex.up, q0, q1, q2), 0.0);
}

// A staggered grid (odd rows at the midpoints of the s intervals) tiles its domain exactly, in both of
// triangulate()'s layouts (a grid whose sides carry its lines, and an inner grid joined to graded sides by strips):
// every triangle counter-clockwise, the areas summing to the square, every inner edge used once each way and the
// boundary edges exactly the sides' segments; the counts are the ones the budget predicts. Its triangles are bounded
// by 0.78 of a square cell's right triangles (circumradius 0.625 against 0.707 of the side).
TEST(AdaptiveTessellation, StaggeredGridsTileTheirDomain) {
    using namespace tessellation_detail;
    const auto check = [](const LimitTessellationPlan::Domain& d) {
        const LocalMesh local = triangulate(d);
        EXPECT_EQ(local.triangles.size(), domain_triangles(d));
        const std::size_t ring = std::size_t(d.side[0] + d.side[1] + d.side[2] + d.side[3]);
        const std::vector<P2> inner = inner_points(d);
        ASSERT_EQ(local.points.size(), ring + inner.size());
        for (std::size_t i = 0; i < inner.size(); ++i) {
            EXPECT_EQ(local.points[ring + i].s, inner[i].s);
            EXPECT_EQ(local.points[ring + i].t, inner[i].t);
            EXPECT_GT(inner[i].s, 0.0);
            EXPECT_LT(inner[i].s, 1.0);
        }
        double area = 0;
        std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
        for (const auto& tri : local.triangles) {
            const P2 &a = local.points[tri[0]], &b = local.points[tri[1]], &c = local.points[tri[2]];
            const double twice = (b.s - a.s) * (c.t - a.t) - (b.t - a.t) * (c.s - a.s);
            EXPECT_GT(twice, 0.0);
            area += 0.5 * twice;
            for (int k = 0; k < 3; ++k) ++edges[{tri[std::size_t(k)], tri[std::size_t((k + 1) % 3)]}];
        }
        EXPECT_NEAR(area, 1.0, 1e-12);
        for (const auto& [edge, count] : edges) {
            EXPECT_EQ(count, 1);
            const bool boundary = edge.first < ring && edge.second < ring && (edge.first + 1) % ring == edge.second;
            EXPECT_EQ(edges.count({edge.second, edge.first}), boundary ? 0u : 1u) << edge.first << " " << edge.second;
        }
    };
    for (const int nu : {2, 3, 5})
        for (const int nv : {2, 3, 4, 7}) {
            SCOPED_TRACE(std::to_string(nu) + " x " + std::to_string(nv));
            LimitTessellationPlan::Domain grid;
            grid.nu = nu;
            grid.nv = nv;
            grid.side[0] = grid.side[2] = nu;
            grid.side[1] = grid.side[3] = nv;
            grid.staggered = true;
            ASSERT_TRUE(is_grid(grid));
            check(grid);
            EXPECT_EQ(domain_triangles(grid), 2u * nu * nv + 2u * (nv / 2));
            // graded inner lines, sides with their own counts and lines
            LimitTessellationPlan::Domain strips = grid;
            strips.s_lines = {0.0};
            for (int i = 1; i < nu; ++i) strips.s_lines.push_back(std::pow(double(i) / nu, 1.5));
            strips.s_lines.push_back(1.0);
            strips.side[0] = nu + 2;
            strips.side[1] = 3;
            strips.side[2] = 1;
            strips.side[3] = nv + 1;
            strips.side_lines[3] = {0.0};
            for (int i = 1; i <= nv; ++i) strips.side_lines[3].push_back(std::sqrt(double(i) / (nv + 1)));
            strips.side_lines[3].push_back(1.0);
            ASSERT_FALSE(is_grid(strips));
            check(strips);
        }
    // the bound of an isotropic form over a square cell's right triangle and over the staggered triangle
    const Bounds isotropic{1.0, 0.0, 1.0};
    const double right = triangle_bound(isotropic, {0, 0}, {1, 0}, {1, 1});
    const double stagger = triangle_bound(isotropic, {0, 0}, {1, 0}, {0.5, 1});
    EXPECT_NEAR(right, 0.25, 1e-15);
    EXPECT_NEAR(stagger / right, 0.78125, 1e-12);
}

// Where the curvature is elliptic and the grid is large enough, the planner staggers (it keeps the layout with fewer
// triangles): some of the smooth cube's domains are staggered at 1e-3 of its diagonal, the tolerance holds, and the
// output has fewer triangles than with plain grids only (options.stagger = false, which staggers none).
TEST(AdaptiveTessellation, EllipticFacesAreStaggered) {
    const PolygonMesh mesh = shapes::cube();
    auto evaluator = LimitSurfaceEvaluator::create(mesh, {});
    ASSERT_TRUE(evaluator.ok());
    LimitTessellationOptions options;
    options.tolerance = 1e-3 * diagonal(mesh);
    auto result = tessellate_limit(*evaluator, mesh, options);
    ASSERT_TRUE(result.ok()) << result.error().message;
    std::size_t staggered = 0;
    for (const auto& d : result->plan.domains) staggered += d.staggered ? 1 : 0;
    EXPECT_GT(staggered, 0u);
    EXPECT_LE(result->achieved_error, options.tolerance);
    EXPECT_LE(sampled_distance(*evaluator, mesh, result->mesh), options.tolerance);
    options.stagger = false;
    auto plain = tessellate_limit(*evaluator, mesh, options);
    ASSERT_TRUE(plain.ok()) << plain.error().message;
    for (const auto& d : plain->plan.domains) EXPECT_FALSE(d.staggered);
    EXPECT_LE(plain->achieved_error, options.tolerance);
    EXPECT_LT(result->mesh.face_count(), plain->mesh.face_count());
}

// With threads = 2 the faces' patches and grids are prepared in two halves on two threads: the output is the same,
// vertex for vertex, and so is a budget error (the running total in face order, as one thread reports it).
TEST(AdaptiveTessellation, TwoThreadsGiveTheSameOutput) {
    for (const char* name : {"catmark_torus_creases0", "catmark_pyramid_creases1", "catmark_nonquads"}) {
        SCOPED_TRACE(name);
        const PolygonMesh mesh = load_opensubdiv_shape(name);
        auto evaluator = LimitSurfaceEvaluator::create(mesh, {});
        ASSERT_TRUE(evaluator.ok());
        LimitTessellationOptions options;
        options.tolerance = 2e-3 * diagonal(mesh);
        auto one = tessellate_limit(*evaluator, mesh, options);
        options.threads = 2;
        auto two = tessellate_limit(*evaluator, mesh, options);
        ASSERT_TRUE(one.ok() && two.ok());
        EXPECT_EQ(one->mesh.face_indices, two->mesh.face_indices);
        ASSERT_EQ(one->mesh.positions.size(), two->mesh.positions.size());
        for (std::size_t i = 0; i < one->mesh.positions.size(); ++i) {
            EXPECT_EQ(one->mesh.positions[i].x, two->mesh.positions[i].x);
            EXPECT_EQ(one->mesh.positions[i].y, two->mesh.positions[i].y);
            EXPECT_EQ(one->mesh.positions[i].z, two->mesh.positions[i].z);
        }
        EXPECT_EQ(one->plan.triangles, two->plan.triangles);
        EXPECT_EQ(one->achieved_error, two->achieved_error);
        // a budget the grids alone exceed part of the way through the faces
        options.max_triangles = one->plan.triangles / 3;
        options.threads = 1;
        auto over_one = tessellate_limit(*evaluator, mesh, options);
        options.threads = 2;
        auto over_two = tessellate_limit(*evaluator, mesh, options);
        ASSERT_FALSE(over_one.ok());
        ASSERT_FALSE(over_two.ok());
        EXPECT_EQ(over_one.error().code, ErrorCode::BudgetExceeded);
        EXPECT_EQ(over_one.error().message, over_two.error().message);
    }
}

}  // namespace
}  // namespace surfaced
