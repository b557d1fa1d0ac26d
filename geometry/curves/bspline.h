// B-spline and NURBS curves of any degree in 3D (2D curves use z = 0): validation, knot vectors, evaluation by de
// Boor's algorithm and by the Cox-de Boor basis functions, derivatives of any order, knot insertion, conversion to
// piecewise Bézier form and polyline tessellation within a tolerance.
//
// Conventions. n control points P_0..P_{n-1}, degree p, m = n + p + 1 knots u_0 <= ... <= u_{m-1}. The curve is
// C(u) = sum_i N_{i,p}(u) w_i P_i / sum_i N_{i,p}(u) w_i on its domain [u_p, u_n] (weights empty = all 1, a
// polynomial B-spline). Basis functions are piecewise polynomials; at a knot they are evaluated from the right
// (the span [u_k, u_{k+1}) holding u), except at the right end of the domain u = u_n, which takes the limit from the
// left (the last non-empty span), so the whole closed domain evaluates without index overruns. Functions taking a
// SpanSide can be asked for the left limit at an interior knot (one-sided derivatives where the curve is not smooth).
// Parameters outside the domain are clamped to it.
//
// Evaluation functions take a curve for which validate() succeeded (asserts only); everything a user can cause is
// checked by validate() or reported by the Result-returning functions.
//
// References:
//  - L. Piegl, W. Tiller, "The NURBS Book", 2nd ed., ch. 2 (basis functions, Cox-de Boor), ch. 3-4 (derivatives:
//    P^(k)_i = (p-k+1) (P^(k-1)_{i+1} - P^(k-1)_i) / (u_{i+p+1} - u_{i+k}); rational curves through the Leibniz
//    rule on the homogeneous form), ch. 5 (knot insertion, decomposition into Bézier pieces), ch. 7 (circles).
//  - W. Boehm, "Inserting new knots into B-spline curves", CAD 12 (1980).
//  - C. de Boor, "On calculating with B-splines", J. Approx. Theory 6 (1972).
#pragma once

#include <cstddef>
#include <span>
#include <utility>
#include <vector>

#include "geometry/core/cancel.h"
#include "geometry/core/result.h"
#include "geometry/core/types.h"
#include "geometry/curves/bezier_curve.h"
#include "geometry/curves/piecewise.h"

namespace surfaced {

struct BSplineCurve {
    int degree = 3;
    std::vector<Vec3> points;     //!< n control points
    std::vector<double> knots;    //!< n + degree + 1 non-decreasing knots
    std::vector<double> weights;  //!< empty (polynomial B-spline) or one positive weight per point (NURBS)

    bool is_rational() const { return !weights.empty(); }
};

//! Which one-sided limit to take when a parameter sits exactly on a knot.
enum class SpanSide {
    Right,  //!< the span [u_k, u_{k+1}) (the default; the right end of the domain always uses Left)
    Left,   //!< the span (u_k, u_{k+1}] (the left end of the domain always uses Right)
};

//! degree >= 1; at least degree + 1 points; knots.size() == points + degree + 1; finite points, knots and weights;
//! knots non-decreasing; the first and the last knot value repeated at most degree + 1 times, any other value at
//! most degree times; weights empty or one finite positive weight per point; a non-empty domain u_p < u_n.
//! Error codes: InvalidArgument (NonFinite for a non-finite point or knot). The message names the knot or point index
//! and says what is wrong; GeoError::element is that index with ElementKind::Vertex for a point or weight and
//! ElementKind::None for a knot (or for a size mismatch, element -1).
Status validate(const BSplineCurve& curve);

// ---- knot vectors ------------------------------------------------------------------------------------------------

//! Clamped (open) uniform knots for `point_count` points of `degree`: degree + 1 copies of u0, point_count - degree - 1
//! equally spaced interior knots, degree + 1 copies of u1. The curve then starts at P_0 and ends at P_{n-1}, tangent
//! to the control polygon there. Errors (InvalidArgument): degree < 1, point_count < degree + 1, !(u0 < u1), non-finite.
Result<std::vector<double>> clamped_uniform_knots(std::size_t point_count, int degree, double u0 = 0.0,
                                                  double u1 = 1.0);

//! Uniform (unclamped, periodic-style) knots: point_count + degree + 1 equally spaced knots, placed so that the domain
//! [u_p, u_n] is exactly [u0, u1]. Same errors as clamped_uniform_knots.
Result<std::vector<double>> uniform_knots(std::size_t point_count, int degree, double u0 = 0.0, double u1 = 1.0);

//! A closed (periodic) uniform B-spline through the control polygon `points` (which is not repeated by the caller):
//! the first `degree` points are appended again and the knots are uniform_knots(points + degree, degree), giving a
//! closed curve of continuity C^(degree-1) everywhere, on the domain [0, 1]. `weights` empty or one per point (wrapped
//! the same way). Errors (InvalidArgument): degree < 1, fewer than 3 points, weights of the wrong size, validate().
Result<BSplineCurve> closed_uniform(std::span<const Vec3> points, int degree, std::span<const double> weights = {});

//! The parameter domain [u_p, u_n].
std::pair<double, double> domain(const BSplineCurve& curve);

//! The knot span index k with u_k <= u < u_{k+1} (Right) or u_k < u <= u_{k+1} (Left), p <= k <= n - 1, of the knot
//! vector `knots` for `point_count` points of `degree`; u is clamped to the domain; at the domain's right end
//! (Right) or left end (Left) the last or first non-empty span is returned. Binary search: O(log n).
std::size_t find_span(std::span<const double> knots, int degree, std::size_t point_count, double u,
                      SpanSide side = SpanSide::Right);

//! The basis function N_{i,p}(u) by the Cox-de Boor recursion on `knots` (independent of de Boor's algorithm; for
//! tests and for the basis-sum evaluator). Degree-0 functions are the indicator of [u_i, u_{i+1}) (Right) or
//! (u_i, u_{i+1}] (Left); 0/0 terms are 0. Unlike the curve evaluators this does not clamp u, and the end-of-domain
//! rule (Left at u_n) is applied by the caller: evaluate_basis does.
double basis_function(std::span<const double> knots, int degree, std::size_t i, double u,
                      SpanSide side = SpanSide::Right);

// ---- evaluation ---------------------------------------------------------------------------------------------------

//! Point at u by de Boor's algorithm (on homogeneous points (w P, w) for a NURBS curve). O(p^2).
Vec3 evaluate(const BSplineCurve& curve, double u);
//! Point at u as sum N_{i,p}(u) w_i P_i / sum N_{i,p}(u) w_i over all i with basis_function (a second, independent
//! evaluator; O(n p^2), meant for tests).
Vec3 evaluate_basis(const BSplineCurve& curve, double u);
//! The order-th derivative dC/du at u (order 0 = the point), from the span on `side` of u. Polynomial: de Boor on the
//! local control points of the derivative curve. NURBS: the same on the homogeneous numerator A and weight w, then
//! the Leibniz rule C^(k) = (A^(k) - sum_{j=1..k} C(k,j) w^(j) C^(k-j)) / w. Orders above the degree of a polynomial
//! curve give the zero vector. order >= 0; a NURBS derivative costs O(order^2 + order p^2) time and O(order) memory, so
//! callers taking `order` from a request bound it first.
Vec3 derivative(const BSplineCurve& curve, double u, int order, SpanSide side = SpanSide::Right);

//! The first-derivative curve of a polynomial B-spline: degree p - 1, points Q_i = p (P_{i+1} - P_i) /
//! (u_{i+p+1} - u_{i+1}) (0 where that span is empty), knots without the first and last one. Its degree may be 0,
//! which validate() rejects but evaluate() and derivative() handle. Errors: Unsupported for a NURBS curve (whose
//! derivative is not a B-spline of the same kind), validate().
Result<BSplineCurve> derivative_curve(const BSplineCurve& curve);

//! Box of the control points: contains the curve (convex hull property; weights are positive).
Box3 bounding_box(const BSplineCurve& curve);

// ---- knot insertion and Bézier form -------------------------------------------------------------------------------

//! Boehm's knot insertion of u, `times` times: n + times points, the same curve (shape and parametrisation; NURBS on
//! homogeneous points). Errors (InvalidArgument): validate(); u not finite or outside the domain [u_p, u_n]; times < 0;
//! the multiplicity of u would exceed the degree (an interior knot of multiplicity p makes the curve only C0, more would
//! break it; a clamped end already has p + 1).
Result<BSplineCurve> insert_knot(const BSplineCurve& curve, double u, int times = 1);

//! The distinct knot values that bound the Bézier pieces of to_bezier: u_p, every distinct interior knot value, u_n.
//! Piece j covers [breaks[j], breaks[j + 1]]. Precondition: validate() succeeded.
std::vector<double> bezier_breaks(const BSplineCurve& curve);

//! The curve as one Bézier curve of the same degree per non-empty knot span, by inserting every knot of the domain
//! (and its ends) up to multiplicity p; piece j is the curve on [breaks[j], breaks[j+1]] (bezier_breaks) reparametrised
//! to [0, 1]: C(u) = piece_j((u - breaks[j]) / (breaks[j+1] - breaks[j])). NURBS pieces are rational Bézier curves
//! with the inserted weights. Consecutive pieces share their end point exactly (bit-for-bit). `closed` is false: a
//! periodic curve closes only up to rounding. Work O(spans p^2), polls `cancel` between spans. Errors: validate(),
//! Cancelled.
Result<BezierChain> to_bezier(const BSplineCurve& curve, const Cancel& cancel = Cancel{});

struct BSplineTessellationOptions {
    double tolerance = 1e-3;               //!< the polyline stays within this distance of the curve
    std::size_t max_segments = 1'000'000;  //!< BudgetExceeded when more would be needed
    Cancel cancel;                         //!< polled between Bézier pieces
};
//! A polyline within `tolerance` of the curve: to_bezier, then the Bézier tessellate() of every piece (guaranteed
//! bound, see bezier_curve.h). params are B-spline parameters u (from u_p to u_n); points at piece boundaries are not
//! repeated; bound and max_deviation are the maxima over the pieces. Errors: validate(), InvalidArgument (tolerance
//! not finite and > 0), BudgetExceeded (more than max_segments in total), Cancelled.
Result<CurveTessellation> tessellate(const BSplineCurve& curve, const BSplineTessellationOptions& options);

}  // namespace surfaced
