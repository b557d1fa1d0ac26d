// Closest points through the hierarchy against brute force over every triangle (with the simplifier's independent
// point-triangle routine), on a sphere, the scanned bunny and a random triangle soup; the triangle routine against
// plane projection and edge distances, and its barycentric coordinates against the point they describe, degenerate
// triangles included.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>

#include "geometry/mesh/shapes.h"
#include "geometry/simplify/mesh_distance.h"
#include "geometry/spatial/closest_point.h"
#include "tests/support/spatial_meshes.h"

namespace surfaced {
namespace {

Vec3 from_barycentric(const std::array<double, 3>& b, const Vec3& p0, const Vec3& p1, const Vec3& p2) {
    return p0 * b[0] + p1 * b[1] + p2 * b[2];
}

//! Brute force: the smallest distance over every triangle of the (triangle) mesh.
double brute_force_distance(const PolygonMesh& mesh, const Vec3& q) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const auto t = mesh.face(f);
        best = std::min(best,
                        point_triangle_distance(q, mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]));
    }
    return best;
}

void expect_matches_brute_force(const PolygonMesh& mesh, int queries, double margin, std::uint64_t seed) {
    auto bvh = build_bvh(mesh);
    ASSERT_TRUE(bvh.ok()) << bvh.error().message;
    std::mt19937_64 rng(seed);
    const Box3 box = mesh.bounds();
    const double scale = box.diagonal();
    for (int i = 0; i < queries; ++i) {
        const Vec3 q = testing::random_point(rng, box, margin);
        const auto hit = closest_point(*bvh, q);
        ASSERT_TRUE(hit.has_value());
        const double expected = brute_force_distance(mesh, q);
        EXPECT_NEAR(hit->distance, expected, 1e-12 * scale) << "query " << i;
        EXPECT_NEAR(norm(hit->point - q), hit->distance, 1e-12 * scale);
        // the reported face and barycentrics describe the reported point
        const auto tri = mesh.face(hit->face);
        for (int c = 0; c < 3; ++c) EXPECT_EQ(hit->vertices[c], tri[c]);
        const Vec3 rebuilt =
            from_barycentric(hit->barycentric, mesh.positions[tri[0]], mesh.positions[tri[1]], mesh.positions[tri[2]]);
        EXPECT_LT(norm(rebuilt - hit->point), 1e-12 * scale);
        for (double b : hit->barycentric) EXPECT_GE(b, -1e-12);
        EXPECT_NEAR(hit->barycentric[0] + hit->barycentric[1] + hit->barycentric[2], 1.0, 1e-12);
    }
}

//! Independent reference: the projection onto the plane when it falls inside the triangle, else the nearest point of
//! the three edges (all a degenerate triangle has).
double reference_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    auto segment = [&](const Vec3& u, const Vec3& v) {
        const Vec3 e = v - u;
        const double len2 = dot(e, e);
        const double t = len2 > 0 ? std::clamp(dot(p - u, e) / len2, 0.0, 1.0) : 0.0;
        return norm(u + e * t - p);
    };
    double best = std::min({segment(a, b), segment(b, c), segment(c, a)});
    const Vec3 n = cross(b - a, c - a);
    const double n2 = dot(n, n);
    if (n2 > 1e-20) {
        const Vec3 q = p - n * (dot(p - a, n) / n2);
        if (dot(cross(b - a, q - a), n) >= 0 && dot(cross(c - b, q - b), n) >= 0 && dot(cross(a - c, q - c), n) >= 0)
            best = std::min(best, norm(q - p));
    }
    return best;
}

TEST(ClosestPoint, TriangleRoutineMatchesIndependentOne) {
    std::mt19937_64 rng(7);
    const Box3 unit{{0, 0, 0}, {1, 1, 1}};
    for (int i = 0; i < 20000; ++i) {
        Vec3 a = testing::random_point(rng, unit, 0), b = testing::random_point(rng, unit, 0),
             c = testing::random_point(rng, unit, 0);
        // three in eight triangles degenerate: a repeated corner, three collinear points, or a single point
        if (i % 8 == 1) b = a;
        if (i % 8 == 3) c = a + (b - a) * 0.25;
        if (i % 8 == 5) b = c = a;
        const Vec3 p = testing::random_point(rng, unit, 0.5);
        const TrianglePoint tp = triangle_closest_point(p, a, b, c);
        EXPECT_NEAR(norm(tp.point - p), reference_distance(p, a, b, c), 1e-12) << "triangle " << i;
        if (i % 8 == 0) {  // a second, independent implementation (the simplifier's) on proper triangles
            EXPECT_NEAR(norm(tp.point - p), norm(closest_point_on_triangle(p, a, b, c) - p), 1e-12);
        }
        EXPECT_LT(norm(from_barycentric(tp.barycentric, a, b, c) - tp.point), 1e-12) << "triangle " << i;
        EXPECT_NEAR(tp.barycentric[0] + tp.barycentric[1] + tp.barycentric[2], 1.0, 1e-12);
        for (double w : tp.barycentric) EXPECT_GE(w, -1e-12);
    }
}

TEST(ClosestPoint, MatchesBruteForceOnSphere) { expect_matches_brute_force(testing::icosphere(4), 500, 0.3, 1); }

TEST(ClosestPoint, MatchesBruteForceOnBunny) {
    const PolygonMesh& bunny = testing::spatial_bunny();
    ASSERT_GT(bunny.face_count(), 0u);
    expect_matches_brute_force(bunny, 50, 0.2, 2);
}

TEST(ClosestPoint, MatchesBruteForceOnTriangleSoup) {
    // overlapping, intersecting, long thin triangles: what SAH and pruning must not get wrong
    std::mt19937_64 rng(3);
    PolygonMesh soup;
    const Box3 box{{-1, -1, -1}, {1, 1, 1}};
    for (int i = 0; i < 3000; ++i) {
        const Vec3 centre = testing::random_point(rng, box, 0);
        const auto base = static_cast<Index>(soup.positions.size());
        const double size = (i % 10 == 0) ? 1.0 : 0.05;
        for (int k = 0; k < 3; ++k) soup.positions.push_back(centre + testing::random_unit(rng) * size);
        soup.add_face({base, base + 1, base + 2});
    }
    expect_matches_brute_force(soup, 500, 0.5, 4);
}

TEST(ClosestPoint, PolygonFacesAndMaxDistance) {
    const PolygonMesh cube = shapes::cube();  // [-0.5, 0.5]^3, quads
    auto bvh = build_bvh(cube);
    ASSERT_TRUE(bvh.ok());
    // above the centre of the top face (z = 0.5)
    const auto top = closest_point(*bvh, {0.1, -0.2, 2.0});
    ASSERT_TRUE(top.has_value());
    EXPECT_NEAR(top->distance, 1.5, 1e-15);
    EXPECT_NEAR(top->point.z, 0.5, 1e-15);
    const auto quad = cube.face(top->face);
    for (Index v : quad) EXPECT_EQ(cube.positions[v].z, 0.5);

    ClosestPointOptions near;
    near.max_distance = 1.0;
    EXPECT_FALSE(closest_point(*bvh, {0.1, -0.2, 2.0}, near).has_value());
    near.max_distance = 1.6;
    const auto within = closest_point(*bvh, {0.1, -0.2, 2.0}, near);
    ASSERT_TRUE(within.has_value());
    EXPECT_EQ(within->distance, top->distance);

    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_FALSE(closest_point(*bvh, {nan, 0, 0}).has_value());
    auto empty = build_bvh(PolygonMesh{});
    ASSERT_TRUE(empty.ok());
    EXPECT_FALSE(closest_point(*empty, {0, 0, 0}).has_value());
}

}  // namespace
}  // namespace surfaced
