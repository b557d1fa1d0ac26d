// Algebraic expressions (parser precedence, errors with offsets, limits), level-set grids (trilinear exactness,
// gradient, Lipschitz bound, outside extension) and fractal distance estimators (inside/outside, iteration limits).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "geometry/implicit/expression.h"
#include "geometry/implicit/fractals.h"
#include "geometry/implicit/level_set.h"

namespace surfaced::implicit {
namespace {

double eval(const std::string& text, const Vec3& p = {}) {
    auto f = parse_expression(text);
    EXPECT_TRUE(f.ok()) << text << ": " << (f.ok() ? "" : f.error().message);
    return f.ok() ? f.value()->value(p) : std::nan("");
}

GeoError error_of(const std::string& text, const ExpressionLimits& limits = {}) {
    auto f = parse_expression(text, limits);
    EXPECT_FALSE(f.ok()) << text;
    return f.ok() ? GeoError{} : f.error();
}

TEST(ImplicitExpression, PrecedenceAssociativityAndFunctions) {
    EXPECT_DOUBLE_EQ(eval("1+2*3"), 7);
    EXPECT_DOUBLE_EQ(eval("(1+2)*3"), 9);
    EXPECT_DOUBLE_EQ(eval("1-2-3"), -4);
    EXPECT_DOUBLE_EQ(eval("8/2/2"), 2);
    EXPECT_DOUBLE_EQ(eval("2^3^2"), 512);  // right associative
    EXPECT_DOUBLE_EQ(eval("-2^2"), -4);    // unary minus binds looser than ^
    EXPECT_DOUBLE_EQ(eval("(-2)^2"), 4);
    EXPECT_DOUBLE_EQ(eval("2^-1"), 0.5);
    EXPECT_DOUBLE_EQ(eval("2*-3"), -6);
    EXPECT_DOUBLE_EQ(eval("--3"), 3);
    EXPECT_DOUBLE_EQ(eval("sqrt(16) + abs(-3) + min(1, 2) + max(1, 2)"), 10);
    EXPECT_DOUBLE_EQ(eval("sin(0) + cos(0) + exp(0)"), 2);
    EXPECT_DOUBLE_EQ(eval("1.5e2 + .5 + 2E-1"), 150.7);
    EXPECT_DOUBLE_EQ(eval(" x^2 + y^2 + z^2 - 1 ", {1, 2, 3}), 13);
    EXPECT_DOUBLE_EQ(eval("x*y - z/2", {2, 3, 4}), 4);
    EXPECT_TRUE(std::isnan(eval("sqrt(x)", {-1, 0, 0})));
}

TEST(ImplicitExpression, GradientIsExact) {
    auto f = parse_expression("x^2 + y^2 + z^2 - 1");
    ASSERT_TRUE(f.ok());
    EXPECT_EQ(f.value()->kind(), FieldKind::General);
    const Vec3 g = f.value()->gradient({1, 2, 3});
    EXPECT_DOUBLE_EQ(g.x, 2);
    EXPECT_DOUBLE_EQ(g.y, 4);
    EXPECT_DOUBLE_EQ(g.z, 6);
    auto h = parse_expression("sin(x*y) + exp(z) / (1 + x^2) + max(x, -y) - sqrt(z^2 + 1)^3");
    ASSERT_TRUE(h.ok());
    const Vec3 p{0.3, -0.7, 0.4};
    const Vec3 gh = h.value()->gradient(p);
    const double e = 1e-6;
    for (int a = 0; a < 3; ++a) {
        Vec3 d;
        d[a] = e;
        EXPECT_NEAR(gh[a], (h.value()->value(p + d) - h.value()->value(p - d)) / (2 * e), 1e-6) << a;
    }
    EXPECT_GE(h.value()->lipschitz(), 1.0);
}

TEST(ImplicitExpression, MalformedInputNamesTheCharacterOffset) {
    struct Case {
        const char* text;
        std::int64_t offset;
    };
    const Case cases[] = {
        {"", 0},       {"x +", 3},      {"2x", 1},      {"(x + 1", 6}, {"foo(x)", 0},
        {"sqrt x", 5}, {"min(x)", 5},   {"1..2", 2},    {"x $ y", 2},  {"x^", 2},
        {"1e+", 3},    {"max(x, y", 8}, {"x * * y", 4}, {")", 0},      {"1e999", 0},
    };
    for (const Case& c : cases) {
        const GeoError e = error_of(c.text);
        EXPECT_EQ(e.code, ErrorCode::ParseError) << c.text;
        EXPECT_EQ(e.offset, c.offset) << c.text << ": " << e.message;
        EXPECT_NE(e.message.find("at character " + std::to_string(c.offset)), std::string::npos) << e.message;
    }
}

TEST(ImplicitExpression, SizeAndDepthLimits) {
    ExpressionLimits small;
    small.max_nodes = 5;
    EXPECT_TRUE(parse_expression("x+y+z", small).ok());  // 5 nodes
    EXPECT_EQ(error_of("x+y+z+1", small).code, ErrorCode::BudgetExceeded);
    ExpressionLimits shallow;
    shallow.max_depth = 3;
    EXPECT_TRUE(parse_expression("(x+y)*z", shallow).ok());
    EXPECT_EQ(error_of("((((x))))", shallow).code, ErrorCode::BudgetExceeded);
    EXPECT_EQ(error_of("-(-(-(-x)))", shallow).code, ErrorCode::BudgetExceeded);
    EXPECT_EQ(error_of("x+x+x+x+x", shallow).code, ErrorCode::BudgetExceeded);  // a left-leaning chain of depth 5
    // defaults: a long flat sum is too deep, deep parentheses do not overflow the stack
    std::string chain = "1";
    for (int i = 0; i < 5000; ++i) chain += "+1";
    EXPECT_EQ(error_of(chain).code, ErrorCode::BudgetExceeded);
    const GeoError deep = error_of(std::string(100000, '(') + "x" + std::string(100000, ')'));
    EXPECT_EQ(deep.code, ErrorCode::BudgetExceeded);
    EXPECT_EQ(deep.offset, 65);
}

LevelSetGrid linear_grid() {
    LevelSetGrid g;
    g.dims = {5, 4, 3};
    g.origin = {-1, -0.5, 0};
    g.spacing = {0.5, 0.25, 1};
    for (std::size_t k = 0; k < 3; ++k)
        for (std::size_t j = 0; j < 4; ++j)
            for (std::size_t i = 0; i < 5; ++i) {
                const Vec3 p = g.origin + Vec3{0.5 * double(i), 0.25 * double(j), 1.0 * double(k)};
                g.values.push_back(2 * p.x - p.y + 0.5 * p.z + 1);
            }
    return g;
}

TEST(ImplicitLevelSet, TrilinearIsExactOnLinearFields) {
    auto f = level_set(linear_grid());
    ASSERT_TRUE(f.ok());
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> ux(-1, 1), uy(-0.5, 0.25), uz(0, 2);
    for (int i = 0; i < 200; ++i) {
        const Vec3 p{ux(rng), uy(rng), uz(rng)};
        EXPECT_NEAR(f.value()->value(p), 2 * p.x - p.y + 0.5 * p.z + 1, 1e-13);
        const Vec3 g = f.value()->gradient(p);
        EXPECT_NEAR(g.x, 2, 1e-12);
        EXPECT_NEAR(g.y, -1, 1e-12);
        EXPECT_NEAR(g.z, 0.5, 1e-12);
    }
    // outside: the value at the clamped point plus the distance to the box
    const Vec3 out{2, 0, 5};
    const Vec3 c{1, 0, 2};
    EXPECT_NEAR(f.value()->value(out), 2 * c.x - c.y + 0.5 * c.z + 1 + norm(out - c), 1e-13);
}

TEST(ImplicitLevelSet, BilinearTermsAndLipschitzBound) {
    LevelSetGrid g;
    g.dims = {3, 3, 3};
    g.origin = {0, 0, 0};
    g.spacing = {1, 1, 1};
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int i = 0; i < 27; ++i) g.values.push_back(u(rng));
    const auto values = g.values;
    auto f = level_set(g);
    ASSERT_TRUE(f.ok());
    // exact at the samples and trilinear in the middle of a cell (the average of its corners)
    EXPECT_DOUBLE_EQ(f.value()->value({1, 2, 1}), values[1 + 3 * (2 + 3 * 1)]);
    double mean = 0;
    for (int dz = 0; dz < 2; ++dz)
        for (int dy = 0; dy < 2; ++dy)
            for (int dx = 0; dx < 2; ++dx) mean += values[static_cast<std::size_t>(dx + 3 * (dy + 3 * dz))] / 8;
    EXPECT_NEAR(f.value()->value({0.5, 0.5, 0.5}), mean, 1e-15);
    const double l = f.value()->lipschitz();
    std::uniform_real_distribution<double> w(-1, 3);
    for (int i = 0; i < 2000; ++i) {
        const Vec3 p{w(rng), w(rng), w(rng)}, q{w(rng), w(rng), w(rng)};
        EXPECT_LE(std::abs(f.value()->value(p) - f.value()->value(q)), l * norm(p - q) + 1e-12);
    }
    const Vec3 p{0.3, 1.7, 0.6};
    const Vec3 grad = f.value()->gradient(p);
    for (int a = 0; a < 3; ++a) {
        Vec3 d;
        d[a] = 1e-6;
        EXPECT_NEAR(grad[a], (f.value()->value(p + d) - f.value()->value(p - d)) / 2e-6, 1e-6);
    }
}

TEST(ImplicitLevelSet, RejectsInvalidGrids) {
    LevelSetGrid g = linear_grid();
    g.values.pop_back();
    EXPECT_EQ(level_set(g).error().code, ErrorCode::InvalidArgument);
    g = linear_grid();
    g.dims[2] = 1;
    EXPECT_FALSE(level_set(g).ok());
    g = linear_grid();
    g.spacing.y = 0;
    EXPECT_FALSE(level_set(g).ok());
    g = linear_grid();
    g.values[7] = std::nan("");
    EXPECT_EQ(level_set(g).error().element, 7);
}

TEST(ImplicitFractals, MandelbulbInsideOutsideAndIterationLimit) {
    const auto bulb = mandelbulb(8, 20, 2);
    EXPECT_EQ(bulb->kind(), FieldKind::DistanceBound);
    EXPECT_LT(bulb->value({0, 0, 0}), 0);
    EXPECT_LT(bulb->value({0.3, 0.2, 0.1}), 0);
    EXPECT_GT(bulb->value({1.5, 0, 0}), 0);
    EXPECT_GT(bulb->value({0, 0, 3}), 1.0);  // at least |p| - 2
    // The estimate does not overestimate the distance to the first inside point along a ray.
    for (const Vec3 dir : {Vec3{0, 0, -1}, Vec3{-1, 0, 0}, Vec3{-0.6, -0.8, 0}, Vec3{-0.48, -0.6, -0.64}}) {
        const Vec3 o = dir * -1.6;
        double first = -1;
        for (int i = 0; i <= 16000; ++i) {
            const double t = i * 1e-4;
            if (bulb->value(o + dir * t) < 0) {
                first = t;
                break;
            }
        }
        ASSERT_GT(first, 0);
        EXPECT_LE(bulb->value(o), first + 1e-4);
    }
    // Fewer iterations give a larger set: inside with 20 implies inside with 3, and some points differ.
    const auto coarse = mandelbulb(8, 3, 2);
    int differ = 0;
    for (int i = 0; i <= 400; ++i) {
        const Vec3 p{0.4 + 0.002 * i, 0.3, 0.2};
        if (bulb->value(p) < 0) {
            EXPECT_LT(coarse->value(p), 0);
        }
        differ += (bulb->value(p) < 0) != (coarse->value(p) < 0);
    }
    EXPECT_GT(differ, 0);
}

TEST(ImplicitFractals, MengerSpongeLevelsAndBound) {
    const auto solid = menger_sponge(0);
    EXPECT_DOUBLE_EQ(solid->value({2, 0, 0}), 1.0);
    EXPECT_LT(solid->value({0, 0, 0}), 0);
    const auto one = menger_sponge(1), two = menger_sponge(2), three = menger_sponge(3);
    EXPECT_GT(one->value({0, 0, 0}), 0);    // the central tunnel
    EXPECT_GT(one->value({0, 0, 0.9}), 0);  // a face tunnel
    EXPECT_LT(one->value({0.9, 0.9, 0}), 0);
    EXPECT_LT(two->value({0.9, 0.9, 0.9}), 0);
    EXPECT_GT(three->value({0.9, 0.9, 0.9}), 0);  // removed at level 3
    EXPECT_NEAR(one->value({0, 0, 0}), 1.0 / 3, 1e-15);
    const auto scaled = menger_sponge(2, 3.0);
    EXPECT_NEAR(scaled->value({0, 0, 0}), 1.0, 1e-12);
    // Lipschitz 1 (so |f| never exceeds the distance to the zero set)
    std::mt19937 rng(2);
    std::uniform_real_distribution<double> u(-1.5, 1.5);
    std::normal_distribution<double> n(0, 0.03);
    for (int i = 0; i < 5000; ++i) {
        const Vec3 p{u(rng), u(rng), u(rng)}, q = p + Vec3{n(rng), n(rng), n(rng)};
        EXPECT_LE(std::abs(three->value(p) - three->value(q)), norm(p - q) + 1e-12);
    }
}

}  // namespace
}  // namespace surfaced::implicit
