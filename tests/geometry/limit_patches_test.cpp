// The limit surface as Bézier patches: exact patches equal the exact evaluator, approximated ones stay within the
// measured error (which shrinks with the level), the layout is conforming (the patch tessellator welds closed shapes
// watertight, with the base mesh's Euler characteristic), and counts and errors are as documented.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "geometry/io/mesh_io.h"
#include "geometry/mesh/shapes.h"
#include "geometry/subdivision/limit_patches.h"
#include "tests/support/opensubdiv_shapes.h"
#include "tests/support/mesh_asserts.h"

namespace surfaced {
namespace {

namespace fs = std::filesystem;

using testing::load_opensubdiv_shape;

double bounding_diagonal(const PolygonMesh& mesh) {
    Box3 box;
    for (const Vec3& p : mesh.positions) box.add(p);
    return box.diagonal();
}

LimitSurfaceEvaluator make_evaluator(const PolygonMesh& mesh) {
    auto evaluator = LimitSurfaceEvaluator::create(mesh, SubdivisionOptions{});
    EXPECT_TRUE(evaluator.ok()) << (evaluator.ok() ? "" : evaluator.error().message);
    return std::move(evaluator.value());
}

//! Every patch against the exact evaluator at random points of its square: exact patches to rounding, approximated
//! ones within `allowance` (the measured error plus the slack of a measurement on a grid).
void expect_patches_match_limit(const std::string& name, const PolygonMesh& mesh,
                                const LimitSurfaceEvaluator& evaluator, const LimitPatchSet& set,
                                int samples_per_patch) {
    const double diagonal = bounding_diagonal(mesh);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    double worst_exact = 0, worst_approximate = 0;
    for (std::size_t p = 0; p < set.patches.size(); ++p)
        for (int k = 0; k < samples_per_patch; ++k) {
            const double s = unit(rng), t = unit(rng);
            const auto& square = set.squares[p];
            auto exact = evaluator.evaluate(set.faces[p], square[0] + square[2] * s, square[1] + square[2] * t);
            ASSERT_TRUE(exact.ok()) << name << " patch " << p;
            const double d = norm(evaluate(set.patches[p], s, t) - exact->position);
            (set.exact[p] ? worst_exact : worst_approximate) =
                std::max(set.exact[p] ? worst_exact : worst_approximate, d);
        }
    EXPECT_LE(worst_exact, 1e-12 * diagonal) << name;
    EXPECT_LE(worst_approximate, 2.0 * set.max_error + 1e-12 * diagonal) << name << " measured " << set.max_error;
}

//! The patch tessellator welds the patches into a surface with the base mesh's topology: closed where it is closed.
void expect_conforming(const std::string& name, const PolygonMesh& mesh, const LimitPatchSet& set) {
    TessellationOptions options;
    options.segments = 3;
    auto tessellation = tessellate_patches(set.patches, options);
    ASSERT_TRUE(tessellation.ok()) << name << ": " << tessellation.error().message;
    EXPECT_EQ(testing::is_watertight(tessellation->mesh), testing::is_watertight(mesh)) << name;
    EXPECT_EQ(testing::euler_characteristic(tessellation->mesh), testing::euler_characteristic(mesh)) << name;
}

TEST(LimitPatches, RegularTorusIsOneExactPatchPerFace) {
    const PolygonMesh mesh = shapes::torus(8, 6);
    const auto evaluator = make_evaluator(mesh);
    auto set = limit_patches(evaluator, mesh, LimitPatchOptions{});
    ASSERT_TRUE(set.ok()) << set.error().message;
    EXPECT_EQ(set->levels, 0);
    EXPECT_EQ(set->patches.size(), mesh.face_count());
    EXPECT_EQ(set->approximate_count, 0u);
    EXPECT_EQ(set->max_error, 0.0);
    expect_patches_match_limit("torus", mesh, evaluator, *set, 20);
    expect_conforming("torus", mesh, *set);
}

TEST(LimitPatches, ClosedShapesAreExactAwayFromIrregularVerticesAndWeldWatertight) {
    for (const std::string name :
         {"catmark_cube", "catmark_gregory_test1", "catmark_cube_creases0", "catmark_cube_corner1",
          "catmark_cubes_semisharp", "catmark_pyramid", "catmark_nonquads", "catmark_torus_creases0"}) {
        const PolygonMesh mesh = load_opensubdiv_shape(name);
        const auto evaluator = make_evaluator(mesh);
        LimitPatchOptions options;
        options.tolerance = 1e-3 * bounding_diagonal(mesh);
        auto set = limit_patches(evaluator, mesh, options);
        ASSERT_TRUE(set.ok()) << name << ": " << set.error().message;
        EXPECT_LE(set->max_error, options.tolerance) << name;
        EXPECT_EQ(set->patches.size(), limit_patch_count(mesh, set->levels)) << name;
        EXPECT_EQ(static_cast<std::size_t>(std::count(set->exact.begin(), set->exact.end(), false)),
                  set->approximate_count)
            << name;
        expect_patches_match_limit(name, mesh, evaluator, *set, 4);
        expect_conforming(name, mesh, *set);
    }
}

TEST(LimitPatches, ApproximationErrorShrinksWithTheLevel) {
    const PolygonMesh mesh = shapes::cube();  // eight valence-3 vertices
    const auto evaluator = make_evaluator(mesh);
    double previous = 0;
    for (int level = 1; level <= 4; ++level) {
        LimitPatchOptions options;
        options.levels = level;
        auto set = limit_patches(evaluator, mesh, options);
        ASSERT_TRUE(set.ok()) << set.error().message;
        EXPECT_EQ(set->levels, level);
        // one approximated square per face corner: the 24 corners of the cube's faces are all irregular
        EXPECT_EQ(set->approximate_count, 24u);
        EXPECT_GT(set->max_error, 0.0);
        if (level > 1) {
            EXPECT_LT(set->max_error, 0.5 * previous) << "level " << level;
        }
        previous = set->max_error;
    }
}

TEST(LimitPatches, ToleranceChoosesTheSmallestLevelThatReachesIt) {
    const PolygonMesh mesh = shapes::cube();
    const auto evaluator = make_evaluator(mesh);
    LimitPatchOptions fixed;
    fixed.levels = 2;
    auto at_two = limit_patches(evaluator, mesh, fixed);
    ASSERT_TRUE(at_two.ok());
    LimitPatchOptions by_tolerance;
    by_tolerance.tolerance = at_two->max_error * 1.0001;
    auto chosen = limit_patches(evaluator, mesh, by_tolerance);
    ASSERT_TRUE(chosen.ok());
    EXPECT_EQ(chosen->levels, 2);
    by_tolerance.tolerance = at_two->max_error * 0.9;
    chosen = limit_patches(evaluator, mesh, by_tolerance);
    ASSERT_TRUE(chosen.ok());
    EXPECT_EQ(chosen->levels, 3);
}

TEST(LimitPatches, HolesHaveNoPatches) {
    PolygonMesh mesh = shapes::grid(4, 4);
    mesh.tags.holes = {5, 10};
    const auto evaluator = make_evaluator(mesh);
    LimitPatchOptions options;
    options.levels = 1;
    auto set = limit_patches(evaluator, mesh, options);
    ASSERT_TRUE(set.ok()) << set.error().message;
    for (std::uint32_t face : set->faces) EXPECT_FALSE(evaluator.is_hole(face));
    EXPECT_EQ(set->patches.size(), limit_patch_count(mesh, 1) - 2 * 4);
    expect_patches_match_limit("grid with hole tags", mesh, evaluator, *set, 4);
}

TEST(LimitPatches, RefusesWhatItCannotDo) {
    const PolygonMesh ngons = shapes::mixed_polygons();
    const auto evaluator = make_evaluator(ngons);
    LimitPatchOptions options;
    options.levels = 0;  // N-gons need their sub-faces
    auto set = limit_patches(evaluator, ngons, options);
    ASSERT_FALSE(set.ok());
    EXPECT_EQ(set.error().code, ErrorCode::InvalidArgument);

    const PolygonMesh cube = shapes::cube();
    const auto cube_evaluator = make_evaluator(cube);
    LimitPatchOptions budget;
    budget.levels = 3;
    budget.max_patches = limit_patch_count(cube, 3) - 1;
    set = limit_patches(cube_evaluator, cube, budget);
    ASSERT_FALSE(set.ok());
    EXPECT_EQ(set.error().code, ErrorCode::BudgetExceeded);

    LimitPatchOptions unreachable;
    unreachable.tolerance = 1e-300;
    unreachable.max_levels = 2;
    set = limit_patches(cube_evaluator, cube, unreachable);
    ASSERT_FALSE(set.ok());
    EXPECT_EQ(set.error().code, ErrorCode::BudgetExceeded);

    const PolygonMesh triangles = shapes::octahedron();
    SubdivisionOptions loop;
    loop.scheme = SubdivisionScheme::Loop;
    auto loop_evaluator = LimitSurfaceEvaluator::create(triangles, loop);
    ASSERT_TRUE(loop_evaluator.ok());
    set = limit_patches(*loop_evaluator, triangles, LimitPatchOptions{});
    ASSERT_FALSE(set.ok());
    EXPECT_EQ(set.error().code, ErrorCode::Unsupported);

    LimitPatchOptions bad_tolerance;
    bad_tolerance.tolerance = -1;
    set = limit_patches(cube_evaluator, cube, bad_tolerance);
    ASSERT_FALSE(set.ok());
    EXPECT_EQ(set.error().code, ErrorCode::InvalidArgument);
}

}  // namespace
}  // namespace surfaced
