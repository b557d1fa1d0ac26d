// POST /curves (see curves.h). Decodes, checks budgets, runs the requested queries on geometry/curves, encodes.
// One of the few api/ translation units that include nlohmann/json: decoding and encoding live together here
// because the response mirrors the request's members.
// Order for every form: the request's shape (members, form, output), then the curve, then every query's options and
// the budgets, and only then any work.
#include "api/operations/curves.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <initializer_list>
#include <new>
#include <optional>
#include <string>
#include <vector>

#include "api/json_util.h"
#include "api/operations/request_forms.h"
#include "api/options/option_reader.h"

#include "geometry/curves/bezier_curve.h"
#include "geometry/curves/bspline.h"
#include "geometry/curves/piecewise.h"
#include "geometry/curves/svg_path.h"
#include "geometry/io/polyline_gltf.h"

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

//! Parameters in [lo, hi] (a chain's [0, pieces], a B-spline's domain); `what` says whose range it is.
ApiResult<std::vector<double>> read_parameters_in(const Json& value, const std::string& field, double lo, double hi,
                                                  const std::string& what) {
    if (!value.is_array()) return invalid(field, field + " must be an array of parameters");
    std::vector<double> out;
    for (std::size_t i = 0; i < value.size(); ++i) {
        const std::string item = at(field, i);
        auto t = read_number(value[i], item);
        if (!t) return std::move(t.error());
        if (t.value() < lo || t.value() > hi)
            return invalid(item, item + " = " + format_double(t.value()) + " is outside " + what + " [" +
                                     format_double(lo) + ", " + format_double(hi) + "]");
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
    if (!value.is_object() || !value.contains("tolerance")) return invalid(field, path + " must be {\"tolerance\": e}");
    if (auto error = check_members(value, path, {"tolerance"})) return std::move(*error);
    auto e = read_number(value["tolerance"], field);
    if (!e) return e;
    if (e.value() <= 0) return invalid(field, field + " must be > 0");
    return e;
}

//! `true` (or `false`: the query is not run) for the switch queries (to_bezier, bounding_box, continuity).
ApiResult<bool> read_switch(const Json& root, const char* name) {
    const auto it = root.find(name);
    if (it == root.end()) return false;
    return read_bool(*it, name);
}

//! Control points at `path` (an array of [x, y] or [x, y, z] of `dimension`) and the weights at `weights_path`
//! (when `weights` is not null) into `curve`. The single-curve form's wording is the original one.
std::optional<ApiError> read_control_points(const Json& points, const std::string& path, std::size_t dimension,
                                            std::vector<Vec3>& out) {
    out.reserve(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        auto p = read_point(points[i], at(path, i), dimension);
        if (!p) return std::move(p.error());
        out.push_back(p.value());
    }
    return std::nullopt;
}

std::optional<ApiError> read_weights(const Json& weights, const std::string& path, std::size_t count,
                                     std::vector<double>& out) {
    if (!weights.is_array() || weights.size() != count)
        return invalid(path, path + " must be an array with one number per point");
    for (std::size_t i = 0; i < weights.size(); ++i) {
        auto w = read_number(weights[i], at(path, i));
        if (!w) return std::move(w.error());
        if (w.value() <= 0) return invalid(at(path, i), at(path, i) + " must be > 0");
        out.push_back(w.value());
    }
    return std::nullopt;
}

ApiError budget(std::string detail, const std::string& field) {
    return make_problem(Problem::BudgetExceeded, std::move(detail), field);
}

//! A geometry error about the request's `field`.
ApiError error_at(const GeoError& error, const std::string& field) {
    ApiError out = from_geo_error(error);
    out.field = field;
    return out;
}

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

// ---- output --------------------------------------------------------------------------------------------------------

//! "output": {"format": "json" | "glb" | "gltf", "compression": "none"} by the option table; when the body names no
//! format, the one the Accept header prefers (json on a tie or without Accept; 406 when Accept takes none of them).
ApiResult<OutputFormat> read_output(const Json& root, const ApiRequest& request) {
    auto values = options::read_json(*options::operation_options("curves"), root);
    if (!values) return std::move(values.error());
    OutputOptions output;
    output.format = OutputFormat::Json;
    output.format_given = values->has("format");
    values->get("format", kOutputFormatNames, output.format);
    if (auto error = negotiate_output_format(request, output)) return std::move(*error);
    const OutputFormat format = output.format;
    if (values->has("compression") && format == OutputFormat::Json)
        return invalid("output.compression", "output.compression applies to glb/gltf output only");
    return format;
}

//! glTF output carries the tessellation only: "tessellate" is required and the other queries are refused
//! (`modifiers` may stay: they change the curve that is tessellated).
std::optional<ApiError> check_gltf_request(const Json& root, OutputFormat format,
                                           std::initializer_list<std::string_view> modifiers) {
    if (format == OutputFormat::Json) return std::nullopt;
    const std::string name(enum_name(kOutputFormatNames, format));
    if (!root.contains("tessellate"))
        return invalid("tessellate", name + " output is the tessellated curve: add \"tessellate\": {\"tolerance\": e}");
    static constexpr std::string_view kCurveMembers[] = {"points",  "weights", "chain",     "svg",
                                                         "bspline", "output",  "tessellate"};
    for (const auto& item : root.items()) {
        const std::string& key = item.key();
        if (std::find(std::begin(kCurveMembers), std::end(kCurveMembers), key) != std::end(kCurveMembers)) continue;
        if (std::find(modifiers.begin(), modifiers.end(), key) != modifiers.end()) continue;
        return invalid(key, "\"" + key + "\" has no place in " + name +
                                " output (which holds only the tessellation): ask for output.format \"json\"");
    }
    return std::nullopt;
}

ApiResponse polyline_response(const std::vector<Polyline>& polylines, OutputFormat format, std::size_t segments,
                              double bound) {
    auto bytes = format == OutputFormat::Gltf ? write_polylines_gltf(polylines) : write_polylines_glb(polylines);
    if (!bytes) return error_response(error_at(bytes.error(), "tessellate"));
    std::size_t points = 0;
    for (const Polyline& line : polylines) points += line.size();
    ApiResponse response;
    response.content_type = std::string(output_media_type(format));
    response.body = std::move(bytes.value());
    response.headers = {{"X-Polylines", std::to_string(polylines.size())},
                        {"X-Output-Points", std::to_string(points)},
                        {"X-Segments", std::to_string(segments)},
                        {"X-Error-Bound", format_double(bound)}};
    return response;
}

ApiResponse json_response(const Json& out) {
    ApiResponse response;
    response.content_type = "application/json";
    response.body = json_text(out);
    return response;
}

//! Members of the root that the form does not take: 400 naming the first.
std::optional<ApiError> check_form_members(const Json& root, std::string_view form, std::string_view description,
                                           std::initializer_list<std::string_view> allowed) {
    for (const auto& item : root.items())
        if (std::find(allowed.begin(), allowed.end(), item.key()) == allowed.end()) {
            std::string names;
            for (std::string_view name : allowed)
                if (name != form) names += (names.empty() ? "" : ", ") + std::string(name);
            return invalid(item.key(), "\"" + item.key() + "\" does not apply to " + std::string(description) + " (\"" +
                                           std::string(form) + "\" takes: " + names + ")");
        }
    return std::nullopt;
}

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

// ---- chains and SVG paths ------------------------------------------------------------------------------------------

//! "chain": {"pieces": [{"points", "weights"?}, ...], "closed"?}; `dimension` from the first point.
ApiResult<BezierChain> decode_chain(const Json& value, std::size_t& dimension) {
    if (!value.is_object())
        return invalid("chain", R"(chain must be {"pieces": [{"points": [...]}, ...], "closed": b})");
    if (auto error = check_members(value, "chain", {"pieces", "closed"})) return std::move(*error);
    BezierChain chain;
    if (auto it = value.find("closed"); it != value.end()) {
        auto closed = read_bool(*it, "chain.closed");
        if (!closed) return std::move(closed.error());
        chain.closed = closed.value();
    }
    const auto pieces = value.find("pieces");
    if (pieces == value.end() || !pieces->is_array() || pieces->empty())
        return invalid("chain.pieces", "chain.pieces must be a non-empty array of {\"points\": [...]}");
    if (pieces->size() > kMaxChainPieces)
        return budget(
            "chain has " + std::to_string(pieces->size()) + " pieces; the limit is " + std::to_string(kMaxChainPieces),
            "chain.pieces");
    // shapes and sizes of every piece before reading any point
    std::size_t total = 0;
    for (std::size_t i = 0; i < pieces->size(); ++i) {
        const std::string path = at("chain.pieces", i);
        const Json& piece = (*pieces)[i];
        if (!piece.is_object()) return invalid(path, path + R"( must be {"points": [...], "weights"?: [...]})");
        if (auto error = check_members(piece, path, {"points", "weights"})) return std::move(*error);
        const auto points = piece.find("points");
        if (points == piece.end() || !points->is_array() || points->empty() || !(*points)[0].is_array())
            return invalid(path + ".points", path + ".points is required: an array of [x, y] or [x, y, z]");
        if (points->size() > static_cast<std::size_t>(kMaxCurveDegree) + 1)
            return budget(path + ".points has " + std::to_string(points->size()) +
                              " control points; the largest degree accepted is " + std::to_string(kMaxCurveDegree),
                          path + ".points");
        total += points->size();
    }
    if (total > kMaxChainPoints)
        return budget(
            "chain has " + std::to_string(total) + " control points; the limit is " + std::to_string(kMaxChainPoints),
            "chain.pieces");
    dimension = (*pieces)[0]["points"][0].size() == 2 ? 2 : 3;
    chain.pieces.resize(pieces->size());
    for (std::size_t i = 0; i < pieces->size(); ++i) {
        const std::string path = at("chain.pieces", i);
        const Json& piece = (*pieces)[i];
        BezierCurve& curve = chain.pieces[i];
        if (auto error = read_control_points(piece["points"], path + ".points", dimension, curve.points))
            return std::move(*error);
        if (auto it = piece.find("weights"); it != piece.end())
            if (auto error = read_weights(*it, path + ".weights", curve.points.size(), curve.weights))
                return std::move(*error);
    }
    if (Status s = validate(chain); !s) {
        const std::int64_t piece = s.error().element;
        return error_at(s.error(), piece >= 0 ? at("chain.pieces", static_cast<std::size_t>(piece)) : "chain");
    }
    return chain;
}

//! An SVG syntax error: 422 (the JSON is fine, the path data in it is not), field "svg", offset in the path data.
ApiError svg_error(const GeoError& error) {
    ApiError out = from_geo_error(error);
    out.field = "svg";
    if (error.code == ErrorCode::ParseError) {
        out.status = 422;
        out.title = "Malformed SVG path data";
    }
    return out;
}

ApiResult<std::vector<BezierChain>> decode_svg(const Json& value) {
    if (!value.is_string()) return invalid("svg", "svg must be a string of SVG path data (\"M 0 0 C 1 1 2 1 3 0\")");
    const auto& data = value.get_ref<const std::string&>();
    if (data.size() > kMaxSvgBytes)
        return budget("svg is " + std::to_string(data.size()) + " bytes; the limit is " + std::to_string(kMaxSvgBytes),
                      "svg");
    SvgPathOptions options;
    options.max_commands = kMaxSvgCommands;
    options.max_pieces = kMaxChainPieces;
    auto chains = parse_svg_path(data, options);
    if (!chains) return svg_error(chains.error());
    if (chains->empty()) return invalid("svg", "svg has no drawing segment (path data with only moves, or empty)");
    return std::move(chains.value());
}

struct ChainQueries {
    std::optional<ContinuityOptions> continuity;
    std::optional<EnforceOptions> enforce;
    std::optional<std::vector<double>> evaluate;
    std::optional<double> length;
    std::optional<double> tessellate;
    bool to_bezier = false;
};

constexpr EnumName<EnforceMode> kEnforceModeNames[] = {{"C1", EnforceMode::C1}, {"G1", EnforceMode::G1}};
constexpr EnumName<JointSide> kJointSideNames[] = {
    {"left", JointSide::Left}, {"right", JointSide::Right}, {"both", JointSide::Both}};

ApiResult<ContinuityOptions> read_continuity(const Json& value) {
    ContinuityOptions options;
    if (value.is_boolean()) return options;
    if (!value.is_object())
        return invalid(
            "continuity",
            R"(continuity must be true or {"position_tolerance", "angle_tolerance", "derivative_tolerance"})");
    if (auto error =
            check_members(value, "continuity", {"position_tolerance", "angle_tolerance", "derivative_tolerance"}))
        return std::move(*error);
    for (auto [name, target] : {std::pair<const char*, double*>{"position_tolerance", &options.position_tolerance},
                                {"angle_tolerance", &options.angle_tolerance},
                                {"derivative_tolerance", &options.derivative_tolerance}}) {
        if (auto it = value.find(name); it != value.end()) {
            const std::string field = member_path("continuity", name);
            auto v = read_number(*it, field);
            if (!v) return std::move(v.error());
            if (v.value() < 0) return invalid(field, field + " must be >= 0");
            *target = v.value();
        }
    }
    return options;
}

ApiResult<EnforceOptions> read_enforce(const Json& value, std::size_t max_joints) {
    if (!value.is_object())
        return invalid(
            "enforce_c1",
            R"(enforce_c1 must be {"mode": "C1" | "G1", "side": "left" | "right" | "both", "joints": [i, ...]})");
    if (auto error = check_members(value, "enforce_c1", {"mode", "side", "joints"})) return std::move(*error);
    EnforceOptions options;
    if (auto it = value.find("mode"); it != value.end()) {
        auto mode = read_enum(*it, "enforce_c1.mode", kEnforceModeNames);
        if (!mode) return std::move(mode.error());
        options.mode = mode.value();
    }
    if (auto it = value.find("side"); it != value.end()) {
        auto side = read_enum(*it, "enforce_c1.side", kJointSideNames);
        if (!side) return std::move(side.error());
        options.side = side.value();
    }
    if (auto it = value.find("joints"); it != value.end()) {
        if (!it->is_array()) return invalid("enforce_c1.joints", "enforce_c1.joints must be an array of joint indices");
        for (std::size_t i = 0; i < it->size(); ++i) {
            const std::string field = at("enforce_c1.joints", i);
            auto j = read_integer((*it)[i], field);
            if (!j) return std::move(j.error());
            if (j.value() < 0 || static_cast<std::size_t>(j.value()) >= max_joints)
                return invalid(field, field + " = " + std::to_string(j.value()) + " is not a joint (the chain has " +
                                          std::to_string(max_joints) + ")");
            options.joints.push_back(static_cast<std::size_t>(j.value()));
        }
    }
    return options;
}

std::size_t joint_count(const BezierChain& chain) { return chain.pieces.size() - 1 + (chain.closed ? 1 : 0); }

ApiResult<ChainQueries> read_chain_queries(const Json& root, const std::vector<BezierChain>& chains, bool svg) {
    ChainQueries q;
    if (auto it = root.find("continuity"); it != root.end()) {
        if (it->is_boolean() && !it->get<bool>()) {
            // false: not asked
        } else {
            auto options = read_continuity(*it);
            if (!options) return std::move(options.error());
            q.continuity = options.value();
        }
    }
    if (auto it = root.find("enforce_c1"); it != root.end()) {
        // joint indices must exist in every subpath they are applied to: the smallest joint count bounds them
        std::size_t joints = static_cast<std::size_t>(-1);
        for (const BezierChain& chain : chains) joints = std::min(joints, joint_count(chain));
        auto options = read_enforce(*it, joints);
        if (!options) return std::move(options.error());
        q.enforce = options.value();
    }
    if (auto it = root.find("evaluate"); it != root.end()) {
        std::size_t pieces = static_cast<std::size_t>(-1);
        for (const BezierChain& chain : chains) pieces = std::min(pieces, chain.pieces.size());
        const std::string what =
            svg && chains.size() > 1 ? "the parameter range of the shortest subpath" : "the chain's parameter range";
        auto ts = read_parameters_in(*it, "evaluate", 0.0, static_cast<double>(pieces), what);
        if (!ts) return std::move(ts.error());
        if (ts->size() * chains.size() > kMaxCurveQueries)
            return budget(std::to_string(ts->size() * chains.size()) + " parameters requested (" +
                              std::to_string(ts->size()) + " per subpath); the limit is " +
                              std::to_string(kMaxCurveQueries),
                          "evaluate");
        q.evaluate = std::move(ts.value());
    }
    if (auto it = root.find("length"); it != root.end()) {
        auto tolerance = read_tolerance(*it, "length");
        if (!tolerance) return std::move(tolerance.error());
        q.length = tolerance.value();
    }
    if (auto it = root.find("tessellate"); it != root.end()) {
        auto tolerance = read_tolerance(*it, "tessellate");
        if (!tolerance) return std::move(tolerance.error());
        q.tessellate = tolerance.value();
    }
    auto to_bezier = read_switch(root, "to_bezier");
    if (!to_bezier) return std::move(to_bezier.error());
    q.to_bezier = to_bezier.value();
    return q;
}

Json encode_continuity(const ContinuityReport& report) {
    Json joints = Json::array();
    for (const JointContinuity& j : report.joints)
        joints.push_back({{"left", j.left},
                          {"right", j.right},
                          {"continuity", to_string(j.continuity)},
                          {"gap", j.gap},
                          {"derivative_mismatch", j.derivative_mismatch},
                          {"angle", j.angle},
                          {"left_order", j.left_order},
                          {"right_order", j.right_order}});
    return {{"weakest", to_string(report.weakest)},
            {"max_gap", report.max_gap},
            {"max_derivative_mismatch", report.max_derivative_mismatch},
            {"max_angle", report.max_angle},
            {"joints", std::move(joints)}};
}

//! The chain queries on one chain; `polylines`, `segments` and `bound` collect the tessellation for glTF output.
struct ChainRun {
    const Limits& limits;
    const Cancel& cancel;
    const Encoder& encoder;
    std::size_t segments = 0;  //!< used so far, over all subpaths (the budget is for the whole request)
    double bound = 0;
    std::vector<Polyline> polylines;
};

ApiResult<Json> run_chain_queries(const BezierChain& input, const ChainQueries& q, ChainRun& run) {
    bool rational = false;
    for (const BezierCurve& piece : input.pieces) rational = rational || piece.is_rational();
    Json out = {{"piece_count", input.pieces.size()}, {"closed", input.closed}, {"rational", rational}};
    if (q.continuity) {
        auto report = continuity(input, *q.continuity);
        if (!report) return error_at(report.error(), "continuity");
        out["continuity"] = encode_continuity(*report);
    }
    const BezierChain* chain = &input;
    EnforceResult enforced;
    if (q.enforce) {
        auto result = enforce_c1(input, *q.enforce);
        if (!result) return error_at(result.error(), "enforce_c1");
        enforced = std::move(result.value());
        chain = &enforced.chain;
        out["enforce_c1"] = {{"chain", run.encoder.chain(enforced.chain)},
                             {"skipped_joints", enforced.skipped_joints},
                             {"max_derivative_mismatch", enforced.max_derivative_mismatch},
                             {"max_angle", enforced.max_angle}};
    }
    if (q.evaluate) {
        Json points = Json::array();
        for (double s : *q.evaluate) points.push_back(run.encoder.point(evaluate(*chain, s)));
        out["evaluate"] = std::move(points);
    }
    if (q.length) {
        // the tolerance is shared out over the pieces; gaps between pieces are not part of the length
        const double per_piece = std::max(*q.length / static_cast<double>(chain->pieces.size()), 1e-12);
        ArcLength total;
        for (const BezierCurve& piece : chain->pieces) {
            if (run.cancel.requested())
                return error_at(make_error(ErrorCode::Cancelled, "the request's deadline passed while measuring"),
                                "length");
            const ArcLength length = arc_length(piece, per_piece);
            total.length += length.length;
            total.error_bound += length.error_bound;
        }
        out["length"] = {{"length", total.length}, {"error_bound", total.error_bound}, {"guaranteed", !rational}};
    }
    if (q.tessellate) {
        ChainTessellationOptions options;
        options.tolerance = *q.tessellate;
        options.max_segments = static_cast<std::size_t>(run.limits.max_output_faces) - run.segments;
        options.cancel = run.cancel;
        auto polyline = tessellate(*chain, options);
        if (!polyline) return error_at(polyline.error(), "tessellate.tolerance");
        run.segments += polyline->segments;
        run.bound = std::max(run.bound, polyline->bound);
        out["tessellate"] = {{"points", run.encoder.points(polyline->points)}, {"params", polyline->params},
                             {"piece_start", polyline->piece_start},           {"segments", polyline->segments},
                             {"max_deviation", polyline->max_deviation},       {"bound", polyline->bound}};
        run.polylines.push_back(std::move(polyline->points));
    }
    if (q.to_bezier) out["to_bezier"] = run.encoder.chain(*chain);
    return out;
}

ApiResponse run_chains(const Json& root, const ApiContext& context, OutputFormat format, bool svg) {
    if (svg) {
        if (auto error = check_form_members(
                root, "svg", "SVG path data",
                {"svg", "continuity", "enforce_c1", "evaluate", "length", "tessellate", "to_bezier", "output"}))
            return error_response(std::move(*error));
    } else if (auto error = check_form_members(
                   root, "chain", "a Bézier chain",
                   {"chain", "continuity", "enforce_c1", "evaluate", "length", "tessellate", "output"})) {
        return error_response(std::move(*error));
    }
    if (auto error = check_gltf_request(root, format, {"enforce_c1"})) return error_response(std::move(*error));

    Encoder encoder;
    std::vector<BezierChain> chains;
    if (svg) {
        auto decoded = decode_svg(root["svg"]);
        if (!decoded) return error_response(std::move(decoded.error()));
        chains = std::move(decoded.value());
        encoder.dimension = 2;
    } else {
        auto decoded = decode_chain(root["chain"], encoder.dimension);
        if (!decoded) return error_response(std::move(decoded.error()));
        chains.push_back(std::move(decoded.value()));
    }
    auto queries = read_chain_queries(root, chains, svg);
    if (!queries) return error_response(std::move(queries.error()));

    ChainRun run{context.limits, context.cancel, encoder, 0, 0.0, {}};
    Json results = Json::array();
    for (const BezierChain& chain : chains) {
        auto result = run_chain_queries(chain, queries.value(), run);
        if (!result) return error_response(std::move(result.error()));
        results.push_back(std::move(result.value()));
    }
    if (format != OutputFormat::Json) return polyline_response(run.polylines, format, run.segments, run.bound);
    if (svg) return json_response({{"subpaths", std::move(results)}});
    return json_response(results[0]);
}

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
            auto u = read_number((*knots)[i], at("bspline.knots", i));
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
            field = at(curve.is_rational() && e.message.find("weight") != std::string::npos ? "bspline.weights"
                                                                                            : "bspline.points",
                       static_cast<std::size_t>(e.element));
        else if (e.element >= 0 && knots != value.end())
            field = at("bspline.knots", static_cast<std::size_t>(e.element));
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

// ---- the request -------------------------------------------------------------------------------------------------

ApiResponse run(const ApiRequest& request, const ApiContext& context) {
    const Limits& limits = context.limits;
    if (auto error = check_json_only_body(request, limits, "POST /curves")) return error_response(std::move(*error));
    Json root;
    if (auto error = json::parse(request.body, root)) return error_response(std::move(*error));
    if (!root.is_object()) return error_response(invalid("", "the body must be a JSON object"));
    static constexpr std::string_view kMembers[] = {
        "points",       "weights",    "evaluate",  "derivatives", "curvature", "split", "elevate",
        "bounding_box", "length",     "closest",   "tessellate",  "chain",     "svg",   "bspline",
        "continuity",   "enforce_c1", "to_bezier", "insert_knot", "output"};
    for (const auto& item : root.items())
        if (std::find(std::begin(kMembers), std::end(kMembers), item.key()) == std::end(kMembers))
            return error_response(
                make_problem(Problem::UnknownField, "unknown field \"" + item.key() + "\" at top level", item.key()));

    // the form: exactly one of them
    static constexpr const char* kForms[] = {"points", "chain", "svg", "bspline"};
    std::vector<std::string> forms;
    for (const char* form : kForms)
        if (root.contains(form)) forms.emplace_back(form);
    if (forms.size() > 1)
        return error_response(invalid(forms[1], "give exactly one curve: \"" + forms[0] + "\" and \"" + forms[1] +
                                                    "\" were both given (forms: points, chain, svg, bspline)"));
    if (forms.empty())
        return error_response(invalid("points",
                                      "a curve is required: \"points\" (one Bézier curve: [[x, y], ...] or "
                                      "[[x, y, z], ...]), \"chain\", \"svg\" or \"bspline\""));
    auto format = read_output(root, request);
    if (!format) return error_response(std::move(format.error()));

    if (forms[0] == "points") return run_single(root, limits, format.value());
    if (forms[0] == "bspline") return run_bspline(root, context, format.value());
    return run_chains(root, context, format.value(), forms[0] == "svg");
}

// ---- files (the CLI) ---------------------------------------------------------------------------------------------

//! The path data of an SVG file: every <path> element's d attribute, joined by spaces (each starts with a move), or
//! the whole file when it is bare path data. `starts` maps each joined piece back to its offset in the file.
struct SvgText {
    std::string data;
    std::vector<std::pair<std::size_t, std::size_t>> starts;  //!< (offset in data, offset in file)
};

SvgText extract_svg_paths(std::string_view file) {
    SvgText out;
    const std::size_t first = file.find_first_not_of(" \t\r\n");
    if (first == std::string_view::npos || file[first] != '<') {
        out.data = std::string(file);
        out.starts.push_back({0, 0});
        return out;
    }
    std::size_t pos = 0;
    while ((pos = file.find("<path", pos)) != std::string_view::npos) {
        const std::size_t end = file.find('>', pos);
        if (end == std::string_view::npos) break;
        const std::string_view element = file.substr(pos, end - pos);
        // the attribute " d=" (not "id=" or "data-d="): preceded by whitespace
        for (std::size_t a = element.find("d="); a != std::string_view::npos; a = element.find("d=", a + 1)) {
            if (a == 0 ||
                (element[a - 1] != ' ' && element[a - 1] != '\t' && element[a - 1] != '\n' && element[a - 1] != '\r'))
                continue;
            if (a + 2 >= element.size() || (element[a + 2] != '"' && element[a + 2] != '\'')) continue;
            const char quote = element[a + 2];
            const std::size_t value = a + 3, close = element.find(quote, value);
            if (close == std::string_view::npos) break;
            if (!out.data.empty()) out.data += ' ';
            out.starts.push_back({out.data.size(), pos + value});
            out.data += element.substr(value, close - value);
            break;
        }
        pos = end;
    }
    return out;
}

ApiResponse run_from_file(std::string_view file, const CurveFileOverrides& overrides, const ApiContext& context) {
    Json root;
    SvgText svg;
    if (overrides.svg) {
        svg = extract_svg_paths(file);
        if (svg.data.find_first_not_of(" \t\r\n") == std::string::npos)
            return error_response(invalid("svg", "the file has no SVG path data (no <path d=\"...\"> element)"));
        root = Json::object();
        root["svg"] = svg.data;
    } else {
        if (auto error = json::parse(file, root)) return error_response(std::move(*error));
        if (!root.is_object())
            return error_response(invalid("", "the file must hold a JSON object (a POST /curves request)"));
    }
    if (overrides.tolerance) root["tessellate"] = {{"tolerance", *overrides.tolerance}};
    if (overrides.continuity) root["continuity"] = true;
    if (overrides.enforce_c1) root["enforce_c1"] = {{"mode", *overrides.enforce_c1}};
    root.erase("output");
    if (overrides.format != OutputFormat::Json) {
        root["output"] = {{"format", std::string(enum_name(kOutputFormatNames, overrides.format))}};
        if (!root.contains("tessellate")) root["tessellate"] = {{"tolerance", kDefaultCurveFileTolerance}};
    }
    // invalid UTF-8 in an SVG file is replaced (the path parser then reports the first such byte)
    const std::string body = json_text(root);
    ApiRequest request;
    request.method = "POST";
    request.path = "/curves";
    request.content_type = "application/json";
    request.body = body;
    ApiResponse response = run(request, context);
    // an SVG error's offset is in the path data: translate it to the file (and a line there)
    if (overrides.svg && response.error && response.error->field == "svg" && response.error->offset) {
        const auto offset = static_cast<std::size_t>(*response.error->offset);
        std::size_t file_offset = offset;
        for (const auto& [data_start, file_start] : svg.starts)
            if (data_start <= offset) file_offset = file_start + (offset - data_start);
        file_offset = std::min(file_offset, file.size());
        response.error->offset = static_cast<std::int64_t>(file_offset);
        response.error->line = static_cast<std::int64_t>(
            1 + std::count(file.begin(), file.begin() + static_cast<std::ptrdiff_t>(file_offset), '\n'));
        response.body = to_problem_json(*response.error);
    }
    return response;
}

}  // namespace

ApiResponse curves(const ApiRequest& request, const ApiContext& context) noexcept {
    return guarded([&] { return run(request, context); });
}

ApiResponse curves_from_file(std::string_view file, const CurveFileOverrides& overrides,
                             const ApiContext& context) noexcept {
    return guarded([&] { return run_from_file(file, overrides, context); });
}

}  // namespace surfaced::api::operations
