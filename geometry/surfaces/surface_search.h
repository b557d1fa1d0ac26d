// Global searches over a B-spline or NURBS surface by branch and bound on its Bézier patches: the closest point to
// a given point (point inversion when the point lies on the surface) and the tight bounding box.
//
// Both rest on the convex hull property: with weights > 0, a Bézier patch lies in the convex hull of its Euclidean
// control points, so any box holding the control points holds the patch. A patch whose box cannot hold anything
// better than the best answer found so far (by more than the tolerance) is dropped; the others are split at their
// parameter midpoints (de Casteljau, in homogeneous coordinates) until every remaining piece is dropped. The answer
// is then proven within the tolerance of the true global optimum; if the budget of splits runs out first, the search
// fails with BudgetExceeded rather than return an unproven answer.
//
// References:
//  - L. Piegl, W. Tiller, "The NURBS Book", 2nd ed., section 6.1 (point inversion and projection: Newton's method
//    on f(u, v) = S_u . (S - P) = 0, g(u, v) = S_v . (S - P) = 0, with the zero-cosine convergence criteria).
//  - G. Farin, "Curves and Surfaces for CAGD", 5th ed., ch. 14-16 (subdivision of tensor-product patches).
#pragma once

#include <cstddef>
#include <span>

#include "geometry/core/cancel.h"
#include "geometry/core/result.h"
#include "geometry/core/types.h"
#include "geometry/surfaces/bspline_surface.h"

namespace surfaced {

struct SurfaceSearchOptions {
    //! Absolute tolerance of the proof (model units): the answer is within it of the true optimum. 0 = automatic:
    //! 1e-9 times (the diagonal of the control net's box + the distance from the query point to that box).
    double tolerance = 0;
    //! Ceiling on patch splits per query; beyond it the query fails with BudgetExceeded. Each split keeps at most
    //! four pieces of (p + 1) (q + 1) control points alive.
    std::size_t max_subdivisions = 4096;
    //! Newton iterations per local refinement.
    int max_newton_iterations = 50;
    Cancel cancel;  //!< polled every 64 splits
};

struct SurfaceClosestPoint {
    double u = 0, v = 0;  //!< surface parameters of `point`
    Vec3 point;           //!< S(u, v)
    double distance = 0;  //!< |point - query|
    //! Whether Newton's iteration at (u, v) met its criteria (|S - P| below 1e-12 of the net's size, or S - P
    //! orthogonal to S_u and S_v to 1e-10 in the cosine, a component that sits on the domain's boundary and points
    //! outward excepted). false means the answer is still the proven one, only not a stationary point to rounding.
    bool converged = false;
    double gap = 0;                //!< proven: distance - (the true minimum distance) <= gap <= tolerance
    std::size_t subdivisions = 0;  //!< patch splits the proof took
};

//! Closest point on the surface to `query`, proven globally within the tolerance (see the file comment). Newton
//! iterations from the centre of each piece that improves the best distance refine it (on the Bézier patch, with
//! the parameters clamped to the patch). Errors: validate() and to_bezier's (InvalidArgument, Cancelled);
//! InvalidArgument for a non-finite query or a negative/non-finite tolerance; BudgetExceeded when the proof needs
//! more than max_subdivisions splits (e.g. a query at the centre of a sphere, where every point is closest).
//! O(patches (p + 1)(q + 1)) to start, then O((p + 1)(q + 1)(p + q)) per split.
Result<SurfaceClosestPoint> closest_point(const BSplineSurface& surface, const Vec3& query,
                                          const SurfaceSearchOptions& options = {});
//! The same on a decomposition already computed (to_bezier(surface)), for many queries on one surface.
Result<SurfaceClosestPoint> closest_point(const SurfaceBezierPatches& patches, const Vec3& query,
                                          const SurfaceSearchOptions& options = {});

//! The box of the control points (it holds the surface by the convex hull property).
Box3 control_hull_box(const BSplineSurface& surface);

//! The tight axis-aligned bounding box of the surface: per axis and side, the extreme value of the coordinate over
//! the surface, proven within the tolerance (the returned box holds the surface and is at most `tolerance` larger
//! than the tightest box on each side). Errors: as closest_point (BudgetExceeded past max_subdivisions splits per side).
Result<Box3> tight_bounding_box(const SurfaceBezierPatches& patches, const SurfaceSearchOptions& options = {});

}  // namespace surfaced
