// Point classification and ray casting: inside/outside vs analytic, ray hits vs analytic intersections (sphere,
// box, plane, transformed), the General-field fallback finding thin features, options, errors and cancellation.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <random>
#include <vector>

#include "geometry/implicit/expression.h"
#include "geometry/implicit/level_set.h"
#include "geometry/implicit/operators.h"
#include "geometry/implicit/query.h"

namespace surfaced::implicit {
namespace {

PointQueryOptions tolerance(double t) {
    PointQueryOptions o;
    o.tolerance = t;
    return o;
}

RayOptions rays(double max_distance, int max_steps, double general_step = 0) {
    RayOptions o;
    o.max_distance = max_distance;
    o.max_steps = max_steps;
    o.general_step = general_step;
    return o;
}

RayHit cast(const FieldPtr& f, const Vec3& o, const Vec3& d, RayOptions options = {}) {
    auto hits = cast_rays(*f, std::vector<Ray>{{o, d}}, options);
    EXPECT_TRUE(hits.ok());
    return hits.ok() ? hits.value()[0] : RayHit{};
}

//! Entry t of the ray o + t d (|d| = 1) into the axis-aligned box [lo, hi] (slab method), or -1.
double slab(const Vec3& o, const Vec3& d, const Vec3& lo, const Vec3& hi) {
    double t0 = 0, t1 = 1e300;
    for (int a = 0; a < 3; ++a) {
        const double inv = 1 / d[a];
        double ta = (lo[a] - o[a]) * inv, tb = (hi[a] - o[a]) * inv;
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    return t0 <= t1 ? t0 : -1;
}

TEST(ImplicitQuery, ClassifiesPointsLikeTheAnalyticSolid) {
    const auto f = csg_difference({box({1, 1, 1}), translate(sphere(0.5), {0, 0, 1})});
    std::vector<Vec3> points;
    for (int i = -6; i <= 6; ++i)
        for (int j = -6; j <= 6; ++j)
            for (int k = -6; k <= 6; ++k) points.push_back({i * 0.3 + 0.01, j * 0.3 + 0.02, k * 0.3 + 0.03});
    points.push_back({1, 0.2, 0.1});  // on a face
    auto samples = query_points(*f, points, tolerance(1e-9));
    ASSERT_TRUE(samples.ok());
    for (std::size_t i = 0; i + 1 < points.size(); ++i) {
        const Vec3& p = points[i];
        const bool in_box = std::abs(p.x) < 1 && std::abs(p.y) < 1 && std::abs(p.z) < 1;
        const bool in_ball = norm(p - Vec3{0, 0, 1}) < 0.5;
        EXPECT_EQ(samples.value()[i].cls, in_box && !in_ball ? PointClass::Inside : PointClass::Outside)
            << p.x << " " << p.y << " " << p.z;
    }
    EXPECT_EQ(samples.value().back().cls, PointClass::On);
    EXPECT_EQ(samples.value().back().gradient, (Vec3{1, 0, 0}));
    EXPECT_EQ(classify(0.5, 1.0), PointClass::On);
    EXPECT_EQ(classify(-2, 1.0), PointClass::Inside);
    EXPECT_EQ(classify(std::nan(""), 1.0), PointClass::Undefined);
    EXPECT_EQ(query_points(*f, points, tolerance(-1)).error().code, ErrorCode::InvalidArgument);
}

TEST(ImplicitQuery, RaysHitSpheresWhereTheQuadraticSays) {
    const auto s = translate(sphere(1.0), {0.5, -0.25, 0.3});
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> u(-1, 1);
    int hits = 0;
    for (int i = 0; i < 200; ++i) {
        const Vec3 o{u(rng) * 4, u(rng) * 4, 4 + u(rng)};
        Vec3 d = Vec3{0.5, -0.25, 0.3} + Vec3{u(rng), u(rng), u(rng)} * 1.2 - o;
        d = d * (1 / norm(d));
        // |o + t d - c|^2 = 1
        const Vec3 oc = o - Vec3{0.5, -0.25, 0.3};
        const double b = dot(oc, d), c = dot(oc, oc) - 1, disc = b * b - c;
        const RayHit h = cast(s, o, d);
        if (disc > 1e-6) {
            ASSERT_TRUE(h.hit) << i;
            ++hits;
            const double t = -b - std::sqrt(disc);
            // never past the surface, within hit_tolerance of it (in distance), and so close in t unless grazing
            EXPECT_LE(h.t, t + 1e-12);
            EXPECT_NEAR(norm(h.point - Vec3{0.5, -0.25, 0.3}), 1.0, 1e-7 + 1e-12);
            EXPECT_NEAR(h.t, t, 2e-7 / std::sqrt(disc) + 1e-9);  // sqrt(disc) = |cos| between ray and normal
            const Vec3 n = (h.point - Vec3{0.5, -0.25, 0.3});
            EXPECT_NEAR(dot(h.normal, n * (1 / norm(n))), 1.0, 1e-9);
            EXPECT_LE(h.steps, 1000);
        } else if (disc < -1e-6) {
            EXPECT_FALSE(h.hit) << i;
        }
    }
    EXPECT_GT(hits, 50);
}

TEST(ImplicitQuery, RaysHitBoxesPlanesAndTransformedShapes) {
    const auto b = box({1, 0.5, 2});
    const auto moved = translate(rotate(box({1, 0.5, 2}), rotation_axis_angle({0, 0, 1}, 90)), {3, 0, 0});
    std::mt19937 rng(8);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int i = 0; i < 200; ++i) {
        const Vec3 o{5 * u(rng), 5 * u(rng), 6};
        Vec3 d = Vec3{u(rng), u(rng), u(rng) * 0.5 - 1};
        d = d * (1 / norm(d));
        const double t = slab(o, d, {-1, -0.5, -2}, {1, 0.5, 2});
        const RayHit h = cast(b, o, d, rays(100, 10000));
        if (t >= 0 && h.hit) {
            EXPECT_NEAR(h.t, t, 1e-5);
        } else if (t < 0) {
            EXPECT_FALSE(h.hit);
        } else {
            // a grazing ray may run out of steps; it must have been close to the box's silhouette
            EXPECT_EQ(h.steps, 10000);
        }
        // the rotated, moved copy is the box [2.5, 3.5] x [-1, 1] x [-2, 2]
        const double tm = slab(o, d, {2.5, -1, -2}, {3.5, 1, 2});
        const RayHit hm = cast(moved, o, d, rays(100, 10000));
        if (tm >= 0 && hm.hit) {
            EXPECT_NEAR(hm.t, tm, 1e-5);
        }
        if (tm < 0) {
            EXPECT_FALSE(hm.hit);
        }
    }
    const RayHit top = cast(b, {0.2, 0.1, 5}, {0, 0, -1});
    ASSERT_TRUE(top.hit);
    EXPECT_NEAR(top.t, 3, 1e-7);
    EXPECT_NEAR(top.normal.z, 1, 1e-12);

    const auto ground = plane({0, 1, 1}, 0.5);  // n = (0, 1, 1)/sqrt(2)
    const Vec3 o{1, 3, 2}, d = Vec3{0.2, -1, -0.3} * (1 / norm(Vec3{0.2, -1, -0.3}));
    const Vec3 n = Vec3{0, 1, 1} * (1 / std::sqrt(2.0));
    const RayHit hp = cast(ground, o, d);
    ASSERT_TRUE(hp.hit);
    EXPECT_NEAR(hp.t, (0.5 - dot(n, o)) / dot(n, d), 1e-7);
    EXPECT_LE(hp.steps, 12);                                   // oblique: the gap shrinks by 1 - |cos| = 0.135 per step
    EXPECT_LE(cast(ground, {0, 2, 2}, {0, -1, -1}).steps, 2);  // head-on: one step lands on it
    EXPECT_FALSE(cast(ground, o, d * -1.0).hit);
}

TEST(ImplicitQuery, RaysFromInsideAndLimits) {
    const auto s = sphere(1);
    const RayHit out = cast(s, {0, 0, 0}, {0, 2, 0});
    ASSERT_TRUE(out.hit);
    EXPECT_NEAR(out.t, 1, 1e-7);
    // max_distance stops before the sphere; max_steps bounds the work
    const RayHit far = cast(s, {0, 0, -10}, {0, 0, 1}, rays(5, 1000));
    EXPECT_FALSE(far.hit);
    const RayHit few = cast(s, {0, 1.0001, -10}, {0, 0, 1}, rays(100, 5));
    EXPECT_FALSE(few.hit);
    EXPECT_EQ(few.steps, 5);
    auto bad = cast_rays(*s, std::vector<Ray>{{{0, 0, 0}, {1, 0, 0}}, {{0, 0, 0}, {0, 0, 0}}});
    ASSERT_FALSE(bad.ok());
    EXPECT_EQ(bad.error().element, 1);
    EXPECT_FALSE(cast_rays(*s, std::vector<Ray>{}, rays(-1, 1000)).ok());
}

TEST(ImplicitQuery, GeneralFieldsUseTheSafeFallback) {
    auto ball = parse_expression("x^2 + y^2 + z^2 - 1");
    ASSERT_TRUE(ball.ok());
    const RayHit h = cast(ball.value(), {-5, 0.6, 0}, {1, 0, 0}, rays(10, 2000));
    ASSERT_TRUE(h.hit);
    EXPECT_NEAR(h.t, 5 - 0.8, 1e-6);
    EXPECT_NEAR(h.normal.x, -0.8, 1e-6);
    EXPECT_NEAR(h.normal.y, 0.6, 1e-6);

    // A slab 0.02 thick whose value is tiny compared to its gradient elsewhere: stepping by |f| / (an estimated L)
    // could jump it; fixed steps of 0.005 cannot.
    auto slab_field = parse_expression("1000*(x^2 - 0.0001)");
    ASSERT_TRUE(slab_field.ok());
    const RayHit thin = cast(slab_field.value(), {-3, 0.1, 0.2}, {1, 0, 0}, rays(6, 2000, 0.005));
    ASSERT_TRUE(thin.hit);
    EXPECT_NEAR(thin.t, 3 - 0.01, 1e-6);
    // two thin walls: the first one is reported
    auto walls = parse_expression("min(abs(x - 1) - 0.004, abs(x - 2) - 0.004)");
    ASSERT_TRUE(walls.ok());
    const RayHit first = cast(walls.value(), {0, 0, 0}, {1, 0, 0}, rays(4, 1000));
    ASSERT_TRUE(first.hit);  // default step 4 / 1000 = 0.004 < wall thickness 0.008
    EXPECT_NEAR(first.t, 0.996, 1e-6);
    // undefined regions (sqrt of a negative) are skipped, not taken for crossings
    auto partial = parse_expression("sqrt(x) - 1");
    ASSERT_TRUE(partial.ok());
    const RayHit through = cast(partial.value(), {-2, 0, 0}, {1, 0, 0}, rays(5, 1000));
    ASSERT_TRUE(through.hit);
    EXPECT_NEAR(through.t, 3, 1e-6);
}

TEST(ImplicitQuery, LevelSetSphereIsTracedWithItsLipschitzBound) {
    LevelSetGrid g;
    g.dims = {41, 41, 41};
    g.origin = {-2, -2, -2};
    g.spacing = {0.1, 0.1, 0.1};
    for (std::size_t k = 0; k < 41; ++k)
        for (std::size_t j = 0; j < 41; ++j)
            for (std::size_t i = 0; i < 41; ++i)
                g.values.push_back(norm(g.origin + Vec3{0.1 * double(i), 0.1 * double(j), 0.1 * double(k)}) - 1);
    auto f = level_set(std::move(g));
    ASSERT_TRUE(f.ok());
    const RayHit h = cast(f.value(), {-6, 0.05, 0.02}, {1, 0, 0});
    ASSERT_TRUE(h.hit);
    EXPECT_NEAR(h.t, 5.0, 5e-3);  // trilinear interpolation of a sphere at h = 0.1
}

TEST(ImplicitQuery, CancelStopsTheWork) {
    std::atomic<bool> stop{true};
    RayOptions options;
    options.cancel.flag = &stop;
    const auto s = sphere(1);
    auto hits = cast_rays(*s, std::vector<Ray>{{{0, 0, -5}, {0, 0, 1}}}, options);
    ASSERT_FALSE(hits.ok());
    EXPECT_EQ(hits.error().code, ErrorCode::Cancelled);
    PointQueryOptions point_options;
    point_options.cancel.flag = &stop;
    EXPECT_EQ(query_points(*s, std::vector<Vec3>{{0, 0, 0}}, point_options).error().code, ErrorCode::Cancelled);
}

}  // namespace
}  // namespace surfaced::implicit
