// Closest point and tight bounding box on B-spline/NURBS surfaces (geometry/surfaces/surface_search.h): against the
// analytic answers on the exact sphere, torus and cylinder (the closest point is the radial projection), against
// dense sampling on random surfaces (no sample may beat the proven answer by more than its tolerance), point
// inversion of points on the surface, the honest failure at the centre of a sphere, and the tight box against the
// analytic boxes and sampling.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "geometry/surfaces/surface_search.h"
#include "tests/support/nurbs_surfaces.h"

namespace surfaced {
namespace {

Vec3 normalized(const Vec3& v) { return v * (1.0 / norm(v)); }

Vec3 random_point(std::mt19937& rng, double extent) {
    std::uniform_real_distribution<double> c(-extent, extent);
    return {c(rng), c(rng), c(rng)};
}

TEST(SurfaceClosestPoint, SphereIsTheRadialProjection) {
    const Vec3 centre{0.5, -1, 2};
    const double r = 1.5;
    const BSplineSurface s = testing::sphere(centre, r);
    std::mt19937 rng(3);
    for (int k = 0; k < 200; ++k) {
        Vec3 q = centre + random_point(rng, 4.0);
        if (norm(q - centre) < 0.2) continue;  // near the centre every point is nearly closest
        auto c = closest_point(s, q);
        ASSERT_TRUE(c.ok()) << c.error().message;
        const Vec3 expected = centre + r * normalized(q - centre);
        EXPECT_NEAR(c->distance, std::abs(norm(q - centre) - r), 1e-9);
        EXPECT_LE(norm(c->point - expected), 1e-6) << "query " << k;
        EXPECT_TRUE(c->converged);
        EXPECT_LE(c->gap, 1e-8);
        // (u, v) is where the point is
        EXPECT_LE(norm(*evaluate(s, c->u, c->v) - c->point), 1e-12);
    }
}

TEST(SurfaceClosestPoint, TorusAndCylinderAreTheRadialProjections) {
    const double R = 3, r = 1;
    const BSplineSurface t = testing::torus({0, 0, 0}, R, r);
    const BSplineSurface cyl = testing::cylinder({0, 0, 0}, 2.0, 3.0);
    std::mt19937 rng(4);
    for (int k = 0; k < 150; ++k) {
        const Vec3 q = random_point(rng, 5.0);
        const double rho = std::hypot(q.x, q.y);
        if (rho < 0.3) continue;
        // torus: the nearest point of the tube's core circle, then r towards q
        const Vec3 core{R * q.x / rho, R * q.y / rho, 0};
        if (norm(q - core) < 0.2) continue;
        auto c = closest_point(t, q);
        ASSERT_TRUE(c.ok()) << c.error().message;
        EXPECT_NEAR(c->distance, std::abs(norm(q - core) - r), 1e-9) << "torus query " << k;
        EXPECT_LE(norm(c->point - (core + r * normalized(q - core))), 1e-6) << "torus query " << k;
        // cylinder of radius 2 over z in [0, 3]: inside the height range and outside the axis region
        if (q.z > 0.1 && q.z < 2.9 && std::abs(rho - 2.0) > 0.05 && rho > 1.2) {
            auto d = closest_point(cyl, q);
            ASSERT_TRUE(d.ok()) << d.error().message;
            EXPECT_NEAR(d->distance, std::abs(rho - 2.0), 1e-9) << "cylinder query " << k;
            EXPECT_LE(norm(d->point - Vec3{2 * q.x / rho, 2 * q.y / rho, q.z}), 1e-6) << "cylinder query " << k;
        }
    }
}

TEST(SurfaceClosestPoint, NoDenseSampleBeatsTheAnswerOnRandomSurfaces) {
    for (unsigned seed = 1; seed <= 25; ++seed) {
        const BSplineSurface s = testing::random_surface(seed);
        const auto [u0, u1] = domain_u(s);
        const auto [v0, v1] = domain_v(s);
        auto patches = to_bezier(s);
        ASSERT_TRUE(patches.ok());
        std::mt19937 rng(seed);
        for (int k = 0; k < 4; ++k) {
            const Vec3 q = random_point(rng, 4.0);
            auto c = closest_point(*patches, q);
            ASSERT_TRUE(c.ok()) << "seed " << seed << ": " << c.error().message;
            EXPECT_LE(norm(*evaluate(s, c->u, c->v) - c->point), 1e-9 * (1 + norm(c->point)));
            EXPECT_NEAR(norm(c->point - q), c->distance, 1e-12 * (1 + c->distance));
            // 200 x 200 samples: none closer than the answer less its proven gap (and rounding)
            double sampled = 1e300;
            for (int i = 0; i <= 200; ++i)
                for (int j = 0; j <= 200; ++j) {
                    const double u = std::min(u1, u0 + (u1 - u0) * i / 200.0),
                                 v = std::min(v1, v0 + (v1 - v0) * j / 200.0);
                    sampled = std::min(sampled, norm(*evaluate(s, u, v) - q));
                }
            EXPECT_GE(sampled, c->distance - c->gap - 1e-12) << "seed " << seed << " query " << k;
            // and the answer is no worse than sampling (sampling only approximates the minimum from above)
            EXPECT_LE(c->distance, sampled + 1e-12) << "seed " << seed << " query " << k;
        }
    }
}

TEST(SurfaceClosestPoint, PointsOnTheSurfaceInvertToTheirParameters) {
    for (unsigned seed = 30; seed <= 45; ++seed) {
        const BSplineSurface s = testing::random_surface(seed);
        const auto [u0, u1] = domain_u(s);
        const auto [v0, v1] = domain_v(s);
        std::mt19937 rng(seed);
        std::uniform_real_distribution<double> a(u0, u1), b(v0, v1);
        for (int k = 0; k < 5; ++k) {
            const double u = a(rng), v = b(rng);
            const Vec3 x = *evaluate(s, u, v);
            auto c = closest_point(s, x);
            ASSERT_TRUE(c.ok()) << c.error().message;
            EXPECT_LE(c->distance, 1e-9) << "seed " << seed;
            EXPECT_TRUE(c->converged);
            // a self-intersecting random net may pass through x twice: compare positions, not parameters
            EXPECT_LE(norm(*evaluate(s, c->u, c->v) - x), 1e-9);
        }
    }
}

TEST(SurfaceClosestPoint, TheCentreOfASphereIsAnHonestFailure) {
    SurfaceSearchOptions options;
    options.max_subdivisions = 500;
    auto c = closest_point(testing::sphere({0, 0, 0}, 1.0), Vec3{0, 0, 0}, options);
    ASSERT_FALSE(c.ok());
    EXPECT_EQ(c.error().code, ErrorCode::BudgetExceeded);
    EXPECT_NE(c.error().message.find("500"), std::string::npos) << c.error().message;
    // a coarse tolerance is provable: every point is at distance 1
    options.tolerance = 1e-2;
    options.max_subdivisions = 100000;
    auto coarse = closest_point(testing::sphere({0, 0, 0}, 1.0), Vec3{0, 0, 0}, options);
    ASSERT_TRUE(coarse.ok()) << coarse.error().message;
    EXPECT_NEAR(coarse->distance, 1.0, 1e-12);
}

TEST(SurfaceClosestPoint, Errors) {
    const BSplineSurface s = testing::sphere({0, 0, 0}, 1.0);
    EXPECT_EQ(closest_point(s, Vec3{std::nan(""), 0, 0}).error().code, ErrorCode::InvalidArgument);
    SurfaceSearchOptions options;
    options.tolerance = -1;
    EXPECT_EQ(closest_point(s, Vec3{2, 0, 0}, options).error().code, ErrorCode::InvalidArgument);
    BSplineSurface bad = s;
    bad.knots_u[4] = 5;
    EXPECT_EQ(closest_point(bad, Vec3{2, 0, 0}).error().code, ErrorCode::InvalidArgument);
}

TEST(SurfaceTightBox, AnalyticBoxesOfSphereAndTorus) {
    auto sphere = to_bezier(testing::sphere({1, 2, 3}, 2.0));
    ASSERT_TRUE(sphere.ok());
    auto box = tight_bounding_box(*sphere);
    ASSERT_TRUE(box.ok()) << box.error().message;
    for (int c = 0; c < 3; ++c) {
        const double centre = c == 0 ? 1 : c == 1 ? 2 : 3;
        EXPECT_NEAR(box->min[c], centre - 2, 1e-8);
        EXPECT_NEAR(box->max[c], centre + 2, 1e-8);
        EXPECT_LE(box->min[c], centre - 2 + 1e-15);  // holds the surface
        EXPECT_GE(box->max[c], centre + 2 - 1e-15);
    }
    auto torus = to_bezier(testing::torus({0, 0, 0}, 3, 1));
    ASSERT_TRUE(torus.ok());
    auto tbox = tight_bounding_box(*torus);
    ASSERT_TRUE(tbox.ok()) << tbox.error().message;
    EXPECT_NEAR(tbox->max.x, 4, 1e-8);
    EXPECT_NEAR(tbox->min.y, -4, 1e-8);
    EXPECT_NEAR(tbox->max.z, 1, 1e-8);
    EXPECT_NEAR(tbox->min.z, -1, 1e-8);
}

TEST(SurfaceTightBox, ABumpIsLowerThanItsControlHull) {
    // biquadratic Bézier surface over [0, 1]^2, middle control point at height 1: the top is B_1(1/2)^2 = 1/4
    BSplineSurface bump;
    bump.degree_u = bump.degree_v = 2;
    bump.count_u = bump.count_v = 3;
    bump.knots_u = bump.knots_v = {0, 0, 0, 1, 1, 1};
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) bump.points.push_back({0.5 * i, 0.5 * j, i == 1 && j == 1 ? 1.0 : 0.0});
    EXPECT_EQ(control_hull_box(bump).max.z, 1.0);
    auto patches = to_bezier(bump);
    ASSERT_TRUE(patches.ok());
    auto box = tight_bounding_box(*patches);
    ASSERT_TRUE(box.ok()) << box.error().message;
    EXPECT_NEAR(box->max.z, 0.25, 1e-8);
    EXPECT_GE(box->max.z, 0.25);
    EXPECT_EQ(box->min.z, 0.0);
    EXPECT_EQ(box->max.x, 1.0);
}

TEST(SurfaceTightBox, HoldsEverySampleOfRandomSurfacesAndIsNoLargerThanTheTolerance) {
    for (unsigned seed = 50; seed <= 70; ++seed) {
        const BSplineSurface s = testing::random_surface(seed);
        auto patches = to_bezier(s);
        ASSERT_TRUE(patches.ok());
        SurfaceSearchOptions options;
        options.tolerance = 1e-7;
        auto box = tight_bounding_box(*patches, options);
        ASSERT_TRUE(box.ok()) << box.error().message;
        const auto [u0, u1] = domain_u(s);
        const auto [v0, v1] = domain_v(s);
        Box3 sampled;
        for (int i = 0; i <= 300; ++i)
            for (int j = 0; j <= 300; ++j)
                sampled.add(
                    *evaluate(s, std::min(u1, u0 + (u1 - u0) * i / 300.0), std::min(v1, v0 + (v1 - v0) * j / 300.0)));
        for (int c = 0; c < 3; ++c) {
            EXPECT_LE(box->min[c], sampled.min[c] + 1e-12) << "seed " << seed;
            EXPECT_GE(box->max[c], sampled.max[c] - 1e-12) << "seed " << seed;
            // sampling at 1/300 of the domain misses the extreme by O(h^2 |S''|) (up to a few 1e-2 on these wild
            // nets): a loose allowance that still catches a box near the control hull's
            EXPECT_LE(sampled.min[c] - box->min[c], 5e-2) << "seed " << seed;
            EXPECT_LE(box->max[c] - sampled.max[c], 5e-2) << "seed " << seed;
        }
    }
}

}  // namespace
}  // namespace surfaced
