// Tensor-product Bézier patches: the textbook properties as assertions, normals at collapsed edges, the tolerance
// guarantee against dense exact evaluation, and crack-freedom on the Utah teapot.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <tuple>
#include <vector>

#include "geometry/curves/de_casteljau.h"
#include "geometry/io/bez.h"
#include "geometry/surfaces/bezier_patch.h"
#include "tests/support/mesh_asserts.h"

namespace surfaced {
namespace {

BezierPatch random_patch(int m, int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> coord(-2.0, 2.0);
    BezierPatch patch;
    patch.degree_u = m;
    patch.degree_v = n;
    for (int k = 0; k < (m + 1) * (n + 1); ++k) patch.points.push_back({coord(rng), coord(rng), coord(rng)});
    return patch;
}

//! Sum over i, j of B_i^m(u) B_j^n(v) b_ij: the Bernstein form, written independently of de Casteljau.
Vec3 bernstein_form(const BezierPatch& patch, double u, double v) {
    Vec3 sum;
    for (int j = 0; j <= patch.degree_v; ++j)
        for (int i = 0; i <= patch.degree_u; ++i)
            sum += bezier::bernstein(patch.degree_u, i, u) * bezier::bernstein(patch.degree_v, j, v) * patch.at(i, j);
    return sum;
}

PatchSet teapot() {
    auto set = read_bez(patch_sample_text("teapot"));
    EXPECT_TRUE(set.ok()) << set.error().message;
    return set.ok() ? set.value() : PatchSet{};
}

void expect_near(const Vec3& a, const Vec3& b, double tol, const char* what = "") {
    EXPECT_LE(norm(a - b), tol) << what << ": (" << a.x << ", " << a.y << ", " << a.z << ") vs (" << b.x << ", " << b.y
                                << ", " << b.z << ")";
}

TEST(BezierPatch, CornersInterpolatedExactly) {
    for (auto [m, n] : {std::pair{3, 3}, {2, 5}, {1, 4}, {6, 1}}) {
        const BezierPatch patch = random_patch(m, n, static_cast<unsigned>(10 * m + n));
        EXPECT_EQ(evaluate(patch, 0, 0), patch.at(0, 0));
        EXPECT_EQ(evaluate(patch, 1, 0), patch.at(m, 0));
        EXPECT_EQ(evaluate(patch, 0, 1), patch.at(0, n));
        EXPECT_EQ(evaluate(patch, 1, 1), patch.at(m, n));
    }
}

TEST(BezierPatch, DeCasteljauEqualsBernsteinForm) {
    const BezierPatch patch = random_patch(3, 4, 7);
    for (int a = 0; a <= 10; ++a)
        for (int b = 0; b <= 10; ++b) {
            const double u = a / 10.0, v = b / 10.0;
            expect_near(evaluate(patch, u, v), bernstein_form(patch, u, v), 1e-12);
        }
}

TEST(BezierPatch, BilinearSpecialCase) {
    const BezierPatch patch = random_patch(1, 1, 3);
    for (double u : {0.0, 0.25, 0.6, 1.0})
        for (double v : {0.0, 0.3, 0.9}) {
            const Vec3 bilinear = (1 - u) * (1 - v) * patch.at(0, 0) + u * (1 - v) * patch.at(1, 0) +
                                  (1 - u) * v * patch.at(0, 1) + u * v * patch.at(1, 1);
            expect_near(evaluate(patch, u, v), bilinear, 1e-14);
        }
    // a planar bilinear patch (a parallelogram) is reproduced by one quad: its error bound is exactly zero
    BezierPatch plane;
    plane.degree_u = plane.degree_v = 1;
    plane.points = {{0, 0, 0}, {2, 0, 0}, {0, 1, 0}, {2, 1, 0}};
    EXPECT_EQ(tessellation_error_bound(plane, 1, 1), 0.0);
    TessellationOptions options;
    options.tolerance = 1e-9;
    auto result = tessellate_patches(std::span<const BezierPatch>(&plane, 1), options);
    ASSERT_TRUE(result.ok()) << result.error().message;
    EXPECT_EQ(result->mesh.face_count(), 2u);
    EXPECT_EQ(result->mesh.vertex_count(), 4u);
}

TEST(BezierPatch, AffineInvariance) {
    const BezierPatch patch = random_patch(3, 2, 11);
    const auto affine = [](const Vec3& p) {
        return Vec3{2 * p.x - p.y + 0.5 * p.z + 1, 0.3 * p.x + p.y - 2, -p.x + 0.25 * p.y + 3 * p.z + 0.5};
    };
    BezierPatch mapped = patch;
    for (Vec3& p : mapped.points) p = affine(p);
    for (double u : {0.1, 0.5, 0.77})
        for (double v : {0.2, 0.5, 0.95}) expect_near(evaluate(mapped, u, v), affine(evaluate(patch, u, v)), 1e-12);
}

TEST(BezierPatch, ConvexHullContainsSurfaceBoundingBox) {
    const BezierPatch patch = random_patch(4, 3, 5);
    Box3 hull;
    for (const Vec3& p : patch.points) hull.add(p);
    for (int a = 0; a <= 20; ++a)
        for (int b = 0; b <= 20; ++b) {
            const Vec3 p = evaluate(patch, a / 20.0, b / 20.0);
            for (int c = 0; c < 3; ++c) {
                EXPECT_GE(p[c], hull.min[c] - 1e-12);
                EXPECT_LE(p[c], hull.max[c] + 1e-12);
            }
        }
}

// S(u, v) = (u, v, uv + u^2) as a degree 2x2 patch: x and y by linear precision (b_ij = (i/2, j/2)), uv has
// coefficients (i/2)(j/2), and u^2 = B_2^2(u) has coefficients (0, 0, 1) in i.
BezierPatch polynomial_graph_patch() {
    BezierPatch patch;
    patch.degree_u = patch.degree_v = 2;
    for (int j = 0; j <= 2; ++j)
        for (int i = 0; i <= 2; ++i)
            patch.points.push_back({i / 2.0, j / 2.0, (i / 2.0) * (j / 2.0) + (i == 2 ? 1.0 : 0.0)});
    return patch;
}

TEST(BezierPatch, ExactDerivativesAndNormal) {
    const BezierPatch patch = polynomial_graph_patch();
    for (double u : {0.0, 0.3, 1.0})
        for (double v : {0.0, 0.6, 1.0}) {
            const PatchDerivatives d = evaluate_derivatives(patch, u, v);
            expect_near(d.position, {u, v, u * v + u * u}, 1e-14, "position");
            expect_near(d.du, {1, 0, v + 2 * u}, 1e-13, "du");
            expect_near(d.dv, {0, 1, u}, 1e-13, "dv");
            expect_near(d.duu, {0, 0, 2}, 1e-13, "duu");
            expect_near(d.duv, {0, 0, 1}, 1e-13, "duv");
            expect_near(d.dvv, {0, 0, 0}, 1e-13, "dvv");
            const Vec3 n{-(v + 2 * u), -u, 1};
            expect_near(unit_normal(patch, u, v), n * (1 / norm(n)), 1e-13, "normal");
        }
}

TEST(BezierPatch, NormalAtCollapsedEdgeIsTheLimit) {
    // Bilinear patch with the v = 0 edge collapsed onto A: S = (1-v) A + v ((1-u) B + u C), a flat triangle.
    // du x dv = v (C - B) x ((1-u) B + u C - A), so the limit as v -> 0 is the direction of (C - B) x (B - A + u(C - B)),
    // which is the triangle's normal (C - B) x (B - A) for every u.
    const Vec3 a{0, 0, 1}, b{2, 0, 0}, c{0, 3, 0};
    BezierPatch patch;
    patch.degree_u = patch.degree_v = 1;
    patch.points = {a, a, b, c};
    const Vec3 expected = cross(c - b, b - a) * (1.0 / norm(cross(c - b, b - a)));
    for (double u : {0.0, 0.4, 1.0}) {
        expect_near(unit_normal(patch, u, 0.0), expected, 1e-12, "on the collapsed edge");
        expect_near(unit_normal(patch, u, 0.5), expected, 1e-12, "inside");
    }
    // A paraboloid cap z = 1 - x^2 - y^2 over a quarter disc is not needed: the teapot lid below has the real case.
}

TEST(BezierPatch, TeapotNormalsUnitAndOutward) {
    const PatchSet set = teapot();
    ASSERT_EQ(set.patches.size(), 32u);
    // The lid apex (patches 20-23, top of the teapot) and the bottom centre (28-31) are collapsed edges on the z
    // axis: the limit normals there are +z and -z.
    int apexes = 0;
    for (int p = 20; p < 24; ++p) {
        const BezierPatch& patch = set.patches[static_cast<std::size_t>(p)];
        for (double u : {0.0, 0.5, 1.0})
            for (double v : {0.0, 1.0}) {
                const Vec3 point = evaluate(patch, u, v);
                if (std::hypot(point.x, point.y) > 1e-12) continue;  // not the apex end
                ++apexes;
                expect_near(unit_normal(patch, u, v), {0, 0, 1}, 1e-9, "lid apex");
            }
    }
    EXPECT_EQ(apexes, 4 * 3);
    int bottom_centres = 0;
    for (int p = 28; p < 32; ++p) {
        const BezierPatch& patch = set.patches[static_cast<std::size_t>(p)];
        for (double u : {0.0, 0.5, 1.0})
            for (double v : {0.0, 1.0}) {
                const Vec3 point = evaluate(patch, u, v);
                if (std::hypot(point.x, point.y) > 1e-12) continue;
                ++bottom_centres;
                expect_near(unit_normal(patch, u, v), {0, 0, -1}, 1e-9, "bottom centre");
            }
    }
    EXPECT_EQ(bottom_centres, 4 * 3);
    // rim and body (patches 0-11) are surfaces of revolution about z: outward = away from the axis
    for (int p = 0; p < 12; ++p)
        for (int a = 0; a <= 8; ++a) {
            for (int b = 0; b <= 8; ++b) {
                const BezierPatch& patch = set.patches[static_cast<std::size_t>(p)];
                const Vec3 point = evaluate(patch, a / 8.0, b / 8.0);
                const Vec3 n = unit_normal(patch, a / 8.0, b / 8.0);
                EXPECT_NEAR(norm(n), 1.0, 1e-12);
                if (p >= 4) {
                    EXPECT_GT(dot(n, {point.x, point.y, 0}), 0) << "patch " << p;
                }
            }
        }
}

TEST(BezierPatch, TessellationNormalsAgreeWithWinding) {
    TessellationOptions options;
    options.tolerance = 0.01;
    const PatchSet set = teapot();
    auto result = tessellate_patches(set.patches, options);
    ASSERT_TRUE(result.ok()) << result.error().message;
    const PolygonMesh& mesh = result->mesh;
    ASSERT_TRUE(validate(mesh).ok());
    ASSERT_TRUE(mesh.is_triangle_mesh());
    ASSERT_EQ(mesh.normals.size(), mesh.vertex_count());
    for (const Vec3& n : mesh.normals) EXPECT_NEAR(norm(n), 1.0, 1e-12);
    std::size_t disagreeing = 0;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const auto face = mesh.face(f);
        const Vec3 geometric =
            cross(mesh.positions[face[1]] - mesh.positions[face[0]], mesh.positions[face[2]] - mesh.positions[face[0]]);
        const Vec3 shading = mesh.normals[face[0]] + mesh.normals[face[1]] + mesh.normals[face[2]];
        if (dot(geometric, shading) <= 0) ++disagreeing;
    }
    EXPECT_EQ(disagreeing, 0u);
}

//! Max distance between each triangle (linear in the parameters of its corners) and the exact surface at the same
//! parameters, sampled densely inside every triangle.
double measured_max_deviation(const PatchSet& set, const PatchTessellation& t, int samples) {
    const PolygonMesh& mesh = t.mesh;
    double worst = 0;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const BezierPatch& patch = set.patches[t.face_patches[f]];
        const auto face = mesh.face(f);
        const std::size_t base = mesh.face_offsets[f];
        for (int a = 0; a <= samples; ++a)
            for (int b = 0; a + b <= samples; ++b) {
                const double l1 = static_cast<double>(a) / samples, l2 = static_cast<double>(b) / samples;
                const double l0 = 1 - l1 - l2;
                const Vec2 uv0 = mesh.uvs[mesh.uv_indices[base]], uv1 = mesh.uvs[mesh.uv_indices[base + 1]],
                           uv2 = mesh.uvs[mesh.uv_indices[base + 2]];
                const Vec3 linear =
                    l0 * mesh.positions[face[0]] + l1 * mesh.positions[face[1]] + l2 * mesh.positions[face[2]];
                const Vec3 exact =
                    evaluate(patch, l0 * uv0.x + l1 * uv1.x + l2 * uv2.x, l0 * uv0.y + l1 * uv1.y + l2 * uv2.y);
                worst = std::max(worst, norm(linear - exact));
            }
    }
    return worst;
}

TEST(BezierPatch, ToleranceHonouredOnTeapot) {
    const PatchSet set = teapot();
    for (double tolerance : {0.1, 0.02, 0.005}) {
        TessellationOptions options;
        options.tolerance = tolerance;
        auto result = tessellate_patches(set.patches, options);
        ASSERT_TRUE(result.ok()) << result.error().message;
        EXPECT_LE(result->plan.error_bound, tolerance);
        const double measured = measured_max_deviation(set, *result, 6);
        EXPECT_LE(measured, tolerance) << "tolerance " << tolerance;
        EXPECT_GT(measured, 0.0);
        EXPECT_EQ(result->face_patches.size(), result->mesh.face_count());
    }
    // tighter tolerance, more triangles
    TessellationOptions coarse, fine;
    coarse.tolerance = 0.1;
    fine.tolerance = 0.005;
    EXPECT_LT(plan_tessellation(set.patches, coarse)->triangles, plan_tessellation(set.patches, fine)->triangles);
}

TEST(BezierPatch, ToleranceHonouredOnRandomPatches) {
    for (unsigned seed = 1; seed <= 5; ++seed) {
        const PatchSet set{{random_patch(static_cast<int>(seed % 4) + 1, static_cast<int>(seed % 3) + 2, seed)}};
        TessellationOptions options;
        options.tolerance = 0.05;
        auto result = tessellate_patches(set.patches, options);
        ASSERT_TRUE(result.ok()) << result.error().message;
        EXPECT_LE(measured_max_deviation(set, *result, 8), 0.05) << "seed " << seed;
    }
}

//! Edges of the patch set (as control point sequences) with how many patch sides use them, matched in either
//! direction: written here independently of the library's canonical-edge code.
struct EdgeCensus {
    std::size_t expected_boundary_edges = 0;  //!< sum of segments over non-collapsed edges used by one side only
    std::size_t shared_edges = 0;
};

EdgeCensus census(const PatchSet& set, const TessellationPlan& plan) {
    std::vector<std::pair<std::vector<Vec3>, int>> sides;  // control points, segments along them
    for (std::size_t p = 0; p < set.patches.size(); ++p) {
        const BezierPatch& patch = set.patches[p];
        const int m = patch.degree_u, n = patch.degree_v;
        std::vector<Vec3> e[4];
        for (int i = 0; i <= m; ++i) e[0].push_back(patch.at(i, 0)), e[1].push_back(patch.at(i, n));
        for (int j = 0; j <= n; ++j) e[2].push_back(patch.at(0, j)), e[3].push_back(patch.at(m, j));
        for (int s = 0; s < 4; ++s) sides.emplace_back(e[s], s < 2 ? plan.segments[p].nu : plan.segments[p].nv);
    }
    EdgeCensus out;
    for (std::size_t a = 0; a < sides.size(); ++a) {
        const auto& pts = sides[a].first;
        if (std::all_of(pts.begin(), pts.end(), [&](const Vec3& q) { return q == pts[0]; })) continue;  // collapsed
        std::size_t uses = 0;
        for (std::size_t b = 0; b < sides.size(); ++b) {
            std::vector<Vec3> reversed(sides[b].first.rbegin(), sides[b].first.rend());
            if (sides[b].first == pts || reversed == pts) ++uses;
        }
        if (uses == 1) out.expected_boundary_edges += static_cast<std::size_t>(sides[a].second);
        if (uses == 2) ++out.shared_edges;
    }
    out.shared_edges /= 2;
    return out;
}

TEST(BezierPatch, TeapotIsCrackFree) {
    const PatchSet set = teapot();
    for (double tolerance : {0.05, 0.003}) {
        TessellationOptions options;
        options.tolerance = tolerance;
        auto result = tessellate_patches(set.patches, options);
        ASSERT_TRUE(result.ok()) << result.error().message;
        const EdgeCensus expected = census(set, result->plan);
        EXPECT_GT(expected.shared_edges, 40u);  // the teapot's pieces are nets of patches, most edges are shared
        const testing::EdgeStats stats = testing::edge_stats(result->mesh);
        EXPECT_GT(stats.boundary_edges, 0u);  // the teapot is open (lid, handle and spout ends)
        // every mesh boundary edge lies on a patch edge no other patch has: shared edges left no cracks
        EXPECT_EQ(stats.boundary_edges, expected.expected_boundary_edges) << "tolerance " << tolerance;
        EXPECT_EQ(stats.non_manifold_edges, 0u);
        EXPECT_EQ(stats.inconsistent_edges, 0u);
        // segment counts agree along every shared edge
        for (std::size_t p = 0; p < set.patches.size(); ++p)
            EXPECT_LE(
                tessellation_error_bound(set.patches[p], result->plan.segments[p].nu, result->plan.segments[p].nv),
                tolerance);
    }
}

TEST(BezierPatch, TeapotPiecesHaveTheirIntendedTopology) {
    // The pieces of Newell's data set: the pot (rim 0-3, body 4-11, bottom 28-31) is a disc open only at the rim's
    // inner edge (the bottom closes at its collapsed centre); lid (20-27) a disc closed at its apex; handle (12-15)
    // and spout (16-19) tubes open at both ends. Welded tessellations must have exactly that topology: any crack
    // would add boundary loops or change the Euler characteristic.
    const PatchSet set = teapot();
    struct PieceCase {
        const char* name;
        std::vector<int> patches;
        std::size_t loops;
        std::int64_t euler;
    };
    const PieceCase pieces[] = {
        {"pot", {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 28, 29, 30, 31}, 1, 1},
        {"lid", {20, 21, 22, 23, 24, 25, 26, 27}, 1, 1},
        {"handle", {12, 13, 14, 15}, 2, 0},
        {"spout", {16, 17, 18, 19}, 2, 0},
    };
    for (const PieceCase& piece : pieces)
        for (double tolerance : {0.05, 0.004}) {
            std::vector<BezierPatch> patches;
            for (int p : piece.patches) patches.push_back(set.patches[static_cast<std::size_t>(p)]);
            TessellationOptions options;
            options.tolerance = tolerance;
            auto result = tessellate_patches(patches, options);
            ASSERT_TRUE(result.ok()) << result.error().message;
            const testing::EdgeStats stats = testing::edge_stats(result->mesh);
            EXPECT_EQ(testing::boundary_loop_count(result->mesh), piece.loops) << piece.name;
            EXPECT_EQ(testing::euler_characteristic(result->mesh), piece.euler) << piece.name;
            EXPECT_EQ(stats.non_manifold_edges, 0u) << piece.name;
            EXPECT_EQ(stats.inconsistent_edges, 0u) << piece.name;
        }
}

TEST(BezierPatch, SharedEdgeVerticesAreIdenticalWithoutWelding) {
    // Two patches meeting along an edge that is left's u = 1 column and right's v = 0 row, run in opposite
    // directions (as two consistently oriented neighbours do): without welding the vertices along it must still be
    // bit-identical (they are computed from the edge's control points alone), and the counts along it equal.
    BezierPatch left = random_patch(3, 3, 21), right = random_patch(3, 3, 22);
    for (int i = 0; i <= 3; ++i) right.points[static_cast<std::size_t>(i)] = left.at(3, 3 - i);
    TessellationOptions options;
    options.tolerance = 0.01;
    options.weld = false;
    const std::vector<BezierPatch> patches{left, right};
    auto result = tessellate_patches(patches, options);
    ASSERT_TRUE(result.ok()) << result.error().message;
    EXPECT_EQ(result->plan.segments[0].nv, result->plan.segments[1].nu);
    std::map<std::array<double, 3>, int> count;
    for (const Vec3& p : result->mesh.positions) ++count[{p.x, p.y, p.z}];
    int duplicated = 0;
    for (const auto& [p, c] : count) duplicated += c == 2;
    EXPECT_EQ(duplicated, result->plan.segments[0].nv + 1);
    // welded, the shared edge becomes interior: the pair is one strip with one boundary loop
    options.weld = true;
    auto welded = tessellate_patches(patches, options);
    ASSERT_TRUE(welded.ok());
    EXPECT_EQ(testing::boundary_loop_count(welded->mesh), 1u);
    EXPECT_EQ(testing::edge_stats(welded->mesh).inconsistent_edges, 0u);
}

TEST(BezierPatch, FixedSegments) {
    const PatchSet set{{random_patch(3, 3, 9)}};
    TessellationOptions options;
    options.segments = 4;
    auto result = tessellate_patches(set.patches, options);
    ASSERT_TRUE(result.ok());
    EXPECT_EQ(result->mesh.face_count(), 32u);
    EXPECT_EQ(result->mesh.vertex_count(), 25u);
    EXPECT_EQ(result->mesh.uv_indices.size(), 96u);
    for (std::size_t k = 0; k < result->mesh.uv_indices.size(); ++k) {
        const Vec2 uv = result->mesh.uvs[result->mesh.uv_indices[k]];
        const Vec3 p = result->mesh.positions[result->mesh.face_indices[k]];
        expect_near(p, evaluate(set.patches[0], uv.x, uv.y), 1e-12, "vertex at its uv");
    }
}

TEST(BezierPatch, Errors) {
    BezierPatch bad = random_patch(3, 3, 1);
    bad.points.pop_back();
    TessellationOptions options;
    auto r1 = tessellate_patches(std::span<const BezierPatch>(&bad, 1), options);
    ASSERT_FALSE(r1.ok());
    EXPECT_EQ(r1.error().code, ErrorCode::InvalidArgument);
    EXPECT_EQ(r1.error().element, 0);

    BezierPatch nan = random_patch(2, 2, 1);
    nan.points[4].y = std::nan("");
    const std::vector<BezierPatch> two{random_patch(2, 2, 2), nan};
    auto r2 = tessellate_patches(two, options);
    ASSERT_FALSE(r2.ok());
    EXPECT_EQ(r2.error().code, ErrorCode::NonFinite);
    EXPECT_EQ(r2.error().element, 1);

    const BezierPatch good = random_patch(3, 3, 1);
    options.tolerance = -1;
    EXPECT_EQ(tessellate_patches(std::span<const BezierPatch>(&good, 1), options).error().code,
              ErrorCode::InvalidArgument);
    options.tolerance = 1e-12;
    EXPECT_EQ(tessellate_patches(std::span<const BezierPatch>(&good, 1), options).error().code,
              ErrorCode::BudgetExceeded);
    options.tolerance.reset();
    options.segments = 0;
    EXPECT_EQ(tessellate_patches(std::span<const BezierPatch>(&good, 1), options).error().code,
              ErrorCode::InvalidArgument);
}

// ---- rational patches ---------------------------------------------------------------------------------------------

//! One octant of the unit sphere as a rational biquadratic patch: the quarter circle (1,0),(1,1),(0,1) with weights
//! 1, sqrt(2)/2, 1 swept (tensor product) along the meridian quarter circle from the equator to the pole. Signs pick
//! the octant; an odd number of flips reverses u so that every octant faces outwards.
BezierPatch sphere_octant(double sx, double sy, double sz) {
    const double s = std::sqrt(0.5);
    const double cx[3] = {1, 1, 0}, cy[3] = {0, 1, 1}, cw[3] = {1, s, 1};  // circle in the xy plane
    const double mr[3] = {1, 1, 0}, mz[3] = {0, 1, 1}, mw[3] = {1, s, 1};  // meridian (radius, height)
    const bool reverse = sx * sy * sz < 0;
    BezierPatch patch;
    patch.degree_u = 2;
    patch.degree_v = 2;
    for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k) {
            const int i = reverse ? 2 - k : k;
            patch.points.push_back({sx * mr[j] * cx[i], sy * mr[j] * cy[i], sz * mz[j]});
            patch.weights.push_back(cw[i] * mw[j]);
        }
    return patch;
}

PatchSet unit_sphere() {
    PatchSet set;
    for (double sz : {1.0, -1.0})
        for (double sy : {1.0, -1.0})
            for (double sx : {1.0, -1.0}) set.patches.push_back(sphere_octant(sx, sy, sz));
    return set;
}

BezierPatch random_rational_patch(int m, int n, unsigned seed) {
    BezierPatch patch = random_patch(m, n, seed);
    std::mt19937 rng(seed + 1000);
    std::uniform_real_distribution<double> weight(0.3, 3.0);
    for (std::size_t k = 0; k < patch.points.size(); ++k) patch.weights.push_back(weight(rng));
    return patch;
}

TEST(RationalPatch, SphereOctantIsExact) {
    const BezierPatch octant = sphere_octant(1, 1, 1);
    ASSERT_TRUE(validate(std::span<const BezierPatch>(&octant, 1)).ok());
    double worst = 0;
    for (int a = 0; a <= 40; ++a)
        for (int b = 0; b <= 40; ++b) {
            const Vec3 p = evaluate(octant, a / 40.0, b / 40.0);
            worst = std::max(worst, std::fabs(norm(p) - 1.0));
            EXPECT_GE(std::min({p.x, p.y, p.z}), -1e-15);
        }
    EXPECT_LE(worst, 1e-12);
    // the corners are the control net's corners; (1/2, 0) is the equator at 45 degrees
    EXPECT_EQ(evaluate(octant, 0, 0), (Vec3{1, 0, 0}));
    expect_near(evaluate(octant, 0.5, 0), Vec3{std::sqrt(0.5), std::sqrt(0.5), 0}, 1e-15, "equator at 45 degrees");
    expect_near(evaluate(octant, 0.3, 1), Vec3{0, 0, 1}, 1e-15, "pole");
}

//! Distance from q to the patch, from above: Gauss-Newton on |S(y) - q|^2 from `start`, kept in [0, 1]^2, the
//! smallest distance met (a point of the patch, so never below the true distance; close to it from a near start).
double distance_to_patch(const BezierPatch& patch, const Vec3& q, Vec2 start) {
    Vec2 y = start;
    double best = norm(evaluate(patch, y.x, y.y) - q);
    for (int iteration = 0; iteration < 12; ++iteration) {
        const PatchDerivatives d = evaluate_derivatives(patch, y.x, y.y);
        const Vec3 r = d.position - q;
        const double a = dot(d.du, d.du), b = dot(d.du, d.dv), c = dot(d.dv, d.dv);
        const double det = a * c - b * b;
        if (!(det > 0)) break;
        const double gu = dot(d.du, r), gv = dot(d.dv, r);
        y = {std::clamp(y.x - (c * gu - b * gv) / det, 0.0, 1.0), std::clamp(y.y - (a * gv - b * gu) / det, 0.0, 1.0)};
        best = std::min(best, norm(evaluate(patch, y.x, y.y) - q));
    }
    return best;
}

//! Largest distance from a barycentric grid on the triangle through S(a), S(b), S(c) to the patch.
double triangle_deviation(const BezierPatch& patch, Vec2 a, Vec2 b, Vec2 c) {
    const Vec3 pa = evaluate(patch, a.x, a.y), pb = evaluate(patch, b.x, b.y), pc = evaluate(patch, c.x, c.y);
    double worst = 0;
    constexpr int n = 8;
    for (int i = 0; i <= n; ++i)
        for (int j = 0; i + j <= n; ++j) {
            const double s = static_cast<double>(i) / n, t = static_cast<double>(j) / n;
            const Vec3 q = pa + s * (pb - pa) + t * (pc - pa);
            const Vec2 x{a.x + s * (b.x - a.x) + t * (c.x - a.x), a.y + s * (b.y - a.y) + t * (c.y - a.y)};
            worst = std::max(worst, distance_to_patch(patch, q, x));
        }
    return worst;
}

TEST(RationalPatch, TriangleDistanceBoundHoldsOnRandomPatches) {
    // random rational and polynomial patches, random triangles inside and on the sides: bound >= measured distance
    std::mt19937 rng(77);
    std::uniform_real_distribution<double> unit(0.0, 1.0), size(0.01, 0.2);
    int local_wins = 0, triangles = 0;  // local_wins: at most half the whole patch's bound
    for (unsigned seed = 1; seed <= 12; ++seed) {
        const int m = static_cast<int>(seed % 3) + 1, n = static_cast<int>(seed % 2) + 2;
        const BezierPatch patch = seed % 3 == 0 ? random_patch(m, n, seed) : random_rational_patch(m, n, seed);
        for (int k = 0; k < 40; ++k) {
            const double w = size(rng), h = size(rng);
            double u0 = unit(rng) * (1 - w), v0 = unit(rng) * (1 - h);
            if (k % 5 == 0) u0 = 0;  // on a patch side
            if (k % 7 == 0) v0 = 1 - h;
            const Vec2 a{u0, v0}, b{u0 + w, v0}, c{u0 + (k % 2 ? w : 0), v0 + h};
            const double bound = triangle_distance_bound(patch, a, b, c);
            const double measured = triangle_deviation(patch, a, b, c);
            EXPECT_GE(bound * (1 + 1e-9) + 1e-14, measured) << "seed " << seed << " triangle " << k;
            // the one-net form (what a caller satisfied with any value below `enough` gets) is a guarantee too, and
            // never tighter than the sub-box form
            const double coarse = triangle_distance_bound(patch, a, b, c, 1e300);
            EXPECT_GE(coarse * (1 + 1e-9) + 1e-14, measured) << "seed " << seed << " triangle " << k;
            EXPECT_LE(bound, coarse) << "seed " << seed << " triangle " << k;
            // the whole patch's equal-parameter bound for these extents (a guarantee too): never beaten by much less
            const PatchDerivativeBounds db = derivative_bounds(patch);
            const double whole = (db.uu * w * w + 2 * db.uv * w * h + db.vv * h * h) / 8;
            ++triangles;
            if (bound < 0.5 * whole) ++local_wins;
        }
    }
    EXPECT_EQ(triangles, 12 * 40);
    EXPECT_GT(local_wins, triangles / 4);
}

TEST(RationalPatch, TriangleDistanceBoundOnSphereOctant) {
    // exact distances (| |q| - 1 |, the unit sphere): the bound holds and is far below the equal-parameter bound of
    // tessellation_error_bound on the same grid, away from the pole (where du x dv vanishes)
    const BezierPatch octant = sphere_octant(1, 1, 1);
    constexpr int n = 16;
    const double whole = tessellation_error_bound(octant, n, n);
    double worst_ratio = 0, interior_ratio = 0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const Vec2 a{static_cast<double>(i) / n, static_cast<double>(j) / n};
            const Vec2 b{a.x + 1.0 / n, a.y}, c{a.x + 1.0 / n, a.y + 1.0 / n}, d{a.x, a.y + 1.0 / n};
            for (const auto& [p, q, r] : {std::tuple{a, b, c}, std::tuple{a, c, d}}) {
                const Vec3 pp = evaluate(octant, p.x, p.y), pq = evaluate(octant, q.x, q.y),
                           pr = evaluate(octant, r.x, r.y);
                double measured = 0;
                for (int s = 0; s <= 10; ++s)
                    for (int t = 0; s + t <= 10; ++t)
                        measured = std::max(measured,
                                            std::fabs(norm(pp + (s / 10.0) * (pq - pp) + (t / 10.0) * (pr - pp)) - 1));
                const double bound = triangle_distance_bound(octant, p, q, r);
                EXPECT_GE(bound, measured) << i << ", " << j;
                EXPECT_LE(bound, whole * (1 + 1e-12)) << i << ", " << j;
                worst_ratio = std::max(worst_ratio, bound / whole);
                if (i > 0 && j > 0 && i + 1 < n && j + 1 < n) interior_ratio = std::max(interior_ratio, bound / whole);
            }
        }
    EXPECT_LT(interior_ratio, 0.75) << "worst " << worst_ratio;
}

TEST(RationalPatch, DerivativesMatchFiniteDifferences) {
    for (unsigned seed = 1; seed <= 4; ++seed) {
        const BezierPatch patch =
            random_rational_patch(static_cast<int>(seed % 3) + 1, static_cast<int>(seed % 2) + 2, seed);
        for (auto [u, v] : {std::pair{0.3, 0.6}, {0.1, 0.9}, {0.5, 0.5}}) {
            const double h = 1e-4;
            const PatchDerivatives d = evaluate_derivatives(patch, u, v);
            const auto S = [&](double du, double dv) { return evaluate(patch, u + du, v + dv); };
            expect_near(d.position, S(0, 0), 1e-13, "position");
            expect_near(d.du, (S(h, 0) - S(-h, 0)) * (1 / (2 * h)), 1e-6, "du");
            expect_near(d.dv, (S(0, h) - S(0, -h)) * (1 / (2 * h)), 1e-6, "dv");
            expect_near(d.duu, (S(h, 0) - 2.0 * S(0, 0) + S(-h, 0)) * (1 / (h * h)), 1e-4, "duu");
            expect_near(d.dvv, (S(0, h) - 2.0 * S(0, 0) + S(0, -h)) * (1 / (h * h)), 1e-4, "dvv");
            expect_near(d.duv, (S(h, h) - S(h, -h) - S(-h, h) + S(-h, -h)) * (1 / (4 * h * h)), 1e-4, "duv");
        }
    }
}

TEST(RationalPatch, EqualWeightsAreThePolynomialPatch) {
    const BezierPatch polynomial = random_patch(3, 2, 5);
    BezierPatch rational = polynomial;
    rational.weights.assign(rational.points.size(), 2.5);
    for (double u : {0.0, 0.25, 0.7, 1.0})
        for (double v : {0.0, 0.4, 1.0}) {
            expect_near(evaluate(rational, u, v), evaluate(polynomial, u, v), 1e-14, "position");
            const PatchDerivatives a = evaluate_derivatives(rational, u, v), b = evaluate_derivatives(polynomial, u, v);
            expect_near(a.duv, b.duv, 1e-12, "duv");
            expect_near(a.dvv, b.dvv, 1e-12, "dvv");
        }
    EXPECT_NEAR(tessellation_error_bound(rational, 5, 7), tessellation_error_bound(polynomial, 5, 7), 1e-12);
}

TEST(RationalPatch, SphereNormalsAreRadialIncludingThePole) {
    for (const BezierPatch& octant : unit_sphere().patches)
        for (double u : {0.0, 0.2, 0.5, 1.0})
            for (double v : {0.0, 0.35, 0.9, 1.0}) {
                const Vec3 p = evaluate(octant, u, v);
                const Vec3 n = unit_normal(octant, u, v);
                EXPECT_NEAR(dot(n, p), 1.0, 1e-9) << "u " << u << " v " << v;
            }
}

TEST(RationalPatch, ToleranceHonouredAndGuaranteed) {
    const PatchSet sphere = unit_sphere();
    for (double tolerance : {0.05, 0.002}) {
        TessellationOptions options;
        options.tolerance = tolerance;
        auto result = tessellate_patches(sphere.patches, options);
        ASSERT_TRUE(result.ok()) << result.error().message;
        EXPECT_LE(result->plan.error_bound, tolerance);
        const double measured = measured_max_deviation(sphere, *result, 4);
        EXPECT_LE(measured, tolerance) << "tolerance " << tolerance;
        EXPECT_GT(measured, tolerance / 10) << "the bound should not be wildly pessimistic on a sphere";
        // every vertex is on the sphere (exact evaluation)
        for (const Vec3& p : result->mesh.positions) EXPECT_NEAR(norm(p), 1.0, 1e-12);
    }
    for (unsigned seed = 1; seed <= 5; ++seed) {
        const PatchSet set{
            {random_rational_patch(static_cast<int>(seed % 4) + 1, static_cast<int>(seed % 3) + 2, seed)}};
        TessellationOptions options;
        options.tolerance = 0.05;
        options.max_segments = 1024;
        auto result = tessellate_patches(set.patches, options);
        ASSERT_TRUE(result.ok()) << result.error().message;
        EXPECT_LE(measured_max_deviation(set, *result, 3), 0.05) << "seed " << seed;
        // the guarantee holds for any grid, not only the planned one
        for (int n : {2, 5, 11}) {
            TessellationOptions fixed;
            fixed.segments = n;
            auto grid = tessellate_patches(set.patches, fixed);
            ASSERT_TRUE(grid.ok());
            EXPECT_LE(measured_max_deviation(set, *grid, 8), grid->plan.error_bound) << "seed " << seed << " n " << n;
        }
    }
}

TEST(RationalPatch, SphereOfEightOctantsIsWatertight) {
    const PatchSet sphere = unit_sphere();
    for (double tolerance : {0.02, 0.001}) {
        TessellationOptions options;
        options.tolerance = tolerance;
        auto result = tessellate_patches(sphere.patches, options);
        ASSERT_TRUE(result.ok()) << result.error().message;
        const testing::EdgeStats stats = testing::edge_stats(result->mesh);
        EXPECT_EQ(stats.boundary_edges, 0u) << "tolerance " << tolerance;
        EXPECT_EQ(stats.non_manifold_edges, 0u);
        EXPECT_EQ(stats.inconsistent_edges, 0u);
        EXPECT_TRUE(testing::is_watertight(result->mesh));
        EXPECT_EQ(testing::euler_characteristic(result->mesh), 2);
        // inscribed polyhedron: volume a little under 4/3 pi, within the chord tolerance's shell
        const double volume = testing::signed_volume(result->mesh);
        EXPECT_LT(volume, 4.0 / 3.0 * std::numbers::pi);
        EXPECT_GT(volume, 4.0 / 3.0 * std::numbers::pi * std::pow(1 - tolerance, 3));
    }
    // unwelded, shared-edge vertices are still bit-identical: welding by position changes nothing but the count
    TessellationOptions unwelded;
    unwelded.segments = 6;
    unwelded.weld = false;
    auto loose = tessellate_patches(sphere.patches, unwelded);
    ASSERT_TRUE(loose.ok());
    std::set<std::array<double, 3>> distinct;
    for (const Vec3& p : loose->mesh.positions) distinct.insert({p.x + 0.0, p.y + 0.0, p.z + 0.0});
    TessellationOptions welded = unwelded;
    welded.weld = true;
    EXPECT_EQ(distinct.size(), tessellate_patches(sphere.patches, welded)->mesh.vertex_count());
}

TEST(RationalPatch, ValidationErrors) {
    BezierPatch patch = sphere_octant(1, 1, 1);
    patch.weights.pop_back();
    auto count = validate(std::span<const BezierPatch>(&patch, 1));
    ASSERT_FALSE(count.ok());
    EXPECT_NE(count.error().message.find("8 weights for 9 control points"), std::string::npos) << count.error().message;
    patch = sphere_octant(1, 1, 1);
    patch.weights[4] = 0;
    auto zero = validate(std::span<const BezierPatch>(&patch, 1));
    ASSERT_FALSE(zero.ok());
    EXPECT_NE(zero.error().message.find("weight 4 must be a finite number > 0"), std::string::npos);
    patch.weights[4] = 1e13;
    auto ratio = validate(std::span<const BezierPatch>(&patch, 1));
    ASSERT_FALSE(ratio.ok());
    EXPECT_NE(ratio.error().message.find("largest weight"), std::string::npos);
}

// ---- corner texture coordinates -------------------------------------------------------------------------------

TEST(BezierPatch, CornerUvsInterpolatedBilinearly) {
    BezierPatch patch = random_patch(3, 2, 9);
    patch.corner_uvs = std::array<Vec2, 4>{Vec2{0.5, 0.25}, Vec2{1, 0.25}, Vec2{0.5, 0.75}, Vec2{2, 1}};
    TessellationOptions options;
    options.segments = 4;
    auto result = tessellate_patches(std::span<const BezierPatch>(&patch, 1), options);
    ASSERT_TRUE(result.ok());
    const PolygonMesh& mesh = result->mesh;
    ASSERT_EQ(mesh.uvs.size(), 25u);
    // grid vertex (i, j) at (u, v) = (i/4, j/4), u fastest
    for (int j = 0; j <= 4; ++j)
        for (int i = 0; i <= 4; ++i) {
            const double u = i / 4.0, v = j / 4.0;
            const Vec2 uv = mesh.uvs[static_cast<std::size_t>(j * 5 + i)];
            EXPECT_NEAR(uv.x, (1 - u) * (1 - v) * 0.5 + u * (1 - v) * 1 + (1 - u) * v * 0.5 + u * v * 2, 1e-15);
            EXPECT_NEAR(uv.y, (1 - v) * 0.25 + v * (1 - u) * 0.75 + u * v * 1, 1e-15);
        }
    // corners exactly
    EXPECT_EQ(mesh.uvs[0].x, 0.5);
    EXPECT_EQ(mesh.uvs[24].x, 2.0);
    EXPECT_EQ(mesh.uvs[24].y, 1.0);
}

}  // namespace
}  // namespace surfaced
