// Tensor-product B-spline and NURBS surfaces: validation, evaluation of the position and the partial derivatives up
// to second order, unit normals (also where a row of control points collapses to a point), Boehm knot insertion and
// degree elevation per direction, decomposition into Bézier patches, and tessellation to a chord tolerance through those patches.
//
// Conventions. Degrees p (along u) and q (along v); count_u = nu and count_v = nv control points per direction;
// knot vectors U (nu + p + 1 non-decreasing values) and V (nv + q + 1). Control point (i, j) -- i along u, j along v --
// is points[j * nu + i] (u varying fastest, the layout of BezierPatch). The surface is
//   S(u, v) = sum_ij N_{i,p}(u) N_{j,q}(v) w_ij P_ij / sum_ij N_{i,p}(u) N_{j,q}(v) w_ij
// (weights empty = all 1, a polynomial B-spline surface) on the domain [U[p], U[nu]] x [V[q], V[nv]]. Knot vectors
// may be clamped (end values repeated p + 1 times: the surface interpolates the net's corners) or unclamped. As for
// curves (bspline.h), basis functions at a knot are evaluated from the right (the span [u_k, u_{k+1}) holding u),
// except at the right end of the domain, which takes the limit from the left; so derivatives at an interior knot where
// the surface is not smooth are the right-hand ones.
//
// Errors. validate() states every rule; the functions returning Result check what depends on their arguments (a
// parameter outside the domain, a knot to insert) and, where cheap relative to their work, validate() too. The
// evaluators take a surface for which validate() succeeded (asserts only) and check (u, v).
//
// References:
//  - L. Piegl, W. Tiller, "The NURBS Book", 2nd ed.: A2.1 (span), A2.3 (basis function derivatives), A3.6
//    (surface derivatives), A4.4 (rational surface derivatives by the quotient rule), A5.3 (surface knot insertion),
//    A5.7 (decomposition into Bézier patches), section 5.5 (degree elevation), ch. 7-8 (circles, surfaces of revolution: the sphere, torus and
//    cylinder of the tests).
//  - W. Boehm, "Inserting new knots into B-spline curves", CAD 12 (1980).
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

#include "geometry/core/cancel.h"
#include "geometry/core/result.h"
#include "geometry/core/types.h"
#include "geometry/surfaces/bezier_patch.h"

namespace surfaced {

//! Largest degree in either direction: the degree of the Bézier patches the surface decomposes into, whose
//! tessellator accepts up to kMaxPatchDegree, so every valid surface can be decomposed and tessellated.
inline constexpr int kMaxBSplineSurfaceDegree = kMaxPatchDegree;

struct BSplineSurface {
    int degree_u = 3;             //!< p
    int degree_v = 3;             //!< q
    int count_u = 0;              //!< nu: control points along u (the length of a row)
    int count_v = 0;              //!< nv: control points along v (the number of rows)
    std::vector<double> knots_u;  //!< U: nu + p + 1 non-decreasing values
    std::vector<double> knots_v;  //!< V: nv + q + 1 non-decreasing values
    std::vector<Vec3> points;     //!< nu * nv Euclidean control points, u fastest: (i, j) at j * nu + i
    std::vector<double> weights;  //!< empty (polynomial) or one weight > 0 per control point, same order

    bool rational() const { return !weights.empty(); }
    const Vec3& at(int i, int j) const { return points[static_cast<std::size_t>(j) * count_u + i]; }
    double weight(int i, int j) const {
        return weights.empty() ? 1.0 : weights[static_cast<std::size_t>(j) * count_u + i];
    }
};

enum class SurfaceDirection { U, V };

//! The rules, checked in this order (the first broken one is reported):
//!  - degree_u and degree_v in 1..kMaxBSplineSurfaceDegree;
//!  - count_u >= degree_u + 1 and count_v >= degree_v + 1;
//!  - knots_u.size() == count_u + degree_u + 1 and knots_v.size() == count_v + degree_v + 1 ("knots_u has 11 entries;
//!    9 control points along u of degree 2 need 12 (count_u + degree_u + 1)");
//!  - points.size() == count_u * count_v; weights empty or of the same size;
//!  - finite control points (NonFinite); finite weights > 0 whose product with their point is finite, the largest at
//!    most kMaxWeightRatio times the smallest (the Bézier patches' rule: it bounds the loss of precision);
//!  - per knot vector: finite values (NonFinite), non-decreasing, the first and the last value repeated at most
//!    degree + 1 times and any other at most degree times, and a non-empty domain U[p] < U[nu].
//! Messages name the knot vector and knot index, or the control point index with its (i, j). GeoError::element is the
//! control point index with ElementKind::Vertex for a point or weight, the knot index with ElementKind::None for a knot,
//! -1 for a count or size mismatch and the weight ratio. Error code InvalidArgument unless said otherwise. O(nu nv + |U| + |V|).
Status validate(const BSplineSurface& surface);

//! The parameter domains [U[p], U[nu]] and [V[q], V[nv]].
std::pair<double, double> domain_u(const BSplineSurface& surface);
std::pair<double, double> domain_v(const BSplineSurface& surface);

//! Point at (u, v): the basis functions of each direction (Cox-de Boor triangle, A2.2), then the (p+1) x (q+1) local
//! net in homogeneous coordinates (w P, w), divided at the end. O(p^2 + q^2 + p q), no allocation. Errors
//! (InvalidArgument): u or v not finite or outside its domain.
Result<Vec3> evaluate(const BSplineSurface& surface, double u, double v);

//! Position and the exact partial derivatives S_u, S_v, S_uu, S_uv, S_vv at (u, v): the derivatives of the basis
//! functions (A2.3) applied to the homogeneous local net (A3.6), then for a NURBS surface the quotient rule (A4.4):
//! S_kl = (A_kl - sum over (i, j) != (0, 0), i <= k, j <= l of C(k,i) C(l,j) w_ij S_{k-i,l-j}) / w. Derivatives of an
//! order above the degree are zero for a polynomial surface. Same errors and cost as evaluate().
Result<PatchDerivatives> evaluate_derivatives(const BSplineSurface& surface, double u, double v);

//! Unit normal S_u x S_v at (u, v). Where it vanishes -- a row or column of control points collapsed to one point,
//! such as the poles of a NURBS sphere, where S_u = 0 -- it returns the limit of the normal as (u, v) is approached
//! from inside the domain, from the second derivatives: the first-order expansion of S_u x S_v along the direction
//! (su, sv) pointing into the domain (+1 in the lower half of a direction's domain, -1 in the upper half),
//! su (S_uu x S_v + S_u x S_uv) + sv (S_uv x S_v + S_u x S_vv), which at a pole with S_u = S_uu = 0 is sv S_uv x S_v.
//! Only if that vanishes too (a higher-order degeneracy) it takes S_u x S_v at offsets 1e-3, 1e-5, 1e-7 of the domain
//! lengths into the domain. "Vanishes" means below 1e-12 of |S_u|^2 + |S_v|^2, or, when both derivatives vanish, of
//! the product over both directions of (local net size x degree / knot span length). Returns (0, 0, 0) only for a
//! surface degenerate around (u, v). Same errors as evaluate(); O(p^2 + q^2 + p q) in the common case.
Result<Vec3> unit_normal(const BSplineSurface& surface, double u, double v);

//! Boehm's knot insertion of t into the knot vector of `direction`, `times` times: every row (direction U) or column
//! (V) of the net is refined as a curve, on homogeneous points for a NURBS surface. The surface is unchanged in shape
//! and parametrisation; the net gains `times` rows or columns. Control points that insertion does not touch are copied
//! exactly, and a row of identical points stays identical (a pole stays a pole). Errors (InvalidArgument): validate();
//! t not finite or outside that direction's domain; times < 0; the multiplicity of t would exceed the degree.
//! O(times (nu + times) nv) (direction U; V alike).
Result<BSplineSurface> insert_knot(const BSplineSurface& surface, SurfaceDirection direction, double t, int times = 1);

//! Degree elevation of `direction` by `times`: the same surface (shape and parametrisation) with the degree along
//! that direction raised by `times` and every distinct knot value's multiplicity raised by one per step, so the
//! continuity at every knot is kept. Each step elevates every row (U) or column (V) of the net as a curve, in
//! homogeneous coordinates for a NURBS surface, by blossoming: the degree-(p+1) control point i is the average over
//! k of the degree-p blossom at the p + 1 knots t^_{i+1..i+p+1} with t^_{i+k} left out, evaluated on a knot span its
//! support covers (de Boor's algorithm with one argument per level; H. Prautzsch, "Degree elevation of B-spline
//! curves", CAGD 1 (1984)). The knots outside the domain keep their values, with the outermost one repeated once
//! more, so the domain is unchanged. A row of identical control points stays identical (a pole stays a pole).
//! Errors (InvalidArgument): validate(); times < 0; the new degree above kMaxBSplineSurfaceDegree.
//! O(times n (p + 1) p^2) per row or column.
Result<BSplineSurface> elevate_degree(const BSplineSurface& surface, SurfaceDirection direction, int times = 1);

//! The distinct knot values that bound the Bézier patches of to_bezier along u: U[p], every distinct knot value inside
//! the domain, U[nu] (and along v alike). Precondition: validate() succeeded.
std::vector<double> bezier_breaks(const BSplineSurface& surface, SurfaceDirection direction);

//! Number of Bézier patches to_bezier produces: (breaks_u - 1) (breaks_v - 1). O(|U| + |V|), no allocation beyond the
//! breaks; use it to check a budget before decomposing.
std::size_t bezier_patch_count(const BSplineSurface& surface);

struct SurfaceBezierPatches {
    //! Patch (a, b) -- a along u, b along v -- is patches[b * (breaks_u.size() - 1) + a]: the surface on
    //! [breaks_u[a], breaks_u[a+1]] x [breaks_v[b], breaks_v[b+1]] reparametrised to [0, 1]^2, of degree (p, q),
    //! rational exactly when the surface is. Its corner_uvs are the surface parameters (u, v) of its corners, so a
    //! tessellation's texture coordinates are the surface parameters.
    std::vector<BezierPatch> patches;
    std::vector<double> breaks_u, breaks_v;
};

//! Decomposition into Bézier patches by raising every knot of the domain to multiplicity p along u (every row of the
//! net, one knot span at a time, A5.7), then q along v (every column of each span's strip). Neighbouring patches share
//! their edge's control points and weights bit for bit (the shared column or row is computed once and copied), so the
//! tessellator welds them; an edge on a row of identical control points (a pole) is a collapsed patch edge exactly;
//! the outer edges of a clamped knot vector are the net's own boundary rows and columns, so where the net is closed
//! (first and last column identical, as in the NURBS sphere and torus) the seam welds too. A periodic net (unclamped
//! uniform knots, the first p columns repeated at the end) closes only up to rounding, its seam being computed at two
//! different knot values: where the first and the last patch column (or row) have edges whose control points agree to
//! 1e-12 of the largest |control point| (and weights to 1e-12 of the largest weight), the last edge is set to a copy
//! of the first, so those seams weld as well. Work O(patches (p + 1) (q + 1) (p + q)), memory
//! O(patches (p + 1) (q + 1)); polls `cancel` before each patch. Errors: validate(), Cancelled.
Result<SurfaceBezierPatches> to_bezier(const BSplineSurface& surface, const Cancel& cancel = Cancel{});

//! Tessellation within a chord tolerance (options.tolerance) or a fixed number of segments per Bézier patch: to_bezier,
//! then tessellate_patches (bezier_patch.h), so its guarantee holds: the triangles stay within the tolerance of the
//! surface, with counts matched along shared patch edges and those edges welded crack-free. face_patches index
//! to_bezier's patches; the uvs are the surface parameters (u, v). Errors: validate(), to_bezier's and
//! tessellate_patches' (InvalidArgument options, BudgetExceeded when a patch needs more than options.max_segments
//! segments, Cancelled). Callers bounding work check bezier_patch_count() and then plan_tessellation on the patches.
Result<PatchTessellation> tessellate(const BSplineSurface& surface, const TessellationOptions& options);

}  // namespace surfaced
