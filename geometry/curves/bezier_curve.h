// Bézier curves of any degree in 3D (2D curves use z = 0), polynomial or rational (positive weights): evaluation
// (de Casteljau and Bernstein form), derivatives of any order, split, degree elevation, bounding box, arc length
// with an error bound, global closest point, curvature, and polyline tessellation within a guaranteed tolerance.
//
// References:
//  - G. Farin, "Curves and Surfaces for CAGD", 5th ed., ch. 4-5 (de Casteljau, derivatives, elevation), ch. 13
//    (rational curves).
//  - G.-J. Wang, "The subdivision method for finding the intersection between two Bézier curves or surfaces" (1984):
//    N >= sqrt(n(n-1) max|D2 b| / (8 tol)) uniform segments keep a polynomial curve within tol of its polyline.
//  - J. Gravesen, "Adaptive subdivision and the length and energy of Bézier curves", CGTA 8 (1997): the length lies
//    between the chord and the control polygon; (2 chord + (n-1) polygon) / (n+1) estimates it.
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

#include "geometry/core/result.h"
#include "geometry/core/types.h"

namespace surfaced {

struct BezierCurve {
    std::vector<Vec3> points;     //!< degree + 1 control points
    std::vector<double> weights;  //!< empty (polynomial) or one positive weight per point (rational)

    int degree() const { return static_cast<int>(points.size()) - 1; }
    bool is_rational() const { return !weights.empty(); }
};

//! At least one point, finite coordinates, weights empty or one finite positive weight per point. The error's
//! element is the offending point (ElementKind::Vertex).
Status validate(const BezierCurve& curve);

//! Point at t by de Casteljau's algorithm (on homogeneous points for a rational curve).
Vec3 evaluate(const BezierCurve& curve, double t);
//! Point at t from the Bernstein form sum B_i^n(t) w_i b_i / sum B_i^n(t) w_i (a second, independent evaluator).
Vec3 evaluate_bernstein(const BezierCurve& curve, double t);
//! The order-th derivative at t (order 0 = the point). Rational curves use the Leibniz rule on C = A / w:
//! C^(k) = (A^(k) - sum_{j=1..k} C(k,j) w^(j) C^(k-j)) / w.
Vec3 derivative(const BezierCurve& curve, double t, int order);

//! The curve on [0, t] and on [t, 1], each reparametrised to [0, 1] (exact: the de Casteljau triangle's sides).
std::pair<BezierCurve, BezierCurve> split(const BezierCurve& curve, double t);
//! The same curve with degree + times (shape and parametrisation unchanged).
BezierCurve elevate_degree(const BezierCurve& curve, int times = 1);

//! Box of the control points: contains the curve (convex hull property; weights are positive).
Box3 bounding_box(const BezierCurve& curve);

//! Unsigned curvature |C' x C''| / |C'|^3 at t; 0 where C' vanishes.
double curvature(const BezierCurve& curve, double t);

struct ArcLength {
    double length = 0;
    double error_bound = 0;  //!< |length - true length| <= error_bound
};
//! Length by adaptive subdivision until every piece's control polygon exceeds its chord by at most a share of
//! `tolerance`. For a polynomial piece the true length lies between chord and polygon (|C'| <= n sum |D b_i|
//! B_i^(n-1)), so error_bound (<= tolerance unless max_depth stopped the subdivision first) is guaranteed. For a
//! rational curve that inequality can fail, and error_bound is the same chord/polygon gap as an estimate only.
ArcLength arc_length(const BezierCurve& curve, double tolerance = 1e-9, int max_depth = 40);

struct ClosestPoint {
    double t = 0;
    Vec3 point;
    double distance = 0;
};
//! Global closest point: branch and bound over subdivided pieces (a piece whose control box is farther than the
//! best distance so far cannot hold the answer), then Newton on (C(t) - q) . C'(t) = 0 from the best candidates.
ClosestPoint closest_point(const BezierCurve& curve, const Vec3& query);

struct CurveTessellation {
    std::vector<Vec3> points;    //!< the polyline, from C(0) to C(1)
    std::vector<double> params;  //!< the curve parameter of each point
    std::size_t segments = 0;
    double max_deviation = 0;  //!< measured: max distance from the curve to the chord of its segment (sampled)
    double bound = 0;          //!< guaranteed: no point of the curve is farther than this from its segment's chord
};
//! A polyline no farther than `tolerance` from the curve. Polynomial curves: Wang's formula applied per piece of an
//! adaptive bisection (a piece is split when its halves need fewer segments together), uniform inside each piece.
//! Rational curves: bisection until every piece's control points lie within tolerance of its chord (the convex
//! hull property then bounds the curve). Errors: InvalidArgument (tolerance not > 0, or validate()),
//! BudgetExceeded (more than max_segments).
Result<CurveTessellation> tessellate(const BezierCurve& curve, double tolerance, std::size_t max_segments = 1'000'000);

}  // namespace surfaced
