// Internal to POST /curves: what its three forms (one Bézier curve and the request in curves.cpp, chains and SVG
// paths in curves_chains.cpp, B-splines in curves_bspline.cpp) share: the readers of parameters, points and
// tolerances with their field paths, the JSON encoder of points and curves, the output helpers, and the forms'
// entry points. Only these translation units include it (it brings in nlohmann/json through api/json_util.h).
#pragma once

#include <cstddef>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "api/json_util.h"
#include "api/operation.h"
#include "api/operations/curves.h"
#include "api/operations/json_request.h"
#include "api/dto.h"
#include "api/limits.h"
#include "geometry/core/result.h"
#include "geometry/core/types.h"
#include "geometry/curves/bezier_curve.h"
#include "geometry/curves/bspline.h"
#include "geometry/curves/piecewise.h"
#include "geometry/io/polyline_gltf.h"

namespace surfaced::api::operations::curve_request {

using Json = json::Json;
using operations::budget;
using operations::error_at;
using operations::json_response;
using operations::read_switch;

ApiResult<double> read_parameter(const Json& value, const std::string& field);

ApiResult<std::vector<double>> read_parameters(const Json& value, const std::string& field);

//! Parameters in [lo, hi] (a chain's [0, pieces], a B-spline's domain); `what` says whose range it is.
ApiResult<std::vector<double>> read_parameters_in(const Json& value, const std::string& field, double lo, double hi,
                                                  const std::string& what);

ApiResult<Vec3> read_point(const Json& value, const std::string& field, std::size_t dimension);

ApiResult<double> read_tolerance(const Json& value, const std::string& path);

//! Control points at `path` (an array of [x, y] or [x, y, z] of `dimension`) and the weights at `weights_path`
//! (when `weights` is not null) into `curve`. The single-curve form's wording is the original one.
std::optional<ApiError> read_control_points(const Json& points, const std::string& path, std::size_t dimension,
                                            std::vector<Vec3>& out);

std::optional<ApiError> read_weights(const Json& weights, const std::string& path, std::size_t count,
                                     std::vector<double>& out);

// ---- output --------------------------------------------------------------------------------------------------------

//! glTF output carries the tessellation only: "tessellate" is required and the other queries are refused
//! (`modifiers` may stay: they change the curve that is tessellated).
std::optional<ApiError> check_gltf_request(const Json& root, OutputFormat format,
                                           std::initializer_list<std::string_view> modifiers);

ApiResponse polyline_response(const std::vector<Polyline>& polylines, OutputFormat format, std::size_t segments,
                              double bound);

//! Members of the root that the form does not take: 400 naming the first.
std::optional<ApiError> check_form_members(const Json& root, std::string_view form, std::string_view description,
                                           std::initializer_list<std::string_view> allowed);

// ---- encoding --------------------------------------------------------------------------------------------------------

struct Encoder {
    std::size_t dimension = 3;
    Json point(const Vec3& p) const { return dimension == 2 ? Json::array({p.x, p.y}) : Json::array({p.x, p.y, p.z}); }
    Json points(const std::vector<Vec3>& ps) const {
        Json out = Json::array();
        for (const Vec3& p : ps) out.push_back(point(p));
        return out;
    }
    Json curve(const BezierCurve& c) const {
        Json out = {{"points", Json::array()}};
        for (const Vec3& p : c.points) out["points"].push_back(point(p));
        if (c.is_rational()) out["weights"] = c.weights;
        return out;
    }
    Json chain(const BezierChain& c) const {
        Json pieces = Json::array();
        for (const BezierCurve& piece : c.pieces) pieces.push_back(curve(piece));
        return {{"pieces", std::move(pieces)}, {"closed", c.closed}};
    }
    Json bspline(const BSplineCurve& c) const {
        Json out = {{"degree", c.degree}, {"points", points(c.points)}, {"knots", c.knots}};
        if (c.is_rational()) out["weights"] = c.weights;
        return out;
    }
    Json tessellation(const CurveTessellation& t) const {
        return {{"points", points(t.points)},
                {"params", t.params},
                {"segments", t.segments},
                {"max_deviation", t.max_deviation},
                {"bound", t.bound}};
    }
};

// ---- the forms ---------------------------------------------------------------------------------------------------

//! {"points": ...}: one Bézier curve and its queries.
ApiResponse run_single(const Json& root, const Limits& limits, OutputFormat format);

//! {"chain": ...} or {"svg": ...}: chains of Bézier pieces and their queries.
ApiResponse run_chains(const Json& root, const ApiContext& context, OutputFormat format, bool svg);

//! {"bspline": ...}: one B-spline or NURBS curve and its queries.
ApiResponse run_bspline(const Json& root, const ApiContext& context, OutputFormat format);

}  // namespace surfaced::api::operations::curve_request
