// SVG path data: every command absolute vs relative, S/T reflections against hand-computed control points, H/V, Z
// and the subpath start, implicit repeats, the number grammar's edge cases, arcs (exact end points, every point on
// the circle/ellipse), errors with byte offsets and budgets.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "geometry/curves/svg_path.h"

namespace surfaced {
namespace {

std::vector<BezierChain> parse_ok(std::string_view d, const SvgPathOptions& options = {}) {
    auto r = parse_svg_path(d, options);
    EXPECT_TRUE(r.ok()) << d << ": " << (r.ok() ? "" : r.error().message);
    return r.ok() ? *r : std::vector<BezierChain>{};
}

GeoError parse_error(std::string_view d, const SvgPathOptions& options = {}) {
    auto r = parse_svg_path(d, options);
    EXPECT_FALSE(r.ok()) << d;
    return r.ok() ? GeoError{} : r.error();
}

std::vector<Vec3> pts(std::initializer_list<std::pair<double, double>> xy) {
    std::vector<Vec3> out;
    for (const auto& p : xy) out.push_back({p.first, p.second, 0});
    return out;
}

void expect_same(const std::vector<BezierChain>& a, const std::vector<BezierChain>& b, double tol,
                 const std::string& what) {
    ASSERT_EQ(a.size(), b.size()) << what;
    for (std::size_t c = 0; c < a.size(); ++c) {
        EXPECT_EQ(a[c].closed, b[c].closed) << what;
        ASSERT_EQ(a[c].pieces.size(), b[c].pieces.size()) << what << " chain " << c;
        for (std::size_t i = 0; i < a[c].pieces.size(); ++i) {
            const BezierCurve &p = a[c].pieces[i], &q = b[c].pieces[i];
            ASSERT_EQ(p.points.size(), q.points.size()) << what << " piece " << i;
            ASSERT_EQ(p.weights.size(), q.weights.size()) << what << " piece " << i;
            for (std::size_t k = 0; k < p.points.size(); ++k)
                EXPECT_LE(norm(p.points[k] - q.points[k]), tol) << what << " piece " << i << " point " << k;
            for (std::size_t k = 0; k < p.weights.size(); ++k)
                EXPECT_NEAR(p.weights[k], q.weights[k], tol) << what << " piece " << i << " weight " << k;
        }
    }
}

TEST(SvgPath, AbsoluteAndRelativeGiveTheSameGeometry) {
    const std::pair<const char*, const char*> cases[] = {
        {"M10 20 L30 45", "m10 20 l20 25"},
        {"M10 20 H30 V-5", "M10 20 h20 v-25"},
        {"M1 1 C2 3 4 3 5 1", "M1 1 c1 2 3 2 4 0"},
        {"M1 1 C2 3 4 3 5 1 S8 -1 9 1", "M1 1 c1 2 3 2 4 0 s3 -2 4 0"},
        {"M1 1 Q2 3 4 1", "M1 1 q1 2 3 0"},
        {"M1 1 Q2 3 4 1 T7 1 T9 2", "M1 1 q1 2 3 0 t3 0 t2 1"},
        {"M0 0 A5 5 0 0 1 10 0", "M0 0 a5 5 0 0 1 10 0"},
        {"M2 3 A4 2 30 1 0 6 5", "m2 3 a4 2 30 1 0 4 2"},
        {"M1 1 L5 1 L5 5 Z L0 9", "m1 1 l4 0 l0 4 z l-1 8"},  // after z: relative to the subpath start
        {"M1 1 L5 1 Z M7 7 L8 8", "m1 1 l4 0 z m6 6 l1 1"},   // m after z: from the start (1, 1)
        {"M1 1 L2 2 M5 5 L6 7", "m1 1 1 1 m3 3 1 2"},         // implicit l after m
    };
    for (const auto& [absolute, relative] : cases) {
        const auto a = parse_ok(absolute), r = parse_ok(relative);
        ASSERT_FALSE(a.empty()) << absolute;
        expect_same(a, r, 1e-12, std::string(absolute) + " vs " + relative);
    }
}

TEST(SvgPath, PiecesAndDegrees) {
    const auto chains = parse_ok("M1 2 L3 4 H0 V-1 C1 1 2 2 3 3 Q4 4 5 5");
    ASSERT_EQ(chains.size(), 1u);
    const auto& p = chains[0].pieces;
    ASSERT_EQ(p.size(), 5u);
    EXPECT_EQ(p[0].points, pts({{1, 2}, {3, 4}}));
    EXPECT_EQ(p[1].points, pts({{3, 4}, {0, 4}}));
    EXPECT_EQ(p[2].points, pts({{0, 4}, {0, -1}}));
    EXPECT_EQ(p[3].points, pts({{0, -1}, {1, 1}, {2, 2}, {3, 3}}));
    EXPECT_EQ(p[4].points, pts({{3, 3}, {4, 4}, {5, 5}}));
    EXPECT_FALSE(chains[0].closed);
    for (const auto& piece : p) EXPECT_FALSE(piece.is_rational());
}

TEST(SvgPath, SmoothReflections) {
    // S after C: c1 = 2 (4, 0) - (3, 2) = (5, -2)
    auto c = parse_ok("M0 0 C1 2 3 2 4 0 S7 -2 8 0");
    ASSERT_EQ(c[0].pieces.size(), 2u);
    EXPECT_EQ(c[0].pieces[1].points, pts({{4, 0}, {5, -2}, {7, -2}, {8, 0}}));
    // S after S: reflects the previous S's second control point (7, -2) about (8, 0): (9, 2)
    c = parse_ok("M0 0 C1 2 3 2 4 0 S7 -2 8 0 S10 1 12 0");
    EXPECT_EQ(c[0].pieces[2].points, pts({{8, 0}, {9, 2}, {10, 1}, {12, 0}}));
    // implicit repeated S reflects too
    EXPECT_EQ(parse_ok("M0 0 C1 2 3 2 4 0 S7 -2 8 0 10 1 12 0")[0].pieces[2].points, c[0].pieces[2].points);
    // S after L, after Q, first in the path: no reflection, c1 = current point
    c = parse_ok("M0 0 L1 1 S2 3 4 4");
    EXPECT_EQ(c[0].pieces[1].points, pts({{1, 1}, {1, 1}, {2, 3}, {4, 4}}));
    c = parse_ok("M0 0 Q1 1 2 0 S3 1 4 0");
    EXPECT_EQ(c[0].pieces[1].points, pts({{2, 0}, {2, 0}, {3, 1}, {4, 0}}));
    c = parse_ok("M5 5 S6 6 7 5");
    EXPECT_EQ(c[0].pieces[0].points, pts({{5, 5}, {5, 5}, {6, 6}, {7, 5}}));
    // T after Q: c1 = 2 (2, 0) - (1, 1) = (3, -1); T after T: 2 (4, 0) - (3, -1) = (5, 1)
    c = parse_ok("M0 0 Q1 1 2 0 T4 0 T6 0");
    ASSERT_EQ(c[0].pieces.size(), 3u);
    EXPECT_EQ(c[0].pieces[1].points, pts({{2, 0}, {3, -1}, {4, 0}}));
    EXPECT_EQ(c[0].pieces[2].points, pts({{4, 0}, {5, 1}, {6, 0}}));
    // relative t after relative q (reflection uses absolute points)
    c = parse_ok("m0 0 q1 1 2 0 t2 0");
    EXPECT_EQ(c[0].pieces[1].points, pts({{2, 0}, {3, -1}, {4, 0}}));
    // T after C, after L: no reflection
    c = parse_ok("M0 0 C1 1 2 1 3 0 T5 0");
    EXPECT_EQ(c[0].pieces[1].points, pts({{3, 0}, {3, 0}, {5, 0}}));
    c = parse_ok("M0 0 L2 2 T5 0");
    EXPECT_EQ(c[0].pieces[1].points, pts({{2, 2}, {2, 2}, {5, 0}}));
    // after Z: no reflection
    c = parse_ok("M0 0 C1 1 2 1 3 0 Z S5 5 6 6");
    ASSERT_EQ(c.size(), 2u);
    EXPECT_EQ(c[1].pieces[0].points, pts({{0, 0}, {0, 0}, {5, 5}, {6, 6}}));
}

TEST(SvgPath, ClosePath) {
    auto c = parse_ok("M0 0 L1 0 L1 1 Z");
    ASSERT_EQ(c.size(), 1u);
    EXPECT_TRUE(c[0].closed);
    ASSERT_EQ(c[0].pieces.size(), 3u);
    EXPECT_EQ(c[0].pieces[2].points, pts({{1, 1}, {0, 0}}));
    // already back at the start: no extra line
    c = parse_ok("M0 0 L1 0 L0 0 z");
    ASSERT_EQ(c[0].pieces.size(), 2u);
    EXPECT_TRUE(c[0].closed);
    // a drawing command after Z starts a new chain at the subpath start
    c = parse_ok("M2 3 L4 3 L4 5 Z L9 9 Z");
    ASSERT_EQ(c.size(), 2u);
    EXPECT_EQ(c[1].pieces[0].points, pts({{2, 3}, {9, 9}}));
    EXPECT_EQ(c[1].pieces[1].points, pts({{9, 9}, {2, 3}}));
    EXPECT_TRUE(c[1].closed);
    // Z directly followed by M, and segment-less subpaths give no chain
    c = parse_ok("M0 0 Z M1 1 M2 2 L3 3 ZM5 5");
    ASSERT_EQ(c.size(), 1u);
    EXPECT_EQ(c[0].pieces[0].points, pts({{2, 2}, {3, 3}}));
    EXPECT_TRUE(parse_ok("").empty());
    EXPECT_TRUE(parse_ok(" \n\t").empty());
    EXPECT_TRUE(parse_ok("M1 2").empty());
}

TEST(SvgPath, ImplicitCommands) {
    auto c = parse_ok("M0 0 1 1 2 2");
    ASSERT_EQ(c[0].pieces.size(), 2u);
    EXPECT_EQ(c[0].pieces[1].points, pts({{1, 1}, {2, 2}}));
    c = parse_ok("m1 1 2 2 1 0");  // the pairs after m are relative l
    EXPECT_EQ(c[0].pieces[0].points, pts({{1, 1}, {3, 3}}));
    EXPECT_EQ(c[0].pieces[1].points, pts({{3, 3}, {4, 3}}));
    c = parse_ok("M0 0 C1 1 2 1 3 0 4 -1 5 -1 6 0");
    ASSERT_EQ(c[0].pieces.size(), 2u);
    EXPECT_EQ(c[0].pieces[1].points, pts({{3, 0}, {4, -1}, {5, -1}, {6, 0}}));
    c = parse_ok("M0 0 h1 2 3 v1,1");
    ASSERT_EQ(c[0].pieces.size(), 5u);
    EXPECT_EQ(c[0].pieces[2].points.back(), (Vec3{6, 0, 0}));
    EXPECT_EQ(c[0].pieces[4].points.back(), (Vec3{6, 2, 0}));
}

TEST(SvgPath, NumberSyntax) {
    const auto first_points = [](std::string_view d) {
        std::vector<Vec3> out;
        for (const auto& chain : parse_ok(d))
            for (const auto& piece : chain.pieces) out.push_back(piece.points.back());
        return out;
    };
    // "0.5.5" is two numbers, "-1-2" too; commas and whitespace mix; exponents with signs; "1." and ".5"
    EXPECT_EQ(first_points("M0.5.5L-1-2"), pts({{-1, -2}}));
    EXPECT_EQ(parse_ok("M0.5.5L-1-2")[0].pieces[0].points.front(), (Vec3{0.5, 0.5, 0}));
    EXPECT_EQ(first_points("M0,0L1e2,1E-1"), pts({{100, 0.1}}));
    EXPECT_EQ(first_points("M0 0L+.5-.5"), pts({{0.5, -0.5}}));
    EXPECT_EQ(first_points("M0 0L1.,2."), pts({{1, 2}}));
    EXPECT_EQ(first_points("M0 0L 1 , 2 ,3\n4"), pts({{1, 2}, {3, 4}}));
    EXPECT_EQ(first_points("M0 0L1e+2-2.5e-1"), pts({{100, -0.25}}));
    EXPECT_EQ(first_points("M0 0L.1.2.3.4"), pts({{0.1, 0.2}, {0.3, 0.4}}));
    EXPECT_EQ(first_points("M0 0L1e-400 7"), pts({{0, 7}}));  // underflow to 0
    EXPECT_EQ(first_points("M0 0L007 -0"), pts({{7, 0}}));
    EXPECT_EQ(first_points("M0\t0\r\nL\f3 4"), pts({{3, 4}}));
}

TEST(SvgPath, CircleArcIsExact) {
    // a semicircle of radius 10 about the origin (sweep 1: increasing angle), and the 270 degree large arc
    const struct {
        const char* d;
        double swept;
    } arcs[] = {{"M10 0 A10 10 0 0 1 -10 0", std::numbers::pi},
                {"M10 0 A10 10 0 1 0 0 10", 1.5 * std::numbers::pi},
                {"M10 0 A10 10 0 0 0 0 -10", 0.5 * std::numbers::pi},
                {"M10 0 A10 10 45 1 1 -7.0710678118654755 -7.0710678118654755", 1.25 * std::numbers::pi}};
    for (const auto& arc : arcs) {
        const auto c = parse_ok(arc.d);
        ASSERT_EQ(c.size(), 1u) << arc.d;
        const auto& pieces = c[0].pieces;
        EXPECT_EQ(pieces.front().points.front(), (Vec3{10, 0, 0})) << arc.d;  // bit-exact end points
        for (std::size_t i = 1; i < pieces.size(); ++i)
            EXPECT_EQ(pieces[i].points.front(), pieces[i - 1].points.back());
        double worst = 0, swept = 0;
        for (const auto& piece : pieces) {
            ASSERT_TRUE(piece.is_rational());
            ASSERT_EQ(piece.degree(), 2);
            const Vec3 a = piece.points.front(), b = piece.points.back();
            const double angle = std::atan2(norm(cross(a, b)), dot(a, b));
            EXPECT_LE(angle, std::numbers::pi / 2 + 1e-12);  // pieces of at most 90 degrees
            swept += angle;
            for (int k = 0; k <= 200; ++k) worst = std::max(worst, std::abs(norm(evaluate(piece, k / 200.0)) - 10));
        }
        EXPECT_LE(worst, 1e-9) << arc.d;
        EXPECT_NEAR(swept, arc.swept, 1e-9) << arc.d;
        EXPECT_EQ(pieces.size(), static_cast<std::size_t>(std::ceil(arc.swept / (std::numbers::pi / 2) - 1e-9)));
    }
    // the semicircle with sweep 1 passes through (0, 10) (angle increasing from 0 to pi)
    const auto c = parse_ok("M10 0 A10 10 0 0 1 -10 0");
    EXPECT_EQ(c[0].pieces.back().points.back(), (Vec3{-10, 0, 0}));
    EXPECT_EQ(c[0].pieces.size(), 2u);
    EXPECT_LT(norm(c[0].pieces[0].points.back() - Vec3{0, 10, 0}), 1e-12);
    // the 270 degree arc from (10, 0) to (0, 10) with sweep 0 goes through (0, -10) and (-10, 0)
    const auto large = parse_ok("M10 0 A10 10 0 1 0 0 10");
    ASSERT_EQ(large[0].pieces.size(), 3u);
    EXPECT_LT(norm(large[0].pieces[0].points.back() - Vec3{0, -10, 0}), 1e-12);
    EXPECT_LT(norm(large[0].pieces[1].points.back() - Vec3{-10, 0, 0}), 1e-12);
}

TEST(SvgPath, RotatedEllipseArc) {
    // end points computed from a known centre, radii, rotation and angles; every point must satisfy the ellipse
    const double cx = 3, cy = -2, rx = 7, ry = 3, phi_deg = 30, phi = phi_deg * std::numbers::pi / 180;
    const auto at = [&](double theta) {
        const double x = rx * std::cos(theta), y = ry * std::sin(theta);
        return Vec3{cx + std::cos(phi) * x - std::sin(phi) * y, cy + std::sin(phi) * x + std::cos(phi) * y, 0};
    };
    const auto on_ellipse = [&](const Vec3& p) {
        const double dx = p.x - cx, dy = p.y - cy;
        const double x = std::cos(phi) * dx + std::sin(phi) * dy, y = -std::sin(phi) * dx + std::cos(phi) * dy;
        return (x / rx) * (x / rx) + (y / ry) * (y / ry) - 1;
    };
    const struct {
        double t0, t1;
    } arcs[] = {{0.3, 2.0}, {0.3, -2.5}, {1.0, 1.0 + 1.9 * std::numbers::pi}, {-0.5, -0.5 - 3.5}};
    for (const auto& arc : arcs) {
        const Vec3 a = at(arc.t0), b = at(arc.t1);
        const double delta = arc.t1 - arc.t0;
        char d[256];
        std::snprintf(d, sizeof d, "M%.17g %.17g A%g %g %g %d %d %.17g %.17g", a.x, a.y, rx, ry, phi_deg,
                      std::abs(delta) > std::numbers::pi ? 1 : 0, delta > 0 ? 1 : 0, b.x, b.y);
        for (SvgArcConversion mode : {SvgArcConversion::RationalQuadratic, SvgArcConversion::Cubic}) {
            SvgPathOptions options;
            options.arcs = mode;
            const auto c = parse_ok(d, options);
            ASSERT_EQ(c.size(), 1u) << d;
            const auto& pieces = c[0].pieces;
            EXPECT_EQ(pieces.front().points.front(), a);
            EXPECT_EQ(pieces.back().points.back(), b);
            const std::size_t expected_min =
                static_cast<std::size_t>(std::ceil(std::abs(delta) / (std::numbers::pi / 2)));
            if (mode == SvgArcConversion::RationalQuadratic) {
                EXPECT_EQ(pieces.size(), expected_min) << d;
            } else {
                EXPECT_GE(pieces.size(), expected_min) << d;
            }
            double worst = 0;
            for (const auto& piece : pieces)
                for (int k = 0; k <= 200; ++k) {
                    const Vec3 p = evaluate(piece, k / 200.0);
                    worst = std::max(worst, std::abs(on_ellipse(p)));
                }
            // |on_ellipse| ~ 2 distance / radius near the curve: 1e-9 for exact arcs, the 1e-6 tolerance for cubics
            EXPECT_LE(worst, mode == SvgArcConversion::Cubic ? 2 * 1e-6 / ry : 1e-12) << d;
            // the sampled middle of the arc is the middle of the true arc
            const double mid_t0 = 0.5 * (arc.t0 + arc.t1);
            double nearest = 1e300;
            for (const auto& piece : pieces)
                for (int k = 0; k <= 400; ++k)
                    nearest = std::min(nearest, norm(evaluate(piece, k / 400.0) - at(mid_t0)));
            EXPECT_LT(nearest, 0.05) << d;
        }
    }
}

TEST(SvgPath, CubicArcsHonourTheTolerance) {
    for (double tolerance : {1e-2, 1e-4, 1e-6}) {
        SvgPathOptions options;
        options.arcs = SvgArcConversion::Cubic;
        options.arc_tolerance = tolerance;
        const auto c = parse_ok("M100 0 A100 100 0 1 1 -100 -1e-9", options);
        ASSERT_EQ(c.size(), 1u);
        double worst = 0;
        for (const auto& piece : c[0].pieces) {
            EXPECT_FALSE(piece.is_rational());
            EXPECT_EQ(piece.degree(), 3);
            for (int k = 0; k <= 200; ++k) worst = std::max(worst, std::abs(norm(evaluate(piece, k / 200.0)) - 100));
        }
        EXPECT_LE(worst, tolerance);
        EXPECT_GT(worst, tolerance / 200);  // not wastefully fine: the bound is at most twice the true error
    }
}

TEST(SvgPath, ArcSpecialCases) {
    // radii too small: scaled up so that the arc is a half circle about the chord's midpoint
    auto c = parse_ok("M0 0 A1 1 0 0 1 10 0");
    double worst = 0;
    for (const auto& piece : c[0].pieces)
        for (int k = 0; k <= 100; ++k)
            worst = std::max(worst, std::abs(norm(evaluate(piece, k / 100.0) - Vec3{5, 0, 0}) - 5));
    EXPECT_LE(worst, 1e-12);
    // zero radius: a line; same end points: omitted; negative radii: as positive
    c = parse_ok("M0 0 A0 5 0 0 1 10 0");
    ASSERT_EQ(c[0].pieces.size(), 1u);
    EXPECT_EQ(c[0].pieces[0].points, pts({{0, 0}, {10, 0}}));
    EXPECT_TRUE(parse_ok("M3 3 A5 5 0 0 1 3 3").empty());
    expect_same(parse_ok("M0 0 A-5 -5 0 0 1 10 0"), parse_ok("M0 0 A5 5 0 0 1 10 0"), 0, "negative radii");
    // compact flags: "1010 0" is flags 1, 0 then 10 0
    expect_same(parse_ok("M0 0 a5 5 0 1010 0"), parse_ok("M0 0 a5 5 0 1 0 10 0"), 0, "compact flags");
    // rejecting arcs names the A
    SvgPathOptions reject;
    reject.arcs = SvgArcConversion::Reject;
    const GeoError e = parse_error("M0 0 L1 1 A5 5 0 0 1 10 0", reject);
    EXPECT_EQ(e.offset, 10);
    EXPECT_NE(e.message.find("arcs are not accepted"), std::string::npos) << e.message;
}

TEST(SvgPath, ErrorsNameOffsetAndToken) {
    const struct {
        const char* d;
        std::int64_t offset;
        const char* text;
    } cases[] = {
        {"L1 2", 0, "must start with 'M' or 'm', found 'L1'"},
        {"  5 5", 2, "must start with 'M'"},
        {"M1 2 X3", 5, "unknown command 'X3'"},
        {"M1 2 C1 2 3", 11, "expected a number after 'C', found the end of the data"},
        {"M1 2 C1 2 3 Z", 12, "expected a number after 'C', found 'Z'"},
        {"M1 2 L3 4 Z 3 4", 12, "expected a command letter after 'Z', found '3'"},
        {"M1e999 0", 1, "number '1e999' is out of range"},
        {"M0 0 A1 1 0 2 1 5 5", 12, "expected a flag (0 or 1) after 'A', found '2'"},
        {"M0 0 L1 2,", 10, "expected a number after ','"},
        {"M0 0 L1,,2", 8, "expected a number after 'L', found ','"},
        {"M,1 2", 1, "expected a number after 'M', found ','"},
        {"M0 0 L1 2e", 9, "unknown command 'e'"},
        {"M0 0 L- 2", 6, "expected a number after 'L', found '-'"},
        {"M0 0 L1 \xff\xfe", 8, "'\\xFF\\xFE'"},
        {"M1e308 0 l1e308 0", 10, "coordinates overflow"},
    };
    for (const auto& c : cases) {
        const GeoError e = parse_error(c.d);
        EXPECT_EQ(e.code, ErrorCode::ParseError) << c.d;
        EXPECT_EQ(e.offset, c.offset) << c.d << ": " << e.message;
        EXPECT_NE(e.message.find(c.text), std::string::npos) << c.d << ": " << e.message;
        EXPECT_EQ(e.message.rfind("svg path: offset " + std::to_string(c.offset) + ": ", 0), 0u) << e.message;
    }
}

TEST(SvgPath, Budgets) {
    SvgPathOptions options;
    options.max_commands = 3;
    EXPECT_TRUE(parse_svg_path("M0 0 L1 1 2 2", options).ok());  // M + 2 L
    GeoError e = parse_error("M0 0 L1 1 2 2 3 3", options);
    EXPECT_EQ(e.code, ErrorCode::BudgetExceeded);
    EXPECT_EQ(e.offset, 14);
    options = {};
    options.max_pieces = 2;
    e = parse_error("M10 0 A10 10 0 1 0 0 10", options);  // 270 degrees: 3 pieces
    EXPECT_EQ(e.code, ErrorCode::BudgetExceeded);
    // a huge radius with a tight cubic tolerance is refused before any piece is made (no hang, no allocation)
    options = {};
    options.arcs = SvgArcConversion::Cubic;
    e = parse_error("M0 0 A1e100 1e100 0 1 1 1 0", options);
    EXPECT_EQ(e.code, ErrorCode::BudgetExceeded);
    options.arc_tolerance = 0;
    EXPECT_EQ(parse_error("M0 0 L1 1", options).code, ErrorCode::InvalidArgument);
}

}  // namespace
}  // namespace surfaced
