// POST /curves (see curves.h). Decodes, checks budgets, runs the requested queries on geometry/curves, encodes.
// One of the few api/ translation units that include nlohmann/json: decoding and encoding live together here
// because the response mirrors the request's members.
#include "api/operations/curves.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <new>
#include <optional>
#include <string>
#include <vector>

#include "api/json_util.h"
#include "api/operations/request_forms.h"

#include "geometry/curves/bezier_curve.h"

namespace surfaced::api::operations {
namespace {

using namespace json;  // the shared readers (api/json_util.h)

std::string at(const std::string& path, std::size_t i) { return path + "[" + std::to_string(i) + "]"; }

ApiResult<double> read_parameter(const Json& value, const std::string& field) {
    auto t = read_number(value, field);
    if (!t) return t;
    if (t.value() < 0 || t.value() > 1) return invalid(field, field + " must be in [0, 1]");
    return t;
}

ApiResult<std::vector<double>> read_parameters(const Json& value, const std::string& field) {
    if (!value.is_array()) return invalid(field, field + " must be an array of parameters in [0, 1]");
    std::vector<double> out;
    for (std::size_t i = 0; i < value.size(); ++i) {
        auto t = read_parameter(value[i], at(field, i));
        if (!t) return std::move(t.error());
        out.push_back(t.value());
    }
    return out;
}

ApiResult<Vec3> read_point(const Json& value, const std::string& field, std::size_t dimension) {
    if (!value.is_array() || value.size() != dimension)
        return invalid(field, field + " must be [x, y" + (dimension == 3 ? ", z]" : "]"));
    Vec3 p;
    for (std::size_t c = 0; c < dimension; ++c) {
        auto x = read_number(value[c], at(field, c));
        if (!x) return std::move(x.error());
        p[static_cast<int>(c)] = x.value();
    }
    return p;
}

ApiResult<double> read_tolerance(const Json& value, const std::string& path) {
    const std::string field = path + ".tolerance";
    if (!value.is_object() || !value.contains("tolerance") || value.size() != 1)
        return invalid(field, path + " must be {\"tolerance\": e}");
    auto e = read_number(value["tolerance"], field);
    if (!e) return e;
    if (e.value() <= 0) return invalid(field, field + " must be > 0");
    return e;
}

struct Encoder {
    std::size_t dimension = 3;
    Json point(const Vec3& p) const {
        return dimension == 2 ? Json::array({p.x, p.y}) : Json::array({p.x, p.y, p.z});
    }
    Json curve(const BezierCurve& c) const {
        Json out = {{"points", Json::array()}};
        for (const Vec3& p : c.points) out["points"].push_back(point(p));
        if (c.is_rational()) out["weights"] = c.weights;
        return out;
    }
};

ApiResponse run(const ApiRequest& request, const ApiContext& context) {
    const Limits& limits = context.limits;
    if (request.body.size() > limits.max_body_bytes)
        return error_response(make_problem(Problem::PayloadTooLarge,
                                           "request body is " + std::to_string(request.body.size()) +
                                               " bytes; the limit is " + std::to_string(limits.max_body_bytes)));
    std::string_view type = std::string_view(request.content_type).substr(0, request.content_type.find(';'));
    while (!type.empty() && type.back() == ' ') type.remove_suffix(1);
    if (type != "application/json")
        return error_response(make_problem(Problem::UnsupportedMediaType, "POST /curves takes application/json"));
    if (!request.query.empty())
        return error_response(make_problem(Problem::UnknownParameter,
                                           "query parameters are not accepted (options go in the body), got \"" +
                                               request.query.begin()->first + "\"",
                                           request.query.begin()->first));
    Json root;
    try {
        root = Json::parse(request.body.begin(), request.body.end());
    } catch (const Json::exception& e) {
        return error_response(make_problem(Problem::InvalidJson, std::string("request body is not valid JSON: ") + e.what()));
    }
    if (!root.is_object()) return error_response(invalid("", "the body must be a JSON object"));
    static constexpr std::string_view kMembers[] = {"points",  "weights", "evaluate", "derivatives", "curvature",
                                                    "split",   "elevate", "bounding_box", "length", "closest",
                                                    "tessellate"};
    for (const auto& item : root.items())
        if (std::find(std::begin(kMembers), std::end(kMembers), item.key()) == std::end(kMembers))
            return error_response(make_problem(Problem::UnknownField, "unknown field \"" + item.key() + "\" at top level",
                                               item.key()));

    // curve
    const auto points = root.find("points");
    if (points == root.end() || !points->is_array() || points->empty() || !(*points)[0].is_array())
        return error_response(invalid("points", "points is required: an array of [x, y] or [x, y, z]"));
    if (points->size() > static_cast<std::size_t>(kMaxCurveDegree) + 1)
        return error_response(make_problem(Problem::BudgetExceeded,
                                           "points has " + std::to_string(points->size()) +
                                               " control points; the largest degree accepted is " +
                                               std::to_string(kMaxCurveDegree),
                                           "points"));
    Encoder encoder;
    encoder.dimension = (*points)[0].size() == 2 ? 2 : 3;
    BezierCurve curve;
    for (std::size_t i = 0; i < points->size(); ++i) {
        auto p = read_point((*points)[i], at("points", i), encoder.dimension);
        if (!p) return error_response(std::move(p.error()));
        curve.points.push_back(p.value());
    }
    if (auto it = root.find("weights"); it != root.end()) {
        if (!it->is_array() || it->size() != curve.points.size())
            return error_response(invalid("weights", "weights must be an array with one number per point"));
        for (std::size_t i = 0; i < it->size(); ++i) {
            auto w = read_number((*it)[i], at("weights", i));
            if (!w) return error_response(std::move(w.error()));
            if (w.value() <= 0) return error_response(invalid(at("weights", i), at("weights", i) + " must be > 0"));
            curve.weights.push_back(w.value());
        }
    }

    // budgets on the number of evaluations, before any of them
    std::size_t queries = 0;
    for (const char* name : {"evaluate", "curvature"})
        if (auto it = root.find(name); it != root.end() && it->is_array()) queries += it->size();
    if (auto it = root.find("derivatives"); it != root.end() && it->is_object() && it->contains("t") && (*it)["t"].is_array())
        queries += (*it)["t"].size();
    if (queries > kMaxCurveQueries)
        return error_response(make_problem(Problem::BudgetExceeded,
                                           std::to_string(queries) + " parameters requested; the limit is " +
                                               std::to_string(kMaxCurveQueries)));

    Json out = {{"degree", curve.degree()}, {"rational", curve.is_rational()}};
    if (auto it = root.find("evaluate"); it != root.end()) {
        auto ts = read_parameters(*it, "evaluate");
        if (!ts) return error_response(std::move(ts.error()));
        out["evaluate"] = Json::array();
        for (double t : ts.value()) out["evaluate"].push_back(encoder.point(evaluate(curve, t)));
    }
    if (auto it = root.find("derivatives"); it != root.end()) {
        if (!it->is_object() || !it->contains("t") || !it->contains("order"))
            return error_response(invalid("derivatives", R"(derivatives must be {"t": [t, ...], "order": k})"));
        auto ts = read_parameters((*it)["t"], "derivatives.t");
        if (!ts) return error_response(std::move(ts.error()));
        const Json& order = (*it)["order"];
        if (!order.is_number_integer() || order.get<std::int64_t>() < 1 || order.get<std::int64_t>() > 64)
            return error_response(invalid("derivatives.order", "derivatives.order must be an integer in 1..64"));
        out["derivatives"] = Json::array();
        for (double t : ts.value())
            out["derivatives"].push_back(encoder.point(derivative(curve, t, static_cast<int>(order.get<std::int64_t>()))));
    }
    if (auto it = root.find("curvature"); it != root.end()) {
        auto ts = read_parameters(*it, "curvature");
        if (!ts) return error_response(std::move(ts.error()));
        out["curvature"] = Json::array();
        for (double t : ts.value()) out["curvature"].push_back(curvature(curve, t));
    }
    if (auto it = root.find("split"); it != root.end()) {
        auto t = read_parameter(*it, "split");
        if (!t) return error_response(std::move(t.error()));
        const auto [left, right] = split(curve, t.value());
        out["split"] = Json::array({encoder.curve(left), encoder.curve(right)});
    }
    if (auto it = root.find("elevate"); it != root.end()) {
        if (!it->is_number_integer() || it->get<std::int64_t>() < 0 ||
            curve.degree() + it->get<std::int64_t>() > kMaxCurveDegree)
            return error_response(invalid("elevate", "elevate must be an integer >= 0 keeping the degree <= " +
                                                         std::to_string(kMaxCurveDegree)));
        out["elevate"] = encoder.curve(elevate_degree(curve, static_cast<int>(it->get<std::int64_t>())));
    }
    if (auto it = root.find("bounding_box"); it != root.end() && it->is_boolean() && it->get<bool>()) {
        const Box3 box = bounding_box(curve);
        out["bounding_box"] = {{"min", encoder.point(box.min)}, {"max", encoder.point(box.max)}};
    }
    if (auto it = root.find("length"); it != root.end()) {
        auto tolerance = read_tolerance(*it, "length");
        if (!tolerance) return error_response(std::move(tolerance.error()));
        const ArcLength length = arc_length(curve, std::max(tolerance.value(), 1e-12));
        out["length"] = {{"length", length.length}, {"error_bound", length.error_bound},
                         {"guaranteed", !curve.is_rational()}};
    }
    if (auto it = root.find("closest"); it != root.end()) {
        auto q = read_point(*it, "closest", encoder.dimension);
        if (!q) return error_response(std::move(q.error()));
        const ClosestPoint c = closest_point(curve, q.value());
        out["closest"] = {{"t", c.t}, {"point", encoder.point(c.point)}, {"distance", c.distance}};
    }
    if (auto it = root.find("tessellate"); it != root.end()) {
        auto tolerance = read_tolerance(*it, "tessellate");
        if (!tolerance) return error_response(std::move(tolerance.error()));
        auto polyline = tessellate(curve, tolerance.value(), static_cast<std::size_t>(limits.max_output_faces));
        if (!polyline) {
            ApiError error = from_geo_error(polyline.error());
            error.field = "tessellate.tolerance";
            return error_response(std::move(error));
        }
        Json pts = Json::array();
        for (const Vec3& p : polyline->points) pts.push_back(encoder.point(p));
        out["tessellate"] = {{"points", pts},
                             {"params", polyline->params},
                             {"segments", polyline->segments},
                             {"max_deviation", polyline->max_deviation},
                             {"bound", polyline->bound}};
    }
    ApiResponse response;
    response.content_type = "application/json";
    response.body = out.dump();
    return response;
}

}  // namespace

ApiResponse curves(const ApiRequest& request, const ApiContext& context) noexcept {
    return guarded([&] { return run(request, context); });
}

}  // namespace surfaced::api::operations
