// POST /surfaces: queries on one B-spline or NURBS surface (geometry/surfaces/bspline_surface.h, surface_search.h),
// answered in JSON.
//
// Request (application/json; "surface" and at least one query required):
//   {"surface": {"degree": [p, q], "knots_u": [...], "knots_v": [...], "points": [[x, y, z], ...], "weights"?: [...]},
//    "evaluate": [[u, v], ...],             position, du, dv and the unit normal (the limit at a pole)
//    "derivatives": [[u, v], ...],          position and the partial derivatives to order 2
//    "closest": [[x, y, z], ...],           the global closest point, proven within 1e-9 of the net's size
//    "insert_knot": {"direction": "u" | "v", "value": t, "times"?: k},   the refined surface
//    "elevate": {"direction": "u" | "v", "times"?: k},                   the degree-elevated surface
//    "to_bezier": true,                     the Bézier patches (POST /tessellate's "patches") and their breaks
//    "bounding_box": true}                  the control hull's box and the tight box (within 1e-9 of the net's size)
// The surface form is api/surface_codec.h's (u varying fastest; count_u = |knots_u| - p - 1). (u, v) lie in the
// domain [knots_u[p], knots_u[count_u]] x [knots_v[q], knots_v[count_v]].
// Response: {"degree": [p, q], "rational": b, "domain": {"u": [u0, u1], "v": [v0, v1]}, and per query:
//   "evaluate": [{"position", "du", "dv", "normal"}, ...], "derivatives": [{"position", "du", "dv", "duu", "duv",
//   "dvv"}, ...], "closest": [{"uv": [u, v], "point", "distance", "converged", "gap"}, ...], "insert_knot": surface,
//   "elevate": surface, "to_bezier": {"patches": [...], "breaks_u", "breaks_v"}, "bounding_box": {"control_hull":
//   {"min", "max"}, "tight": {"min", "max"}}}.
// Errors: problem+json with field paths: 400 for the request's shape ("evaluate[2]" not a pair); 422 for the
// surface's rules ("surface.knots_u[5]", "surface.weights[3]", "surface.degree[1]"), a parameter outside the domain
// ("evaluate[2][1]", "insert_knot.value"), a knot multiplicity or degree past the limit ("insert_knot.times",
// "elevate.times"); 422 budget_exceeded past the budgets below or Limits (control points, Bézier patches) and for a
// closest point whose proof needs more than its budget of splits ("closest[4]"), all but the last checked before
// any work; 503 when the compute deadline passes.
#pragma once

#include <cstddef>

#include "api/operation.h"

namespace surfaced::api::operations {

inline constexpr std::size_t kMaxSurfaceQueries = 100'000;  //!< parameters in evaluate + derivatives
inline constexpr std::size_t kMaxSurfaceClosest = 10'000;   //!< points in closest (each a branch and bound)

ApiResponse surfaces(const ApiRequest& request, const ApiContext& context) noexcept;

}  // namespace surfaced::api::operations
