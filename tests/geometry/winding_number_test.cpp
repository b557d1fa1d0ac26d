// Winding numbers and signed distance: the hierarchical value within its error bound of the exact sum; the exact
// solid angle of known triangles; inside/outside right on closed meshes (the analytic sphere, the bunny), on a sphere
// with a hole and on two overlapping spheres, where ray parity is wrong for some points (both counted); signed
// distance against brute-force distance and the analytic sphere.
#include <gtest/gtest.h>

#include <cstdio>
#include <map>
#include <numbers>
#include <random>

#include "geometry/mesh/shapes.h"
#include "geometry/spatial/ray_cast.h"
#include "geometry/spatial/signed_distance.h"
#include "tests/support/spatial_meshes.h"

namespace surfaced {
namespace {

struct Solid {
    TriangleBvh bvh;
    WindingTree tree;
};

Solid solid(const PolygonMesh& mesh) {
    auto bvh = build_bvh(mesh);
    EXPECT_TRUE(bvh.ok());
    Solid s{std::move(bvh.value()), {}};
    s.tree = build_winding_tree(s.bvh);
    return s;
}

double fast(const Solid& s, const Vec3& q, double accuracy = 2.0) {
    WindingNumberOptions options;
    options.accuracy = accuracy;
    return winding_number(s.bvh, s.tree, q, options)->value;
}

double exact(const Solid& s, const Vec3& q) {
    WindingNumberOptions options;
    options.exact = true;
    return winding_number(s.bvh, s.tree, q, options)->value;
}

//! Inside by ray parity: odd number of crossings along a fixed generic direction.
bool parity_inside(const Solid& s, const Vec3& q) {
    return ray_all_hits(s.bvh, {q, {0.5773, 0.5774, 0.5775}}).size() % 2 == 1;
}

TEST(WindingNumber, SolidAngleOfKnownTriangles) {
    // the octant triangle seen from the origin: an eighth of the sphere, positive from behind
    const Vec3 o{0, 0, 0};
    EXPECT_NEAR(triangle_solid_angle(o, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}), std::numbers::pi / 2, 1e-14);
    EXPECT_NEAR(triangle_solid_angle(o, {1, 0, 0}, {0, 0, 1}, {0, 1, 0}), -std::numbers::pi / 2, 1e-14);
    // in the triangle's plane, outside it: nothing
    EXPECT_NEAR(triangle_solid_angle({5, 5, 0}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}), 0.0, 1e-15);
    // a closed tetrahedron: 4 pi inside, 0 outside
    const PolygonMesh tet = shapes::tetrahedron();
    Vec3 centre;
    for (const Vec3& p : tet.positions) centre += p * 0.25;
    const Solid s = solid(tet);
    EXPECT_NEAR(exact(s, centre), 1.0, 1e-14);
    EXPECT_NEAR(exact(s, centre + Vec3{10, 3, 1}), 0.0, 1e-14);
}

TEST(WindingNumber, HierarchicalWithinItsBoundOfExactSum) {
    const PolygonMesh& bunny = testing::spatial_bunny();
    ASSERT_GT(bunny.face_count(), 0u);
    const Solid s = solid(bunny);
    std::mt19937_64 rng(1);
    const Box3 box = bunny.bounds();
    for (double accuracy : {1.5, 2.0, 3.0}) {
        double worst = 0, worst_bound = 0;
        for (int i = 0; i < 20; ++i) {
            const Vec3 q = testing::random_point(rng, box, 0.1);
            WindingNumberOptions options;
            options.accuracy = accuracy;
            const auto w = winding_number(s.bvh, s.tree, q, options);
            ASSERT_TRUE(w.ok());
            // the value alone is the same sum, bit for bit
            const auto value = winding_number_value(s.bvh, s.tree, q, options);
            ASSERT_TRUE(value.ok());
            EXPECT_EQ(*value, w->value);
            const double reference = exact(s, q);
            // the bound is exact-arithmetic; rounding over 70k terms adds far less than 1e-9
            EXPECT_LE(std::fabs(w->value - reference), w->error_bound + 1e-9)
                << "accuracy " << accuracy << " query " << i;
            worst = std::max(worst, std::fabs(w->value - reference));
            worst_bound = std::max(worst_bound, w->error_bound);
        }
        std::printf("bunny, accuracy %.1f: largest error %.2e, largest bound %.2e\n", accuracy, worst, worst_bound);
        // observed: about 7e-3, 3e-3 and 5e-4 for 1.5, 2 and 3
        EXPECT_LT(worst, accuracy >= 3.0 ? 1e-3 : 1e-2);
    }
}

TEST(WindingNumber, ExpansionErrorFallsAsFifthPowerOfDistance) {
    // A small random soup seen from afar is replaced by its expansion at the root. With the second-order term the
    // remaining error falls like d^-5: doubling d divides it by about 32 (a first-order expansion gives 16).
    std::mt19937_64 rng(6);
    PolygonMesh soup;
    for (int i = 0; i < 60; ++i) {
        const auto base = static_cast<Index>(soup.positions.size());
        const Vec3 c = testing::random_unit(rng) * 0.07;
        for (int k = 0; k < 3; ++k) soup.positions.push_back(c + testing::random_unit(rng) * 0.03);
        soup.add_face({base, base + 1, base + 2});
    }
    const Solid s = solid(soup);
    const Vec3 dir = testing::random_unit(rng);
    std::vector<double> errors;
    for (double d : {1.0, 2.0, 4.0}) {
        const Vec3 q = dir * d;
        WindingNumberOptions options;
        options.accuracy = 1.5;
        const auto w = winding_number(s.bvh, s.tree, q, options);
        ASSERT_TRUE(w.ok());
        EXPECT_GT(w->error_bound, 0.0);  // the root was expanded
        const double error = std::fabs(w->value - exact(s, q));
        EXPECT_LE(error, w->error_bound);
        errors.push_back(error);
    }
    EXPECT_LT(errors[1], errors[0] / 24);
    EXPECT_LT(errors[2], errors[1] / 24);
}

TEST(WindingNumber, InsideOutsideOfSphere) {
    const PolygonMesh sphere = testing::icosphere(4);  // inscribed in the unit sphere, within 0.002 of it
    const Solid s = solid(sphere);
    std::mt19937_64 rng(2);
    for (int i = 0; i < 400; ++i) {
        const Vec3 dir = testing::random_unit(rng);
        const double r = std::uniform_real_distribution<double>(0.0, 3.0)(rng);
        if (std::fabs(r - 1.0) < 0.01) continue;
        const Vec3 q = dir * r;
        const double expected = r < 1.0 ? 1.0 : 0.0;
        EXPECT_NEAR(exact(s, q), expected, 1e-10);
        EXPECT_NEAR(fast(s, q), expected, 0.01);  // accuracy 2 (the default)
        EXPECT_NEAR(fast(s, q, 3.0), expected, 1e-3);
        const auto sd = signed_distance(s.bvh, s.tree, q);
        ASSERT_TRUE(sd.ok());
        EXPECT_NEAR(sd->distance, r - 1.0, 0.0025) << "r " << r;
        EXPECT_EQ(sd->distance < 0, r < 1.0);
        EXPECT_EQ(std::fabs(sd->distance), sd->closest.distance);
    }
}

TEST(WindingNumber, InsideOutsideOfBunny) {
    // Points just in front of and behind the middle of faces that are away from the scan's holes: the bunny is
    // closed there, so outside (w ~ 0) and inside (w ~ 1) are known. Offsets are small against the ears' thickness.
    const PolygonMesh& bunny = testing::spatial_bunny();
    ASSERT_GT(bunny.face_count(), 0u);
    const Solid s = solid(bunny);
    const double eps = 1e-4 * bunny.bounds().diagonal();
    // boundary vertices: faces touching them are skipped (their neighbourhood is not closed)
    std::map<std::pair<Index, Index>, int> edge_count;
    for (std::size_t f = 0; f < bunny.face_count(); ++f) {
        const auto t = bunny.face(f);
        for (int k = 0; k < 3; ++k) edge_count[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}]++;
    }
    std::vector<char> near_hole(bunny.vertex_count(), 0);
    for (const auto& [edge, n] : edge_count)
        if (n == 1) near_hole[edge.first] = near_hole[edge.second] = 1;
    std::size_t checked = 0, wrong = 0, parity_wrong = 0;
    for (std::size_t f = 0; f < bunny.face_count(); f += 97) {
        const auto t = bunny.face(f);
        if (near_hole[t[0]] || near_hole[t[1]] || near_hole[t[2]]) continue;
        const Vec3 a = bunny.positions[t[0]], b = bunny.positions[t[1]], c = bunny.positions[t[2]];
        const Vec3 n = cross(b - a, c - a);
        const Vec3 centre = (a + b + c) * (1.0 / 3.0);
        const Vec3 unit = n * (1.0 / norm(n));
        for (const bool inside : {false, true}) {
            const Vec3 q = centre + unit * (inside ? -eps : eps);
            ++checked;
            if ((fast(s, q) >= 0.5) != inside) ++wrong;
            if (parity_inside(s, q) != inside) ++parity_wrong;
        }
    }
    std::printf("bunny: %zu points, winding number wrong %zu, ray parity wrong %zu\n", checked, wrong, parity_wrong);
    EXPECT_GT(checked, 1000u);
    EXPECT_EQ(wrong, 0u);
}

TEST(WindingNumber, RightWhereRayParityIsWrong) {
    std::mt19937_64 rng(3);
    // a sphere with a cap cut away where the parity rays leave it, and two overlapping spheres in one mesh (not
    // merged)
    const Vec3 axis = Vec3{1, 1, 1} * (1 / std::sqrt(3.0));
    const PolygonMesh holed =
        testing::without_faces(testing::icosphere(3), [&](const Vec3& c) { return dot(c, axis) > 0.8; });
    const PolygonMesh both = testing::concatenate(testing::translated(testing::icosphere(3), {-0.5, 0, 0}),
                                                  testing::translated(testing::icosphere(3), {0.5, 0, 0}));
    const Solid holed_solid = solid(holed), both_solid = solid(both);

    std::size_t points = 0, wrong = 0, parity_wrong = 0;
    for (int i = 0; i < 400; ++i) {
        // inside the holed sphere, away from the rim
        const Vec3 q = testing::random_unit(rng) * (0.7 * std::cbrt(std::uniform_real_distribution<double>(0, 1)(rng)));
        ++points;
        if (fast(holed_solid, q) < 0.5) ++wrong;
        if (!parity_inside(holed_solid, q)) ++parity_wrong;
    }
    std::size_t overlap_points = 0;
    for (int i = 0; i < 2000; ++i) {
        const Vec3 q = testing::random_point(rng, {{-1.6, -1.1, -1.1}, {1.6, 1.1, 1.1}}, 0);
        const double da = norm(q - Vec3{-0.5, 0, 0}), db = norm(q - Vec3{0.5, 0, 0});
        if (std::fabs(da - 1) < 0.01 || std::fabs(db - 1) < 0.01) continue;  // too near a surface for the facets
        const int expected = (da < 1) + (db < 1);
        const double w = fast(both_solid, q);
        EXPECT_NEAR(w, expected, 0.01);
        EXPECT_NEAR(fast(both_solid, q, 3.0), expected, 1e-3);
        ++points;
        if ((w >= 0.5) != (expected > 0)) ++wrong;
        if (parity_inside(both_solid, q) != (expected > 0)) ++parity_wrong;
        overlap_points += expected == 2;
    }
    std::printf("holes and overlaps: %zu points, winding number wrong %zu, ray parity wrong %zu\n", points, wrong,
                parity_wrong);
    EXPECT_EQ(wrong, 0u);
    EXPECT_GT(overlap_points, 50u);
    // parity calls every overlap point outside, and the holed sphere's points whose ray leaves through the hole
    EXPECT_GT(parity_wrong, overlap_points);

    // the signed distance follows the winding number: negative inside the holed sphere, under the hole too
    const auto sd = signed_distance(holed_solid.bvh, holed_solid.tree, axis * 0.5);
    ASSERT_TRUE(sd.ok());
    EXPECT_LT(sd->distance, 0);
    EXPECT_GT(sd->winding.value, 0.5);
}

TEST(WindingNumber, SignedDistanceMatchesBruteForce) {
    const PolygonMesh& bunny = testing::spatial_bunny();
    ASSERT_GT(bunny.face_count(), 0u);
    const Solid s = solid(bunny);
    std::mt19937_64 rng(4);
    for (int i = 0; i < 12; ++i) {
        const Vec3 q = testing::random_point(rng, bunny.bounds(), 0.1);
        const auto sd = signed_distance(s.bvh, s.tree, q);
        ASSERT_TRUE(sd.ok());
        double best = std::numeric_limits<double>::infinity();
        for (const BvhTriangle& t : s.bvh.triangles)
            best = std::min(best, norm(triangle_closest_point(q, t.p[0], t.p[1], t.p[2]).point - q));
        EXPECT_EQ(std::fabs(sd->distance), best);
        EXPECT_EQ(sd->distance < 0, exact(s, q) >= 0.5);
    }
}

TEST(WindingNumber, InvalidOptionsAndEmptyMesh) {
    const Solid s = solid(shapes::tetrahedron());
    for (double accuracy : {1.0, 0.5, std::numeric_limits<double>::infinity()}) {
        WindingNumberOptions options;
        options.accuracy = accuracy;
        auto w = winding_number(s.bvh, s.tree, {0, 0, 0}, options);
        ASSERT_FALSE(w.ok());
        EXPECT_EQ(w.error().code, ErrorCode::InvalidArgument);
        auto value = winding_number_value(s.bvh, s.tree, {0, 0, 0}, options);
        ASSERT_FALSE(value.ok());
        EXPECT_EQ(value.error().code, ErrorCode::InvalidArgument);
    }
    const Solid empty = solid(PolygonMesh{});
    auto w = winding_number(empty.bvh, empty.tree, {0, 0, 0});
    ASSERT_TRUE(w.ok());
    EXPECT_EQ(w->value, 0.0);
    auto sd = signed_distance(empty.bvh, empty.tree, {0, 0, 0});
    ASSERT_FALSE(sd.ok());
    EXPECT_EQ(sd.error().code, ErrorCode::InvalidArgument);
}

}  // namespace
}  // namespace surfaced
