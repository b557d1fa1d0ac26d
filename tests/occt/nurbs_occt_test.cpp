// B-spline and NURBS surfaces against OpenCASCADE's Geom_BSplineSurface (the reference CAD kernel, linked into this
// test only): position and derivatives to order 2 at random (u, v) of random surfaces (degrees 1..5, clamped and
// unclamped knot vectors with repeated interior knots, rational and polynomial), and the surfaces produced by knot
// insertion, degree elevation and the Bézier decomposition evaluated against OCCT's evaluation of the original.
#include <Geom_BSplineSurface.hxx>
#include <Standard_Failure.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColStd_Array2OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <gp_Pnt.hxx>
#include <gp_Vec.hxx>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "geometry/surfaces/bezier_patch.h"
#include "geometry/surfaces/bspline_surface.h"
#include "tests/support/nurbs_surfaces.h"
#include "tests/support/occt_nurbs.h"

namespace surfaced {
namespace {

using testing::random_surface;
using testing::to_occt_surface;

Vec3 vec(const gp_Pnt& p) { return {p.X(), p.Y(), p.Z()}; }
Vec3 vec(const gp_Vec& v) { return {v.X(), v.Y(), v.Z()}; }

PatchDerivatives occt_derivatives(const Handle(Geom_BSplineSurface) & s, double u, double v) {
    gp_Pnt p;
    gp_Vec du, dv, duu, dvv, duv;
    s->D2(u, v, p, du, dv, duu, dvv, duv);
    PatchDerivatives d;
    d.position = vec(p);
    d.du = vec(du);
    d.dv = vec(dv);
    d.duu = vec(duu);
    d.duv = vec(duv);
    d.dvv = vec(dvv);
    return d;
}

//! The size derivatives of order (k, l) have on this surface: the largest control point's distance from the origin,
//! times degree / shortest knot span per order along each direction, times the weight ratio per order for a NURBS
//! surface (the quotient rule multiplies by it). Differences are judged relative to this (and to the value itself).
double derivative_scale(const BSplineSurface& s, int k, int l) {
    double biggest = 0;
    for (const Vec3& p : s.points) biggest = std::max(biggest, norm(p));
    const auto shortest = [](const std::vector<double>& knots) {
        double h = INFINITY;
        for (std::size_t i = 1; i < knots.size(); ++i)
            if (knots[i] > knots[i - 1]) h = std::min(h, knots[i] - knots[i - 1]);
        return h;
    };
    double ratio = 1;
    if (s.rational()) {
        const auto [lo, hi] = std::minmax_element(s.weights.begin(), s.weights.end());
        ratio = *hi / *lo;
    }
    return biggest * std::pow(s.degree_u / shortest(s.knots_u), k) * std::pow(s.degree_v / shortest(s.knots_v), l) *
           std::pow(ratio, k + l + 1);
}

std::string describe(const BSplineSurface& s, unsigned seed) {
    return "seed " + std::to_string(seed) + ": degrees " + std::to_string(s.degree_u) + "x" +
           std::to_string(s.degree_v) + ", net " + std::to_string(s.count_u) + "x" + std::to_string(s.count_v) +
           (s.rational() ? ", rational" : "") +
           (s.knots_u.front() == s.knots_u[static_cast<std::size_t>(s.degree_u)] ? ", clamped u" : ", unclamped u") +
           (s.knots_v.front() == s.knots_v[static_cast<std::size_t>(s.degree_v)] ? ", clamped v" : ", unclamped v");
}

//! Largest relative difference seen, per derivative, over a test: reported so the margin under 1e-12 is visible.
struct Worst {
    double value[6] = {};
    void report(const char* what) const {
        std::printf(
            "%s: largest relative difference to OCCT: position %.2e, du %.2e, dv %.2e, duu %.2e, duv %.2e, "
            "dvv %.2e\n",
            what, value[0], value[1], value[2], value[3], value[4], value[5]);
    }
};

//! Every component of `ours` within 1e-12 of OCCT's, relative to the larger of the value and the surface's scale
//! for that order.
void expect_matches(const BSplineSurface& s, const PatchDerivatives& ours, const PatchDerivatives& occt, Worst& worst,
                    const std::string& where) {
    const Vec3 PatchDerivatives::*member[6] = {&PatchDerivatives::position, &PatchDerivatives::du,
                                               &PatchDerivatives::dv,       &PatchDerivatives::duu,
                                               &PatchDerivatives::duv,      &PatchDerivatives::dvv};
    const int order_u[6] = {0, 1, 0, 2, 1, 0}, order_v[6] = {0, 0, 1, 0, 1, 2};
    static const char* names[6] = {"position", "du", "dv", "duu", "duv", "dvv"};
    for (int m = 0; m < 6; ++m) {
        const Vec3 a = ours.*member[m], b = occt.*member[m];
        const double scale = std::max(norm(b), derivative_scale(s, order_u[m], order_v[m]));
        const double relative = norm(a - b) / scale;
        worst.value[m] = std::max(worst.value[m], relative);
        EXPECT_LE(relative, 1e-12) << where << " " << names[m] << ": ours (" << a.x << ", " << a.y << ", " << a.z
                                   << "), OCCT (" << b.x << ", " << b.y << ", " << b.z << ")";
    }
}

//! Parameters of one direction: both ends of the domain and random values inside it. (At an interior knot where the
//! surface is not smooth the two libraries take different one-sided derivatives.)
std::vector<double> parameters(const BSplineSurface& s, SurfaceDirection d, std::mt19937& rng) {
    const auto [lo, hi] = d == SurfaceDirection::U ? domain_u(s) : domain_v(s);
    std::uniform_real_distribution<double> any(lo, hi);
    std::vector<double> out{lo, hi};
    for (int k = 0; k < 6; ++k) out.push_back(any(rng));
    return out;
}

constexpr unsigned kSurfaces = 200;

TEST(NurbsAgainstOcct, EvaluationAndDerivativesOnRandomSurfaces) {
    Worst worst;
    int points = 0;
    for (unsigned seed = 1; seed <= kSurfaces; ++seed) {
        const BSplineSurface s = random_surface(seed);
        ASSERT_TRUE(validate(s).ok());
        const Handle(Geom_BSplineSurface) reference = to_occt_surface(s);
        std::mt19937 rng(seed);
        const std::vector<double> us = parameters(s, SurfaceDirection::U, rng);
        const std::vector<double> vs = parameters(s, SurfaceDirection::V, rng);
        const auto [u_lo, u_hi] = domain_u(s);
        const auto [v_lo, v_hi] = domain_v(s);
        double occt_u0 = 0, occt_u1 = 0, occt_v0 = 0, occt_v1 = 0;
        reference->Bounds(occt_u0, occt_u1, occt_v0, occt_v1);
        ASSERT_EQ(occt_u0, u_lo) << describe(s, seed);
        ASSERT_EQ(occt_u1, u_hi) << describe(s, seed);
        ASSERT_EQ(occt_v0, v_lo) << describe(s, seed);
        ASSERT_EQ(occt_v1, v_hi) << describe(s, seed);
        for (double u : us)
            for (double v : vs) {
                auto ours = evaluate_derivatives(s, u, v);
                ASSERT_TRUE(ours.ok()) << ours.error().message;
                const PatchDerivatives occt = occt_derivatives(reference, u, v);
                // at the domain's ends both take the one-sided derivative from inside; inside, both the right-hand one
                expect_matches(s, *ours, occt, worst,
                               describe(s, seed) + " at (" + std::to_string(u) + ", " + std::to_string(v) + ")");
                auto position = evaluate(s, u, v);
                ASSERT_TRUE(position.ok());
                EXPECT_LE(norm(*position - occt.position), 1e-12 * derivative_scale(s, 0, 0));
                ++points;
            }
        if (HasFailure()) return;
    }
    worst.report("random surfaces");
    EXPECT_GT(points, 10000);
}

TEST(NurbsAgainstOcct, KnotInsertionAndDegreeElevationKeepOcctsSurface) {
    Worst inserted, elevated;
    for (unsigned seed = 1; seed <= kSurfaces / 2; ++seed) {
        const BSplineSurface s = random_surface(seed);
        const Handle(Geom_BSplineSurface) reference = to_occt_surface(s);
        std::mt19937 rng(seed * 7 + 1);
        // a fresh knot along u inserted up to the degree, one along v once
        const auto [u_lo, u_hi] = domain_u(s);
        const auto [v_lo, v_hi] = domain_v(s);
        const double tu = std::uniform_real_distribution<double>(u_lo, u_hi)(rng);
        const double tv = std::uniform_real_distribution<double>(v_lo, v_hi)(rng);
        auto a = insert_knot(s, SurfaceDirection::U, tu, s.degree_u);
        ASSERT_TRUE(a.ok()) << a.error().message;
        auto b = insert_knot(*a, SurfaceDirection::V, tv, 1);
        ASSERT_TRUE(b.ok()) << b.error().message;
        auto c = elevate_degree(s, SurfaceDirection::U, 1);
        auto d = c.ok() ? elevate_degree(*c, SurfaceDirection::V, 2) : c;
        ASSERT_TRUE(d.ok()) << d.error().message;
        for (double u : parameters(s, SurfaceDirection::U, rng))
            for (double v : parameters(s, SurfaceDirection::V, rng)) {
                const PatchDerivatives occt = occt_derivatives(reference, u, v);
                const std::string at = describe(s, seed) + " at (" + std::to_string(u) + ", " + std::to_string(v) + ")";
                // inserting knots and raising degrees keep the surface and its parametrisation
                auto ours = evaluate_derivatives(*b, u, v);
                ASSERT_TRUE(ours.ok());
                expect_matches(s, *ours, occt, inserted, at + " after knot insertion");
                auto raised = evaluate_derivatives(*d, u, v);
                ASSERT_TRUE(raised.ok());
                expect_matches(s, *raised, occt, elevated, at + " after degree elevation");
            }
        if (HasFailure()) return;
    }
    inserted.report("knot insertion");
    elevated.report("degree elevation");
}

TEST(NurbsAgainstOcct, BezierPatchesAreOcctsSurfacePieceByPiece) {
    Worst worst;
    for (unsigned seed = 1; seed <= kSurfaces / 2; ++seed) {
        const BSplineSurface s = random_surface(seed);
        const Handle(Geom_BSplineSurface) reference = to_occt_surface(s);
        auto bezier = to_bezier(s);
        ASSERT_TRUE(bezier.ok()) << bezier.error().message;
        const std::size_t nu = bezier->breaks_u.size() - 1;
        std::mt19937 rng(seed * 13 + 5);
        std::uniform_real_distribution<double> unit(0, 1);
        for (std::size_t k = 0; k < bezier->patches.size(); ++k) {
            const BezierPatch& patch = bezier->patches[k];
            const std::size_t a = k % nu, b = k / nu;
            const double u0 = bezier->breaks_u[a], lu = bezier->breaks_u[a + 1] - u0;
            const double v0 = bezier->breaks_v[b], lv = bezier->breaks_v[b + 1] - v0;
            for (int n = 0; n < 6; ++n) {
                const double x = unit(rng), y = unit(rng);
                PatchDerivatives ours = evaluate_derivatives(patch, x, y);
                // the patch runs over [0, 1]^2: the surface's derivatives are the patch's divided by the span lengths
                ours.du = ours.du * (1 / lu);
                ours.dv = ours.dv * (1 / lv);
                ours.duu = ours.duu * (1 / (lu * lu));
                ours.duv = ours.duv * (1 / (lu * lv));
                ours.dvv = ours.dvv * (1 / (lv * lv));
                expect_matches(s, ours, occt_derivatives(reference, u0 + x * lu, v0 + y * lv), worst,
                               describe(s, seed) + " patch " + std::to_string(k));
            }
        }
        if (HasFailure()) return;
    }
    worst.report("Bézier patches");
}

}  // namespace
}  // namespace surfaced
