// JSON -> patch sets and tessellation options, for POST /tessellate. The second api/ translation unit that
// includes nlohmann/json (kept apart from json_codec.cpp so the mesh codec does not grow with every endpoint).
//
// Request form:
//   {"patches": [{"degree": [m, n], "points": [[x, y, z], ...]}, ...],   (m+1)(n+1) points, u varying fastest
//              optional per patch "weights": [w, ...] (one > 0 per point, same order): a rational patch
//    "surfaces": [{"degree": [p, q], "knots_u": [...], "knots_v": [...], "points": [...], "weights"?: [...]}, ...],
//              B-spline/NURBS surfaces (api/surface_codec.h), tessellated through their Bézier patches; with
//              "trim": {"outer"?: [curve, ...], "holes"?: [[curve, ...], ...]} (api/trim_codec.h) a trimmed surface
//    "tolerance": t | "segments": n,
//    "output": {"format": "glb"|"obj"|"ply", "compression": "draco"|"none", "quantize_position": 14, "normals": true}}
// "patches" or "surfaces" (or both) is required. Errors name the field: "patches[2].points[7][1] must be a finite number",
// "patches[0].points has 15 points; degree [3, 3] needs 16", "tolerance must be a number". Budgets (number of
// patches, total control points) are checked before the points are copied out of the document.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "api/dto.h"
#include "api/options/option_reader.h"
#include "api/trim_codec.h"
#include "api/errors.h"
#include "api/limits.h"
#include "geometry/surfaces/bezier_patch.h"
#include "geometry/surfaces/bspline_surface.h"

namespace surfaced::api {

struct TessellateParams {
    std::optional<double> tolerance;       //!< "tolerance" (model units), as sent; checked by the operation
    std::optional<std::int64_t> segments;  //!< "segments" per patch direction, as sent
    OutputOptions output;                  //!< normals default to true here (see operations/tessellate.h)
    bool patches_format = false;           //!< format "patches": the Bézier patches as JSON instead of a mesh
};

struct TessellateJsonRequest {
    PatchSet patches;
    std::vector<BSplineSurface> surfaces;           //!< validated; decomposed into patches by the operation
    std::vector<std::optional<SurfaceTrim>> trims;  //!< parallel to surfaces: the trim, for a trimmed surface
    TessellateParams params;
};

ApiResult<TessellateJsonRequest> decode_tessellate_request(std::string_view body, const Limits& limits);
//! The params from option values read by the table of "tessellate" or "patches" (api/options).
TessellateParams tessellate_params(const options::OptionValues& values);

//! {"patches":[{"degree":[m,n],"points":[[x,y,z],...],"weights":[...]},...]}: the JSON form of POST /tessellate's
//! body, numbers printed shortest-round-trip.
std::string patch_set_json(const PatchSet& set);

}  // namespace surfaced::api
