// Limit surface evaluation at (face, u, v): against OpenSubdiv's Bfr::Surface (approximation levels at their
// maximum) at random points, against Far uniform refinement + limit masks at dyadic points (corners of level-k child
// faces, where the masks are exact), and against our own vertex limit positions at face corners.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "geometry/io/mesh_io.h"
#include "geometry/mesh/shapes.h"
#include "geometry/subdivision/limit_evaluation.h"
#include "geometry/subdivision/subdivide.h"
#include "tests/support/opensubdiv_shapes.h"
#include "tests/support/bfr_reference.h"
#include "tests/support/mesh_asserts.h"
#include "tests/support/osd_reference.h"

namespace surfaced {
namespace {

namespace fs = std::filesystem;
using namespace OpenSubdiv;

using Reference = testing::BfrSample;
using testing::BfrReference;

//! The columns of Bfr's quad sub-face tiling of an N-gon.
int subface_columns(std::size_t n) {
    return n < 10 ? 2 + (n > 4 ? 1 : 0) : 1 + static_cast<int>(std::sqrt(static_cast<float>(n - 1)));
}

//! A uniformly random point of face f's domain.
std::pair<double, double> random_uv(const PolygonMesh& mesh, std::size_t f, std::mt19937_64& rng) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const std::size_t n = mesh.face_size(f);
    if (n == 4) return {unit(rng), unit(rng)};
    const int columns = subface_columns(n);
    const int sub = static_cast<int>(rng() % n);
    return {sub % columns + 0.5 * unit(rng), sub / columns + 0.5 * unit(rng)};
}

using testing::load_opensubdiv_shape;

struct Case {
    std::string name;
    PolygonMesh mesh;
    SubdivisionOptions options;
    //! Bfr's surface differs from Far's uniform refinement here (Chaikin creases: see
    //! BfrApproximatesChaikinCreasesFarDoesNot; edges with more than two faces): compared with Far at dyadic points
    //! only
    bool bfr_differs = false;
};

std::vector<Case> cases() {
    std::vector<Case> out;
    auto add = [&](std::string name, PolygonMesh mesh, SubdivisionOptions options = {}) {
        out.push_back({std::move(name), std::move(mesh), options});
    };
    add("cube", shapes::cube());
    add("torus", shapes::torus(8, 6));
    add("irregular_torus", shapes::irregular_torus());
    add("grid", shapes::grid(4, 3));
    SubdivisionOptions corners;
    corners.boundary = BoundaryInterpolation::EdgeAndCorner;
    add("grid_edge_and_corner", shapes::grid(4, 3), corners);
    add("mixed_polygons", shapes::mixed_polygons());
    add("icosahedron", shapes::icosahedron());
    for (const char* name :
         {"catmark_cube",          "catmark_gregory_test0", "catmark_gregory_test1",    "catmark_gregory_test2",
          "catmark_gregory_test3", "catmark_edgecorner",    "catmark_edgeonly",         "catmark_cube_creases0",
          "catmark_cube_creases1", "catmark_cube_corner0",  "catmark_cube_corner1",     "catmark_cube_corner2",
          "catmark_cube_corner3",  "catmark_cube_corner4",  "catmark_cubes_semisharp",  "catmark_cubes_infsharp",
          "catmark_inf_crease0",   "catmark_inf_crease1",   "catmark_pyramid_creases0", "catmark_pyramid_creases1",
          "catmark_nonquads",      "catmark_dart_edgeonly", "catmark_dart_edgecorner",  "catmark_torus_creases0",
          "catmark_quadstrips",    "catmark_pyramid"}) {
        if (!fs::exists(fs::path(SURFACED_TEST_DATA_DIR) / "opensubdiv-shapes" / (std::string(name) + ".obj")))
            continue;
        add(name, load_opensubdiv_shape(name));
    }
    SubdivisionOptions chaikin;
    chaikin.crease_method = CreaseMethod::Chaikin;
    add("catmark_chaikin0 (chaikin)", load_opensubdiv_shape("catmark_chaikin0"), chaikin);
    add("catmark_chaikin1 (chaikin)", load_opensubdiv_shape("catmark_chaikin1"), chaikin);
    out[out.size() - 1].bfr_differs = out[out.size() - 2].bfr_differs = true;
    for (const char* name :
         {"catmark_nonman_quadpole8", "catmark_nonman_quadpole64", "catmark_nonman_verts", "catmark_nonman_edges"})
        add(name, load_opensubdiv_shape(name));
    SubdivisionOptions smooth_tris;
    smooth_tris.triangle_rule = TriangleRule::Smooth;
    add("catmark_smoothtris0 (smooth triangles)", load_opensubdiv_shape("catmark_smoothtris0"), smooth_tris);
    return out;
}

//! Whether face f uses a vertex twice (irregular: always refined).
bool repeats_vertex(const PolygonMesh& mesh, std::size_t f) {
    auto face = mesh.face(f);
    for (std::size_t i = 0; i < face.size(); ++i)
        for (std::size_t j = i + 1; j < face.size(); ++j)
            if (face[i] == face[j]) return true;
    return false;
}

bool is_hole(const PolygonMesh& mesh, std::size_t f) {
    return std::find(mesh.tags.holes.begin(), mesh.tags.holes.end(), static_cast<Index>(f)) != mesh.tags.holes.end();
}

TEST(LimitEvaluation, MatchesBfrSurfaceAtRandomPoints) {
    std::mt19937_64 rng(20240611);
    for (const Case& c : cases()) {
        if (c.bfr_differs) continue;
        auto evaluator = LimitSurfaceEvaluator::create(c.mesh, c.options);
        ASSERT_TRUE(evaluator.ok()) << c.name << ": " << evaluator.error().message;
        BfrReference bfr(c.mesh, c.options);
        const double diag = c.mesh.bounds().diagonal();
        double worst_p = 0, worst_d = 0, worst_dd = 0;
        int compared = 0, inexact = 0, deepest = 0, repeated = 0;
        for (int i = 0; i < 300; ++i) {
            const std::size_t f = rng() % c.mesh.face_count();
            if (is_hole(c.mesh, f)) continue;
            const auto [u, v] = random_uv(c.mesh, f, rng);
            repeated += repeats_vertex(c.mesh, f);
            Reference ref;
            if (!bfr.evaluate(f, u, v, ref)) continue;
            auto ours = evaluator->evaluate(f, u, v, true);
            ASSERT_TRUE(ours.ok()) << c.name << " face " << f << ": " << ours.error().message;
            inexact += !ours->exact;
            deepest = std::max(deepest, ours->level);
            const double dp = norm(ours->position - ref.p);
            const double dd = std::max(norm(ours->du - ref.du), norm(ours->dv - ref.dv));
            const double d2 =
                std::max({norm(ours->duu - ref.duu), norm(ours->duv - ref.duv), norm(ours->dvv - ref.dvv)});
            worst_p = std::max(worst_p, dp);
            worst_d = std::max(worst_d, dd);
            worst_dd = std::max(worst_dd, d2);
            EXPECT_LE(dp, 1e-9 * diag) << c.name << " face " << f << " (" << u << ", " << v << ")";
            EXPECT_LE(dd, 1e-9 * diag) << c.name << " face " << f << " (" << u << ", " << v << ") du/dv";
            EXPECT_LE(d2, 1e-7 * diag) << c.name << " face " << f << " (" << u << ", " << v << ") 2nd";
            // the normal is the normalized cross product of the derivatives
            const Vec3 n = cross(ours->du, ours->dv);
            if (norm(n) > 1e-12 * diag * diag) {
                EXPECT_LE(norm(ours->normal - n * (1.0 / norm(n))), 1e-12) << c.name;
            }
            ++compared;
        }
        EXPECT_GT(compared, 100) << c.name;
        EXPECT_EQ(inexact, 0) << c.name;
        std::printf(
            "[limit-eval] %-40s %3d points (%2d on faces using a vertex twice), deepest level %2d: |dP| %.2g "
            "|dD| %.2g |dDD| %.2g (rel. diag)\n",
            c.name.c_str(), compared, repeated, deepest, worst_p / diag, worst_d / diag, worst_dd / diag);
    }
}

// Far refined uniformly to level k with the limit masks applied there is exact at the level's vertices: each is a
// corner of a level-k child face, whose (u, v) in the base face is dyadic. Child faces follow Far's order (grouped by
// parent face, one per corner; quads keep their parent's orientation), so a random path of corners names a vertex.
TEST(LimitEvaluation, MatchesFarLimitMasksAtDyadicPoints) {
    std::mt19937_64 rng(7);
    for (const Case& c : cases()) {
        SubdivisionOptions options = c.options;
        options.limit_surface = true;
        options.levels = 3;
        const int k = 3 + limit_extra_levels(c.mesh, options);  // past every semi-sharp feature
        if (predicted_face_count(c.mesh, SubdivisionScheme::CatmullClark, k) > 200000) continue;
        options.levels = k;
        options.limit_surface = false;
        const PolygonMesh fine = testing::osd_subdivide(c.mesh, options);
        const auto limit = testing::osd_limit(c.mesh, options, k, fine.vertex_count());
        auto evaluator = LimitSurfaceEvaluator::create(c.mesh, c.options);
        ASSERT_TRUE(evaluator.ok()) << c.name;
        const double diag = c.mesh.bounds().diagonal();
        // osd_subdivide drops hole faces: only meshes without holes can be indexed this way
        if (!c.mesh.tags.holes.empty()) continue;
        double worst = 0;
        for (int i = 0; i < 100; ++i) {
            const std::size_t f = rng() % c.mesh.face_count();
            const std::size_t n = c.mesh.face_size(f);
            std::size_t face = c.mesh.face_offsets[f];  // level-1 child index
            double u = 0, v = 0, size = 1;
            if (n == 4) {
                const int j = static_cast<int>(rng() % 4);
                face += j;
                size = 0.5;
                u = (j == 1 || j == 2) ? 0.5 : 0.0;
                v = j >= 2 ? 0.5 : 0.0;
            } else {
                const int j = static_cast<int>(rng() % n), columns = subface_columns(n);
                face += j;
                size = 0.5;
                u = j % columns;
                v = j / columns;
            }
            for (int level = 2; level <= k; ++level) {
                const int j = static_cast<int>(rng() % 4);
                face = 4 * face + j;
                size *= 0.5;
                u += (j == 1 || j == 2) ? size : 0.0;
                v += j >= 2 ? size : 0.0;
            }
            const int corner = static_cast<int>(rng() % 4);
            const Index vertex = fine.face_indices[4 * face + corner];
            u += (corner == 1 || corner == 2) ? size : 0.0;
            v += corner >= 2 ? size : 0.0;
            auto ours = evaluator->evaluate(f, u, v);
            ASSERT_TRUE(ours.ok()) << c.name << ": " << ours.error().message;
            const double d = norm(ours->position - limit.positions[vertex]);
            worst = std::max(worst, d);
            EXPECT_LE(d, 1e-9 * diag) << c.name << " face " << f << " (" << u << ", " << v << ") vertex " << vertex;
        }
        std::printf("[limit-eval] dyadic level %d %-40s |dP| %.2g (rel. diag)\n", k, c.name.c_str(), worst / diag);
    }
}

// Chaikin creasing: Far's uniform refinement (whose limit masks are exact at the level's vertices once the
// sharpness has decayed) and Bfr::Surface disagree near the creases of catmark_chaikin0, by up to 1e-3 of the
// mesh's size at maximum approximation levels; the evaluator agrees with Far to rounding at the same points.
TEST(LimitEvaluation, BfrApproximatesChaikinCreasesFarDoesNot) {
    SubdivisionOptions options;
    options.crease_method = CreaseMethod::Chaikin;
    const PolygonMesh mesh = load_opensubdiv_shape("catmark_chaikin0");
    const int k = 7;  // past the sharpest crease (5)
    SubdivisionOptions uniform = options;
    uniform.levels = k;
    const PolygonMesh fine = testing::osd_subdivide(mesh, uniform);
    const auto limit = testing::osd_limit(mesh, uniform, k, fine.vertex_count());
    auto evaluator = LimitSurfaceEvaluator::create(mesh, options);
    ASSERT_TRUE(evaluator.ok());
    BfrReference bfr(mesh, options);
    const double diag = mesh.bounds().diagonal();
    double bfr_worst = 0;
    const std::size_t face = 11;
    for (auto [iu, iv] : {std::pair{9, 10}, {8, 10}, {2, 3}, {20, 30}, {64, 64}, {127, 1}}) {
        // the level-k vertex at (iu, iv) / 2^k: corner 0 of the level-k face along the binary digits
        std::size_t child = mesh.face_offsets[face];
        for (int l = 1; l <= k; ++l) {
            const int bu = (iu >> (k - l)) & 1, bv = (iv >> (k - l)) & 1;
            const std::size_t j = bu ? (bv ? 2 : 1) : (bv ? 3 : 0);
            child = l == 1 ? child + j : 4 * child + j;
        }
        const Index vertex = fine.face_indices[4 * child];
        const double u = std::ldexp(iu, -k), v = std::ldexp(iv, -k);
        auto ours = evaluator->evaluate(face, u, v);
        ASSERT_TRUE(ours.ok());
        EXPECT_LE(norm(ours->position - limit.positions[vertex]), 1e-12 * diag) << u << ", " << v;
        Reference ref;
        ASSERT_TRUE(bfr.evaluate(face, u, v, ref));
        bfr_worst = std::max(bfr_worst, norm(ref.p - limit.positions[vertex]));
    }
    std::printf("[limit-eval] chaikin0 face 11: Bfr vs Far uniform + limit masks up to %.3g (rel. diag)\n",
                bfr_worst / diag);
    EXPECT_GT(bfr_worst, 1e-6 * diag);  // a real difference, not rounding
}

// At a base face's corner the evaluator gives the vertex's limit position (limit.h, through subdivide's
// limit_surface at level 0) and its limit normal, extraordinary or not.
TEST(LimitEvaluation, FaceCornersAreVertexLimitPositions) {
    for (const char* name : {"cube", "catmark_gregory_test1", "catmark_edgeonly", "catmark_cube_creases1"}) {
        const PolygonMesh mesh = std::string(name) == "cube" ? shapes::cube() : load_opensubdiv_shape(name);
        SubdivisionOptions options;
        options.levels = 0;
        options.limit_surface = true;
        auto limit = subdivide(mesh, options);
        ASSERT_TRUE(limit.ok()) << name;
        auto evaluator = LimitSurfaceEvaluator::create(mesh, {});
        ASSERT_TRUE(evaluator.ok()) << name;
        const double diag = mesh.bounds().diagonal();
        for (std::size_t f = 0; f < mesh.face_count(); ++f) {
            const std::size_t n = mesh.face_size(f);
            for (std::size_t j = 0; j < n; ++j) {
                double u, v;
                if (n == 4) {
                    u = (j == 1 || j == 2) ? 1.0 : 0.0;
                    v = j >= 2 ? 1.0 : 0.0;
                } else {
                    u = static_cast<double>(j % subface_columns(n));
                    v = static_cast<double>(j / subface_columns(n));
                }
                auto ours = evaluator->evaluate(f, u, v);
                ASSERT_TRUE(ours.ok()) << name;
                const Index vertex = mesh.face_indices[mesh.face_offsets[f] + j];
                EXPECT_LE(norm(ours->position - limit->positions[vertex]), 1e-12 * diag)
                    << name << " face " << f << " corner " << j;
                EXPECT_LE(norm(ours->normal - limit->normals[vertex]), 1e-9)
                    << name << " face " << f << " corner " << j;
            }
        }
    }
}

// A smooth Catmull-Clark vertex of valence 2 (faces glued back to back) is where the surface around it converges,
// (4 v + 4 (e0 + e1) + f0 + f1) / 14, not the vertex itself (the corner mask OpenSubdiv's Sdc gives it and limit.h
// keeps for subdivide's limit_surface, as darts keep theirs).
TEST(LimitEvaluation, ValenceTwoVerticesAreTheLimitAroundThem) {
    const PolygonMesh mesh = load_opensubdiv_shape("catmark_val2_back2back");
    auto evaluator = LimitSurfaceEvaluator::create(mesh, {});
    ASSERT_TRUE(evaluator.ok());
    const double diag = mesh.bounds().diagonal();
    int corners = 0;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const std::size_t n = mesh.face_size(f);
        for (std::size_t j = 0; j < n; ++j) {
            double u, v, du = 1e-6, dv = 1e-6;
            if (n == 4) {
                u = (j == 1 || j == 2) ? 1.0 : 0.0;
                v = j >= 2 ? 1.0 : 0.0;
                du = u == 1.0 ? -du : du;
                dv = v == 1.0 ? -dv : dv;
            } else {
                u = static_cast<double>(j % subface_columns(n));
                v = static_cast<double>(j / subface_columns(n));
            }
            auto at = evaluator->evaluate(f, u, v);
            auto near = evaluator->evaluate(f, u + du, v + dv);
            ASSERT_TRUE(at.ok() && near.ok());
            EXPECT_LE(norm(at->position - near->position), 1e-9 * diag) << "face " << f << " corner " << j;
            const Vec3& p = mesh.positions[mesh.face_indices[mesh.face_offsets[f] + j]];
            EXPECT_GT(norm(at->position - p), 0.05 * diag) << "face " << f << " corner " << j;
            ++corners;
        }
    }
    EXPECT_GT(corners, 0);
    // the quad pair (faces 2 and 3): corner 0 of face 2 by the valence-2 formula
    const auto corner = [&](std::size_t k) { return mesh.positions[mesh.face_indices[mesh.face_offsets[2] + k]]; };
    const Vec3 expected = (4.0 * corner(0) + 4.0 * (corner(1) + corner(3)) + 2.0 * corner(2)) * (1.0 / 14.0);
    auto at = evaluator->evaluate(2, 0, 0);
    ASSERT_TRUE(at.ok());
    EXPECT_LE(norm(at->position - expected), 1e-12 * diag);
}

TEST(LimitEvaluation, RejectsBadInput) {
    const PolygonMesh cube = shapes::cube();
    auto evaluator = LimitSurfaceEvaluator::create(cube, {});
    ASSERT_TRUE(evaluator.ok());
    EXPECT_EQ(evaluator->evaluate(6, 0.5, 0.5).error().code, ErrorCode::IndexOutOfRange);
    EXPECT_EQ(evaluator->evaluate(0, std::nan(""), 0.5).error().code, ErrorCode::NonFinite);
    EXPECT_EQ(evaluator->evaluate(0, 0.5, INFINITY).error().code, ErrorCode::NonFinite);
    EXPECT_EQ(evaluator->evaluate(0, 1.5, 0.5).error().code, ErrorCode::InvalidArgument);
    EXPECT_EQ(evaluator->evaluate(0, 0.5, -1e-9).error().code, ErrorCode::InvalidArgument);

    const PolygonMesh mixed = shapes::mixed_polygons();
    auto ngons = LimitSurfaceEvaluator::create(mixed, {});
    ASSERT_TRUE(ngons.ok());
    for (std::size_t f = 0; f < mixed.face_count(); ++f) {
        if (mixed.face_size(f) == 4) continue;
        EXPECT_TRUE(ngons->evaluate(f, 0.25, 0.25).ok());
        EXPECT_EQ(ngons->evaluate(f, 0.75, 0.25).error().code, ErrorCode::InvalidArgument);  // between sub-faces
        EXPECT_EQ(ngons->evaluate(f, 0.25, 9.25).error().code, ErrorCode::InvalidArgument);  // past the last one
    }

    LimitEvaluationOptions shallow;
    shallow.max_level = 3;
    EXPECT_EQ(LimitSurfaceEvaluator::create(cube, {}, shallow).error().code, ErrorCode::InvalidArgument);

    const PolygonMesh holed = load_opensubdiv_shape("catmark_hole_test1");
    ASSERT_FALSE(holed.tags.holes.empty());
    auto with_holes = LimitSurfaceEvaluator::create(holed, {});
    ASSERT_TRUE(with_holes.ok());
    EXPECT_EQ(with_holes->evaluate(holed.tags.holes[0], 0.5, 0.5).error().code, ErrorCode::InvalidArgument);
}

// A face surface (the face's regular sub-faces prepared as patches) answers as the evaluator does, at random points
// and at points nearer an extraordinary vertex than its prepared levels reach.
TEST(LimitEvaluation, FaceSurfacesAnswerAsTheEvaluator) {
    std::mt19937_64 rng(99);
    for (const Case& c : cases()) {
        auto evaluator = LimitSurfaceEvaluator::create(c.mesh, c.options);
        ASSERT_TRUE(evaluator.ok()) << c.name;
        const double diag = c.mesh.bounds().diagonal();
        for (std::size_t f = 0; f < c.mesh.face_count(); f += 1 + c.mesh.face_count() / 8) {
            if (is_hole(c.mesh, f)) {
                EXPECT_FALSE(evaluator->face_surface(f).ok()) << c.name;
                continue;
            }
            auto surface = evaluator->face_surface(f, 3);
            ASSERT_TRUE(surface.ok()) << c.name << ": " << surface.error().message;
            for (int i = 0; i < 40; ++i) {
                auto [u, v] = random_uv(c.mesh, f, rng);
                if (i % 4 == 0) {  // within 2^-3 of the domain's first corner
                    u = std::floor(u) + (u - std::floor(u)) * 0.01;
                    v = std::floor(v) + (v - std::floor(v)) * 0.01;
                }
                auto a = surface->evaluate(u, v, true);
                auto b = evaluator->evaluate(f, u, v, true);
                ASSERT_TRUE(a.ok() && b.ok()) << c.name;
                EXPECT_LE(norm(a->position - b->position), 1e-15 * diag) << c.name << " face " << f;
                EXPECT_LE(norm(a->du - b->du) + norm(a->dv - b->dv), 1e-13 * diag) << c.name << " face " << f;
                EXPECT_LE(norm(a->duu - b->duu) + norm(a->dvv - b->dvv) + norm(a->duv - b->duv), 1e-10 * diag)
                    << c.name << " face " << f;
                EXPECT_EQ(a->exact, b->exact);
                EXPECT_EQ(a->level, b->level) << c.name << " face " << f;
            }
            // exactly at corners of the face and of its prepared leaves (where the descent may stop early, at an
            // irregular vertex): the same answers
            const double corners[][2] = {{0.0, 0.0}, {0.125, 0.0}, {0.0, 0.125}, {0.125, 0.125}};
            const double scale = c.mesh.face_size(f) == 4 ? 1.0 : 0.5;  // an N-gon's first sub-face
            for (const auto& corner : corners) {
                auto a = surface->evaluate(scale * corner[0], scale * corner[1]);
                auto b = evaluator->evaluate(f, scale * corner[0], scale * corner[1]);
                ASSERT_TRUE(a.ok() && b.ok()) << c.name;
                EXPECT_EQ(norm(a->position - b->position), 0.0) << c.name << " face " << f;
                EXPECT_EQ(norm(a->du - b->du) + norm(a->dv - b->dv), 0.0) << c.name << " face " << f;
                EXPECT_EQ(a->level, b->level) << c.name << " face " << f;
                EXPECT_EQ(a->exact, b->exact) << c.name << " face " << f;
            }
            EXPECT_EQ(surface->evaluate(-0.25, 0.25).error().code, ErrorCode::InvalidArgument);
        }
    }
}

// A face surface shares its evaluator's data: it still answers, deeper than its prepared levels too, once the
// evaluator it came from is gone.
TEST(LimitEvaluation, FaceSurfaceOutlivesItsEvaluator) {
    std::optional<LimitFaceSurface> surface;
    LimitSample near_corner, inside;
    {
        auto evaluator = LimitSurfaceEvaluator::create(shapes::cube(), {});
        ASSERT_TRUE(evaluator.ok());
        auto prepared = evaluator->face_surface(2, 2);
        ASSERT_TRUE(prepared.ok());
        surface.emplace(*prepared);
        near_corner = *evaluator->evaluate(2, 1e-3, 2e-3);
        inside = *evaluator->evaluate(2, 0.4, 0.7);
    }
    auto a = surface->evaluate(1e-3, 2e-3);
    auto b = surface->evaluate(0.4, 0.7);
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_EQ(norm(a->position - near_corner.position), 0.0);
    EXPECT_EQ(norm(b->position - inside.position), 0.0);
    EXPECT_GT(a->level, 2);  // answered by the evaluator's descent, past the prepared levels
}

// On a regular mesh a semi-sharp crease is isolated for ceil(sharpness) levels, no more: a torus (valence 4
// everywhere) with one edge loop of sharpness 2.5 reaches a regular patch within 3 levels at every point, and
// matches Bfr there.
TEST(LimitEvaluation, SemiSharpIsolationEndsWhenTheSharpnessHasDecayed) {
    PolygonMesh torus = shapes::torus(8, 6);
    // the loop of edges around the tube's first ring: vertices 0..5 (ring 0 of the 8 x 6 grid)
    for (Index j = 0; j < 6; ++j) torus.tags.creases.push_back({j, static_cast<Index>((j + 1) % 6), 2.5});
    auto evaluator = LimitSurfaceEvaluator::create(torus, {});
    ASSERT_TRUE(evaluator.ok());
    BfrReference bfr(torus, {});
    const double diag = torus.bounds().diagonal();
    std::mt19937_64 rng(3);
    int deepest = 0;
    for (int i = 0; i < 400; ++i) {
        const std::size_t f = rng() % torus.face_count();
        const auto [u, v] = random_uv(torus, f, rng);
        auto ours = evaluator->evaluate(f, u, v);
        ASSERT_TRUE(ours.ok());
        EXPECT_TRUE(ours->exact);
        deepest = std::max(deepest, ours->level);
        Reference ref;
        ASSERT_TRUE(bfr.evaluate(f, u, v, ref));
        EXPECT_LE(norm(ours->position - ref.p), 1e-9 * diag);
    }
    EXPECT_EQ(deepest, 3);
}

// Near an irregular vertex the descent goes as deep as the point is close; past max_level the answer is flagged
// and still within the stated error of the exact one.
TEST(LimitEvaluation, ConvergesOnExtraordinaryVertices) {
    const PolygonMesh cube = shapes::cube();  // every vertex has valence 3
    auto evaluator = LimitSurfaceEvaluator::create(cube, {});
    ASSERT_TRUE(evaluator.ok());
    BfrReference bfr(cube, {});
    const double diag = cube.bounds().diagonal();
    int previous_level = -1;
    for (int e = 2; e <= 9; ++e) {
        const double d = std::ldexp(1.0, -e) * 0.7;
        auto ours = evaluator->evaluate(0, d, d);
        ASSERT_TRUE(ours.ok());
        EXPECT_TRUE(ours->exact);
        EXPECT_GT(ours->level, previous_level);
        previous_level = ours->level;
        Reference ref;
        ASSERT_TRUE(bfr.evaluate(0, d, d, ref));
        EXPECT_LE(norm(ours->position - ref.p), 1e-9 * diag) << d;
    }
    auto at_cap = evaluator->evaluate(0, 1e-12, 1e-12);
    ASSERT_TRUE(at_cap.ok());
    EXPECT_FALSE(at_cap->exact);
    auto corner = evaluator->evaluate(0, 0, 0);
    ASSERT_TRUE(corner.ok());
    EXPECT_LE(norm(at_cap->position - corner->position), 1e-9 * diag);
}

}  // namespace
}  // namespace surfaced
