// Point-to-triangle distance against analytic cases, the AABB tree against brute force, and mesh-to-mesh distances
// with known answers (identity, symmetry, offset planes, concentric spheres).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>

#include "geometry/mesh/shapes.h"
#include "geometry/simplify/mesh_distance.h"
#include "tests/support/simplify_meshes.h"

namespace surfaced {
namespace {

const Vec3 kA{0, 0, 0}, kB{2, 0, 0}, kC{0, 2, 0};

TEST(PointTriangleDistance, AnalyticRegions) {
    // inside the face: the height above the plane
    EXPECT_DOUBLE_EQ(point_triangle_distance({0.5, 0.5, 3}, kA, kB, kC), 3);
    EXPECT_DOUBLE_EQ(point_triangle_distance({0.5, 0.5, -2}, kA, kB, kC), 2);
    // vertex regions
    EXPECT_DOUBLE_EQ(point_triangle_distance({-3, -4, 0}, kA, kB, kC), 5);
    EXPECT_DOUBLE_EQ(point_triangle_distance({5, 0, 4}, kA, kB, kC), 5);
    EXPECT_DOUBLE_EQ(point_triangle_distance({0, 6, 0}, kA, kB, kC), 4);
    // edge regions: below edge AB, left of AC, beyond the hypotenuse BC
    EXPECT_DOUBLE_EQ(point_triangle_distance({1, -3, 4}, kA, kB, kC), 5);
    EXPECT_DOUBLE_EQ(point_triangle_distance({-1, 1, 0}, kA, kB, kC), 1);
    EXPECT_NEAR(point_triangle_distance({2, 2, 0}, kA, kB, kC), std::sqrt(2.0), 1e-15);
    // on the triangle
    EXPECT_DOUBLE_EQ(point_triangle_distance({1, 1, 0}, kA, kB, kC), 0);
    EXPECT_DOUBLE_EQ(point_triangle_distance(kB, kA, kB, kC), 0);
}

TEST(PointTriangleDistance, DegenerateTriangles) {
    // a segment (collinear corners) and a point
    EXPECT_NEAR(point_triangle_distance({1, 1, 0}, {0, 0, 0}, {1, 0, 0}, {2, 0, 0}), 1, 1e-15);
    EXPECT_NEAR(point_triangle_distance({3, 0, 0}, {0, 0, 0}, {1, 0, 0}, {2, 0, 0}), 1, 1e-15);
    EXPECT_NEAR(point_triangle_distance({0, 3, 4}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}), 5, 1e-15);
    // two corners at one position: a segment from them to the third, whichever two they are; the point lies 1 above
    // the segment's middle, so the answer is 1 (not the distance to the repeated corner, sqrt(2))
    const Vec3 o{0, 0, 0}, e{2, 0, 0}, p{1, 1, 0};
    for (const auto& [a, b, c] : {std::array{o, o, e}, std::array{o, e, o}, std::array{e, o, o}, std::array{e, e, o},
                                  std::array{e, o, e}, std::array{o, e, e}})
        EXPECT_NEAR(point_triangle_distance(p, a, b, c), 1, 1e-15) << a.x << b.x << c.x;
}

TEST(SurfaceDistance, MatchesBruteForce) {
    const PolygonMesh sphere = testing::icosphere(3);
    const SurfaceDistance tree(sphere);
    std::uint64_t state = 12345;
    auto next = [&] {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return static_cast<double>(state >> 11) * 0x1.0p-53 * 4 - 2;
    };
    for (int i = 0; i < 500; ++i) {
        const Vec3 p{next(), next(), next()};
        double brute = std::numeric_limits<double>::infinity();
        for (std::size_t f = 0; f < sphere.face_count(); ++f) {
            auto t = sphere.face(f);
            brute = std::min(brute, point_triangle_distance(p, sphere.positions[t[0]], sphere.positions[t[1]],
                                                            sphere.positions[t[2]]));
        }
        EXPECT_DOUBLE_EQ(tree.distance(p), brute);
    }
}

TEST(SurfaceDistance, EmptyMeshIsInfinitelyFar) {
    const SurfaceDistance tree(PolygonMesh{});
    EXPECT_TRUE(std::isinf(tree.distance({0, 0, 0})));
}

TEST(MeshDistance, MeshToItselfIsZero) {
    const PolygonMesh torus = shapes::torus(24, 12);
    const MeshDistance d = mesh_distance(torus, torus);
    // vertices are exactly 0; samples inside faces only up to rounding of the closest-point computation
    EXPECT_LT(d.hausdorff, 1e-12);
    EXPECT_LT(d.rms, 1e-12);
    EXPECT_EQ(d.forward_samples, torus.vertex_count() + MeshDistanceOptions{}.samples);
}

TEST(MeshDistance, IsSymmetricAndDeterministic) {
    const PolygonMesh fine = testing::icosphere(4);
    const PolygonMesh coarse = testing::icosphere(1);
    const MeshDistance ab = mesh_distance(fine, coarse);
    const MeshDistance ba = mesh_distance(coarse, fine);
    // the same sample streams run the other way round: directions swap exactly
    EXPECT_EQ(ab.hausdorff, ba.hausdorff);
    EXPECT_EQ(ab.forward_max, ba.backward_max);
    EXPECT_EQ(ab.backward_max, ba.forward_max);
    EXPECT_EQ(ab.rms, ba.rms);
    const MeshDistance again = mesh_distance(fine, coarse);
    EXPECT_EQ(ab.hausdorff, again.hausdorff);
    EXPECT_EQ(ab.rms, again.rms);
    // the coarse chords are inside the sphere; its farthest point is a face centre, 1 - inradius away
    EXPECT_GT(ab.hausdorff, 0.05);
    EXPECT_LT(ab.hausdorff, 0.1);
}

TEST(MeshDistance, ParallelPlanesAreTheirOffsetApart) {
    const PolygonMesh a = shapes::grid(8, 8, true);
    PolygonMesh b = shapes::grid(3, 5, true);
    for (Vec3& p : b.positions) p.z = 0.25;
    const MeshDistance d = mesh_distance(a, b);
    EXPECT_NEAR(d.hausdorff, 0.25, 1e-12);
    EXPECT_NEAR(d.rms, 0.25, 1e-12);
    EXPECT_NEAR(d.forward_rms, 0.25, 1e-12);
}

TEST(MeshDistance, ConcentricSpheresAreTheRadiusDifferenceApart) {
    const PolygonMesh inner = testing::icosphere(3, 1.0);
    const PolygonMesh outer = testing::icosphere(3, 1.5);
    const MeshDistance d = mesh_distance(inner, outer);
    // vertices sit on the true spheres; face interiors are slightly inside: within the chord sagitta of 0.5
    EXPECT_GT(d.hausdorff, 0.5 - 1e-9);
    EXPECT_LT(d.hausdorff, 0.5 + 0.02);
    EXPECT_NEAR(d.rms, 0.5, 0.02);
}

TEST(MeshDistance, VerticesOnlyWhenNoSamples) {
    const PolygonMesh a = testing::icosphere(2);
    MeshDistanceOptions options;
    options.samples = 0;
    const MeshDistance d = mesh_distance(a, a, options);
    EXPECT_EQ(d.forward_samples, a.vertex_count());
    EXPECT_EQ(d.hausdorff, 0);
}

}  // namespace
}  // namespace surfaced
