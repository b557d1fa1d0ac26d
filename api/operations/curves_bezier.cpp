// POST /curves, one Bézier curve (curves.h has the request): its control points and weights, the parameter and
// curve queries (evaluation, derivatives, curvature, split, elevation, bounding box, length, closest point,
// tessellation), and the answer.
#include <algorithm>
#include <cmath>
#include <exception>
#include <initializer_list>
#include <new>
#include <optional>
#include <string>
#include <vector>

#include "api/operations/curve_request.h"
#include "api/operations/request_forms.h"
#include "api/options/option_reader.h"
#include "geometry/curves/svg_path.h"

namespace surfaced::api::operations::curve_request {
namespace {

using namespace json;  // the shared readers (api/json_util.h)

// ---- one Bézier curve ----------------------------------------------------------------------------------------------

//! "points" (2D or 3D, at most kMaxCurveDegree + 1) and optional "weights"; sets the encoder's dimension.
std::optional<ApiError> read_single_curve(const Json& root, Encoder& encoder, BezierCurve& curve) {
    const auto points = root.find("points");
    if (points == root.end() || !points->is_array() || points->empty() || !(*points)[0].is_array())
        return invalid("points", "points is required: an array of [x, y] or [x, y, z]");
    if (points->size() > static_cast<std::size_t>(kMaxCurveDegree) + 1)
        return make_problem(Problem::BudgetExceeded,
                            "points has " + std::to_string(points->size()) +
                                " control points; the largest degree accepted is " + std::to_string(kMaxCurveDegree),
                            "points");
    encoder.dimension = (*points)[0].size() == 2 ? 2 : 3;
    if (auto error = read_control_points(*points, "points", encoder.dimension, curve.points)) return error;
    if (auto it = root.find("weights"); it != root.end())
        if (auto error = read_weights(*it, "weights", curve.points.size(), curve.weights)) return error;
    return std::nullopt;
}

//! The budget on the number of evaluations (evaluate, curvature, derivatives.t), before any of them.
std::optional<ApiError> check_query_budget(const Json& root) {
    std::size_t queries = 0;
    for (const char* name : {"evaluate", "curvature"})
        if (auto it = root.find(name); it != root.end() && it->is_array()) queries += it->size();
    if (auto it = root.find("derivatives");
        it != root.end() && it->is_object() && it->contains("t") && (*it)["t"].is_array())
        queries += (*it)["t"].size();
    if (queries > kMaxCurveQueries)
        return make_problem(Problem::BudgetExceeded, std::to_string(queries) + " parameters requested; the limit is " +
                                                         std::to_string(kMaxCurveQueries));
    return std::nullopt;
}

//! Queries at given parameters: "evaluate", "derivatives" {"t", "order"}, "curvature".
std::optional<ApiError> answer_parameter_queries(const Json& root, const BezierCurve& curve, const Encoder& encoder,
                                                 Json& out) {
    if (auto it = root.find("evaluate"); it != root.end()) {
        auto ts = read_parameters(*it, "evaluate");
        if (!ts) return std::move(ts.error());
        out["evaluate"] = Json::array();
        for (double t : ts.value()) out["evaluate"].push_back(encoder.point(evaluate(curve, t)));
    }
    if (auto it = root.find("derivatives"); it != root.end()) {
        if (!it->is_object() || !it->contains("t") || !it->contains("order"))
            return invalid("derivatives", R"(derivatives must be {"t": [t, ...], "order": k})");
        auto ts = read_parameters((*it)["t"], "derivatives.t");
        if (!ts) return std::move(ts.error());
        const Json& order = (*it)["order"];
        if (!order.is_number_integer() || order.get<std::int64_t>() < 1 || order.get<std::int64_t>() > 64)
            return invalid("derivatives.order", "derivatives.order must be an integer in 1..64");
        out["derivatives"] = Json::array();
        for (double t : ts.value())
            out["derivatives"].push_back(
                encoder.point(derivative(curve, t, static_cast<int>(order.get<std::int64_t>()))));
    }
    if (auto it = root.find("curvature"); it != root.end()) {
        auto ts = read_parameters(*it, "curvature");
        if (!ts) return std::move(ts.error());
        out["curvature"] = Json::array();
        for (double t : ts.value()) out["curvature"].push_back(curvature(curve, t));
    }
    return std::nullopt;
}

//! Queries on the whole curve: "split", "elevate", "bounding_box", "length", "closest".
std::optional<ApiError> answer_curve_queries(const Json& root, const BezierCurve& curve, const Encoder& encoder,
                                             Json& out) {
    if (auto it = root.find("split"); it != root.end()) {
        auto t = read_parameter(*it, "split");
        if (!t) return std::move(t.error());
        const auto [left, right] = split(curve, t.value());
        out["split"] = Json::array({encoder.curve(left), encoder.curve(right)});
    }
    if (auto it = root.find("elevate"); it != root.end()) {
        if (!it->is_number_integer() || it->get<std::int64_t>() < 0 ||
            curve.degree() + it->get<std::int64_t>() > kMaxCurveDegree)
            return invalid("elevate",
                           "elevate must be an integer >= 0 keeping the degree <= " + std::to_string(kMaxCurveDegree));
        out["elevate"] = encoder.curve(elevate_degree(curve, static_cast<int>(it->get<std::int64_t>())));
    }
    auto box_asked = read_switch(root, "bounding_box");
    if (!box_asked) return std::move(box_asked.error());
    if (box_asked.value()) {
        const Box3 box = bounding_box(curve);
        out["bounding_box"] = {{"min", encoder.point(box.min)}, {"max", encoder.point(box.max)}};
    }
    if (auto it = root.find("length"); it != root.end()) {
        auto tolerance = read_tolerance(*it, "length");
        if (!tolerance) return std::move(tolerance.error());
        const ArcLength length = arc_length(curve, std::max(tolerance.value(), 1e-12));
        out["length"] = {
            {"length", length.length}, {"error_bound", length.error_bound}, {"guaranteed", !curve.is_rational()}};
    }
    if (auto it = root.find("closest"); it != root.end()) {
        auto q = read_point(*it, "closest", encoder.dimension);
        if (!q) return std::move(q.error());
        const ClosestPoint c = closest_point(curve, q.value());
        out["closest"] = {{"t", c.t}, {"point", encoder.point(c.point)}, {"distance", c.distance}};
    }
    return std::nullopt;
}

}  // namespace

ApiResponse run_single(const Json& root, const Limits& limits, OutputFormat format) {
    if (auto error = check_form_members(root, "points", "one Bézier curve",
                                        {"points", "weights", "evaluate", "derivatives", "curvature", "split",
                                         "elevate", "bounding_box", "length", "closest", "tessellate", "output"}))
        return error_response(std::move(*error));
    if (auto error = check_gltf_request(root, format, {})) return error_response(std::move(*error));
    Encoder encoder;
    BezierCurve curve;
    if (auto error = read_single_curve(root, encoder, curve)) return error_response(std::move(*error));
    if (auto error = check_query_budget(root)) return error_response(std::move(*error));

    Json out = {{"degree", curve.degree()}, {"rational", curve.is_rational()}};
    if (auto error = answer_parameter_queries(root, curve, encoder, out)) return error_response(std::move(*error));
    if (auto error = answer_curve_queries(root, curve, encoder, out)) return error_response(std::move(*error));
    if (auto it = root.find("tessellate"); it != root.end()) {
        auto tolerance = read_tolerance(*it, "tessellate");
        if (!tolerance) return error_response(std::move(tolerance.error()));
        auto polyline = tessellate(curve, tolerance.value(), static_cast<std::size_t>(limits.max_output_faces));
        if (!polyline) {
            ApiError error = from_geo_error(polyline.error());
            error.field = "tessellate.tolerance";
            return error_response(std::move(error));
        }
        if (format != OutputFormat::Json)
            return polyline_response({polyline->points}, format, polyline->segments, polyline->bound);
        out["tessellate"] = encoder.tessellation(*polyline);
    }
    return json_response(out);
}

}  // namespace surfaced::api::operations::curve_request
