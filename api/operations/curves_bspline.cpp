// POST /curves, B-spline and NURBS curves (curves.h has the request): decoding with the knot vector's checks, the
// queries (evaluation, derivatives, knot insertion, Bézier pieces, bounding box, tessellation), and the answer.
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

// ---- B-splines -----------------------------------------------------------------------------------------------------

constexpr std::string_view kKnotVectors[] = {"clamped", "uniform", "closed"};

ApiResult<BSplineCurve> decode_bspline(const Json& value, std::size_t& dimension) {
    if (!value.is_object())
        return invalid("bspline",
                       R"(bspline must be {"degree": p, "points": [...], "knots"?: [...], "knot_vector"?: "clamped"})");
    if (auto error = check_members(value, "bspline", {"degree", "points", "weights", "knots", "knot_vector"}))
        return std::move(*error);
    BSplineCurve curve;
    const auto degree_it = value.find("degree");
    if (degree_it == value.end()) return invalid("bspline.degree", "bspline.degree is required: an integer >= 1");
    auto degree = read_integer(*degree_it, "bspline.degree");
    if (!degree) return std::move(degree.error());
    if (degree.value() < 1 || degree.value() > kMaxBsplineDegree)
        return invalid("bspline.degree", "bspline.degree must be in 1.." + std::to_string(kMaxBsplineDegree));
    curve.degree = static_cast<int>(degree.value());

    const auto points = value.find("points");
    if (points == value.end() || !points->is_array() || points->empty() || !(*points)[0].is_array())
        return invalid("bspline.points", "bspline.points is required: an array of [x, y] or [x, y, z]");
    if (points->size() > kMaxBsplinePoints)
        return budget("bspline.points has " + std::to_string(points->size()) + " control points; the limit is " +
                          std::to_string(kMaxBsplinePoints),
                      "bspline.points");
    if (points->size() < static_cast<std::size_t>(curve.degree) + 1)
        return invalid("bspline.points",
                       "bspline.points needs at least degree + 1 = " + std::to_string(curve.degree + 1) +
                           " control points, got " + std::to_string(points->size()));
    dimension = (*points)[0].size() == 2 ? 2 : 3;
    if (auto error = read_control_points(*points, "bspline.points", dimension, curve.points)) return std::move(*error);
    if (auto it = value.find("weights"); it != value.end())
        if (auto error = read_weights(*it, "bspline.weights", curve.points.size(), curve.weights))
            return std::move(*error);

    const auto knots = value.find("knots");
    const auto kind = value.find("knot_vector");
    if (knots != value.end() && kind != value.end())
        return invalid("bspline.knot_vector", "give bspline.knots or bspline.knot_vector, not both");
    if (knots != value.end()) {
        const std::size_t expected = curve.points.size() + static_cast<std::size_t>(curve.degree) + 1;
        if (!knots->is_array() || knots->size() != expected)
            return invalid("bspline.knots", "bspline.knots must be an array of points + degree + 1 = " +
                                                std::to_string(expected) + " numbers");
        for (std::size_t i = 0; i < knots->size(); ++i) {
            auto u = read_number((*knots)[i], index_path("bspline.knots", i));
            if (!u) return std::move(u.error());
            curve.knots.push_back(u.value());
        }
    } else {
        std::string_view name = "clamped";
        if (kind != value.end()) {
            if (!kind->is_string() || std::find(std::begin(kKnotVectors), std::end(kKnotVectors),
                                                kind->get_ref<const std::string&>()) == std::end(kKnotVectors))
                return invalid("bspline.knot_vector",
                               R"(bspline.knot_vector must be one of "clamped", "uniform", "closed")");
            name = kind->get_ref<const std::string&>();
        }
        if (name == "closed") {
            auto closed = closed_uniform(curve.points, curve.degree, curve.weights);
            if (!closed) return error_at(closed.error(), "bspline.points");
            curve = std::move(closed.value());
        } else {
            auto generated = name == "clamped" ? clamped_uniform_knots(curve.points.size(), curve.degree)
                                               : uniform_knots(curve.points.size(), curve.degree);
            if (!generated) return error_at(generated.error(), "bspline.knot_vector");
            curve.knots = std::move(generated.value());
        }
    }
    if (Status s = validate(curve); !s) {
        const GeoError& e = s.error();
        std::string field = "bspline";
        if (e.element >= 0 && e.element_kind == ElementKind::Vertex)
            field = index_path(curve.is_rational() && e.message.find("weight") != std::string::npos ? "bspline.weights"
                                                                                                    : "bspline.points",
                               static_cast<std::size_t>(e.element));
        else if (e.element >= 0 && knots != value.end())
            field = index_path("bspline.knots", static_cast<std::size_t>(e.element));
        else if (knots != value.end())
            field = "bspline.knots";
        return error_at(e, field);
    }
    return curve;
}

//! What a B-spline request asks, read and checked in full before any work.
struct BSplineQueries {
    std::optional<std::vector<double>> evaluate_at, derivatives_at;
    int order = 1;
    std::optional<std::pair<double, int>> insert;  //!< (u, times)
    bool to_bezier = false;
    bool bounding_box = false;
    std::optional<double> tessellate_tolerance;
};

//! "insert_knot": {"u": u in the domain, "times"?: 1..degree}.
std::optional<ApiError> read_insert_knot(const Json& value, const BSplineCurve& curve, double u0, double u1,
                                         BSplineQueries& q) {
    if (!value.is_object() || !value.contains("u"))
        return invalid("insert_knot", R"(insert_knot must be {"u": u, "times"?: k})");
    if (auto error = check_members(value, "insert_knot", {"u", "times"})) return error;
    auto u = read_number(value["u"], "insert_knot.u");
    if (!u) return std::move(u.error());
    if (u.value() < u0 || u.value() > u1)
        return invalid("insert_knot.u", "insert_knot.u = " + format_double(u.value()) + " is outside the domain [" +
                                            format_double(u0) + ", " + format_double(u1) + "]");
    std::int64_t times = 1;
    if (auto t = value.find("times"); t != value.end()) {
        auto k = read_integer(*t, "insert_knot.times");
        if (!k) return std::move(k.error());
        if (k.value() < 1 || k.value() > curve.degree)
            return invalid("insert_knot.times",
                           "insert_knot.times must be in 1.." + std::to_string(curve.degree) + " (the degree)");
        times = k.value();
    }
    q.insert = std::pair{u.value(), static_cast<int>(times)};
    return std::nullopt;
}

std::optional<ApiError> read_bspline_queries(const Json& root, const BSplineCurve& curve, double u0, double u1,
                                             BSplineQueries& q) {
    if (auto it = root.find("evaluate"); it != root.end()) {
        auto us = read_parameters_in(*it, "evaluate", u0, u1, "the domain");
        if (!us) return std::move(us.error());
        q.evaluate_at = std::move(us.value());
    }
    if (auto it = root.find("derivatives"); it != root.end()) {
        if (!it->is_object() || !it->contains("t") || !it->contains("order"))
            return invalid("derivatives", R"(derivatives must be {"t": [u, ...], "order": k})");
        if (auto error = check_members(*it, "derivatives", {"t", "order"})) return error;
        auto us = read_parameters_in((*it)["t"], "derivatives.t", u0, u1, "the domain");
        if (!us) return std::move(us.error());
        auto k = read_integer((*it)["order"], "derivatives.order");
        if (!k) return std::move(k.error());
        if (k.value() < 1 || k.value() > 64)
            return invalid("derivatives.order", "derivatives.order must be an integer in 1..64");
        q.derivatives_at = std::move(us.value());
        q.order = static_cast<int>(k.value());
    }
    const std::size_t queries =
        (q.evaluate_at ? q.evaluate_at->size() : 0) + (q.derivatives_at ? q.derivatives_at->size() : 0);
    if (queries > kMaxCurveQueries)
        return budget(
            std::to_string(queries) + " parameters requested; the limit is " + std::to_string(kMaxCurveQueries),
            q.evaluate_at ? "evaluate" : "derivatives.t");
    if (auto it = root.find("insert_knot"); it != root.end())
        if (auto error = read_insert_knot(*it, curve, u0, u1, q)) return error;
    auto to_bezier_asked = read_switch(root, "to_bezier");
    if (!to_bezier_asked) return std::move(to_bezier_asked.error());
    q.to_bezier = to_bezier_asked.value();
    auto box_asked = read_switch(root, "bounding_box");
    if (!box_asked) return std::move(box_asked.error());
    q.bounding_box = box_asked.value();
    if (auto it = root.find("tessellate"); it != root.end()) {
        auto tolerance = read_tolerance(*it, "tessellate");
        if (!tolerance) return std::move(tolerance.error());
        q.tessellate_tolerance = tolerance.value();
    }
    return std::nullopt;
}

}  // namespace

ApiResponse run_bspline(const Json& root, const ApiContext& context, OutputFormat format) {
    if (auto error = check_form_members(
            root, "bspline", "a B-spline",
            {"bspline", "evaluate", "derivatives", "insert_knot", "to_bezier", "bounding_box", "tessellate", "output"}))
        return error_response(std::move(*error));
    if (auto error = check_gltf_request(root, format, {})) return error_response(std::move(*error));
    Encoder encoder;
    auto decoded = decode_bspline(root["bspline"], encoder.dimension);
    if (!decoded) return error_response(std::move(decoded.error()));
    const BSplineCurve& curve = decoded.value();
    const auto [u0, u1] = domain(curve);
    BSplineQueries q;
    if (auto error = read_bspline_queries(root, curve, u0, u1, q)) return error_response(std::move(*error));

    Json out = {{"degree", curve.degree}, {"rational", curve.is_rational()}, {"domain", Json::array({u0, u1})}};
    if (q.evaluate_at) {
        Json points = Json::array();
        for (double u : *q.evaluate_at) points.push_back(encoder.point(evaluate(curve, u)));
        out["evaluate"] = std::move(points);
    }
    if (q.derivatives_at) {
        Json values = Json::array();
        for (double u : *q.derivatives_at) values.push_back(encoder.point(derivative(curve, u, q.order)));
        out["derivatives"] = std::move(values);
    }
    if (q.insert) {
        auto inserted = insert_knot(curve, q.insert->first, q.insert->second);
        if (!inserted) return error_response(error_at(inserted.error(), "insert_knot"));
        out["insert_knot"] = encoder.bspline(*inserted);
    }
    if (q.to_bezier) {
        auto chain = to_bezier(curve, context.cancel);
        if (!chain) return error_response(error_at(chain.error(), "to_bezier"));
        Json encoded = encoder.chain(*chain);
        encoded["breaks"] = bezier_breaks(curve);
        out["to_bezier"] = std::move(encoded);
    }
    if (q.bounding_box) {
        const Box3 box = bounding_box(curve);
        out["bounding_box"] = {{"min", encoder.point(box.min)}, {"max", encoder.point(box.max)}};
    }
    if (q.tessellate_tolerance) {
        BSplineTessellationOptions options;
        options.tolerance = *q.tessellate_tolerance;
        options.max_segments = static_cast<std::size_t>(context.limits.max_output_faces);
        options.cancel = context.cancel;
        auto polyline = tessellate(curve, options);
        if (!polyline) return error_response(error_at(polyline.error(), "tessellate.tolerance"));
        if (format != OutputFormat::Json)
            return polyline_response({polyline->points}, format, polyline->segments, polyline->bound);
        out["tessellate"] = encoder.tessellation(*polyline);
    }
    return json_response(out);
}

}  // namespace surfaced::api::operations::curve_request
