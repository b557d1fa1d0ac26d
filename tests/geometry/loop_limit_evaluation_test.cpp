// Loop limit surface evaluation at (face, u, v): against OpenSubdiv's Bfr::Surface (approximation levels at their
// maximum) at random points, against Far uniform refinement + limit masks at dyadic points (corners of level-k child
// triangles), and against our own subdivide() where OpenSubdiv has no counterpart (Warren's weights).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "geometry/io/mesh_io.h"
#include "geometry/mesh/shapes.h"
#include "geometry/mesh/triangulate.h"
#include "geometry/subdivision/limit_evaluation.h"
#include "geometry/subdivision/subdivide.h"
#include "tests/support/opensubdiv_shapes.h"
#include "tests/support/bfr_reference.h"
#include "tests/support/mesh_asserts.h"
#include "tests/support/osd_reference.h"

namespace surfaced {
namespace {

namespace fs = std::filesystem;

using testing::load_opensubdiv_shape;

struct Case {
    std::string name;
    PolygonMesh mesh;
    SubdivisionOptions options;
    //! Bfr departs from Far's uniform refinement here (Chaikin creasing with unequal sharpness, as under
    //! Catmull-Clark): the evaluator is held to Far (MatchesFarLimitMasksAtDyadicPoints)
    bool bfr_differs = false;
};

SubdivisionOptions loop_options(BoundaryInterpolation boundary = BoundaryInterpolation::EdgeOnly,
                                CreaseMethod creasing = CreaseMethod::Uniform) {
    SubdivisionOptions options;
    options.scheme = SubdivisionScheme::Loop;
    options.boundary = boundary;
    options.crease_method = creasing;
    return options;
}

//! Meshes that Bfr and Far agree on (Chaikin creasing is compared with Far only: see the Catmull-Clark tests).
std::vector<Case> cases() {
    std::vector<Case> out;
    auto add = [&](std::string name, PolygonMesh mesh, SubdivisionOptions options = loop_options()) {
        out.push_back({std::move(name), std::move(mesh), options});
    };
    add("icosahedron", shapes::icosahedron());
    add("octahedron", shapes::octahedron());
    add("tetrahedron", shapes::tetrahedron());
    add("regular torus", triangulate(shapes::torus(8, 6)));
    add("irregular torus", triangulate(shapes::irregular_torus()));
    add("grid (edge only)", shapes::grid(4, 3, true));
    add("grid (edge and corner)", shapes::grid(4, 3, true), loop_options(BoundaryInterpolation::EdgeAndCorner));
    add("grid (none)", shapes::grid(5, 4, true), loop_options(BoundaryInterpolation::None));
    for (const char* name :
         {"loop_cube",           "loop_cube_asymmetric",     "loop_cube_creases0",     "loop_cube_creases1",
          "loop_cubes_infsharp", "loop_cubes_semisharp",     "loop_icos_infsharp",     "loop_icos_semisharp",
          "loop_icosahedron",    "loop_saddle_edgecorner",   "loop_saddle_edgeonly",   "loop_tetrahedron",
          "loop_toroidal_tet",   "loop_triangle_edgecorner", "loop_triangle_edgeonly", "loop_triangle_edgenone",
          "loop_val2_interior",  "loop_xord_boundary",       "loop_xord_interior",     "loop_pole8",
          "loop_nonman_verts",   "loop_nonman_edges",        "loop_fvar_bound0",       "loop_fvar_bound1"})
        add(name, load_opensubdiv_shape(name));
    // both sharp boundary modes on the shapes that have a boundary, whatever their tag says ("boundary none" makes
    // every face of these holes; the grid and loop_triangle_edgenone above have interior faces left)
    for (const char* name : {"loop_saddle_edgeonly", "loop_xord_boundary", "loop_triangle_edgeonly"})
        for (BoundaryInterpolation boundary : {BoundaryInterpolation::EdgeOnly, BoundaryInterpolation::EdgeAndCorner}) {
            SubdivisionOptions options = loop_options(boundary);
            options.use_mesh_boundary_tag = false;
            add(std::string(name) +
                    (boundary == BoundaryInterpolation::EdgeOnly ? " (edge only)" : " (edge and corner)"),
                load_opensubdiv_shape(name), options);
        }
    return out;
}

//! Whether face f has no limit surface (a hole: tagged, or at an open boundary with "boundary none").
bool is_hole(const LimitSurfaceEvaluator& evaluator, std::size_t f) {
    auto probe = evaluator.evaluate(f, 0.25, 0.25);
    return !probe.ok() && probe.error().message.find("is a hole") != std::string::npos;
}

//! Whether no edge has more than two faces.
bool manifold_edges(const PolygonMesh& mesh) {
    std::map<std::pair<Index, Index>, int> uses;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        auto face = mesh.face(f);
        for (std::size_t i = 0; i < face.size(); ++i) {
            const Index a = face[i], b = face[(i + 1) % face.size()];
            if (++uses[{std::min(a, b), std::max(a, b)}] > 2) return false;
        }
    }
    return true;
}

//! A uniformly random point of the unit triangle.
std::pair<double, double> random_uv(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    double u = unit(rng), v = unit(rng);
    if (u + v > 1.0) {
        u = 1.0 - u;
        v = 1.0 - v;
    }
    return {u, v};
}

TEST(LoopLimitEvaluation, MatchesBfrSurfaceAtRandomPoints) {
    std::mt19937_64 rng(20251203);
    std::vector<Case> all = cases();
    for (const char* name : {"loop_chaikin0", "loop_chaikin1", "loop_icos_semisharp"})
        all.push_back({std::string(name) + " (chaikin)", load_opensubdiv_shape(name),
                       loop_options(BoundaryInterpolation::EdgeOnly, CreaseMethod::Chaikin),
                       std::string(name) != "loop_icos_semisharp"});
    for (const Case& c : all) {
        auto evaluator = LimitSurfaceEvaluator::create(c.mesh, c.options);
        ASSERT_TRUE(evaluator.ok()) << c.name << ": " << evaluator.error().message;
        testing::BfrReference bfr(c.mesh, c.options);
        const double diag = c.mesh.bounds().diagonal();
        double worst_p = 0, worst_d = 0, worst_dd = 0;
        int compared = 0, inexact = 0, deepest = 0, regular = 0, flipped = 0;
        for (int i = 0; i < 300; ++i) {
            const std::size_t f = rng() % c.mesh.face_count();
            const auto [u, v] = random_uv(rng);
            testing::BfrSample ref;
            if (!bfr.evaluate(f, u, v, ref)) {
                EXPECT_TRUE(is_hole(*evaluator, f)) << c.name << " face " << f;
                continue;
            }
            auto ours = evaluator->evaluate(f, u, v, true);
            ASSERT_TRUE(ours.ok()) << c.name << " face " << f << ": " << ours.error().message;
            inexact += !ours->exact;
            regular += ours->level == 0;
            deepest = std::max(deepest, ours->level);
            const double dp = norm(ours->position - ref.p);
            const double dd = std::max(norm(ours->du - ref.du), norm(ours->dv - ref.dv));
            // OpenSubdiv 3.5 and 3.6 (Far::internal::EvaluatePatchBasis, which Bfr uses) scale the second
            // derivatives of a triangle patch turned half round (an odd number of middle children on the way down)
            // by -4^depth instead of 4^depth: Bfr's sign is wrong there, and its depth is not ours. Second
            // derivatives are compared up to sign here; SecondDerivativesDifferentiateTheFirst checks the sign.
            auto second_error = [&](double sign) {
                return std::max({norm(ours->duu - sign * ref.duu), norm(ours->duv - sign * ref.duv),
                                 norm(ours->dvv - sign * ref.dvv)});
            };
            const double d2 = std::min(second_error(1.0), second_error(-1.0));
            flipped += second_error(1.0) > second_error(-1.0);
            worst_p = std::max(worst_p, dp);
            worst_d = std::max(worst_d, dd);
            worst_dd = std::max(worst_dd, d2);
            if (!c.bfr_differs) {
                EXPECT_LE(dp, 1e-9 * diag) << c.name << " face " << f << " (" << u << ", " << v << ")";
                EXPECT_LE(dd, 1e-9 * diag) << c.name << " face " << f << " (" << u << ", " << v << ") du/dv";
                EXPECT_LE(d2, 1e-7 * diag) << c.name << " face " << f << " (" << u << ", " << v << ") 2nd";
            }
            const Vec3 n = cross(ours->du, ours->dv);
            if (norm(n) > 1e-12 * diag * diag) {
                EXPECT_LE(norm(ours->normal - n * (1.0 / norm(n))), 1e-12) << c.name;
            }
            ++compared;
        }
        EXPECT_GT(compared, 100) << c.name;
        EXPECT_EQ(inexact, 0) << c.name;
        if (c.bfr_differs) {
            EXPECT_GT(worst_p, 1e-6 * diag) << c.name;  // a real difference, not rounding
        }
        std::printf(
            "[loop-limit] %-44s %3d points (%3d on base patches), deepest level %2d: |dP| %.2g |dD| %.2g "
            "|dDD| %.2g (rel. diag; Bfr's sign flipped at %d)\n",
            c.name.c_str(), compared, regular, deepest, worst_p / diag, worst_d / diag, worst_dd / diag, flipped);
    }
}

// A regular mesh (valence 6 everywhere): every face is one box-spline patch, no refinement at all.
TEST(LoopLimitEvaluation, RegularTrianglesAreBoxSplinePatches) {
    const PolygonMesh torus = triangulate(shapes::torus(8, 6));
    auto evaluator = LimitSurfaceEvaluator::create(torus, loop_options());
    ASSERT_TRUE(evaluator.ok());
    std::mt19937_64 rng(5);
    for (int i = 0; i < 100; ++i) {
        const auto [u, v] = random_uv(rng);
        auto ours = evaluator->evaluate(rng() % torus.face_count(), u, v);
        ASSERT_TRUE(ours.ok());
        EXPECT_EQ(ours->level, 0);
        EXPECT_TRUE(ours->exact);
    }
}

//! The (u, v) of corner `corner` of a level-k child triangle reached by `path` (child indices, Far's order: three
//! corners, then the middle one, turned half round).
std::pair<double, double> child_corner(const std::vector<int>& path, int corner) {
    double ox = 0, oy = 0, ax = 1, ay = 0, bx = 0, by = 1;  // point = o + s a + t b
    static constexpr double kOrigin[4][2] = {{0, 0}, {0.5, 0}, {0, 0.5}, {0.5, 0.5}};
    for (int j : path) {
        const double px = ox + kOrigin[j][0] * ax + kOrigin[j][1] * bx;
        const double py = oy + kOrigin[j][0] * ay + kOrigin[j][1] * by;
        const double f = j == 3 ? -0.5 : 0.5;
        ox = px;
        oy = py;
        ax *= f;
        ay *= f;
        bx *= f;
        by *= f;
    }
    const double s = corner == 1 ? 1 : 0, t = corner == 2 ? 1 : 0;
    return {ox + s * ax + t * bx, oy + s * ay + t * by};
}

// Far refined uniformly to level k with the limit masks applied there is exact at the level's vertices, each a
// corner of a level-k child triangle. Chaikin creasing included (Far is the reference there).
TEST(LoopLimitEvaluation, MatchesFarLimitMasksAtDyadicPoints) {
    std::mt19937_64 rng(11);
    std::vector<Case> all = cases();
    all.push_back({"loop_chaikin0 (chaikin)", load_opensubdiv_shape("loop_chaikin0"),
                   loop_options(BoundaryInterpolation::EdgeOnly, CreaseMethod::Chaikin)});
    all.push_back({"loop_chaikin1 (chaikin)", load_opensubdiv_shape("loop_chaikin1"),
                   loop_options(BoundaryInterpolation::EdgeOnly, CreaseMethod::Chaikin)});
    all.push_back({"loop_icos_semisharp (chaikin)", load_opensubdiv_shape("loop_icos_semisharp"),
                   loop_options(BoundaryInterpolation::EdgeOnly, CreaseMethod::Chaikin)});
    for (const Case& c : all) {
        auto evaluator = LimitSurfaceEvaluator::create(c.mesh, c.options);
        ASSERT_TRUE(evaluator.ok()) << c.name;
        // osd_subdivide drops hole faces: no indexing by path
        bool holes = false;
        for (std::size_t f = 0; f < c.mesh.face_count(); ++f) holes = holes || is_hole(*evaluator, f);
        if (holes) continue;
        SubdivisionOptions options = c.options;
        options.limit_surface = true;
        options.levels = 3;
        const int k = 3 + limit_extra_levels(c.mesh, options);
        if (predicted_face_count(c.mesh, SubdivisionScheme::Loop, k) > 200000) continue;
        options.levels = k;
        options.limit_surface = false;
        const PolygonMesh fine = testing::osd_subdivide(c.mesh, options);
        const auto limit = testing::osd_limit(c.mesh, options, k, fine.vertex_count());
        const double diag = c.mesh.bounds().diagonal();
        double worst = 0, worst_normal = 0;
        const bool sharp_features = !c.mesh.tags.creases.empty() || !c.mesh.tags.corners.empty() ||
                                    !manifold_edges(c.mesh) || c.name == "loop_val2_interior";
        for (int i = 0; i < 100; ++i) {
            const std::size_t f = rng() % c.mesh.face_count();
            std::vector<int> path;
            std::size_t face = f;
            for (int level = 1; level <= k; ++level) {
                path.push_back(static_cast<int>(rng() % 4));
                face = 4 * face + static_cast<std::size_t>(path.back());
            }
            const int corner = static_cast<int>(rng() % 3);
            const Index vertex = fine.face_indices[3 * face + static_cast<std::size_t>(corner)];
            const auto [u, v] = child_corner(path, corner);
            auto ours = evaluator->evaluate(f, u, v);
            ASSERT_TRUE(ours.ok()) << c.name << ": " << ours.error().message;
            const double d = norm(ours->position - limit.positions[vertex]);
            worst = std::max(worst, d);
            EXPECT_LE(d, 1e-9 * diag) << c.name << " face " << f << " (" << u << ", " << v << ") vertex " << vertex;
            // the normals agree where the surface has one: away from infinitely sharp creases and non-manifold edges
            // (ours is the face's side there), not at an extraordinary boundary vertex (Loop's boundary rules leave
            // no tangent plane there: ours, Far's and the limit of nearby normals all differ), and not on the flat
            // pillows of loop_val2_interior (two faces on one plane, facing opposite ways)
            if (!sharp_features && ours->exact && norm(ours->normal) > 0 && norm(limit.normals[vertex]) > 0) {
                const double dn = norm(ours->normal - limit.normals[vertex]);
                worst_normal = std::max(worst_normal, dn);
                EXPECT_LE(dn, 1e-6) << c.name << " face " << f << " (" << u << ", " << v << ") normal";
            }
        }
        std::printf("[loop-limit] dyadic level %d %-40s |dP| %.2g (rel. diag), |dN| %.2g\n", k, c.name.c_str(),
                    worst / diag, worst_normal);
    }
}

// Warren's weights have no OpenSubdiv counterpart: our own subdivide() with limit positions is the reference at the
// dyadic points.
TEST(LoopLimitEvaluation, WarrenWeightsMatchSubdivideAtDyadicPoints) {
    for (const char* name : {"loop_xord_interior", "loop_cube_creases1", "loop_xord_boundary"}) {
        const PolygonMesh mesh = load_opensubdiv_shape(name);
        SubdivisionOptions options = loop_options();
        options.loop_weights = LoopWeights::Warren;
        const int k = 4;
        SubdivisionOptions uniform = options;
        uniform.levels = k;
        uniform.limit_surface = true;
        auto fine = subdivide(mesh, uniform);
        ASSERT_TRUE(fine.ok()) << name;
        auto evaluator = LimitSurfaceEvaluator::create(mesh, options);
        ASSERT_TRUE(evaluator.ok()) << name;
        const double diag = mesh.bounds().diagonal();
        std::mt19937_64 rng(13);
        for (int i = 0; i < 100; ++i) {
            const std::size_t f = rng() % mesh.face_count();
            std::vector<int> path;
            std::size_t face = f;
            for (int level = 1; level <= k; ++level) {
                path.push_back(static_cast<int>(rng() % 4));
                face = 4 * face + static_cast<std::size_t>(path.back());
            }
            const int corner = static_cast<int>(rng() % 3);
            const auto [u, v] = child_corner(path, corner);
            auto ours = evaluator->evaluate(f, u, v);
            ASSERT_TRUE(ours.ok());
            const Index vertex = fine->face_indices[3 * face + static_cast<std::size_t>(corner)];
            EXPECT_LE(norm(ours->position - fine->positions[vertex]), 1e-9 * diag) << name << " face " << f;
        }
    }
}

// A face surface answers as the evaluator does, near irregular corners (past its prepared levels) too.
TEST(LoopLimitEvaluation, FaceSurfacesAnswerAsTheEvaluator) {
    std::mt19937_64 rng(17);
    for (const Case& c : cases()) {
        auto evaluator = LimitSurfaceEvaluator::create(c.mesh, c.options);
        ASSERT_TRUE(evaluator.ok()) << c.name;
        const double diag = c.mesh.bounds().diagonal();
        for (std::size_t f = 0; f < c.mesh.face_count(); f += 1 + c.mesh.face_count() / 6) {
            if (is_hole(*evaluator, f)) continue;
            auto surface = evaluator->face_surface(f, 3);
            ASSERT_TRUE(surface.ok()) << c.name << ": " << surface.error().message;
            for (int i = 0; i < 30; ++i) {
                auto [u, v] = random_uv(rng);
                if (i % 4 == 0) {
                    u *= 0.01;
                    v *= 0.01;
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
            const double corners[][2] = {{0.0, 0.0}, {0.125, 0.0}, {0.0, 0.125}, {1.0, 0.0}, {0.5, 0.5}};
            for (const auto& corner : corners) {
                auto a = surface->evaluate(corner[0], corner[1]);
                auto b = evaluator->evaluate(f, corner[0], corner[1]);
                ASSERT_TRUE(a.ok() && b.ok()) << c.name;
                EXPECT_EQ(norm(a->position - b->position), 0.0) << c.name << " face " << f;
                EXPECT_EQ(norm(a->du - b->du) + norm(a->dv - b->dv), 0.0) << c.name << " face " << f;
                EXPECT_EQ(a->level, b->level) << c.name << " face " << f;
                EXPECT_EQ(a->exact, b->exact) << c.name << " face " << f;
            }
        }
    }
}

// Near an extraordinary vertex the descent goes as deep as the point is close; at the vertex itself the answer is
// its limit position and normal (limit.h), flagged inexact.
TEST(LoopLimitEvaluation, ConvergesOnExtraordinaryVertices) {
    const PolygonMesh ico = shapes::icosahedron();  // valence 5 everywhere
    auto evaluator = LimitSurfaceEvaluator::create(ico, loop_options());
    ASSERT_TRUE(evaluator.ok());
    testing::BfrReference bfr(ico, loop_options());
    const double diag = ico.bounds().diagonal();
    int previous_level = -1;
    for (int e = 2; e <= 9; ++e) {
        const double d = std::ldexp(1.0, -e) * 0.4;
        auto ours = evaluator->evaluate(0, d, d);
        ASSERT_TRUE(ours.ok());
        EXPECT_TRUE(ours->exact);
        EXPECT_GT(ours->level, previous_level);
        previous_level = ours->level;
        testing::BfrSample ref;
        ASSERT_TRUE(bfr.evaluate(0, d, d, ref));
        EXPECT_LE(norm(ours->position - ref.p), 1e-9 * diag) << d;
    }
    SubdivisionOptions at_vertices = loop_options();
    at_vertices.levels = 0;
    at_vertices.limit_surface = true;
    auto limit = subdivide(ico, at_vertices);
    ASSERT_TRUE(limit.ok());
    for (int corner = 0; corner < 3; ++corner) {
        const double u = corner == 1 ? 1 : 0, v = corner == 2 ? 1 : 0;
        auto ours = evaluator->evaluate(0, u, v);
        ASSERT_TRUE(ours.ok());
        EXPECT_FALSE(ours->exact);
        const Index vertex = ico.face_indices[static_cast<std::size_t>(corner)];
        EXPECT_LE(norm(ours->position - limit->positions[vertex]), 1e-12 * diag);
        EXPECT_LE(norm(ours->normal - limit->normals[vertex]), 1e-9);
    }
    auto at_cap = evaluator->evaluate(0, 1e-12, 1e-12);
    ASSERT_TRUE(at_cap.ok());
    EXPECT_FALSE(at_cap->exact);
    EXPECT_LE(norm(at_cap->position - limit->positions[ico.face_indices[0]]), 1e-9 * diag);
    // within 2^-24 of the vertex (inexact): against the exact answer of a deeper evaluator, for the header's number
    LimitEvaluationOptions deep;
    deep.max_level = 40;
    auto exact = LimitSurfaceEvaluator::create(ico, loop_options(), deep);
    ASSERT_TRUE(exact.ok());
    double worst = 0;
    for (double d : {std::ldexp(0.3, -25), std::ldexp(0.2, -28), std::ldexp(0.7, -32)}) {
        auto capped = evaluator->evaluate(0, d, 0.5 * d);
        auto reference = exact->evaluate(0, d, 0.5 * d);
        ASSERT_TRUE(capped.ok() && reference.ok());
        EXPECT_FALSE(capped->exact);
        EXPECT_TRUE(reference->exact);
        worst = std::max(worst, norm(capped->position - reference->position) / diag);
    }
    // a fraction of the last face's size (about 0.45^24 of the base face's): the parameterization is not linear there
    EXPECT_LE(worst, 1e-9);
    std::printf("[loop-limit] within 2^-24 of a valence-5 vertex: position off by %.2g (rel. diag)\n", worst);
}

TEST(LoopLimitEvaluation, RejectsBadInput) {
    auto evaluator = LimitSurfaceEvaluator::create(shapes::icosahedron(), loop_options());
    ASSERT_TRUE(evaluator.ok());
    EXPECT_EQ(evaluator->evaluate(20, 0.2, 0.2).error().code, ErrorCode::IndexOutOfRange);
    EXPECT_EQ(evaluator->evaluate(0, std::nan(""), 0.2).error().code, ErrorCode::NonFinite);
    EXPECT_EQ(evaluator->evaluate(0, 0.6, 0.6).error().code, ErrorCode::InvalidArgument);  // past u + v = 1
    EXPECT_EQ(evaluator->evaluate(0, -1e-9, 0.5).error().code, ErrorCode::InvalidArgument);
    EXPECT_TRUE(evaluator->evaluate(0, 0.5, 0.5).ok());  // on the edge u + v = 1
    // Loop needs triangles, as subdivide() does: the error names the first other face
    auto quads = LimitSurfaceEvaluator::create(shapes::cube(), loop_options());
    ASSERT_FALSE(quads.ok());
    EXPECT_EQ(quads.error().code, ErrorCode::NotTriangleMesh);
    EXPECT_NE(quads.error().message.find("face 0"), std::string::npos);
    SubdivisionOptions subdivide_options = loop_options();
    subdivide_options.levels = 1;
    EXPECT_EQ(subdivide(shapes::cube(), subdivide_options).error().code, quads.error().code);
}

// The second derivatives are the derivatives of the first ones: central differences of du and dv at points answered
// on the same level agree with duu, duv, dvv (this checks their sign, which Bfr gets wrong on some sub-patches).
TEST(LoopLimitEvaluation, SecondDerivativesDifferentiateTheFirst) {
    for (const Case& c : cases()) {
        const PolygonMesh& mesh = c.mesh;
        const char* name = c.name.c_str();
        auto evaluator = LimitSurfaceEvaluator::create(mesh, c.options);
        ASSERT_TRUE(evaluator.ok());
        std::mt19937_64 rng(23);
        double worst = 0;
        for (int i = 0; i < 100; ++i) {
            const std::size_t f = rng() % mesh.face_count();
            auto [u, v] = random_uv(rng);
            u = 0.05 + 0.9 * u;
            v = 0.05 + 0.9 * v;
            if (u + v > 0.95) continue;
            const double h = 1e-6;
            if (is_hole(*evaluator, f)) continue;
            auto at = evaluator->evaluate(f, u, v, true);
            auto pu = evaluator->evaluate(f, u + h, v), mu = evaluator->evaluate(f, u - h, v);
            auto pv = evaluator->evaluate(f, u, v + h), mv = evaluator->evaluate(f, u, v - h);
            ASSERT_TRUE(at.ok() && pu.ok() && mu.ok() && pv.ok() && mv.ok());
            if (pu->level != at->level || mu->level != at->level || pv->level != at->level || mv->level != at->level)
                continue;  // a patch boundary between the samples
            const Vec3 duu = (pu->du - mu->du) * (0.5 / h), dvv = (pv->dv - mv->dv) * (0.5 / h);
            const Vec3 duv = (pv->du - mv->du) * (0.5 / h);
            const double d = std::max({norm(duu - at->duu), norm(dvv - at->dvv), norm(duv - at->duv)}) /
                             std::max(1.0, norm(at->duu) + norm(at->dvv));
            worst = std::max(worst, d);
            EXPECT_LE(d, 1e-4) << name << " face " << f << " (" << u << ", " << v << ") level " << at->level;
        }
        std::printf("[loop-limit] %s: second derivatives vs differences of the first: %.2g\n", name, worst);
    }
}

}  // namespace
}  // namespace surfaced
