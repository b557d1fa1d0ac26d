// POST /curves: one Bézier curve (2D or 3D, optionally rational) and the queries to run on it, answered in JSON.
//
// Request (application/json; only "points" is required):
//   {"points": [[x, y], ...] | [[x, y, z], ...],   all of one dimension; degree = count - 1 (at most kMaxCurveDegree)
//    "weights": [w, ...],                          positive, one per point: a rational curve
//    "evaluate": [t, ...],                         points at parameters in [0, 1]
//    "derivatives": {"t": [t, ...], "order": k},   k-th derivatives (k >= 1)
//    "curvature": [t, ...],
//    "split": t,                                   control points of both halves
//    "elevate": k,                                 control points after raising the degree k times
//    "bounding_box": true,
//    "length": {"tolerance": e},                   arc length and its error bound
//    "closest": [x, y(, z)],                       global closest point: t, point, distance
//    "tessellate": {"tolerance": e}}               polyline within e: points, params, segments, bounds
// Response: {"degree": n, "rational": bool, ...one member per query, points in the input's dimension}.
// Errors: problem+json with field paths ("points[3][1]", "evaluate[2]", "tessellate.tolerance"); 422
// budget_exceeded when more than Limits::max_curve_queries parameters or a tessellation over max_output_faces
// segments is asked for.
#pragma once

#include <cstddef>

#include "api/operation.h"

namespace surfaced::api::operations {

inline constexpr int kMaxCurveDegree = 64;
inline constexpr std::size_t kMaxCurveQueries = 100'000;  //!< parameters in evaluate + derivatives + curvature

ApiResponse curves(const ApiRequest& request, const ApiContext& context) noexcept;

}  // namespace surfaced::api::operations
