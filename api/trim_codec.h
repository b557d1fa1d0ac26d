// JSON <-> trim loops of a B-spline/NURBS surface (geometry/surfaces/trim_loops.h), for POST /tessellate's
// "surfaces[i].trim". Internal to api/ (nlohmann/json forward-declared only).
//
// Form: {"outer"?: [curve, ...], "holes"?: [[curve, ...], ...]}: one outer loop (none: the whole parameter
// rectangle) and any number of holes, each a list of curves, each ending where the next starts. A curve is
// {"degree": d, "points": [[u, v], ...], "knots"?: [...], "weights"?: [...]} in the surface's parameter space: d in
// 1..kMaxTrimCurveDegree, at least d + 1 points, |points| + d + 1 knots (omitted: clamped uniform over [0, 1], as
// POST /curves' "bspline" takes by default, so d + 1 points without knots are a Bézier curve), one weight > 0 per
// point for a rational curve.
// Shape errors (not an object or array, a number that is not finite, a wrong count, a degree out of range) are 400
// invalid_field with the path ("surfaces[2].trim.holes[0][1].points[3][0]"). The rules of validate_trims (a curve
// that is not a valid B-spline, open loops, self-intersections, crossings, holes outside the outer loop) are checked
// by the operation: trim_error() turns its TrimError into a 422 whose field names the loop and curve
// ("surfaces[2].trim.holes[0][1]", the outer loop's curve 3: "surfaces[2].trim.outer[3]").
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "api/errors.h"
#include "geometry/surfaces/trim_loops.h"

namespace surfaced::api {

inline constexpr int kMaxTrimCurveDegree = kMaxPatchDegree;  //!< as OBJ's deg statement allows
inline constexpr std::size_t kMaxTrimLoops = 10'000;         //!< outer loops and holes of one request
inline constexpr std::size_t kMaxTrimCurves = 100'000;       //!< trim curves of one request
inline constexpr std::size_t kMaxTrimPoints = 1'000'000;     //!< trim control points of one request
inline constexpr std::size_t kMaxTrimSegments = 1'000'000;   //!< chords of the validated loops of one request

struct SurfaceTrim {
    std::vector<TrimLoop> outer;  //!< none or one
    std::vector<TrimLoop> holes;
};

//! The loops, curves and control points the trims in `surfaces` (a JSON array of surfaces) would hold, counted
//! from the array sizes without copying anything: a 422 budget_exceeded past kMaxTrimLoops / Curves / Points.
std::optional<ApiError> check_trim_budgets(const nlohmann::json& surfaces);

//! `value` (the "trim" member) at `path` ("surfaces[2].trim").
ApiResult<SurfaceTrim> decode_trim(const nlohmann::json& value, const std::string& path);

//! The JSON path of a loop or curve of the trim at `trim_path`: outer loop 0 is "<trim_path>.outer", hole 1 is
//! "<trim_path>.holes[1]", their curves add "[j]".
std::string trim_field(const std::string& trim_path, TrimLoopKind kind, int loop, int curve = -1);

//! A TrimError as a 422 (budget_exceeded for TooManySegments): the field of its loop and curve, the message with
//! every loop named by its JSON path.
ApiError trim_error(const TrimError& error, const std::string& trim_path);

}  // namespace surfaced::api
