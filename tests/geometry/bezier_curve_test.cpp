// Bézier curves: the lecture's properties as assertions, analytic derivatives/curvature/length, rational circles,
// global closest point against brute force, and the tessellation tolerance against dense exact evaluation.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "geometry/curves/bezier_curve.h"
#include "geometry/curves/de_casteljau.h"

namespace surfaced {
namespace {

BezierCurve random_curve(int degree, unsigned seed, bool rational = false, bool planar = false) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> coord(-3.0, 3.0), weight(0.3, 3.0);
    BezierCurve curve;
    for (int i = 0; i <= degree; ++i) {
        curve.points.push_back({coord(rng), coord(rng), planar ? 0.0 : coord(rng)});
        if (rational) curve.weights.push_back(weight(rng));
    }
    return curve;
}

//! Quarter of the unit circle, (1, 0) to (0, 1): the classic rational quadratic with middle weight sqrt(2)/2.
BezierCurve quarter_circle() {
    BezierCurve c;
    c.points = {{1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    c.weights = {1, std::numbers::sqrt2 / 2, 1};
    return c;
}

//! (t, t^2, t^3) in Bézier form: x = t has coefficients i/3, t^2 -> (0, 0, 1/3, 1), t^3 -> (0, 0, 0, 1).
BezierCurve twisted_cubic() {
    BezierCurve c;
    c.points = {{0, 0, 0}, {1.0 / 3, 0, 0}, {2.0 / 3, 1.0 / 3, 0}, {1, 1, 1}};
    return c;
}

void expect_near(const Vec3& a, const Vec3& b, double tol, const std::string& what = "") {
    EXPECT_LE(norm(a - b), tol) << what << ": (" << a.x << ", " << a.y << ", " << a.z << ") vs (" << b.x << ", " << b.y
                                << ", " << b.z << ")";
}

TEST(BezierCurve, DeCasteljauEqualsBernstein) {
    for (int degree = 1; degree <= 10; ++degree)
        for (bool rational : {false, true}) {
            const BezierCurve c = random_curve(degree, static_cast<unsigned>(degree), rational);
            for (int k = 0; k <= 50; ++k)
                expect_near(evaluate(c, k / 50.0), evaluate_bernstein(c, k / 50.0), 1e-12,
                            "degree " + std::to_string(degree));
        }
}

TEST(BezierCurve, PartitionOfUnity) {
    for (int n = 0; n <= 12; ++n)
        for (int k = 0; k <= 20; ++k) {
            double sum = 0;
            for (int i = 0; i <= n; ++i) {
                const double b = bezier::bernstein(n, i, k / 20.0);
                EXPECT_GE(b, 0.0);
                sum += b;
            }
            EXPECT_NEAR(sum, 1.0, 1e-14);
        }
}

TEST(BezierCurve, EndpointsAndEndTangents) {
    for (int degree = 1; degree <= 7; ++degree) {
        const BezierCurve c = random_curve(degree, 100u + static_cast<unsigned>(degree));
        const auto& b = c.points;
        const double n = degree;
        EXPECT_EQ(evaluate(c, 0), b.front());
        EXPECT_EQ(evaluate(c, 1), b.back());
        expect_near(derivative(c, 0, 1), n * (b[1] - b[0]), 1e-12, "start tangent");
        expect_near(derivative(c, 1, 1), n * (b[b.size() - 1] - b[b.size() - 2]), 1e-12, "end tangent");
    }
    // rational: C'(0) = n (w1 / w0) (b1 - b0)
    const BezierCurve r = random_curve(4, 7, true);
    expect_near(evaluate(r, 0), r.points[0], 1e-15);
    expect_near(derivative(r, 0, 1), 4 * (r.weights[1] / r.weights[0]) * (r.points[1] - r.points[0]), 1e-11);
    expect_near(derivative(r, 1, 1), 4 * (r.weights[3] / r.weights[4]) * (r.points[4] - r.points[3]), 1e-11);
}

TEST(BezierCurve, AffineInvariance) {
    const auto affine = [](const Vec3& p) {
        return Vec3{0.5 * p.x - 2 * p.y + p.z + 3, p.x + p.y - 1, 2 * p.z - 0.5 * p.x};
    };
    for (bool rational : {false, true}) {
        const BezierCurve c = random_curve(5, 9, rational);
        BezierCurve mapped = c;
        for (Vec3& p : mapped.points) p = affine(p);
        for (int k = 0; k <= 10; ++k) expect_near(evaluate(mapped, k / 10.0), affine(evaluate(c, k / 10.0)), 1e-12);
    }
}

TEST(BezierCurve, ConvexHullContainment) {
    for (bool rational : {false, true}) {
        const BezierCurve c = random_curve(6, 13, rational);
        const Box3 box = bounding_box(c);
        for (int k = 0; k <= 200; ++k) {
            const Vec3 p = evaluate(c, k / 200.0);
            for (int a = 0; a < 3; ++a) {
                EXPECT_GE(p[a], box.min[a] - 1e-12);
                EXPECT_LE(p[a], box.max[a] + 1e-12);
            }
        }
    }
}

TEST(BezierCurve, DerivativesOfAnyOrder) {
    const BezierCurve c = twisted_cubic();
    for (double t : {0.0, 0.25, 0.7, 1.0}) {
        expect_near(evaluate(c, t), {t, t * t, t * t * t}, 1e-15);
        expect_near(derivative(c, t, 1), {1, 2 * t, 3 * t * t}, 1e-13);
        expect_near(derivative(c, t, 2), {0, 2, 6 * t}, 1e-12);
        expect_near(derivative(c, t, 3), {0, 0, 6}, 1e-12);
        expect_near(derivative(c, t, 4), {0, 0, 0}, 0.0);
    }
    // rational circle: C(t) on the unit circle, so C . C' = 0 and |C'|^2 + C . C'' = 0
    const BezierCurve circle = quarter_circle();
    for (double t : {0.1, 0.5, 0.9}) {
        const Vec3 p = evaluate(circle, t), d1 = derivative(circle, t, 1), d2 = derivative(circle, t, 2);
        EXPECT_NEAR(norm(p), 1.0, 1e-14);
        EXPECT_NEAR(dot(p, d1), 0.0, 1e-13);
        EXPECT_NEAR(dot(d1, d1) + dot(p, d2), 0.0, 1e-12);
        // third derivative against a central difference of the second
        const double h = 1e-4;
        expect_near(derivative(circle, t, 3), (derivative(circle, t + h, 2) - derivative(circle, t - h, 2)) * (0.5 / h),
                    1e-5);
    }
}

TEST(BezierCurve, SplitHalvesReproduceTheCurve) {
    for (bool rational : {false, true})
        for (double t : {0.3, 0.5, 0.81}) {
            const BezierCurve c = random_curve(5, 17, rational);
            const auto [left, right] = split(c, t);
            for (int k = 0; k <= 20; ++k) {
                const double s = k / 20.0;
                expect_near(evaluate(left, s), evaluate(c, t * s), 1e-12, "left");
                expect_near(evaluate(right, s), evaluate(c, t + (1 - t) * s), 1e-12, "right");
            }
        }
}

TEST(BezierCurve, DegreeElevationPreservesShape) {
    for (bool rational : {false, true}) {
        const BezierCurve c = random_curve(4, 23, rational);
        const BezierCurve e = elevate_degree(c, 3);
        EXPECT_EQ(e.degree(), 7);
        for (int k = 0; k <= 30; ++k) expect_near(evaluate(e, k / 30.0), evaluate(c, k / 30.0), 1e-12);
    }
}

TEST(BezierCurve, Curvature) {
    // parabola (t, t^2): kappa = 2 / (1 + 4 t^2)^(3/2)
    BezierCurve parabola;
    parabola.points = {{0, 0, 0}, {0.5, 0, 0}, {1, 1, 0}};
    for (double t : {0.0, 0.3, 1.0}) EXPECT_NEAR(curvature(parabola, t), 2 / std::pow(1 + 4 * t * t, 1.5), 1e-12);
    for (double t : {0.0, 0.4, 1.0}) EXPECT_NEAR(curvature(quarter_circle(), t), 1.0, 1e-12);
    BezierCurve line;
    line.points = {{0, 0, 0}, {1, 2, 3}, {3, 6, 9}};
    EXPECT_NEAR(curvature(line, 0.5), 0.0, 1e-12);
}

TEST(BezierCurve, ArcLengthWithinItsBound) {
    // parabola (t, t^2), t in [0, 1]: length = (2 sqrt(5) + asinh(2)) / 4
    BezierCurve parabola;
    parabola.points = {{0, 0, 0}, {0.5, 0, 0}, {1, 1, 0}};
    const double exact = (2 * std::sqrt(5.0) + std::asinh(2.0)) / 4;
    for (double tol : {1e-3, 1e-6, 1e-10}) {
        const ArcLength a = arc_length(parabola, tol);
        EXPECT_LE(a.error_bound, tol);
        EXPECT_LE(std::abs(a.length - exact), a.error_bound + 1e-15);
    }
    // a straight line with unevenly spaced but increasing control points (x' > 0, no backtracking): length =
    // distance between the ends
    BezierCurve line;
    line.points = {{0, 0, 0}, {0.2, 0, 0}, {1.5, 0, 0}, {2, 0, 0}};
    EXPECT_NEAR(arc_length(line, 1e-9).length, 2.0, 1e-9);
    // the quarter circle (rational; the bound is an estimate there): pi / 2
    EXPECT_NEAR(arc_length(quarter_circle(), 1e-10).length, std::numbers::pi / 2, 1e-8);
}

TEST(BezierCurve, ClosestPointIsGlobal) {
    // circle: the closest point to (2, 2) is (1, 1)/sqrt 2
    const ClosestPoint c = closest_point(quarter_circle(), {2, 2, 0});
    expect_near(c.point, Vec3{1, 1, 0} * (1 / std::numbers::sqrt2), 1e-10);
    EXPECT_NEAR(c.distance, 2 * std::numbers::sqrt2 - 1, 1e-10);
    // wiggly curves with many local minima: against brute force over a dense sampling
    for (unsigned seed = 1; seed <= 20; ++seed) {
        const BezierCurve curve = random_curve(7, seed, seed % 2 == 0, true);
        std::mt19937 rng(seed * 7);
        std::uniform_real_distribution<double> coord(-3.0, 3.0);
        const Vec3 q{coord(rng), coord(rng), 0.0};
        double brute = std::numeric_limits<double>::infinity();
        for (int k = 0; k <= 100000; ++k) brute = std::min(brute, norm(evaluate(curve, k / 100000.0) - q));
        const ClosestPoint found = closest_point(curve, q);
        EXPECT_LE(found.distance, brute + 1e-12) << "seed " << seed;
        EXPECT_NEAR(found.distance, norm(evaluate(curve, found.t) - q), 1e-12);
        EXPECT_GE(found.distance, brute - 1e-6) << "seed " << seed;  // sampling is that fine
    }
}

//! Max over a dense sampling of the distance from C(t) to the chord of the polyline segment containing t.
double dense_deviation(const BezierCurve& curve, const CurveTessellation& t) {
    double worst = 0;
    std::size_t segment = 0;
    for (int k = 0; k <= 20000; ++k) {
        const double u = k / 20000.0;
        while (segment + 2 < t.params.size() && t.params[segment + 1] < u) ++segment;
        const Vec3 p = evaluate(curve, u), a = t.points[segment], b = t.points[segment + 1];
        const Vec3 ab = b - a;
        const double s = dot(ab, ab) > 0 ? std::clamp(dot(p - a, ab) / dot(ab, ab), 0.0, 1.0) : 0.0;
        worst = std::max(worst, norm(p - (a + ab * s)));
    }
    return worst;
}

TEST(BezierCurve, TessellationHonoursTolerance) {
    for (int degree : {2, 3, 7})
        for (bool rational : {false, true})
            for (double tol : {0.1, 0.01, 0.001}) {
                const BezierCurve curve = random_curve(degree, static_cast<unsigned>(degree * 31), rational);
                auto t = tessellate(curve, tol);
                ASSERT_TRUE(t.ok()) << t.error().message;
                EXPECT_EQ(t->segments + 1, t->points.size());
                EXPECT_EQ(t->points.front(), curve.points.front());
                EXPECT_LE(t->bound, tol);
                EXPECT_LE(t->max_deviation, t->bound + 1e-12);
                EXPECT_LE(dense_deviation(curve, *t), tol)
                    << "degree " << degree << (rational ? " rational" : "") << " tol " << tol;
                EXPECT_GT(t->segments, 0u);
            }
}

TEST(BezierCurve, AdaptiveUsesNoMoreSegmentsThanUniformWang) {
    // one sharp bend: uniform Wang over the whole curve pays for the bend everywhere
    BezierCurve curve;
    curve.points = {{0, 0, 0}, {10, 0, 0}, {10, 0.2, 0}, {0, 0.2, 0}, {0, 10, 0}};
    const int n = curve.degree();
    double m = 0;
    for (std::size_t i = 0; i + 2 < curve.points.size(); ++i)
        m = std::max(m, norm(curve.points[i + 2] - 2.0 * curve.points[i + 1] + curve.points[i]));
    const double tol = 1e-3;
    const auto uniform = static_cast<std::size_t>(std::ceil(std::sqrt(n * (n - 1) * m / (8 * tol))));
    auto t = tessellate(curve, tol);
    ASSERT_TRUE(t.ok());
    EXPECT_LE(t->segments, uniform);
    EXPECT_LE(dense_deviation(curve, *t), tol);
}

TEST(BezierCurve, Errors) {
    BezierCurve empty;
    EXPECT_FALSE(validate(empty).ok());
    BezierCurve c = random_curve(3, 1);
    EXPECT_EQ(tessellate(c, 0).error().code, ErrorCode::InvalidArgument);
    EXPECT_EQ(tessellate(c, 1e-30, 1000).error().code, ErrorCode::BudgetExceeded);
    c.weights = {1, -1, 1, 1};
    const auto bad = validate(c);
    ASSERT_FALSE(bad.ok());
    EXPECT_EQ(bad.error().element, 1);
    c.weights = {1, 1};
    EXPECT_FALSE(validate(c).ok());
}

}  // namespace
}  // namespace surfaced
