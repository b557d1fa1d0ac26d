// The readers and output helpers the forms of POST /curves share (curve_request.h).
#include "api/operations/curve_request.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "api/operations/request_forms.h"

namespace surfaced::api::operations::curve_request {

using namespace json;  // the shared readers (api/json_util.h)

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
        auto t = read_parameter(value[i], index_path(field, i));
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
        const std::string item = index_path(field, i);
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
        auto x = read_number(value[c], index_path(field, c));
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

//! Control points at `path` (an array of [x, y] or [x, y, z] of `dimension`) and the weights at `weights_path`
//! (when `weights` is not null) into `curve`. The single-curve form's wording is the original one.
std::optional<ApiError> read_control_points(const Json& points, const std::string& path, std::size_t dimension,
                                            std::vector<Vec3>& out) {
    out.reserve(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        auto p = read_point(points[i], index_path(path, i), dimension);
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
        auto w = read_number(weights[i], index_path(path, i));
        if (!w) return std::move(w.error());
        if (w.value() <= 0) return invalid(index_path(path, i), index_path(path, i) + " must be > 0");
        out.push_back(w.value());
    }
    return std::nullopt;
}

// ---- output --------------------------------------------------------------------------------------------------------

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

}  // namespace surfaced::api::operations::curve_request
