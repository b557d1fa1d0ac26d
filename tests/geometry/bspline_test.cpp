// B-spline and NURBS curves: de Boor against the Cox-de Boor basis sum and against the Bézier conversion, basis
// function properties, knot insertion, clamped end conditions, derivatives against central differences, exact NURBS
// circles, continuity at knots, tessellation within tolerance, and validation messages.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numbers>
#include <random>
#include <string>

#include "geometry/curves/bspline.h"

namespace surfaced {
namespace {

void expect_near(const Vec3& a, const Vec3& b, double tol, const std::string& what = "") {
    EXPECT_LE(norm(a - b), tol) << what << ": (" << a.x << ", " << a.y << ", " << a.z << ") vs (" << b.x << ", " << b.y
                                << ", " << b.z << ")";
}

BSplineTessellationOptions options(double tolerance, std::size_t max_segments = 1'000'000) {
    BSplineTessellationOptions o;
    o.tolerance = tolerance;
    o.max_segments = max_segments;
    return o;
}

//! Random knots for n points of degree p: steps in [0.2, 1], interior values repeated up to p times (often once),
//! the ends p + 1 times when clamped, at most p times otherwise.
std::vector<double> random_knots(std::size_t n, int p, bool clamped, std::mt19937& rng) {
    std::uniform_real_distribution<double> step(0.2, 1.0);
    std::uniform_int_distribution<int> mult(1, p), coin(0, 3);
    const std::size_t m = n + static_cast<std::size_t>(p) + 1;
    std::vector<double> knots;
    double value = -1.3;
    if (clamped) knots.assign(static_cast<std::size_t>(p) + 1, value);
    const std::size_t interior_end = clamped ? m - static_cast<std::size_t>(p) - 1 : m;
    while (knots.size() < interior_end) {
        value += step(rng);
        const std::size_t r = std::min<std::size_t>(coin(rng) == 0 ? static_cast<std::size_t>(mult(rng)) : 1,
                                                    interior_end - knots.size());
        knots.insert(knots.end(), r, value);
    }
    if (clamped) knots.insert(knots.end(), static_cast<std::size_t>(p) + 1, value + step(rng));
    return knots;
}

BSplineCurve random_curve(int p, std::size_t n, unsigned seed, bool rational, bool clamped) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> coord(-3.0, 3.0), weight(0.3, 3.0);
    for (;;) {
        BSplineCurve c;
        c.degree = p;
        for (std::size_t i = 0; i < n; ++i) {
            c.points.push_back({coord(rng), coord(rng), coord(rng)});
            if (rational) c.weights.push_back(weight(rng));
        }
        c.knots = random_knots(n, p, clamped, rng);
        if (validate(c)) return c;  // an unclamped vector can have an empty domain: draw again
    }
}

//! Every (degree, rational, clamped) combination with a few point counts.
template <class F>
void for_each_curve(F&& f) {
    unsigned seed = 1;
    for (int p = 1; p <= 6; ++p)
        for (std::size_t extra : {0u, 1u, 4u, 9u})
            for (bool rational : {false, true})
                for (bool clamped : {true, false}) {
                    const BSplineCurve c =
                        random_curve(p, static_cast<std::size_t>(p) + 1 + extra, seed++, rational, clamped);
                    f(c, "degree " + std::to_string(p) + " n " + std::to_string(c.points.size()) +
                             (rational ? " rational" : "") + (clamped ? " clamped" : " unclamped"));
                }
}

//! Parameters: a uniform sweep of the domain plus every knot inside it and both ends.
std::vector<double> sample_params(const BSplineCurve& c, int count = 200) {
    const auto [lo, hi] = domain(c);
    std::vector<double> us;
    for (int k = 0; k <= count; ++k) us.push_back(lo + (hi - lo) * k / count);
    for (double u : c.knots)
        if (u >= lo && u <= hi) us.push_back(u);
    return us;
}

TEST(BSpline, DeBoorEqualsBasisFunctionSum) {
    for_each_curve([](const BSplineCurve& c, const std::string& what) {
        for (double u : sample_params(c)) expect_near(evaluate(c, u), evaluate_basis(c, u), 1e-12, what);
    });
}

TEST(BSpline, BasisPartitionOfUnityNonNegativityLocalSupport) {
    std::mt19937 rng(7);
    for (int p = 1; p <= 7; ++p)
        for (bool clamped : {true, false}) {
            const std::size_t n = static_cast<std::size_t>(p) + 6;
            std::vector<double> U;
            do U = random_knots(n, p, clamped, rng);
            while (!(U[static_cast<std::size_t>(p)] < U[n]));
            const double lo = U[static_cast<std::size_t>(p)], hi = U[n];
            for (int k = 0; k <= 300; ++k) {
                const double u = k == 300 ? hi : lo + (hi - lo) * k / 300.0;
                const SpanSide side = k == 300 ? SpanSide::Left : SpanSide::Right;
                double sum = 0;
                int nonzero = 0;
                for (std::size_t i = 0; i < n; ++i) {
                    const double b = basis_function(U, p, i, u, side);
                    EXPECT_GE(b, 0.0);
                    // support: N_{i,p} vanishes outside [u_i, u_{i+p+1}]
                    if (u < U[i] || u > U[i + static_cast<std::size_t>(p) + 1]) {
                        EXPECT_EQ(b, 0.0) << "i " << i;
                    }
                    sum += b;
                    nonzero += b != 0.0;
                }
                EXPECT_NEAR(sum, 1.0, 1e-14) << "p " << p << " u " << u;
                EXPECT_LE(nonzero, p + 1);
                // exactly the p + 1 functions of the span can be non-zero
                const std::size_t span = find_span(U, p, n, u, side);
                for (std::size_t i = 0; i < n; ++i)
                    if (i + static_cast<std::size_t>(p) < span || i > span) {
                        EXPECT_EQ(basis_function(U, p, i, u, side), 0.0);
                    }
            }
        }
}

TEST(BSpline, EqualsItsBezierConversion) {
    for_each_curve([](const BSplineCurve& c, const std::string& what) {
        auto chain = to_bezier(c);
        ASSERT_TRUE(chain) << chain.error().message;
        const std::vector<double> breaks = bezier_breaks(c);
        ASSERT_EQ(breaks.size(), chain->pieces.size() + 1) << what;
        EXPECT_FALSE(chain->closed);
        for (std::size_t j = 0; j < chain->pieces.size(); ++j) {
            const BezierCurve& piece = chain->pieces[j];
            EXPECT_EQ(piece.degree(), c.degree);
            EXPECT_EQ(piece.is_rational(), c.is_rational());
            if (j > 0) {
                EXPECT_EQ(piece.points.front(), chain->pieces[j - 1].points.back()) << what;
            }
            for (int k = 0; k <= 40; ++k) {
                const double t = k / 40.0, u = breaks[j] + t * (breaks[j + 1] - breaks[j]);
                expect_near(evaluate(piece, t), evaluate(c, u), 1e-12, what + " piece " + std::to_string(j));
            }
        }
    });
}

TEST(BSpline, SingleSpanIsTheBezierCurve) {
    for (int p = 1; p <= 8; ++p)
        for (bool rational : {false, true}) {
            BSplineCurve c =
                random_curve(p, static_cast<std::size_t>(p) + 1, 50u + static_cast<unsigned>(p), rational, true);
            c.knots = clamped_uniform_knots(c.points.size(), p, 2.0, 5.0).value();
            BezierCurve b;
            b.points = c.points;
            b.weights = c.weights;
            for (int k = 0; k <= 50; ++k)
                expect_near(evaluate(c, 2.0 + 3.0 * k / 50.0), evaluate(b, k / 50.0), 1e-13,
                            "degree " + std::to_string(p));
            auto chain = to_bezier(c);
            ASSERT_TRUE(chain);
            ASSERT_EQ(chain->pieces.size(), 1u);
            for (std::size_t i = 0; i < b.points.size(); ++i)
                expect_near(chain->pieces[0].points[i], b.points[i], 1e-14);
        }
}

TEST(BSpline, KnotInsertionPreservesTheCurve) {
    for_each_curve([](const BSplineCurve& c, const std::string& what) {
        const auto [lo, hi] = domain(c);
        std::mt19937 rng(static_cast<unsigned>(c.points.size() * 31 + static_cast<std::size_t>(c.degree)));
        std::uniform_real_distribution<double> where(lo, hi);
        // a new value, an existing interior knot, and both domain ends
        std::vector<double> candidates = {where(rng), where(rng), lo, hi};
        for (std::size_t i = static_cast<std::size_t>(c.degree) + 1; i < c.points.size(); ++i)
            candidates.push_back(c.knots[i]);
        for (double u : candidates) {
            const int s = static_cast<int>(std::count(c.knots.begin(), c.knots.end(), u));
            const int room = c.degree - s;
            if (room < 1) {
                auto refused = insert_knot(c, u, 1);
                ASSERT_FALSE(refused) << what;
                EXPECT_NE(refused.error().message.find("multiplicity"), std::string::npos);
                continue;
            }
            for (int times = 1; times <= room; ++times) {
                auto r = insert_knot(c, u, times);
                ASSERT_TRUE(r) << what << ": " << r.error().message;
                EXPECT_EQ(r->points.size(), c.points.size() + static_cast<std::size_t>(times));
                EXPECT_EQ(std::count(r->knots.begin(), r->knots.end(), u), s + times);
                ASSERT_TRUE(validate(*r)) << validate(*r).error().message;
                for (double v : sample_params(c, 60)) expect_near(evaluate(*r, v), evaluate(c, v), 1e-12, what);
            }
            EXPECT_FALSE(insert_knot(c, u, room + 1)) << what;
        }
    });
}

TEST(BSpline, KnotInsertionKnownValues) {
    // Linear B-spline: inserting u = 0.5 into [0,0,1,1] with P0=(0,0,0), P1=(2,0,0) adds the midpoint (1,0,0).
    BSplineCurve line{1, {{0, 0, 0}, {2, 0, 0}}, {0, 0, 1, 1}, {}};
    auto r = insert_knot(line, 0.5);
    ASSERT_TRUE(r);
    ASSERT_EQ(r->points.size(), 3u);
    EXPECT_EQ(r->points[1], (Vec3{1, 0, 0}));
    EXPECT_EQ(r->knots, (std::vector<double>{0, 0, 0.5, 1, 1}));
    // A quadratic Bézier with one knot at 1/2 inserted: the control points of the two halves' de Casteljau split
    // meet at C(1/2) once the knot has multiplicity 2.
    BSplineCurve q{2, {{0, 0, 0}, {1, 2, 0}, {2, 0, 0}}, {0, 0, 0, 1, 1, 1}, {}};
    auto q2 = insert_knot(q, 0.5, 2);
    ASSERT_TRUE(q2);
    ASSERT_EQ(q2->points.size(), 5u);
    expect_near(q2->points[1], {0.5, 1, 0}, 1e-15);
    expect_near(q2->points[2], {1, 1, 0}, 1e-15);
    expect_near(q2->points[3], {1.5, 1, 0}, 1e-15);
}

TEST(BSpline, ClampedEndPointsAndTangents) {
    for_each_curve([](const BSplineCurve& c, const std::string& what) {
        std::vector<double> U = c.knots;
        std::size_t p = static_cast<std::size_t>(c.degree), n = c.points.size();
        if (U.front() != U[p]) return;  // unclamped: covered below by the clamped_uniform variant
        const auto [lo, hi] = domain(c);
        if (c.is_rational()) {  // w P / w: exact up to rounding
            expect_near(evaluate(c, lo), c.points.front(), 1e-15 * (1 + norm(c.points.front())), what);
            expect_near(evaluate(c, hi), c.points.back(), 1e-15 * (1 + norm(c.points.back())), what);
            return;
        }
        EXPECT_EQ(evaluate(c, lo), c.points.front()) << what;  // bit-exact for a polynomial curve
        EXPECT_EQ(evaluate(c, hi), c.points.back()) << what;
        expect_near(derivative(c, lo, 1), (static_cast<double>(p) / (U[p + 1] - U[p])) * (c.points[1] - c.points[0]),
                    1e-11, what + " start tangent");
        expect_near(derivative(c, hi, 1),
                    (static_cast<double>(p) / (U[n] - U[n - 1])) * (c.points[n - 1] - c.points[n - 2]), 1e-11,
                    what + " end tangent");
    });
    // clamped uniform knots: the same with the helper's knot vector
    BSplineCurve c = random_curve(3, 7, 3, false, true);
    c.knots = clamped_uniform_knots(7, 3).value();
    EXPECT_EQ(c.knots, (std::vector<double>{0, 0, 0, 0, 0.25, 0.5, 0.75, 1, 1, 1, 1}));
    EXPECT_EQ(evaluate(c, 0), c.points.front());
    EXPECT_EQ(evaluate(c, 1), c.points.back());
    expect_near(derivative(c, 0, 1), 12.0 * (c.points[1] - c.points[0]), 1e-12);
    expect_near(derivative(c, 1, 1), 12.0 * (c.points[6] - c.points[5]), 1e-12);
}

TEST(BSpline, RightEndOfTheDomain) {
    for_each_curve([](const BSplineCurve& c, const std::string& what) {
        const auto [lo, hi] = domain(c);
        const std::size_t k = find_span(c.knots, c.degree, c.points.size(), hi);
        EXPECT_LT(k, c.points.size());
        EXPECT_LT(c.knots[k], c.knots[k + 1]);
        EXPECT_EQ(c.knots[k + 1], hi);
        // the value at u_max is the limit from inside: continuous with points just before it
        const double eps = (hi - lo) * 1e-9;
        expect_near(evaluate(c, hi), evaluate(c, hi - eps), 1e-5, what);
        expect_near(evaluate(c, hi), evaluate_basis(c, hi), 1e-12, what);
        // beyond the domain: clamped to it
        EXPECT_EQ(evaluate(c, hi + 10), evaluate(c, hi));
        EXPECT_EQ(evaluate(c, lo - 10), evaluate(c, lo));
        EXPECT_EQ(evaluate(c, std::nan("")), evaluate(c, lo));
    });
}

TEST(BSpline, DerivativesMatchCentralDifferences) {
    for_each_curve([](const BSplineCurve& c, const std::string& what) {
        const auto [lo, hi] = domain(c);
        const double h = (hi - lo) * 1e-5;
        for (int k = 1; k <= 39; ++k) {
            const double u = lo + (hi - lo) * (k + 0.37) / 40.0;
            // skip points within 2h of a knot: the difference quotient would straddle a non-smooth joint
            bool near_knot = false;
            for (double t : c.knots) near_knot |= std::abs(t - u) < 2 * h;
            if (near_knot) continue;
            for (int order = 1; order <= 3; ++order) {
                const Vec3 fd = (derivative(c, u + h, order - 1) - derivative(c, u - h, order - 1)) * (0.5 / h);
                const Vec3 exact = derivative(c, u, order);
                const double scale = 1.0 + norm(exact);
                EXPECT_LE(norm(fd - exact) / scale, 1e-5) << what << " order " << order << " u " << u;
            }
        }
        if (!c.is_rational()) {
            // the derivative curve gives the same first and second derivatives
            auto d1 = derivative_curve(c);
            ASSERT_TRUE(d1);
            EXPECT_EQ(d1->degree, c.degree - 1);
            for (double u : sample_params(c, 50)) {
                const Vec3 exact = derivative(c, u, 1);
                expect_near(evaluate(*d1, u), exact, 1e-11 * (1 + norm(exact)), what);
            }
            // and twice, where the first derivative curve is itself a valid spline (no interior knot of
            // multiplicity p, where C' jumps)
            if (c.degree >= 2 && validate(*d1)) {
                auto d2 = derivative_curve(*d1);
                ASSERT_TRUE(d2);
                for (double u : sample_params(c, 50)) {
                    const Vec3 exact = derivative(c, u, 2);
                    expect_near(evaluate(*d2, u), exact, 1e-10 * (1 + norm(exact)), what + " second");
                }
            }
            EXPECT_EQ(derivative(c, 0.5 * (lo + hi), c.degree + 1), Vec3{});
        }
    });
}

TEST(BSpline, NurbsCircles) {
    const double r2 = std::numbers::sqrt2 / 2;
    // quarter circle: one rational quadratic span
    BSplineCurve quarter{2, {{1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {0, 0, 0, 1, 1, 1}, {1, r2, 1}};
    // full circle, 9 points on the square, knots at quarters (The NURBS Book, ex. 7.1)
    BSplineCurve nine{
        2,
        {{1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {-1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}, {0, -1, 0}, {1, -1, 0}, {1, 0, 0}},
        {0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1},
        {1, r2, 1, r2, 1, r2, 1, r2, 1}};
    // full circle, 7 points on an equilateral triangle circumscribing it, weights 1, 1/2 (ex. 7.2)
    const double s3 = std::sqrt(3.0);
    BSplineCurve seven{
        2,
        {{s3 / 2, 0.5, 0}, {0, 2, 0}, {-s3 / 2, 0.5, 0}, {-s3, -1, 0}, {0, -1, 0}, {s3, -1, 0}, {s3 / 2, 0.5, 0}},
        {0, 0, 0, 1.0 / 3, 1.0 / 3, 2.0 / 3, 2.0 / 3, 1, 1, 1},
        {1, 0.5, 1, 0.5, 1, 0.5, 1}};
    for (const BSplineCurve* c : {&quarter, &nine, &seven}) {
        ASSERT_TRUE(validate(*c));
        for (double u : sample_params(*c, 1000)) {
            const Vec3 p = evaluate(*c, u), d1 = derivative(*c, u, 1), d2 = derivative(*c, u, 2);
            EXPECT_NEAR(norm(p), 1.0, 1e-12) << u;
            EXPECT_NEAR(p.z, 0.0, 0.0);
            EXPECT_NEAR(dot(p, d1) / norm(d1), 0.0, 1e-12) << u;  // tangent perpendicular to the radius
            EXPECT_NEAR(norm(cross(d1, d2)) / std::pow(norm(d1), 3), 1.0, 1e-9) << u;  // curvature 1
            expect_near(evaluate_basis(*c, u), p, 1e-12);
        }
        // the tessellation of a circle stays within tolerance of it: every vertex on it, every chord's midpoint
        // inside by at most tol
        auto t = tessellate(*c, options(1e-4));
        ASSERT_TRUE(t) << t.error().message;
        for (std::size_t i = 0; i + 1 < t->points.size(); ++i) {
            EXPECT_NEAR(norm(t->points[i]), 1.0, 1e-12);
            EXPECT_LE(1.0 - norm(0.5 * (t->points[i] + t->points[i + 1])), 1e-4);
        }
    }
    // the 9-point circle passes through its knot points: (1,0), (0,1), (-1,0), (0,-1)
    expect_near(evaluate(nine, 0.25), {0, 1, 0}, 1e-15);
    expect_near(evaluate(nine, 0.5), {-1, 0, 0}, 1e-15);
    expect_near(evaluate(nine, 0.75), {0, -1, 0}, 1e-15);
    EXPECT_EQ(evaluate(nine, 1.0), (Vec3{1, 0, 0}));
}

TEST(BSpline, UniformCubicIsC2AtKnots) {
    BSplineCurve c = random_curve(3, 9, 99, false, true);
    c.knots = uniform_knots(9, 3).value();
    const auto [lo, hi] = domain(c);
    EXPECT_EQ(lo, 0.0);
    EXPECT_EQ(hi, 1.0);
    double third_jump = 0;
    for (std::size_t k = 4; k < 9; ++k) {
        const double u = c.knots[k];
        for (int order = 0; order <= 2; ++order) {
            const Vec3 left = derivative(c, u, order, SpanSide::Left), right = derivative(c, u, order, SpanSide::Right);
            expect_near(left, right, 1e-10 * (1 + norm(left)),
                        "order " + std::to_string(order) + " at knot " + std::to_string(k));
        }
        // the third derivative is piecewise constant and jumps at the knots (random control points)
        third_jump =
            std::max(third_jump, norm(derivative(c, u, 3, SpanSide::Left) - derivative(c, u, 3, SpanSide::Right)));
    }
    EXPECT_GT(third_jump, 1e-3);
    // a double interior knot leaves a cubic C1 but not C2
    BSplineCurve d = c;
    d.points.pop_back();  // 8 points for 12 knots
    d.knots = {0, 0, 0, 0, 0.25, 0.5, 0.5, 0.75, 1, 1, 1, 1};
    ASSERT_TRUE(validate(d)) << validate(d).error().message;
    expect_near(derivative(d, 0.5, 1, SpanSide::Left), derivative(d, 0.5, 1, SpanSide::Right), 1e-10);
    EXPECT_GT(norm(derivative(d, 0.5, 2, SpanSide::Left) - derivative(d, 0.5, 2, SpanSide::Right)), 1e-3);
}

TEST(BSpline, ClosedUniformIsPeriodic) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> coord(-2, 2);
    std::vector<Vec3> polygon;
    for (int i = 0; i < 6; ++i) polygon.push_back({coord(rng), coord(rng), coord(rng)});
    for (int p = 1; p <= 4; ++p) {
        auto c = closed_uniform(polygon, p);
        ASSERT_TRUE(c) << c.error().message;
        EXPECT_EQ(c->points.size(), polygon.size() + static_cast<std::size_t>(p));
        for (int order = 0; order < p; ++order)
            expect_near(derivative(*c, 0.0, order), derivative(*c, 1.0, order),
                        1e-10 * (1 + norm(derivative(*c, 0.0, order))),
                        "degree " + std::to_string(p) + " order " + std::to_string(order));
    }
    EXPECT_FALSE(closed_uniform(std::vector<Vec3>(2), 3));
    EXPECT_FALSE(closed_uniform(polygon, 0));
    EXPECT_FALSE(closed_uniform(polygon, 2, std::vector<double>{1, 1}));
}

TEST(BSpline, KnotVectorHelpers) {
    const std::vector<double> uniform = uniform_knots(5, 2).value();
    const std::vector<double> expected{-2.0 / 3, -1.0 / 3, 0, 1.0 / 3, 2.0 / 3, 1, 4.0 / 3, 5.0 / 3};
    ASSERT_EQ(uniform.size(), expected.size());
    for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_NEAR(uniform[i], expected[i], 1e-15);
    EXPECT_EQ(uniform[2], 0.0);  // the domain ends are exact
    EXPECT_EQ(uniform[5], 1.0);
    EXPECT_EQ(clamped_uniform_knots(3, 2, -1, 1).value(), (std::vector<double>{-1, -1, -1, 1, 1, 1}));
    EXPECT_EQ(clamped_uniform_knots(2, 2).error().code, ErrorCode::InvalidArgument);
    EXPECT_EQ(clamped_uniform_knots(5, 0).error().code, ErrorCode::InvalidArgument);
    EXPECT_FALSE(uniform_knots(5, 2, 1, 1));
    EXPECT_FALSE(uniform_knots(5, 2, 0, std::nan("")));
}

TEST(BSpline, TessellationWithinTolerance) {
    for_each_curve([](const BSplineCurve& c, const std::string& what) {
        for (double tol : {1e-2, 1e-3}) {
            auto t = tessellate(c, options(tol));
            ASSERT_TRUE(t) << what << ": " << t.error().message;
            ASSERT_EQ(t->points.size(), t->params.size());
            EXPECT_EQ(t->segments, t->points.size() - 1);
            EXPECT_LE(t->bound, tol);
            EXPECT_LE(t->max_deviation, tol);
            const auto [lo, hi] = domain(c);
            EXPECT_EQ(t->params.front(), lo);
            EXPECT_EQ(t->params.back(), hi);
            expect_near(t->points.front(), evaluate(c, lo), 1e-12, what);
            expect_near(t->points.back(), evaluate(c, hi), 1e-12, what);
            for (std::size_t i = 0; i + 1 < t->points.size(); ++i) {
                ASSERT_LT(t->params[i], t->params[i + 1]) << what;
                expect_near(t->points[i], evaluate(c, t->params[i]), 1e-12, what);
                const Vec3 a = t->points[i], b = t->points[i + 1], ab = b - a;
                for (int j = 1; j < 6; ++j) {
                    const Vec3 q = evaluate(c, t->params[i] + (t->params[i + 1] - t->params[i]) * j / 6.0);
                    const double s = dot(ab, ab) > 0 ? std::clamp(dot(q - a, ab) / dot(ab, ab), 0.0, 1.0) : 0.0;
                    EXPECT_LE(norm(q - (a + s * ab)), tol * (1 + 1e-9)) << what;
                }
            }
        }
    });
    const BSplineCurve c = random_curve(3, 20, 4, false, true);
    auto budget = tessellate(c, options(1e-9, 100));
    ASSERT_FALSE(budget);
    EXPECT_EQ(budget.error().code, ErrorCode::BudgetExceeded);
    EXPECT_EQ(tessellate(c, options(0)).error().code, ErrorCode::InvalidArgument);
    EXPECT_EQ(tessellate(c, options(std::nan(""))).error().code, ErrorCode::InvalidArgument);
    std::atomic<bool> stop{true};
    BSplineTessellationOptions cancelled;
    cancelled.cancel.flag = &stop;
    EXPECT_EQ(tessellate(c, cancelled).error().code, ErrorCode::Cancelled);
    Cancel cancel;
    cancel.flag = &stop;
    EXPECT_EQ(to_bezier(c, cancel).error().code, ErrorCode::Cancelled);
}

GeoError invalid(const BSplineCurve& c) {
    auto v = validate(c);
    EXPECT_FALSE(v);
    return v ? GeoError{} : v.error();
}

TEST(BSpline, ValidationErrorsNameTheElement) {
    const BSplineCurve good{2, {{0, 0, 0}, {1, 1, 0}, {2, 0, 0}, {3, 1, 0}}, {0, 0, 0, 0.5, 1, 1, 1}, {}};
    ASSERT_TRUE(validate(good));

    BSplineCurve c = good;
    c.degree = 0;
    EXPECT_NE(invalid(c).message.find("degree must be >= 1"), std::string::npos);
    c = good;
    c.degree = 4;
    EXPECT_NE(invalid(c).message.find("needs at least 5 control points"), std::string::npos);
    c = good;
    c.knots.pop_back();
    EXPECT_NE(invalid(c).message.find("knots has 6 entries"), std::string::npos);
    c = good;
    c.weights = {1, 1};
    EXPECT_NE(invalid(c).message.find("weights has 2 entries"), std::string::npos);

    c = good;
    c.points[2].y = std::nan("");
    GeoError e = invalid(c);
    EXPECT_EQ(e.code, ErrorCode::NonFinite);
    EXPECT_EQ(e.element, 2);
    EXPECT_EQ(e.element_kind, ElementKind::Vertex);
    EXPECT_NE(e.message.find("control point 2"), std::string::npos);

    c = good;
    c.weights = {1, 1, -0.5, 1};
    e = invalid(c);
    EXPECT_EQ(e.element, 2);
    EXPECT_NE(e.message.find("weight 2 must be a finite number > 0"), std::string::npos);
    c.weights = {1, 1, 1, 0};
    EXPECT_EQ(invalid(c).element, 3);

    c = good;
    c.knots[4] = INFINITY;
    e = invalid(c);
    EXPECT_EQ(e.code, ErrorCode::NonFinite);
    EXPECT_EQ(e.element, 4);
    EXPECT_EQ(e.element_kind, ElementKind::None);
    EXPECT_NE(e.message.find("knot 4 is not finite"), std::string::npos);

    c = good;
    c.knots = {0, 0, 0, 1.5, 1, 1, 1};
    e = invalid(c);
    EXPECT_EQ(e.element, 4);
    EXPECT_NE(e.message.find("knot 4 (1) is smaller than knot 3 (1.5)"), std::string::npos) << e.message;

    // an interior value repeated degree + 1 times (the curve would break apart)
    c = BSplineCurve{2, std::vector<Vec3>(6), {0, 0, 0, 0.5, 0.5, 0.5, 1, 1, 1}, {}};
    e = invalid(c);
    EXPECT_EQ(e.element, 5);
    EXPECT_NE(e.message.find("the value 0.5 is repeated 3 times (from knot 3)"), std::string::npos) << e.message;
    // an end value repeated degree + 2 times
    c = BSplineCurve{2, std::vector<Vec3>(4), {0, 0, 0, 0, 1, 1, 1}, {}};
    e = invalid(c);
    EXPECT_EQ(e.element, 3);
    EXPECT_NE(e.message.find("repeated 4 times"), std::string::npos) << e.message;
    // empty domain: u_p == u_n
    c = BSplineCurve{2, std::vector<Vec3>(3), {0, 0.5, 1, 1, 2, 3}, {}};
    e = invalid(c);
    EXPECT_EQ(e.element, 3);
    EXPECT_NE(e.message.find("the domain [knots[2], knots[3]] = [1, 1] is empty"), std::string::npos) << e.message;

    // functions that validate report the same errors
    c = good;
    c.knots[4] = INFINITY;
    EXPECT_EQ(insert_knot(c, 0.5).error().element, 4);
    EXPECT_EQ(to_bezier(c).error().element, 4);
    EXPECT_EQ(tessellate(c, BSplineTessellationOptions{}).error().element, 4);
    EXPECT_EQ(derivative_curve(c).error().element, 4);
    EXPECT_NE(insert_knot(good, 1.5).error().message.find("outside the domain [0, 1]"), std::string::npos);
    EXPECT_FALSE(insert_knot(good, std::nan("")));
    EXPECT_FALSE(insert_knot(good, 0.5, -1));
    BSplineCurve rational = good;
    rational.weights = {1, 2, 1, 1};
    EXPECT_EQ(derivative_curve(rational).error().code, ErrorCode::Unsupported);
}

}  // namespace
}  // namespace surfaced
