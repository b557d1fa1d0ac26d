// JSON <-> B-spline/NURBS surfaces, shared by POST /tessellate ("surfaces") and POST /surfaces ("surface").
// Internal to api/ (it includes nlohmann/json through json_util.h).
//
// A surface: {"degree": [p, q], "knots_u": [...], "knots_v": [...], "points": [[x, y, z], ...], "weights"?: [...]}.
// The net has count_u = |knots_u| - p - 1 points along u and count_v = |knots_v| - q - 1 along v, u varying fastest
// (as for patches); "weights" (one > 0 per point) makes it rational. The rules are geometry's validate()
// (bspline_surface.h); its errors name the field: "surfaces[2].knots_u[5]", "surface.weights[7]". A "trim" member
// (api/trim_codec.h) is read by the caller that takes it (POST /tessellate) and refused as unknown elsewhere.
#pragma once

#include <cstdint>
#include <string>

#include "api/json_util.h"
#include "geometry/surfaces/bspline_surface.h"

namespace surfaced::api {

//! `value` at `path`; `max_points` bounds the net (count_u * count_v), checked before any point is read (422
//! budget_exceeded at path.points). Structural errors (not an object, not an array, not a number) are 400; broken
//! rules (degrees, knot vectors, weights) 422 with the field of the offending entry.
//! `allow_trim`: a "trim" member is left for the caller instead of refused.
ApiResult<BSplineSurface> decode_surface(const json::Json& value, const std::string& path, std::uint64_t max_points,
                                         bool allow_trim = false);

//! The surface in the form decode_surface reads.
json::Json surface_json(const BSplineSurface& surface);
//! A Bézier patch in the form of POST /tessellate's "patches" entries.
json::Json patch_json(const BezierPatch& patch);

}  // namespace surfaced::api
