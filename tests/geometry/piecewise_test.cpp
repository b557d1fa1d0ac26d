// Piecewise Bézier chains: parameter mapping, continuity classes on joints built with known mismatches (mixed
// degrees, rational pieces, coincident control points), the mirror rule (measured C1 afterwards, untouched pieces
// bit-identical), and tessellation of a chain against dense exact evaluation.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <random>

#include "geometry/curves/piecewise.h"

namespace surfaced {
namespace {

BezierCurve curve(std::vector<Vec3> points, std::vector<double> weights = {}) {
    BezierCurve c;
    c.points = std::move(points);
    c.weights = std::move(weights);
    return c;
}

//! Left piece of the classification tests: a cubic ending at (3, 1) with end derivative 3 ((3,1) - (2,1)) = (3, 0).
BezierCurve left_cubic() { return curve({{0, 0, 0}, {1, 0, 0}, {2, 1, 0}, {3, 1, 0}}); }

double distance_to_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 ab = b - a;
    const double len2 = dot(ab, ab);
    const double s = len2 > 0 ? std::clamp(dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    return norm(p - (a + ab * s));
}

//! A random open chain of polynomial pieces of the given degrees, meeting exactly (C0) but not C1.
BezierChain random_chain(const std::vector<int>& degrees, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> coord(-3.0, 3.0);
    BezierChain chain;
    Vec3 start{coord(rng), coord(rng), coord(rng)};
    for (int degree : degrees) {
        BezierCurve c;
        c.points.push_back(start);
        for (int i = 1; i <= degree; ++i) c.points.push_back({coord(rng), coord(rng), coord(rng)});
        start = c.points.back();
        chain.pieces.push_back(std::move(c));
    }
    return chain;
}

TEST(Piecewise, ChainParameter) {
    BezierChain chain = random_chain({3, 2, 4}, 1);
    const auto check = [&](double s, std::size_t piece, double t) {
        const ChainParameter p = chain_parameter(chain, s);
        EXPECT_EQ(p.piece, piece) << "s = " << s;
        EXPECT_EQ(p.t, t) << "s = " << s;
    };
    check(0.0, 0, 0.0);
    check(0.25, 0, 0.25);
    check(1.0, 1, 0.0);
    check(1.5, 1, 0.5);
    check(2.75, 2, 0.75);
    check(3.0, 2, 1.0);
    check(7.0, 2, 1.0);
    check(-2.0, 0, 0.0);
    check(std::nan(""), 0, 0.0);
    // the global evaluation is the piece's, and continuous across joints of a C0 chain
    EXPECT_EQ(evaluate(chain, 1.5), evaluate(chain.pieces[1], 0.5));
    for (double s : {1.0, 2.0}) {
        const Vec3 below = evaluate(chain, std::nextafter(s, 0.0)), at = evaluate(chain, s);
        EXPECT_LT(norm(below - at), 1e-12);
    }
    EXPECT_EQ(derivative(chain, 2, 0.5, 1), derivative(chain.pieces[2], 0.5, 1));
}

TEST(Piecewise, ValidateNamesThePiece) {
    BezierChain chain = random_chain({3, 3}, 2);
    ASSERT_TRUE(validate(chain).ok());
    chain.pieces[1].points[2].y = std::nan("");
    const Status s = validate(chain);
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.error().element, 1);
    EXPECT_NE(s.error().message.find("piece 1"), std::string::npos) << s.error().message;
    EXPECT_FALSE(validate(BezierChain{}).ok());
}

TEST(Piecewise, ContinuityClassesWithKnownMismatches) {
    // right pieces are quadratics (degree 2): derivative at 0 is 2 (c_1 - c_0)
    const Vec3 p{3, 1, 0};
    struct Case {
        const char* name;
        BezierCurve right;
        double gap, mismatch, angle;
        Continuity expected;
    };
    const Case cases[] = {
        // C1 across degrees 3 and 2: 3 (b3 - b2) = (3, 0) = 2 (c1 - c0) -> c1 = p + (1.5, 0)
        {"C1", curve({p, p + Vec3{1.5, 0, 0}, {6, 3, 0}}), 0.0, 0.0, 0.0, Continuity::C1},
        // G1 only: same direction, derivative (2, 0): mismatch |(3,0) - (2,0)| = 1
        {"G1", curve({p, p + Vec3{1, 0, 0}, {6, 3, 0}}), 0.0, 1.0, 0.0, Continuity::G1},
        // C0 only: a right angle, derivative (0, 2): mismatch sqrt(9 + 4)
        {"C0", curve({p, p + Vec3{0, 1, 0}, {6, 3, 0}}), 0.0, std::sqrt(13.0), std::numbers::pi / 2, Continuity::C0},
        // a gap of 0.5 (and otherwise C1: 2 (c1 - c0) = (3, 0))
        {"gap", curve({p + Vec3{0, 0.5, 0}, p + Vec3{1.5, 0.5, 0}, {6, 3, 0}}), 0.5, 0.0, 0.0, Continuity::None},
    };
    for (const Case& c : cases) {
        BezierChain chain;
        chain.pieces = {left_cubic(), c.right};
        auto report = continuity(chain);
        ASSERT_TRUE(report.ok()) << c.name;
        ASSERT_EQ(report->joints.size(), 1u);
        const JointContinuity& j = report->joints[0];
        EXPECT_EQ(j.left, 0u);
        EXPECT_EQ(j.right, 1u);
        EXPECT_NEAR(j.gap, c.gap, 1e-15) << c.name;
        EXPECT_NEAR(j.derivative_mismatch, c.mismatch, 1e-14) << c.name;
        EXPECT_NEAR(j.angle, c.angle, 1e-15) << c.name;
        EXPECT_EQ(j.continuity, c.expected) << c.name << ": got " << to_string(j.continuity);
        EXPECT_EQ(report->weakest, c.expected);
        EXPECT_EQ(report->max_gap, j.gap);
    }
}

TEST(Piecewise, RationalPiecesUseTheirActualDerivatives) {
    const double h = std::numbers::sqrt2 / 2;
    // two quarters of the unit circle in the standard form: C'(1) of the first = 2 (w1/w2)(b2 - b1) = -sqrt2 x,
    // C'(0) of the second = 2 (w1/w0)(b1 - b0) = -sqrt2 x: C1
    BezierChain chain;
    chain.pieces = {curve({{1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {1, h, 1}),
                    curve({{0, 1, 0}, {-1, 1, 0}, {-1, 0, 0}}, {1, h, 1})};
    auto report = continuity(chain);
    ASSERT_TRUE(report.ok());
    EXPECT_EQ(report->joints[0].continuity, Continuity::C1);
    EXPECT_LT(report->joints[0].derivative_mismatch, 1e-15);
    // the same first quarter reparametrised (weights 1, 2h, 4: same curve, C'(1) = 2 (2h/4)(-1, 0) = -(sqrt2/2) x):
    // still G1, the mismatch is sqrt2 - sqrt2/2
    chain.pieces[0].weights = {1, 2 * h, 4};
    EXPECT_NEAR(norm(evaluate(chain.pieces[0], 0.3)), 1.0, 1e-15);
    report = continuity(chain);
    ASSERT_TRUE(report.ok());
    EXPECT_EQ(report->joints[0].continuity, Continuity::G1);
    EXPECT_NEAR(report->joints[0].derivative_mismatch, std::numbers::sqrt2 / 2, 1e-14);
    EXPECT_NEAR(report->joints[0].angle, 0.0, 1e-15);
}

TEST(Piecewise, ZeroLengthEndDerivativesUseTheNextControlPoint) {
    // left: b2 = b3, so C'(1) = 0 and the direction comes from b3 - b1 (second derivative); right: straight on
    BezierChain chain;
    chain.pieces = {curve({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {2, 0, 0}}), curve({{2, 0, 0}, {3, 0, 0}, {4, 0, 0}})};
    auto report = continuity(chain);
    ASSERT_TRUE(report.ok());
    JointContinuity j = report->joints[0];
    EXPECT_EQ(j.left_order, 2);
    EXPECT_EQ(j.right_order, 1);
    EXPECT_EQ(j.angle, 0.0);
    EXPECT_NEAR(j.derivative_mismatch, 2.0, 1e-15);  // |0 - 2 (1, 0)|
    EXPECT_EQ(j.continuity, Continuity::G1);
    // a cusp: both first derivatives vanish (mismatch 0: parametrically C1) but the directions are opposite: C0
    chain.pieces[1] = curve({{2, 0, 0}, {2, 0, 0}, {1, 0.5, 0}, {0, 0, 0}});
    report = continuity(chain);
    ASSERT_TRUE(report.ok());
    j = report->joints[0];
    EXPECT_EQ(j.derivative_mismatch, 0.0);
    EXPECT_EQ(j.right_order, 2);
    EXPECT_NEAR(j.angle, std::numbers::pi - std::atan(0.5), 1e-15);
    EXPECT_EQ(j.continuity, Continuity::C0);
    // a piece collapsed to a point has no direction: C0 at best
    chain.pieces[1] = curve({{2, 0, 0}, {2, 0, 0}});
    report = continuity(chain);
    ASSERT_TRUE(report.ok());
    EXPECT_EQ(report->joints[0].right_order, 0);
    EXPECT_EQ(report->joints[0].continuity, Continuity::C0);
}

TEST(Piecewise, ClosedChainReportsTheClosingJoint) {
    BezierChain chain = random_chain({3, 3, 3}, 5);
    chain.pieces[2].points.back() = chain.pieces[0].points.front() + Vec3{0, 0, 0.25};
    chain.closed = true;
    auto report = continuity(chain);
    ASSERT_TRUE(report.ok());
    ASSERT_EQ(report->joints.size(), 3u);
    EXPECT_EQ(report->joints[2].left, 2u);
    EXPECT_EQ(report->joints[2].right, 0u);
    EXPECT_NEAR(report->joints[2].gap, 0.25, 1e-15);
    EXPECT_EQ(report->weakest, Continuity::None);
    EXPECT_NEAR(report->max_gap, 0.25, 1e-15);
    ContinuityOptions bad;
    bad.angle_tolerance = -1;
    EXPECT_FALSE(continuity(chain, bad).ok());
}

TEST(Piecewise, MirrorRuleAnalytic) {
    // left cubic ends at P = (3, 1) with derivative (3, 0); right quadratic starts with derivative 2 (0, 1)
    const Vec3 p{3, 1, 0};
    BezierChain chain;
    chain.pieces = {left_cubic(), curve({p, p + Vec3{0, 1, 0}, {6, 3, 0}})};
    EnforceOptions options;
    options.side = JointSide::Left;  // b2 = P - (2/3)(c1 - P)
    auto r = enforce_c1(chain, options);
    ASSERT_TRUE(r.ok());
    EXPECT_LT(norm(r->chain.pieces[0].points[2] - Vec3{3, 1 - 2.0 / 3, 0}), 1e-15);
    EXPECT_EQ(r->chain.pieces[1].points, chain.pieces[1].points);
    options.side = JointSide::Right;  // c1 = P + (3/2)(P - b2)
    r = enforce_c1(chain, options);
    ASSERT_TRUE(r.ok());
    EXPECT_LT(norm(r->chain.pieces[1].points[1] - Vec3{4.5, 1, 0}), 1e-15);
    EXPECT_EQ(r->chain.pieces[0].points, chain.pieces[0].points);
    options.side = JointSide::Both;  // D = ((3,0) + (0,2)) / 2 = (1.5, 1): b2 = P - D/3, c1 = P + D/2
    r = enforce_c1(chain, options);
    ASSERT_TRUE(r.ok());
    EXPECT_LT(norm(r->chain.pieces[0].points[2] - Vec3{2.5, 1 - 1.0 / 3, 0}), 1e-15);
    EXPECT_LT(norm(r->chain.pieces[1].points[1] - Vec3{3.75, 1.5, 0}), 1e-15);
    EXPECT_LT(r->max_derivative_mismatch, 1e-14);
}

TEST(Piecewise, EnforceC1MakesEveryJointC1) {
    const std::vector<std::vector<int>> degree_sets = {{3, 3, 3, 3}, {3, 5, 4, 3, 6}, {2, 2, 2, 2}, {2, 3, 2, 4, 2}};
    for (std::size_t set = 0; set < degree_sets.size(); ++set)
        for (JointSide side : {JointSide::Left, JointSide::Right, JointSide::Both}) {
            // Both with quadratics cannot satisfy two joints with one point: only degree >= 3 sets for Both
            const bool has_quadratic =
                std::find(degree_sets[set].begin(), degree_sets[set].end(), 2) != degree_sets[set].end();
            if (side == JointSide::Both && has_quadratic) continue;
            const BezierChain chain = random_chain(degree_sets[set], static_cast<unsigned>(10 + set));
            EnforceOptions options;
            options.side = side;
            auto r = enforce_c1(chain, options);
            ASSERT_TRUE(r.ok());
            auto report = continuity(r->chain);
            ASSERT_TRUE(report.ok());
            for (const JointContinuity& j : report->joints) {
                EXPECT_EQ(j.gap, 0.0);
                EXPECT_LT(j.derivative_mismatch, 1e-12)
                    << "set " << set << " side " << static_cast<int>(side) << " joint " << j.left;
                EXPECT_EQ(j.continuity, Continuity::C1);
            }
            EXPECT_LT(r->max_derivative_mismatch, 1e-12);
            // only the control points next to joints moved; the joint points and the rest are bit-identical
            for (std::size_t i = 0; i < chain.pieces.size(); ++i) {
                const auto& before = chain.pieces[i].points;
                const auto& after = r->chain.pieces[i].points;
                ASSERT_EQ(before.size(), after.size());
                for (std::size_t k = 0; k < before.size(); ++k)
                    if (k != 1 && k + 2 != before.size()) {
                        EXPECT_EQ(before[k], after[k]) << i << " " << k;
                    }
            }
        }
}

TEST(Piecewise, UntouchedPiecesAreBitIdentical) {
    BezierChain chain = random_chain({3, 4, 3, 5}, 21);
    chain.pieces[2].points.front() += Vec3{0.1, 0, 0};  // a gap at joint 1
    EnforceOptions options;
    options.joints = {1};
    auto r = enforce_c1(chain, options);
    ASSERT_TRUE(r.ok());
    EXPECT_EQ(r->chain.pieces[0].points, chain.pieces[0].points);
    EXPECT_EQ(r->chain.pieces[3].points, chain.pieces[3].points);
    // the gap was closed at the midpoint, and the joint is C1 now
    const Vec3 mid = 0.5 * (chain.pieces[1].points.back() + chain.pieces[2].points.front());
    EXPECT_EQ(r->chain.pieces[1].points.back(), mid);
    EXPECT_EQ(r->chain.pieces[2].points.front(), mid);
    auto report = continuity(r->chain);
    ASSERT_TRUE(report.ok());
    EXPECT_LT(report->joints[1].derivative_mismatch, 1e-12);
    EXPECT_GT(report->joints[0].derivative_mismatch, 1e-3);  // not selected: as it was
    // an already C1 chain comes back bit-identical
    auto again = enforce_c1(r->chain, options);
    ASSERT_TRUE(again.ok());
    for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(again->chain.pieces[i].points, r->chain.pieces[i].points);
}

TEST(Piecewise, EnforceG1KeepsLengths) {
    const BezierChain chain = random_chain({3, 4, 3}, 31);
    for (JointSide side : {JointSide::Left, JointSide::Right, JointSide::Both}) {
        EnforceOptions options;
        options.mode = EnforceMode::G1;
        options.side = side;
        auto r = enforce_c1(chain, options);
        ASSERT_TRUE(r.ok());
        EXPECT_LT(r->max_angle, 1e-12);
        auto report = continuity(r->chain);
        ASSERT_TRUE(report.ok());
        for (const JointContinuity& j : report->joints) EXPECT_LT(j.angle, 1e-12);
        for (std::size_t i = 0; i < chain.pieces.size(); ++i) {
            const auto& a = chain.pieces[i].points;
            const auto& b = r->chain.pieces[i].points;
            EXPECT_NEAR(norm(a[1] - a[0]), norm(b[1] - b[0]), 1e-12);
            EXPECT_NEAR(norm(a[a.size() - 1] - a[a.size() - 2]), norm(b[b.size() - 1] - b[b.size() - 2]), 1e-12);
        }
    }
}

TEST(Piecewise, EnforceClosedChain) {
    BezierChain chain = random_chain({3, 3, 4}, 41);
    chain.pieces[2].points.back() = chain.pieces[0].points.front();
    chain.closed = true;
    auto r = enforce_c1(chain);
    ASSERT_TRUE(r.ok());
    auto report = continuity(r->chain);
    ASSERT_TRUE(report.ok());
    ASSERT_EQ(report->joints.size(), 3u);
    EXPECT_EQ(report->weakest, Continuity::C1);
    EXPECT_LT(report->max_derivative_mismatch, 1e-12);
}

Result<EnforceResult> enforced(const BezierChain& chain, JointSide side, EnforceMode mode = EnforceMode::C1) {
    EnforceOptions options;
    options.side = side;
    options.mode = mode;
    return enforce_c1(chain, options);
}

TEST(Piecewise, LinesNeverMove) {
    // line, cubic, line, line: joints 0 and 1 are corrected on the cubic, joint 2 (two lines) is skipped
    BezierChain chain;
    chain.pieces = {curve({{0, 0, 0}, {1, 0, 0}}), curve({{1, 0, 0}, {1, 1, 0}, {2, 1, 0}, {2, 2, 0}}),
                    curve({{2, 2, 0}, {3, 2, 0}}), curve({{3, 2, 0}, {3, 3, 0}})};
    for (JointSide side : {JointSide::Left, JointSide::Right, JointSide::Both}) {
        auto r = enforced(chain, side);
        ASSERT_TRUE(r.ok());
        EXPECT_EQ(r->skipped_joints, std::vector<std::size_t>{2});
        EXPECT_EQ(r->chain.pieces[0].points, chain.pieces[0].points);
        EXPECT_EQ(r->chain.pieces[2].points, chain.pieces[2].points);
        EXPECT_EQ(r->chain.pieces[3].points, chain.pieces[3].points);
        // cubic: b1 = P + (1/3)(1, 0), b2 = Q - (1/3)(1, 0)
        EXPECT_LT(norm(r->chain.pieces[1].points[1] - Vec3{1 + 1.0 / 3, 0, 0}), 1e-15);
        EXPECT_LT(norm(r->chain.pieces[1].points[2] - Vec3{2 - 1.0 / 3, 2, 0}), 1e-15);
        EXPECT_LT(r->max_derivative_mismatch, 1e-14);
    }
}

// A piece of degree 0 (one point: derivative 0) next to a cubic: C1 gives the cubic a zero end derivative, G1 has no
// direction to follow and leaves it; two points next to each other are skipped. (fuzz_json_curves found the mirror
// rule reading past a one-point piece.)
TEST(Piecewise, PointPiecesNeverMoveAndNeverOverrun) {
    BezierChain chain;
    chain.pieces = {left_cubic(), curve({{3, 1, 0}}), curve({{3, 1, 0}}), curve({{3, 1, 0}, {4, 1, 0}, {5, 0, 0}})};
    for (EnforceMode mode : {EnforceMode::C1, EnforceMode::G1})
        for (JointSide side : {JointSide::Left, JointSide::Right, JointSide::Both}) {
            auto r = enforced(chain, side, mode);
            ASSERT_TRUE(r.ok());
            EXPECT_EQ(r->skipped_joints, std::vector<std::size_t>{1});
            EXPECT_EQ(r->chain.pieces[1].points, chain.pieces[1].points);
            EXPECT_EQ(r->chain.pieces[2].points, chain.pieces[2].points);
            if (mode == EnforceMode::C1) {
                EXPECT_EQ(r->chain.pieces[0].points[2], (Vec3{3, 1, 0}));  // b_2 on the joint: derivative 0
                EXPECT_EQ(r->chain.pieces[3].points[1], (Vec3{3, 1, 0}));
            } else {
                EXPECT_EQ(r->chain.pieces[0].points, chain.pieces[0].points);
                EXPECT_EQ(r->chain.pieces[3].points, chain.pieces[3].points);
            }
        }
}

TEST(Piecewise, EnforceErrors) {
    BezierChain chain = random_chain({3, 2, 3}, 51);
    chain.pieces[1].weights = {1, 2, 1};
    auto r = enforce_c1(chain);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, ErrorCode::InvalidArgument);
    EXPECT_EQ(r.error().element, 1);
    EXPECT_NE(r.error().message.find("piece 1 is rational"), std::string::npos) << r.error().message;
    chain.pieces[1].weights.clear();
    EnforceOptions options;
    options.joints = {2};  // open chain of 3 pieces: joints 0 and 1
    r = enforce_c1(chain, options);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("joint 2"), std::string::npos);
}

//! Every curve point between two consecutive polyline params is within `tolerance` of that segment.
void expect_within(const BezierChain& chain, const ChainTessellation& t, double tolerance) {
    double worst = 0;
    for (std::size_t k = 0; k + 1 < t.points.size(); ++k) {
        // the segment lies on piece floor(s0): s0 in [i, i + 1), s1 <= i + 1 (the chains here have no bridges)
        const double s0 = t.params[k], s1 = t.params[k + 1];
        const double piece = std::floor(s0);
        ASSERT_LE(s1, piece + 1);
        for (int j = 0; j <= 64; ++j) {
            const double local = std::min(1.0, s0 + (s1 - s0) * j / 64.0 - piece);
            const Vec3 q = evaluate(chain.pieces[static_cast<std::size_t>(piece)], local);
            worst = std::max(worst, distance_to_segment(q, t.points[k], t.points[k + 1]));
        }
    }
    EXPECT_LE(worst, tolerance);
    EXPECT_LE(t.bound, tolerance);
    EXPECT_LE(t.max_deviation, tolerance);
}

TEST(Piecewise, TessellationHonoursTheTolerance) {
    const double h = std::numbers::sqrt2 / 2;
    BezierChain chain = random_chain({3, 5, 2}, 61);
    const Vec3 end = chain.pieces.back().points.back();
    // a rational quarter circle of radius 2 attached at the end
    chain.pieces.push_back(curve({end, end + Vec3{2, 0, 0}, end + Vec3{2, 2, 0}}, {1, h, 1}));
    for (double tolerance : {1e-2, 1e-4}) {
        ChainTessellationOptions options;
        options.tolerance = tolerance;
        auto t = tessellate(chain, options);
        ASSERT_TRUE(t.ok()) << t.error().message;
        EXPECT_EQ(t->segments + 1, t->points.size());
        ASSERT_EQ(t->piece_start.size(), 4u);
        EXPECT_EQ(t->piece_start[0], 0u);
        for (std::size_t i = 0; i < 4; ++i) {
            EXPECT_EQ(t->points[t->piece_start[i]], chain.pieces[i].points.front());  // joints appear once
            EXPECT_EQ(t->params[t->piece_start[i]], static_cast<double>(i));
        }
        EXPECT_EQ(t->points.back(), chain.pieces.back().points.back());
        expect_within(chain, *t, tolerance);
        // the sum of the pieces' own tessellations
        std::size_t total = 0;
        for (const BezierCurve& c : chain.pieces) total += tessellate(c, tolerance)->segments;
        EXPECT_EQ(t->segments, total);
    }
}

TEST(Piecewise, TessellationClosedBudgetCancel) {
    BezierChain chain = random_chain({3, 3}, 71);
    chain.pieces.push_back(curve({chain.pieces.back().points.back(), chain.pieces.front().points.front()}));
    chain.closed = true;
    ChainTessellationOptions options;
    options.tolerance = 1e-3;
    auto t = tessellate(chain, options);
    ASSERT_TRUE(t.ok());
    EXPECT_EQ(t->points.back(), t->points.front());
    expect_within(chain, *t, 1e-3);
    // budget: the whole chain needs t->segments; one fewer is refused
    options.max_segments = t->segments - 1;
    auto small = tessellate(chain, options);
    ASSERT_FALSE(small.ok());
    EXPECT_EQ(small.error().code, ErrorCode::BudgetExceeded);
    options.max_segments = t->segments;
    EXPECT_TRUE(tessellate(chain, options).ok());
    options.tolerance = 0;
    EXPECT_EQ(tessellate(chain, options).error().code, ErrorCode::InvalidArgument);
    options.tolerance = 1e-3;
    options.cancel.deadline = Cancel::Clock::now() - std::chrono::seconds(1);  // already passed
    EXPECT_EQ(tessellate(chain, options).error().code, ErrorCode::Cancelled);
}

}  // namespace
}  // namespace surfaced
