// Narrow-band signed distance grids (geometry/implicit/distance_grid.h): every node against brute force (the minimum
// distance over all triangles, the sign of the exact winding-number sum), on closed meshes, a mesh with a hole and
// overlapping shells; the field sampler against analytic distances; budgets and cancellation.
#include "geometry/implicit/distance_grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <vector>

#include "geometry/implicit/mesh_field.h"
#include "geometry/implicit/operators.h"
#include "geometry/implicit/primitives.h"
#include "geometry/mesh/shapes.h"
#include "geometry/spatial/bvh.h"
#include "geometry/spatial/closest_point.h"
#include "geometry/spatial/winding_number.h"
#include "tests/support/mesh_asserts.h"
#include "tests/support/simplify_meshes.h"
#include "tests/support/spatial_meshes.h"

namespace surfaced::implicit {
namespace {

Vec3 node_position(const LevelSetGrid& g, std::size_t i, std::size_t j, std::size_t k) {
    return {g.origin.x + static_cast<double>(i) * g.spacing.x, g.origin.y + static_cast<double>(j) * g.spacing.y,
            g.origin.z + static_cast<double>(k) * g.spacing.z};
}

struct Mismatches {
    std::size_t band_nodes = 0, far_nodes = 0, checked_signs = 0, wrong_signs = 0;
    double max_distance_error = 0;
};

//! Every node of `grid` against brute force on `mesh`: |value| = min(distance, band * h) to within 1e-12 relative,
//! the sign that of the exact winding number wherever it is at least `margin` from 1/2 and the node is not on the
//! surface.
Mismatches compare_with_brute_force(const PolygonMesh& mesh, const LevelSetGrid& grid, int band, double margin) {
    const auto bvh = build_bvh(mesh).value();
    const WindingTree tree = build_winding_tree(bvh);
    WindingNumberOptions exact;
    exact.exact = true;
    const double h = grid.spacing.x, limit = band * h;
    Mismatches out;
    for (std::size_t k = 0; k < grid.dims[2]; ++k)
        for (std::size_t j = 0; j < grid.dims[1]; ++j)
            for (std::size_t i = 0; i < grid.dims[0]; ++i) {
                const Vec3 p = node_position(grid, i, j, k);
                double best = INFINITY;
                for (const BvhTriangle& t : bvh.triangles)
                    best = std::min(best, norm(triangle_closest_point(p, t.p[0], t.p[1], t.p[2]).point - p));
                const double value = grid.values[i + grid.dims[0] * (j + grid.dims[1] * k)];
                const double expected = std::min(best, limit);
                (best <= limit ? out.band_nodes : out.far_nodes) += 1;
                out.max_distance_error = std::max(out.max_distance_error, std::abs(std::abs(value) - expected));
                const double w = winding_number(bvh, tree, p, exact).value().value;
                if (std::abs(w - 0.5) < margin || best < 1e-9) continue;
                ++out.checked_signs;
                if ((value < 0) != (w >= 0.5)) ++out.wrong_signs;
            }
    return out;
}

TEST(DistanceGrid, TorusMatchesBruteForceAtEveryNode) {
    const PolygonMesh torus = shapes::torus(24, 12, 1.0, 0.35);
    DistanceGridOptions options;
    options.voxel_size = 0.1;
    options.band = 2;
    DistanceGridStats stats;
    const auto grid = mesh_distance_grid(torus, options, &stats);
    ASSERT_TRUE(grid.ok()) << grid.error().message;
    // default bounds: the mesh's box grown by band + 1 voxels
    EXPECT_NEAR(grid->origin.x, torus.bounds().min.x - 0.3, 1e-12);
    EXPECT_EQ(stats.layout.nodes, grid->values.size());
    EXPECT_TRUE(stats.closed);
    EXPECT_GE(stats.components, 2u);
    const Mismatches m = compare_with_brute_force(torus, grid.value(), options.band, 0.01);
    EXPECT_GT(m.band_nodes, 1000u);
    EXPECT_GT(m.far_nodes, 1000u);
    EXPECT_EQ(m.band_nodes, stats.band_nodes);
    EXPECT_LT(m.max_distance_error, 1e-12);
    EXPECT_GT(m.checked_signs, 0.9 * static_cast<double>(grid->values.size()));
    EXPECT_EQ(m.wrong_signs, 0u);
}

TEST(DistanceGrid, IcosphereWithOffsetBoundsMatchesBruteForce) {
    // bounds that are not a multiple of h from the mesh, cutting the sphere: nodes on both sides of the boundary
    const PolygonMesh sphere = testing::icosphere(2, 1.0);
    DistanceGridOptions options;
    options.voxel_size = 0.13;
    options.band = 3;
    options.bounds = Box3{{-0.71, -1.37, -0.2}, {1.43, 1.21, 1.05}};
    DistanceGridStats stats;
    const auto grid = mesh_distance_grid(sphere, options, &stats);
    ASSERT_TRUE(grid.ok()) << grid.error().message;
    EXPECT_EQ(grid->origin, options.bounds->min);
    EXPECT_GE(grid->origin.x + static_cast<double>(grid->dims[0] - 1) * 0.13, 1.43);
    const Mismatches m = compare_with_brute_force(sphere, grid.value(), options.band, 0.01);
    EXPECT_LT(m.max_distance_error, 1e-12);
    EXPECT_EQ(m.wrong_signs, 0u);
}

TEST(DistanceGrid, OverlappingShellsAreClosedAndSignedByWindingNumber) {
    // two intersecting spheres in one mesh: closed (every edge matched), winding number 2 where they overlap
    const PolygonMesh a = testing::icosphere(2, 1.0);
    const PolygonMesh both = testing::concatenate(a, testing::translated(a, {0.8, 0.3, 0}));
    DistanceGridOptions options;
    options.voxel_size = 0.12;
    options.band = 2;
    DistanceGridStats stats;
    const auto grid = mesh_distance_grid(both, options, &stats);
    ASSERT_TRUE(grid.ok()) << grid.error().message;
    EXPECT_TRUE(stats.closed);
    const Mismatches m = compare_with_brute_force(both, grid.value(), options.band, 0.01);
    EXPECT_LT(m.max_distance_error, 1e-12);
    EXPECT_EQ(m.wrong_signs, 0u);
}

TEST(DistanceGrid, MeshWithHolesSignedByWindingNumber) {
    // a sphere without a cap wider than the band: the inside connects to the outside through the hole, beyond the
    // band too, where the runs along x carry the winding number's sign
    const PolygonMesh open =
        testing::without_faces(testing::icosphere(3, 1.0), [](const Vec3& c) { return c.z > 0.8; });
    DistanceGridOptions options;
    options.voxel_size = 0.1;
    options.band = 2;
    DistanceGridStats stats;
    const auto grid = mesh_distance_grid(open, options, &stats);
    ASSERT_TRUE(grid.ok()) << grid.error().message;
    EXPECT_FALSE(stats.closed);
    const Mismatches m = compare_with_brute_force(open, grid.value(), options.band, 0.05);
    EXPECT_LT(m.max_distance_error, 1e-12);
    EXPECT_GT(m.checked_signs, 0.8 * static_cast<double>(grid->values.size()));
    EXPECT_EQ(m.wrong_signs, 0u);
    // the centre, beyond the band, is inside
    const std::size_t c = grid->dims[0] / 2 + grid->dims[0] * (grid->dims[1] / 2 + grid->dims[1] * (grid->dims[2] / 2));
    EXPECT_LT(grid->values[c], 0);
}

TEST(DistanceGrid, OpenMeshSignsCarriedBetweenRowsByTheGradientBound) {
    // two holes and a grid fine enough that most nodes are signed from their neighbours in the rows before, through
    // the bound on how fast w can change (|grad w| from the boundary edges alone): fewer queries than runs, and
    // every node still against the exact winding number
    const PolygonMesh open = testing::without_faces(
        testing::icosphere(3, 1.0), [](const Vec3& c) { return c.z > 0.95 || (c.x > 0.93 && std::abs(c.y) < 0.3); });
    DistanceGridOptions options;
    options.voxel_size = 0.07;
    options.band = 2;
    DistanceGridStats stats;
    const auto grid = mesh_distance_grid(open, options, &stats);
    ASSERT_TRUE(grid.ok()) << grid.error().message;
    EXPECT_FALSE(stats.closed);
    EXPECT_LT(stats.winding_queries, stats.components);
    const Mismatches m = compare_with_brute_force(open, grid.value(), options.band, 0.05);
    EXPECT_LT(m.max_distance_error, 1e-12);
    EXPECT_GT(m.checked_signs, 0.8 * static_cast<double>(grid->values.size()));
    EXPECT_EQ(m.wrong_signs, 0u);
}

TEST(DistanceGrid, TorusWithHolesAndAFlippedFaceSignedByWindingNumber) {
    // holes on the outer rim and a face turned around: open, the runs between crossings carry the signs
    PolygonMesh open = testing::without_faces(shapes::torus(24, 12, 1.0, 0.35),
                                              [](const Vec3& c) { return c.x > 1.2 && std::abs(c.y) < 0.3; });
    std::vector<Index> face(open.face(3).begin(), open.face(3).end());
    std::reverse(face.begin(), face.end());
    PolygonMesh flipped;
    flipped.positions = open.positions;
    for (std::size_t f = 0; f < open.face_count(); ++f) {
        if (f == 3)
            flipped.add_face(face);
        else
            flipped.add_face(open.face(f));
    }
    DistanceGridOptions options;
    options.voxel_size = 0.07;
    options.band = 2;
    DistanceGridStats stats;
    const auto grid = mesh_distance_grid(flipped, options, &stats);
    ASSERT_TRUE(grid.ok()) << grid.error().message;
    EXPECT_FALSE(stats.closed);
    EXPECT_LT(stats.winding_queries, grid->values.size() / 2);
    const Mismatches m = compare_with_brute_force(flipped, grid.value(), options.band, 0.05);
    EXPECT_LT(m.max_distance_error, 1e-12);
    EXPECT_GT(m.checked_signs, 0.8 * static_cast<double>(grid->values.size()));
    EXPECT_EQ(m.wrong_signs, 0u);
}

TEST(DistanceGrid, SphereRoundTripsThroughTheLevelSetField) {
    // the grid as a level_set field, meshed: the volume of the original mesh to within 1%
    const PolygonMesh sphere = testing::icosphere(4, 1.0);
    DistanceGridOptions options;
    options.voxel_size = 0.04;
    options.band = 3;
    auto grid = mesh_distance_grid(sphere, options);
    ASSERT_TRUE(grid.ok()) << grid.error().message;
    const Box3 box{grid->origin, grid->origin + Vec3{static_cast<double>(grid->dims[0] - 1) * 0.04,
                                                     static_cast<double>(grid->dims[1] - 1) * 0.04,
                                                     static_cast<double>(grid->dims[2] - 1) * 0.04}};
    auto field = level_set(std::move(grid.value()));
    ASSERT_TRUE(field.ok());
    MeshFieldOptions mesh_options;
    mesh_options.cell_size = 0.04;
    const auto meshed = mesh_field(*field.value(), box, mesh_options);
    ASSERT_TRUE(meshed.ok()) << meshed.error().message;
    const double expected = testing::signed_volume(sphere);
    EXPECT_NEAR(testing::signed_volume(meshed.value()), expected, 0.01 * expected);
}

TEST(DistanceGrid, FieldIsSampledAndClampedWithLipschitzSkips) {
    const FieldPtr f = translate(sphere(0.8), {0.1, 0, 0});
    DistanceGridOptions options;
    options.voxel_size = 0.05;
    options.band = 3;
    options.bounds = Box3{{-1.5, -1.2, -1.1}, {1.5, 1.2, 1.1}};
    DistanceGridStats stats;
    const auto grid = field_distance_grid(*f, options, &stats);
    ASSERT_TRUE(grid.ok()) << grid.error().message;
    const double limit = options.band * options.voxel_size;
    std::size_t band = 0;
    for (std::size_t k = 0; k < grid->dims[2]; ++k)
        for (std::size_t j = 0; j < grid->dims[1]; ++j)
            for (std::size_t i = 0; i < grid->dims[0]; ++i) {
                const double exact = f->value(node_position(grid.value(), i, j, k));
                const double value = grid->values[i + grid->dims[0] * (j + grid->dims[1] * k)];
                ASSERT_EQ(value, std::clamp(exact, -limit, limit)) << i << " " << j << " " << k;
                band += std::abs(exact) < limit;
            }
    EXPECT_EQ(stats.band_nodes, band);
    // an exact distance lets most nodes beyond the band be skipped
    EXPECT_LT(stats.field_evaluations, grid->values.size() / 2);
    EXPECT_GE(stats.field_evaluations, band);
}

TEST(DistanceGrid, BudgetsAndInvalidOptions) {
    const PolygonMesh cube = shapes::cube();
    DistanceGridOptions options;
    options.voxel_size = 0.01;
    options.max_nodes = 1000;
    auto grid = mesh_distance_grid(cube, options);
    ASSERT_FALSE(grid.ok());
    EXPECT_EQ(grid.error().code, ErrorCode::BudgetExceeded);
    // the layout alone says the same before any work, and huge counts do not overflow
    auto layout = distance_grid_layout(Box3{{0, 0, 0}, {1e300, 1e300, 1e300}}, 1e-300, 1'000'000);
    ASSERT_FALSE(layout.ok());
    EXPECT_EQ(layout.error().code, ErrorCode::BudgetExceeded);
    options.max_nodes = 1'000'000;
    options.voxel_size = 0;
    EXPECT_EQ(mesh_distance_grid(cube, options).error().code, ErrorCode::InvalidArgument);
    options.voxel_size = 0.1;
    options.band = 0;
    EXPECT_EQ(mesh_distance_grid(cube, options).error().code, ErrorCode::InvalidArgument);
    options.band = 3;
    EXPECT_EQ(mesh_distance_grid(PolygonMesh{}, options).error().code, ErrorCode::InvalidArgument);
    EXPECT_EQ(field_distance_grid(*sphere(1), options).error().code, ErrorCode::InvalidArgument);  // no bounds
    // a flat box: two nodes along the flat axis
    layout = distance_grid_layout(Box3{{0, 0, 0}, {1, 1, 0}}, 0.25, 1000);
    ASSERT_TRUE(layout.ok());
    EXPECT_EQ(layout->dims[0], 5u);
    EXPECT_EQ(layout->dims[2], 2u);
}

TEST(DistanceGrid, CancelStopsTheWork) {
    std::atomic<bool> abort{true};
    DistanceGridOptions options;
    options.voxel_size = 0.05;
    options.cancel.flag = &abort;
    EXPECT_EQ(mesh_distance_grid(shapes::cube(), options).error().code, ErrorCode::Cancelled);
    options.bounds = Box3{{-1, -1, -1}, {1, 1, 1}};
    EXPECT_EQ(field_distance_grid(*sphere(1), options).error().code, ErrorCode::Cancelled);
}

}  // namespace
}  // namespace surfaced::implicit
