// B-spline and NURBS surfaces: the evaluator and its derivatives against an independent Cox-de Boor evaluator (the
// recursive definition, written here) and against central differences on random surfaces; exact shapes (sphere,
// torus, cylinder) against their analytic surfaces and normals, including the sphere's poles; knot insertion and
// Bézier decomposition leave the surface unchanged; the sphere's tessellation keeps the chord tolerance and is closed;
// every validation error.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "geometry/curves/bspline.h"
#include "geometry/surfaces/bspline_surface.h"
#include "tests/support/mesh_asserts.h"
#include "tests/support/nurbs_surfaces.h"

namespace surfaced {
namespace {

using testing::cylinder;
using testing::random_knots;
using testing::random_surface;
using testing::revolve;
using testing::sphere;
using testing::torus;

// ---- the reference: Cox-de Boor by its recursive definition ----------------------------------------------------

//! N_{i,p}(u), degree 0 the indicator of [U_i, U_{i+1}), or of (U_i, U_{i+1}] when `left` (the right end of the
//! domain, where the library takes the limit from the left); 0/0 terms are 0.
double cox_de_boor(const std::vector<double>& U, int i, int p, double u, bool left) {
    const auto at = [&](int k) { return U[static_cast<std::size_t>(k)]; };
    if (p == 0) return (left ? (at(i) < u && u <= at(i + 1)) : (at(i) <= u && u < at(i + 1))) ? 1.0 : 0.0;
    double value = 0;
    if (at(i + p) > at(i)) value += (u - at(i)) / (at(i + p) - at(i)) * cox_de_boor(U, i, p - 1, u, left);
    if (at(i + p + 1) > at(i + 1))
        value += (at(i + p + 1) - u) / (at(i + p + 1) - at(i + 1)) * cox_de_boor(U, i + 1, p - 1, u, left);
    return value;
}

//! The k-th derivative of N_{i,p}: p (N^(k-1)_{i,p-1} / (U_{i+p} - U_i) - N^(k-1)_{i+1,p-1} / (U_{i+p+1} - U_{i+1})).
double cox_de_boor_derivative(const std::vector<double>& U, int i, int p, double u, bool left, int k) {
    if (k == 0) return cox_de_boor(U, i, p, u, left);
    if (p == 0) return 0;
    const auto at = [&](int j) { return U[static_cast<std::size_t>(j)]; };
    double value = 0;
    if (at(i + p) > at(i)) value += cox_de_boor_derivative(U, i, p - 1, u, left, k - 1) / (at(i + p) - at(i));
    if (at(i + p + 1) > at(i + 1))
        value -= cox_de_boor_derivative(U, i + 1, p - 1, u, left, k - 1) / (at(i + p + 1) - at(i + 1));
    return p * value;
}

struct Reference {
    PatchDerivatives d;
    //! size of the terms summed for each derivative (k along u, l along v): the largest control point times the sums
    //! of |basis derivative| products the numerator and the quotient rule add up
    double scale[3][3] = {};
};

//! Sums over the whole net (no spans), then the quotient rule written out for orders <= 2.
Reference reference(const BSplineSurface& s, double u, double v) {
    const bool left_u = u == s.knots_u[static_cast<std::size_t>(s.count_u)];
    const bool left_v = v == s.knots_v[static_cast<std::size_t>(s.count_v)];
    Vec3 A[3][3] = {};
    double W[3][3] = {}, M[3][3] = {}, biggest = 0;
    for (const Vec3& p : s.points) biggest = std::max(biggest, norm(p));
    for (int j = 0; j < s.count_v; ++j)
        for (int i = 0; i < s.count_u; ++i)
            for (int k = 0; k <= 2; ++k)
                for (int l = 0; k + l <= 2; ++l) {
                    const double b = cox_de_boor_derivative(s.knots_u, i, s.degree_u, u, left_u, k) *
                                     cox_de_boor_derivative(s.knots_v, j, s.degree_v, v, left_v, l) * s.weight(i, j);
                    A[k][l] += b * s.at(i, j);
                    W[k][l] += b;
                    M[k][l] += std::fabs(b) * biggest;
                }
    Reference r;
    const double w = W[0][0];
    PatchDerivatives& d = r.d;
    d.position = A[0][0] * (1 / w);
    d.du = (A[1][0] - W[1][0] * d.position) * (1 / w);
    d.dv = (A[0][1] - W[0][1] * d.position) * (1 / w);
    d.duu = (A[2][0] - 2 * W[1][0] * d.du - W[2][0] * d.position) * (1 / w);
    d.dvv = (A[0][2] - 2 * W[0][1] * d.dv - W[0][2] * d.position) * (1 / w);
    d.duv = (A[1][1] - W[1][0] * d.dv - W[0][1] * d.du - W[1][1] * d.position) * (1 / w);
    // B[k][l]: the size of the basis derivatives summed (B[0][0] = 1); the quotient rule multiplies them in pairs
    for (int k = 0; k <= 2; ++k)
        for (int l = 0; k + l <= 2; ++l) {
            double sum = 0;
            for (int i = 0; i <= k; ++i)
                for (int j = 0; j <= l; ++j) sum += M[i][j] * M[k - i][l - j];
            r.scale[k][l] = sum / (biggest * w * w);
        }
    return r;
}

// ---- random surfaces ------------------------------------------------------------------------------------------

std::string describe(const BSplineSurface& s) {
    return "degrees " + std::to_string(s.degree_u) + "x" + std::to_string(s.degree_v) + " net " +
           std::to_string(s.count_u) + "x" + std::to_string(s.count_v) + (s.rational() ? " rational" : "") +
           (s.knots_u.front() == s.knots_u[static_cast<std::size_t>(s.degree_u)] ? " clamped-u" : " unclamped-u") +
           (s.knots_v.front() == s.knots_v[static_cast<std::size_t>(s.degree_v)] ? " clamped-v" : " unclamped-v");
}

//! Parameters of one direction: random values in the domain, every knot inside it, both ends.
std::vector<double> parameters(const std::vector<double>& knots, int degree, int count, std::mt19937& rng) {
    const double lo = knots[static_cast<std::size_t>(degree)], hi = knots[static_cast<std::size_t>(count)];
    std::uniform_real_distribution<double> any(lo, hi);
    std::vector<double> out{lo, hi};
    for (int k = 0; k < 5; ++k) out.push_back(any(rng));
    for (double t : knots)
        if (t > lo && t < hi) out.push_back(t);
    return out;
}

void expect_close(const Vec3& a, const Vec3& b, double tolerance, const std::string& what) {
    EXPECT_LE(norm(a - b), tolerance) << what << ": (" << a.x << ", " << a.y << ", " << a.z << ") vs (" << b.x << ", "
                                      << b.y << ", " << b.z << ")";
}

TEST(BSplineSurface, MatchesCoxDeBoorOnRandomSurfaces) {
    std::size_t compared = 0;
    for (unsigned seed = 1; seed <= 60; ++seed) {
        const BSplineSurface s = random_surface(seed);
        std::mt19937 rng(seed + 500);
        const std::string name = describe(s) + " seed " + std::to_string(seed);
        for (double u : parameters(s.knots_u, s.degree_u, s.count_u, rng))
            for (double v : parameters(s.knots_v, s.degree_v, s.count_v, rng)) {
                const auto got = evaluate_derivatives(s, u, v);
                ASSERT_TRUE(got.ok()) << got.error().message;
                const Reference r = reference(s, u, v);
                const std::string at = name + " at (" + std::to_string(u) + ", " + std::to_string(v) + ")";
                // 1e-12 relative to the size of the terms each derivative sums (and at least to its own size)
                const auto tol = [&](int k, int l, const Vec3& value) {
                    return 1e-12 * std::max(r.scale[k][l], norm(value));
                };
                expect_close(got->position, r.d.position, tol(0, 0, r.d.position), at + " position");
                expect_close(got->du, r.d.du, tol(1, 0, r.d.du), at + " du");
                expect_close(got->dv, r.d.dv, tol(0, 1, r.d.dv), at + " dv");
                expect_close(got->duu, r.d.duu, tol(2, 0, r.d.duu), at + " duu");
                expect_close(got->duv, r.d.duv, tol(1, 1, r.d.duv), at + " duv");
                expect_close(got->dvv, r.d.dvv, tol(0, 2, r.d.dvv), at + " dvv");
                const auto position = evaluate(s, u, v);
                ASSERT_TRUE(position.ok());
                expect_close(*position, r.d.position, tol(0, 0, r.d.position), at + " evaluate");
                ++compared;
                if (::testing::Test::HasFailure()) return;
            }
    }
    EXPECT_GT(compared, 3000u);
}

TEST(BSplineSurface, DerivativesMatchCentralDifferences) {
    std::size_t compared = 0;
    for (unsigned seed = 100; seed <= 140; ++seed) {
        const BSplineSurface s = random_surface(seed);
        std::mt19937 rng(seed);
        const auto [u0, u1] = domain_u(s);
        const auto [v0, v1] = domain_v(s);
        const double hu = 1e-4 * (u1 - u0), hv = 1e-4 * (v1 - v0);
        const auto far_from_knots = [](const std::vector<double>& knots, double t, double h) {
            return std::all_of(knots.begin(), knots.end(), [&](double k) { return std::fabs(k - t) > 3 * h; });
        };
        std::uniform_real_distribution<double> any_u(u0, u1), any_v(v0, v1);
        for (int trial = 0; trial < 20; ++trial) {
            const double u = any_u(rng), v = any_v(rng);
            if (!far_from_knots(s.knots_u, u, hu) || !far_from_knots(s.knots_v, v, hv)) continue;
            const auto S = [&](double a, double b) { return *evaluate(s, u + a, v + b); };
            const PatchDerivatives d = *evaluate_derivatives(s, u, v);
            const Reference r = reference(s, u, v);
            const std::string at = describe(s) + " at (" + std::to_string(u) + ", " + std::to_string(v) + ")";
            // the truncation error (relative), plus the rounding of the difference quotient: a few ulps of the
            // position divided by h^(k + l)
            const auto tol = [&](double relative, int k, int l, const Vec3& value) {
                return relative * std::max(r.scale[k][l], norm(value)) +
                       4e-15 * r.scale[0][0] / (std::pow(hu, k) * std::pow(hv, l));
            };
            expect_close(d.du, (S(hu, 0) - S(-hu, 0)) * (1 / (2 * hu)), tol(1e-6, 1, 0, d.du), at + " du");
            expect_close(d.dv, (S(0, hv) - S(0, -hv)) * (1 / (2 * hv)), tol(1e-6, 0, 1, d.dv), at + " dv");
            expect_close(d.duu, (S(hu, 0) - 2.0 * S(0, 0) + S(-hu, 0)) * (1 / (hu * hu)), tol(1e-4, 2, 0, d.duu),
                         at + " duu");
            expect_close(d.dvv, (S(0, hv) - 2.0 * S(0, 0) + S(0, -hv)) * (1 / (hv * hv)), tol(1e-4, 0, 2, d.dvv),
                         at + " dvv");
            expect_close(d.duv, (S(hu, hv) - S(hu, -hv) - S(-hu, hv) + S(-hu, -hv)) * (1 / (4 * hu * hv)),
                         tol(1e-4, 1, 1, d.duv), at + " duv");
            ++compared;
        }
    }
    EXPECT_GT(compared, 300u);
}

TEST(BSplineSurface, PolynomialDerivativesAboveTheDegreeAreZero) {
    BSplineSurface s = random_surface(7);
    s.weights.clear();
    s.degree_u = 1;
    s.knots_u = {0, 0, 0.5, 1, 1};
    s.count_u = 3;
    s.points.resize(static_cast<std::size_t>(s.count_u * s.count_v));
    ASSERT_TRUE(validate(s).ok());
    const PatchDerivatives d = *evaluate_derivatives(s, 0.3, domain_v(s).first);
    EXPECT_EQ(d.duu, Vec3{});
}

// ---- exact shapes -------------------------------------------------------------------------------------------------

struct Analytic {
    double distance;  //!< from the analytic surface
    Vec3 normal;      //!< outward unit normal at the closest point
};

template <class Shape>
void expect_exact(const BSplineSurface& s, Shape&& analytic, const std::string& name) {
    ASSERT_TRUE(validate(s).ok()) << validate(s).error().message;
    std::mt19937 rng(3);
    std::vector<double> us = parameters(s.knots_u, s.degree_u, s.count_u, rng),
                        vs = parameters(s.knots_v, s.degree_v, s.count_v, rng);
    for (int k = 0; k <= 40; ++k) {
        us.push_back(k / 40.0);
        vs.push_back(k / 40.0);
    }
    double worst_distance = 0, worst_normal = 0;
    for (double u : us)
        for (double v : vs) {
            const auto p = evaluate(s, u, v);
            const auto n = unit_normal(s, u, v);
            ASSERT_TRUE(p.ok() && n.ok());
            const Analytic a = analytic(*p);
            worst_distance = std::max(worst_distance, std::fabs(a.distance));
            worst_normal = std::max(worst_normal, norm(*n - a.normal));
            EXPECT_LE(norm(*n - a.normal), 1e-12) << name << " normal at (" << u << ", " << v << ")";
        }
    EXPECT_LE(worst_distance, 1e-12) << name;
    EXPECT_LE(worst_normal, 1e-12) << name;
}

TEST(BSplineSurface, SphereIsExactWithRadialNormalsIncludingThePoles) {
    const Vec3 c{0.5, -1, 0.25};
    const double r = 2;
    const BSplineSurface s = sphere(c, r);
    expect_exact(
        s,
        [&](const Vec3& p) {
            return Analytic{norm(p - c) - r, (p - c) * (1 / norm(p - c))};
        },
        "sphere");
    // the poles: S_u vanishes along the whole row; the normal is the limit, for every u
    for (double u : {0.0, 0.1, 0.25, 0.6, 1.0}) {
        EXPECT_LE(norm(evaluate_derivatives(s, u, 0)->du), 1e-14);
        expect_close(*evaluate(s, u, 0), c + Vec3{0, 0, -r}, 1e-15, "south pole");
        expect_close(*unit_normal(s, u, 0), Vec3{0, 0, -1}, 1e-12, "south pole normal");
        expect_close(*unit_normal(s, u, 1), Vec3{0, 0, 1}, 1e-12, "north pole normal");
    }
}

TEST(BSplineSurface, TorusIsExact) {
    const Vec3 c{-1, 2, 0.5};
    const double R = 3, r = 1;
    expect_exact(
        torus(c, R, r),
        [&](const Vec3& p) {
            const Vec3 d = p - c;
            const double rho = std::hypot(d.x, d.y);
            const Vec3 axis_point = c + Vec3{d.x * R / rho, d.y * R / rho, 0};
            return Analytic{norm(p - axis_point) - r, (p - axis_point) * (1 / norm(p - axis_point))};
        },
        "torus");
}

TEST(BSplineSurface, CylinderIsExact) {
    const Vec3 c{0.25, 0, -2};
    const double r = 1.5, h = 4;
    expect_exact(
        cylinder(c, r, h),
        [&](const Vec3& p) {
            const Vec3 d = p - c;
            const double rho = std::hypot(d.x, d.y);
            EXPECT_GE(d.z, -1e-15);
            EXPECT_LE(d.z, h + 1e-15);
            return Analytic{rho - r, Vec3{d.x / rho, d.y / rho, 0}};
        },
        "cylinder");
}

TEST(BSplineSurface, ConeApexNormalIsTheLimitAlongEachGenerator) {
    // a cone of base radius r at z = 0 and apex at z = h: the row v = 1 collapses; the surface has no tangent plane
    // there, and the normal returned is the limit along the generator of fixed u
    const Vec3 c{1, 0, -1};
    const double r = 2, h = 3;
    const BSplineSurface cone = revolve(c, {r, 0}, {0, h}, {1, 1}, {0, 0, 1, 1}, 1);
    ASSERT_TRUE(validate(cone).ok());
    for (double u : {0.0, 0.1, 0.3, 0.55, 0.8, 1.0}) {
        const Vec3 below = *evaluate(cone, u, 0.5) - c;
        const double theta = std::atan2(below.y, below.x);
        const Vec3 expected = Vec3{h * std::cos(theta), h * std::sin(theta), r} * (1 / std::hypot(h, r));
        expect_close(*evaluate(cone, u, 1), c + Vec3{0, 0, h}, 1e-15, "apex");
        expect_close(*unit_normal(cone, u, 1), expected, 1e-12, "apex normal at u " + std::to_string(u));
        expect_close(*unit_normal(cone, u, 0.5), expected, 1e-12, "normal at u " + std::to_string(u));
    }
}

TEST(BSplineSurface, OutOfDomainIsInvalidArgument) {
    const BSplineSurface s = sphere({}, 1);
    for (auto [u, v] :
         {std::pair{-1e-9, 0.5}, {1.0 + 1e-9, 0.5}, {0.5, -0.1}, {0.5, 2.0}, {NAN, 0.5}, {0.5, INFINITY}}) {
        for (const GeoError& e :
             {evaluate(s, u, v).error(), evaluate_derivatives(s, u, v).error(), unit_normal(s, u, v).error()}) {
            EXPECT_EQ(e.code, ErrorCode::InvalidArgument);
            EXPECT_NE(e.message.find("outside the domain [0, 1]"), std::string::npos) << e.message;
        }
    }
    EXPECT_TRUE(evaluate(s, 0, 0).ok());
    EXPECT_TRUE(evaluate(s, 1, 1).ok());
}

// ---- knot insertion and Bézier form ----------------------------------------------------------------------------

//! Compares two surfaces with the same domain at random parameters and at the knots of both.
void expect_same_surface(const BSplineSurface& a, const BSplineSurface& b, const std::string& what) {
    std::mt19937 rng(11);
    for (double u : parameters(a.knots_u, a.degree_u, a.count_u, rng))
        for (double v : parameters(a.knots_v, a.degree_v, a.count_v, rng)) {
            const PatchDerivatives x = *evaluate_derivatives(a, u, v), y = *evaluate_derivatives(b, u, v);
            const Reference r = reference(a, u, v);
            const std::string at = what + " at (" + std::to_string(u) + ", " + std::to_string(v) + ")";
            expect_close(x.position, y.position, 1e-12 * r.scale[0][0], at + " position");
            expect_close(x.du, y.du, 1e-12 * r.scale[1][0], at + " du");
            expect_close(x.dv, y.dv, 1e-12 * r.scale[0][1], at + " dv");
            expect_close(x.duv, y.duv, 1e-12 * r.scale[1][1], at + " duv");
            if (::testing::Test::HasFailure()) return;
        }
}

TEST(BSplineSurface, KnotInsertionLeavesTheSurfaceUnchanged) {
    for (unsigned seed = 1; seed <= 30; ++seed) {
        const BSplineSurface s = random_surface(seed);
        std::mt19937 rng(seed);
        BSplineSurface refined = s;
        for (SurfaceDirection d : {SurfaceDirection::U, SurfaceDirection::V}) {
            const bool along_u = d == SurfaceDirection::U;
            const auto [lo, hi] = along_u ? domain_u(refined) : domain_v(refined);
            const int degree = along_u ? s.degree_u : s.degree_v;
            std::uniform_real_distribution<double> any(lo, hi);
            // a new value to full multiplicity, then an existing interior knot up to the degree where possible
            const double fresh = any(rng);
            auto once = insert_knot(refined, d, fresh, degree);
            ASSERT_TRUE(once.ok()) << once.error().message;
            EXPECT_EQ((along_u ? once->count_u : once->count_v),
                      (along_u ? refined.count_u : refined.count_v) + degree);
            refined = std::move(*once);
            const std::vector<double>& knots = along_u ? refined.knots_u : refined.knots_v;
            EXPECT_TRUE(std::is_sorted(knots.begin(), knots.end()));
            for (double t : std::vector<double>(knots)) {
                if (!(t > lo && t < hi)) continue;
                const auto have = std::count(knots.begin(), knots.end(), t);
                if (have >= degree) continue;
                auto again = insert_knot(refined, d, t, 1);
                ASSERT_TRUE(again.ok()) << again.error().message;
                refined = std::move(*again);
                break;
            }
        }
        ASSERT_TRUE(validate(refined).ok());
        expect_same_surface(s, refined, describe(s) + " seed " + std::to_string(seed));
        if (::testing::Test::HasFailure()) return;
    }
}

TEST(BSplineSurface, DegreeElevationLeavesTheSurfaceUnchanged) {
    for (unsigned seed = 1; seed <= 40; ++seed) {
        const BSplineSurface s = random_surface(seed);
        for (SurfaceDirection d : {SurfaceDirection::U, SurfaceDirection::V}) {
            const bool along_u = d == SurfaceDirection::U;
            const int times = 1 + static_cast<int>(seed % 3);
            auto elevated = elevate_degree(s, d, times);
            ASSERT_TRUE(elevated.ok()) << describe(s) << ": " << elevated.error().message;
            ASSERT_TRUE(validate(*elevated).ok()) << describe(s) << ": " << validate(*elevated).error().message;
            EXPECT_EQ(along_u ? elevated->degree_u : elevated->degree_v, (along_u ? s.degree_u : s.degree_v) + times);
            EXPECT_EQ(domain_u(*elevated), domain_u(s));
            EXPECT_EQ(domain_v(*elevated), domain_v(s));
            // every distinct knot value gains `times` copies: the continuity is kept
            const std::vector<double>& before = along_u ? s.knots_u : s.knots_v;
            const std::vector<double>& after = along_u ? elevated->knots_u : elevated->knots_v;
            const double lo = along_u ? domain_u(s).first : domain_v(s).first;
            const double hi = along_u ? domain_u(s).second : domain_v(s).second;
            for (double t : before) {
                if (!(t > lo && t < hi)) continue;
                EXPECT_EQ(std::count(after.begin(), after.end(), t),
                          std::count(before.begin(), before.end(), t) + times)
                    << describe(s) << " knot " << t;
            }
            expect_same_surface(s, *elevated,
                                describe(s) + " elevated " + std::to_string(times) + " seed " + std::to_string(seed));
            if (::testing::Test::HasFailure()) return;
        }
    }
}

TEST(BSplineSurface, DegreeElevationOfTheSphereKeepsItExactAndThePolesPoints) {
    const BSplineSurface s = sphere({1, -2, 0.5}, 2.0);
    auto elevated = elevate_degree(s, SurfaceDirection::V, 2);
    ASSERT_TRUE(elevated.ok()) << elevated.error().message;
    auto both = elevate_degree(*elevated, SurfaceDirection::U, 1);
    ASSERT_TRUE(both.ok()) << both.error().message;
    EXPECT_EQ(both->degree_u, 3);
    EXPECT_EQ(both->degree_v, 4);
    for (int j : {0, both->count_v - 1})
        for (int i = 1; i < both->count_u; ++i) EXPECT_EQ(both->at(i, j), both->at(0, j)) << "pole row " << j;
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> any(0.0, 1.0);
    for (int k = 0; k < 200; ++k) {
        const Vec3 x = *evaluate(*both, any(rng), any(rng));
        EXPECT_NEAR(norm(x - Vec3{1, -2, 0.5}), 2.0, 1e-13);
    }
}

TEST(BSplineSurface, DegreeElevationErrors) {
    const BSplineSurface s = sphere({0, 0, 0}, 1.0);
    EXPECT_EQ(elevate_degree(s, SurfaceDirection::U, -1).error().code, ErrorCode::InvalidArgument);
    auto too_far = elevate_degree(s, SurfaceDirection::U, kMaxBSplineSurfaceDegree);
    ASSERT_FALSE(too_far.ok());
    EXPECT_NE(too_far.error().message.find("largest degree"), std::string::npos) << too_far.error().message;
    auto top = elevate_degree(s, SurfaceDirection::U, kMaxBSplineSurfaceDegree - 2);
    ASSERT_TRUE(top.ok()) << top.error().message;
    EXPECT_EQ(top->degree_u, kMaxBSplineSurfaceDegree);
    auto same = elevate_degree(s, SurfaceDirection::V, 0);
    ASSERT_TRUE(same.ok());
    EXPECT_EQ(same->points, s.points);
}

TEST(BSplineSurface, KnotInsertionKeepsThePoleAPoint) {
    const BSplineSurface s = sphere({}, 1);
    auto refined = insert_knot(s, SurfaceDirection::U, 0.3, 2);
    ASSERT_TRUE(refined.ok());
    refined = insert_knot(*refined, SurfaceDirection::V, 0.8, 1);
    ASSERT_TRUE(refined.ok());
    for (int i = 0; i < refined->count_u; ++i) {
        EXPECT_EQ(refined->at(i, 0), (Vec3{0, 0, -1}));
        EXPECT_EQ(refined->at(i, refined->count_v - 1), (Vec3{0, 0, 1}));
    }
    expect_same_surface(s, *refined, "sphere");
}

TEST(BSplineSurface, BezierDecompositionEqualsTheSurfacePatchByPatch) {
    for (unsigned seed = 1; seed <= 40; ++seed) {
        const BSplineSurface s = random_surface(seed);
        auto bezier = to_bezier(s);
        ASSERT_TRUE(bezier.ok()) << bezier.error().message;
        const std::size_t nu = bezier->breaks_u.size() - 1, nv = bezier->breaks_v.size() - 1;
        ASSERT_EQ(bezier->patches.size(), nu * nv);
        EXPECT_EQ(bezier_patch_count(s), nu * nv);
        ASSERT_TRUE(validate(std::span<const BezierPatch>(bezier->patches)).ok());
        std::mt19937 rng(seed);
        std::uniform_real_distribution<double> unit(0, 1);
        for (std::size_t b = 0; b < nv; ++b)
            for (std::size_t a = 0; a < nu; ++a) {
                const BezierPatch& patch = bezier->patches[b * nu + a];
                EXPECT_EQ(patch.degree_u, s.degree_u);
                EXPECT_EQ(patch.degree_v, s.degree_v);
                EXPECT_EQ(patch.rational(), s.rational());
                const double u0 = bezier->breaks_u[a], lu = bezier->breaks_u[a + 1] - u0;
                const double v0 = bezier->breaks_v[b], lv = bezier->breaks_v[b + 1] - v0;
                for (int k = 0; k < 8; ++k) {
                    const double x = k < 2 ? k : unit(rng), y = k < 2 ? 1 - k : unit(rng);
                    const double u = std::min(u0 + x * lu, bezier->breaks_u[a + 1]);
                    const double v = std::min(v0 + y * lv, bezier->breaks_v[b + 1]);
                    const Reference r = reference(s, u, v);
                    const PatchDerivatives d = evaluate_derivatives(patch, x, y);
                    const std::string at =
                        describe(s) + " patch (" + std::to_string(a) + ", " + std::to_string(b) + ")";
                    expect_close(d.position, r.d.position, 1e-12 * r.scale[0][0], at + " position");
                    // the patch's parameter runs over [0, 1]: its derivatives are the surface's times the span lengths
                    if (x > 0 && x < 1 && y > 0 && y < 1) {
                        expect_close(d.du, r.d.du * lu, 1e-12 * r.scale[1][0] * lu, at + " du");
                        expect_close(d.dv, r.d.dv * lv, 1e-12 * r.scale[0][1] * lv, at + " dv");
                    }
                }
                ASSERT_TRUE(patch.corner_uvs.has_value());
                EXPECT_EQ((*patch.corner_uvs)[3].x, bezier->breaks_u[a + 1]);
                EXPECT_EQ((*patch.corner_uvs)[3].y, bezier->breaks_v[b + 1]);
                // neighbours share their edge's control points and weights bit for bit
                if (a > 0) {
                    const BezierPatch& left = bezier->patches[b * nu + a - 1];
                    for (int j = 0; j <= s.degree_v; ++j) {
                        EXPECT_EQ(left.at(s.degree_u, j), patch.at(0, j));
                        EXPECT_EQ(left.weight(s.degree_u, j), patch.weight(0, j));
                    }
                }
                if (b > 0) {
                    const BezierPatch& below = bezier->patches[(b - 1) * nu + a];
                    for (int i = 0; i <= s.degree_u; ++i) {
                        EXPECT_EQ(below.at(i, s.degree_v), patch.at(i, 0));
                        EXPECT_EQ(below.weight(i, s.degree_v), patch.weight(i, 0));
                    }
                }
            }
        if (::testing::Test::HasFailure()) return;
    }
}

// ---- tessellation ---------------------------------------------------------------------------------------------

TEST(BSplineSurface, SphereTessellationKeepsTheToleranceAndIsClosed) {
    const Vec3 c{0.5, -1, 0.25};
    const double r = 2;
    const BSplineSurface s = sphere(c, r);
    for (double tolerance : {0.02, 0.002}) {
        TessellationOptions options;
        options.tolerance = tolerance;
        auto result = tessellate(s, options);
        ASSERT_TRUE(result.ok()) << result.error().message;
        const PolygonMesh& mesh = result->mesh;
        EXPECT_LE(result->plan.error_bound, tolerance);
        for (const Vec3& p : mesh.positions) EXPECT_NEAR(norm(p - c), r, 1e-12);
        // dense samples of every triangle: inside the ball (chords) and within the tolerance of the sphere; and within
        // the tolerance of the surface point at the same (interpolated) surface parameters
        double worst = 0, worst_parametric = 0;
        constexpr int samples = 6;
        for (std::size_t f = 0; f < mesh.face_count(); ++f) {
            const auto face = mesh.face(f);
            const std::size_t base = mesh.face_offsets[f];
            for (int a = 0; a <= samples; ++a)
                for (int b = 0; a + b <= samples; ++b) {
                    const double l1 = static_cast<double>(a) / samples, l2 = static_cast<double>(b) / samples;
                    const double l0 = 1 - l1 - l2;
                    const Vec3 x =
                        l0 * mesh.positions[face[0]] + l1 * mesh.positions[face[1]] + l2 * mesh.positions[face[2]];
                    worst = std::max(worst, r - norm(x - c));
                    EXPECT_LE(norm(x - c), r + 1e-12);
                    const Vec2 t0 = mesh.uvs[mesh.uv_indices[base]], t1 = mesh.uvs[mesh.uv_indices[base + 1]],
                               t2 = mesh.uvs[mesh.uv_indices[base + 2]];
                    const double u = std::clamp(l0 * t0.x + l1 * t1.x + l2 * t2.x, 0.0, 1.0);
                    const double v = std::clamp(l0 * t0.y + l1 * t1.y + l2 * t2.y, 0.0, 1.0);
                    worst_parametric = std::max(worst_parametric, norm(x - *evaluate(s, u, v)));
                }
        }
        EXPECT_LE(worst, tolerance);
        EXPECT_LE(worst_parametric, tolerance);
        EXPECT_GT(worst, tolerance / 20) << "the bound should not be wildly pessimistic on a sphere";
        // closed: the seam (first and last column of the net) and the poles are welded
        const testing::EdgeStats stats = testing::edge_stats(mesh);
        EXPECT_EQ(stats.boundary_edges, 0u) << "tolerance " << tolerance;
        EXPECT_EQ(stats.non_manifold_edges, 0u);
        EXPECT_EQ(stats.inconsistent_edges, 0u);
        EXPECT_TRUE(testing::is_watertight(mesh));
        EXPECT_EQ(testing::euler_characteristic(mesh), 2);
        EXPECT_GT(testing::signed_volume(mesh), 0.0);  // outward
        for (std::size_t k = 0; k < mesh.positions.size(); ++k)
            EXPECT_NEAR(dot(mesh.normals[k], (mesh.positions[k] - c) * (1 / r)), 1.0, 1e-9);
    }
}

TEST(BSplineSurface, TorusTessellationIsClosed) {
    const BSplineSurface s = torus({}, 3, 1);
    TessellationOptions options;
    options.tolerance = 0.01;
    auto result = tessellate(s, options);
    ASSERT_TRUE(result.ok()) << result.error().message;
    const testing::EdgeStats stats = testing::edge_stats(result->mesh);
    EXPECT_EQ(stats.boundary_edges, 0u);
    EXPECT_EQ(stats.non_manifold_edges, 0u);
    EXPECT_TRUE(testing::is_watertight(result->mesh));
    EXPECT_EQ(testing::euler_characteristic(result->mesh), 0);
    EXPECT_EQ(result->face_patches.size(), result->mesh.face_count());
}

//! A periodic cubic torus-like surface: an 8 x 6 ring of points on a torus, the first 3 columns and rows repeated at
//! the end, uniform (unclamped) knots; optionally with weights periodic like the points.
BSplineSurface periodic_torus(bool rational) {
    constexpr int n = 8, m = 6, p = 3;
    BSplineSurface s;
    s.degree_u = s.degree_v = p;
    s.count_u = n + p;
    s.count_v = m + p;
    s.knots_u = *uniform_knots(static_cast<std::size_t>(s.count_u), p);
    s.knots_v = *uniform_knots(static_cast<std::size_t>(s.count_v), p);
    for (int j = 0; j < s.count_v; ++j)
        for (int i = 0; i < s.count_u; ++i) {
            const double theta = 2 * std::numbers::pi * (i % n) / n, phi = 2 * std::numbers::pi * (j % m) / m;
            const double rho = 3 + std::cos(phi);
            s.points.push_back({rho * std::cos(theta), rho * std::sin(theta), std::sin(phi)});
            if (rational) s.weights.push_back(1 + 0.3 * (i % n % 3) + 0.2 * (j % m % 2));
        }
    return s;
}

TEST(BSplineSurface, PeriodicSeamsAreWelded) {
    for (bool rational : {false, true}) {
        const BSplineSurface s = periodic_torus(rational);
        ASSERT_TRUE(validate(s).ok()) << validate(s).error().message;
        auto bezier = to_bezier(s);
        ASSERT_TRUE(bezier.ok());
        const std::size_t nu = bezier->breaks_u.size() - 1, nv = bezier->breaks_v.size() - 1;
        for (std::size_t b = 0; b < nv; ++b)
            for (int j = 0; j <= 3; ++j) {
                EXPECT_EQ(bezier->patches[b * nu].at(0, j), bezier->patches[b * nu + nu - 1].at(3, j));
                EXPECT_EQ(bezier->patches[b * nu].weight(0, j), bezier->patches[b * nu + nu - 1].weight(3, j));
            }
        // still the surface: the seam moved by rounding only
        for (std::size_t b = 0; b < nv; ++b)
            for (double y : {0.0, 0.3, 1.0}) {
                const double v = bezier->breaks_v[b] + y * (bezier->breaks_v[b + 1] - bezier->breaks_v[b]);
                expect_close(evaluate(bezier->patches[b * nu + nu - 1], 1, y), *evaluate(s, 1, std::min(v, 1.0)), 1e-13,
                             "seam");
            }
        TessellationOptions options;
        options.tolerance = 0.01;
        auto result = tessellate(s, options);
        ASSERT_TRUE(result.ok()) << result.error().message;
        const testing::EdgeStats stats = testing::edge_stats(result->mesh);
        EXPECT_EQ(stats.boundary_edges, 0u) << (rational ? "rational" : "polynomial");
        EXPECT_EQ(stats.non_manifold_edges, 0u);
        EXPECT_TRUE(testing::is_watertight(result->mesh));
        EXPECT_EQ(testing::euler_characteristic(result->mesh), 0);
    }
}

TEST(BSplineSurface, TessellationOfRandomSurfacesKeepsTheTolerance) {
    for (unsigned seed = 1; seed <= 12; ++seed) {
        const BSplineSurface s = random_surface(seed);
        TessellationOptions options;
        options.tolerance = 0.05;
        options.max_segments = 2048;
        auto result = tessellate(s, options);
        ASSERT_TRUE(result.ok()) << result.error().message;
        const PolygonMesh& mesh = result->mesh;
        // no cracks between the Bézier patches: the only boundary is the surface's own (4 sides)
        EXPECT_EQ(testing::boundary_loop_count(mesh), 1u) << describe(s);
        double worst = 0;
        for (std::size_t f = 0; f < mesh.face_count(); ++f) {
            const auto face = mesh.face(f);
            const std::size_t base = mesh.face_offsets[f];
            for (int a = 0; a <= 3; ++a)
                for (int b = 0; a + b <= 3; ++b) {
                    const double l1 = a / 3.0, l2 = b / 3.0, l0 = 1 - l1 - l2;
                    const Vec3 x =
                        l0 * mesh.positions[face[0]] + l1 * mesh.positions[face[1]] + l2 * mesh.positions[face[2]];
                    const Vec2 t0 = mesh.uvs[mesh.uv_indices[base]], t1 = mesh.uvs[mesh.uv_indices[base + 1]],
                               t2 = mesh.uvs[mesh.uv_indices[base + 2]];
                    const auto [u0, u1] = domain_u(s);
                    const auto [v0, v1] = domain_v(s);
                    const double u = std::clamp(l0 * t0.x + l1 * t1.x + l2 * t2.x, u0, u1);
                    const double v = std::clamp(l0 * t0.y + l1 * t1.y + l2 * t2.y, v0, v1);
                    worst = std::max(worst, norm(x - *evaluate(s, u, v)));
                }
        }
        EXPECT_LE(worst, 0.05) << describe(s);
    }
}

// ---- validation -------------------------------------------------------------------------------------------------

void expect_error(const BSplineSurface& s, ErrorCode code, const std::string& text, std::int64_t element = -1,
                  ElementKind kind = ElementKind::None) {
    const Status status = validate(s);
    ASSERT_FALSE(status.ok()) << "expected: " << text;
    EXPECT_EQ(status.error().code, code) << status.error().message;
    EXPECT_NE(status.error().message.find(text), std::string::npos) << status.error().message;
    EXPECT_EQ(status.error().element, element) << status.error().message;
    EXPECT_EQ(status.error().element_kind, kind) << status.error().message;
}

TEST(BSplineSurface, ValidationErrors) {
    const BSplineSurface good = sphere({}, 1);
    ASSERT_TRUE(validate(good).ok());
    BSplineSurface s = good;
    s.degree_u = 0;
    expect_error(s, ErrorCode::InvalidArgument, "degree_u 0 is outside 1..15");
    s = good;
    s.degree_v = 16;
    expect_error(s, ErrorCode::InvalidArgument, "degree_v 16 is outside 1..15");
    s = good;
    s.degree_v = 5;
    expect_error(s, ErrorCode::InvalidArgument, "count_v is 5; degree 5 along v needs at least 6 control points");
    s = good;
    s.knots_u.pop_back();
    expect_error(s, ErrorCode::InvalidArgument,
                 "knots_u has 11 entries; 9 control points along u of degree 2 need 12 (count_u + degree_u + 1)");
    s = good;
    s.knots_v.push_back(1);
    expect_error(s, ErrorCode::InvalidArgument,
                 "knots_v has 9 entries; 5 control points along v of degree 2 need 8 (count_v + degree_v + 1)");
    s = good;
    s.points.pop_back();
    expect_error(s, ErrorCode::InvalidArgument, "points has 44 entries; a net of 9 x 5 (count_u x count_v) needs 45");
    s = good;
    s.weights.pop_back();
    expect_error(s, ErrorCode::InvalidArgument, "weights has 44 entries for 45 control points");
    s = good;
    s.points[21].y = NAN;
    expect_error(s, ErrorCode::NonFinite, "control point 21 (i 3, j 2) is not finite", 21, ElementKind::Vertex);
    s = good;
    s.weights[10] = 0;
    expect_error(s, ErrorCode::InvalidArgument, "weight 10 (i 1, j 1) must be a finite number > 0 (got 0)", 10,
                 ElementKind::Vertex);
    s.weights[10] = -1;
    expect_error(s, ErrorCode::InvalidArgument, "weight 10 (i 1, j 1) must be a finite number > 0 (got -1)", 10,
                 ElementKind::Vertex);
    s.weights[10] = INFINITY;
    expect_error(s, ErrorCode::InvalidArgument, "weight 10 (i 1, j 1) must be a finite number > 0", 10,
                 ElementKind::Vertex);
    s = good;
    s.points[12] = {1e300, 0, 0};
    s.weights[12] = 1e10;
    expect_error(s, ErrorCode::InvalidArgument, "weight 12 (i 3, j 1) times its control point overflows", 12,
                 ElementKind::Vertex);
    s = good;
    s.weights[12] = 1e13;
    expect_error(s, ErrorCode::InvalidArgument, "is more than 1e12 times the smallest");
    s = good;
    s.knots_u[4] = INFINITY;
    expect_error(s, ErrorCode::NonFinite, "knots_u[4] is not finite", 4);
    s = good;
    s.knots_v[4] = 0.25;
    expect_error(s, ErrorCode::InvalidArgument,
                 "knots_v[4] (0.25) is smaller than knots_v[3] (0.5): knots must be non-decreasing", 4);
    s = good;
    s.knots_v = {0, 0, 0, 0.5, 0.5, 0.5, 1, 1};
    expect_error(s, ErrorCode::InvalidArgument,
                 "knots_v[5]: the value 0.5 is repeated 3 times (from knots_v[3]); at most degree + 1 = 3 for the "
                 "first or last value, degree = 2 for any other",
                 5);
    s = good;
    s.knots_u = {0, 0, 0, 0, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1};
    expect_error(s, ErrorCode::InvalidArgument, "knots_u[3]: the value 0 is repeated 4 times", 3);
    s = good;
    s.knots_v = {0, 0, 1, 1, 1, 1, 1, 1};  // clamped start, but the domain [V[2], V[5]] is [1, 1]
    expect_error(s, ErrorCode::InvalidArgument, "knots_v[5]: the value 1 is repeated 6 times", 5);
    s = good;
    s.count_v = 3;
    s.knots_v = {0, 0, 0, 0, 0, 0};
    s.points.resize(27);
    s.weights.resize(27);
    expect_error(s, ErrorCode::InvalidArgument, "knots_v[3]: the value 0 is repeated 6 times", 3);
    // an empty domain with legal multiplicities: unclamped, U[p] == U[n]
    s = good;
    s.degree_v = 1;
    s.count_v = 5;
    s.knots_v = {0, 1, 2, 2, 2, 3, 4};
    expect_error(s, ErrorCode::InvalidArgument, "knots_v[3]: the value 2 is repeated 3 times", 3);
    s.degree_v = 2;
    s.count_v = 3;
    s.points.resize(27);
    s.weights.resize(27);
    s.knots_v = {0, 0.5, 1, 1, 2, 3};
    expect_error(s, ErrorCode::InvalidArgument, "knots_v: the domain [knots_v[2], knots_v[3]] = [1, 1] is empty", 3);
}

TEST(BSplineSurface, InsertKnotDecompositionAndTessellationErrors) {
    const BSplineSurface s = sphere({}, 1);
    auto outside = insert_knot(s, SurfaceDirection::V, 1.5);
    ASSERT_FALSE(outside.ok());
    EXPECT_NE(outside.error().message.find("the knot v = 1.5 is outside the domain [0, 1]"), std::string::npos);
    auto too_many = insert_knot(s, SurfaceDirection::U, 0.25, 1);
    ASSERT_FALSE(too_many.ok());
    EXPECT_NE(too_many.error().message.find("already has multiplicity 2; inserting it 1 more times would exceed the "
                                            "degree 2"),
              std::string::npos)
        << too_many.error().message;
    auto negative = insert_knot(s, SurfaceDirection::U, 0.3, -1);
    ASSERT_FALSE(negative.ok());
    EXPECT_NE(negative.error().message.find("times must be >= 0"), std::string::npos);
    std::atomic<bool> stop{true};
    Cancel cancel;
    cancel.flag = &stop;
    EXPECT_EQ(to_bezier(s, cancel).error().code, ErrorCode::Cancelled);
    TessellationOptions cancelled;
    cancelled.cancel.flag = &stop;
    EXPECT_EQ(tessellate(s, cancelled).error().code, ErrorCode::Cancelled);
    TessellationOptions budget;
    budget.tolerance = 1e-9;
    EXPECT_EQ(tessellate(s, budget).error().code, ErrorCode::BudgetExceeded);
    BSplineSurface broken = s;
    broken.degree_u = 0;
    EXPECT_FALSE(insert_knot(broken, SurfaceDirection::U, 0.3).ok());
    EXPECT_FALSE(to_bezier(broken).ok());
    EXPECT_FALSE(tessellate(broken, TessellationOptions{}).ok());
}

}  // namespace
}  // namespace surfaced
