#include "api/patch_codec.h"

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace surfaced::api {
namespace {

using Json = nlohmann::json;

ApiError invalid(const std::string& field, std::string detail) {
    return make_problem(Problem::InvalidField, std::move(detail), field);
}

std::string at(const std::string& path, std::size_t i) { return path + "[" + std::to_string(i) + "]"; }

//! nlohmann reports parse errors by exception, which must not leave this function.
std::optional<ApiError> parse(std::string_view text, Json& out) {
    try {
        out = Json::parse(text.begin(), text.end());
        return std::nullopt;
    } catch (const Json::parse_error& e) {
        std::string message = e.what();
        if (const auto pos = message.find("] "); message.starts_with("[json.exception") && pos != std::string::npos)
            message.erase(0, pos + 2);
        ApiError error = make_problem(Problem::InvalidJson, "request body is not valid JSON: " + message);
        error.offset = e.byte > 0 ? static_cast<std::int64_t>(e.byte - 1) : 0;
        return error;
    } catch (const Json::out_of_range& e) {
        return from_geo_error(make_error(ErrorCode::NonFinite,
                                         std::string("a number in the body does not fit a double: ") + e.what()));
    } catch (const Json::exception& e) {
        return make_problem(Problem::InvalidJson, std::string("request body is not valid JSON: ") + e.what());
    }
}

std::optional<ApiError> check_members(const Json& object, const std::string& path,
                                      std::initializer_list<std::string_view> allowed) {
    for (const auto& item : object.items()) {
        bool known = false;
        for (std::string_view name : allowed) known = known || item.key() == name;
        if (known) continue;
        std::string allowed_names;
        for (std::string_view name : allowed)
            allowed_names += (allowed_names.empty() ? "\"" : ", \"") + std::string(name) + "\"";
        const std::string field = path.empty() ? item.key() : path + "." + item.key();
        return make_problem(Problem::UnknownField,
                            "unknown field \"" + item.key() + "\" " + (path.empty() ? "at top level" : "in " + path) +
                                " (allowed: " + allowed_names + ")",
                            field);
    }
    return std::nullopt;
}

ApiResult<std::int64_t> read_integer(const Json& value, const std::string& field) {
    if (value.is_number_unsigned()) {
        const auto v = value.get<std::uint64_t>();
        return v > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())
                   ? std::numeric_limits<std::int64_t>::max()
                   : static_cast<std::int64_t>(v);
    }
    if (value.is_number_integer()) return value.get<std::int64_t>();
    return invalid(field, field + " must be an integer");
}

template <class E, std::size_t N>
ApiResult<E> read_enum(const Json& value, const std::string& field, const EnumName<E> (&table)[N]) {
    if (!value.is_string()) return invalid(field, field + " must be a string, one of " + enum_names(table));
    const auto& text = value.get_ref<const std::string&>();
    if (auto parsed = enum_from_name(table, text)) return *parsed;
    return invalid(field, field + ": unknown value \"" + text + "\" (allowed: " + enum_names(table) + ")");
}

ApiResult<OutputOptions> decode_output(const Json& value) {
    if (!value.is_object())
        return invalid("output", R"(output must be an object {"format", "compression", "quantize_position", "normals"})");
    if (auto error = check_members(value, "output", {"format", "compression", "quantize_position", "normals"}))
        return std::move(*error);
    OutputOptions out;
    if (auto it = value.find("format"); it != value.end()) {
        auto format = read_enum(*it, "output.format", kOutputFormatNames);
        if (!format) return std::move(format.error());
        out.format = format.value();
    }
    if (auto it = value.find("compression"); it != value.end()) {
        auto draco = read_enum(*it, "output.compression", kCompressionNames);
        if (!draco) return std::move(draco.error());
        out.draco = draco.value();
    }
    if (auto it = value.find("quantize_position"); it != value.end()) {
        auto bits = read_integer(*it, "output.quantize_position");
        if (!bits) return std::move(bits.error());
        out.quantize_position = bits.value();
    }
    if (auto it = value.find("normals"); it != value.end()) {
        if (!it->is_boolean()) return invalid("output.normals", "output.normals must be true or false");
        out.normals = it->get<bool>();
    }
    return out;
}

ApiResult<BezierPatch> decode_patch(const Json& value, const std::string& path) {
    if (!value.is_object())
        return invalid(path, path + R"( must be an object {"degree": [m, n], "points": [[x, y, z], ...]})");
    if (auto error = check_members(value, path, {"degree", "points"})) return std::move(*error);
    BezierPatch patch;
    const std::string degree_path = path + ".degree";
    const auto degree = value.find("degree");
    if (degree == value.end() || !degree->is_array() || degree->size() != 2)
        return invalid(degree_path, degree_path + " is required: [m, n], the degrees in u and v");
    int* targets[2] = {&patch.degree_u, &patch.degree_v};
    for (std::size_t k = 0; k < 2; ++k) {
        auto d = read_integer((*degree)[k], at(degree_path, k));
        if (!d) return std::move(d.error());
        if (d.value() < 1 || d.value() > kMaxPatchDegree)
            return invalid(at(degree_path, k), at(degree_path, k) + " must be between 1 and " +
                                                   std::to_string(kMaxPatchDegree) + ", got " +
                                                   std::to_string(d.value()));
        *targets[k] = static_cast<int>(d.value());
    }
    const std::string points_path = path + ".points";
    const auto points = value.find("points");
    if (points == value.end() || !points->is_array())
        return invalid(points_path, points_path + " is required: an array of [x, y, z], u varying fastest");
    const auto expected = static_cast<std::size_t>((patch.degree_u + 1) * (patch.degree_v + 1));
    if (points->size() != expected)
        return invalid(points_path, points_path + " has " + std::to_string(points->size()) + " points; degree [" +
                                        std::to_string(patch.degree_u) + ", " + std::to_string(patch.degree_v) +
                                        "] needs " + std::to_string(expected));
    patch.points.reserve(expected);
    for (std::size_t i = 0; i < expected; ++i) {
        const Json& p = (*points)[i];
        const std::string point_path = at(points_path, i);
        if (!p.is_array() || p.size() != 3) return invalid(point_path, point_path + " must be [x, y, z]");
        Vec3 q;
        for (std::size_t c = 0; c < 3; ++c) {
            if (!p[c].is_number()) return invalid(at(point_path, c), at(point_path, c) + " must be a finite number");
            q[static_cast<int>(c)] = p[c].get<double>();
            if (!std::isfinite(q[static_cast<int>(c)])) {
                ApiError error = from_geo_error(make_error(ErrorCode::NonFinite, at(point_path, c) + " is not finite"));
                error.field = at(point_path, c);
                return error;
            }
        }
        patch.points.push_back(q);
    }
    return patch;
}

}  // namespace

ApiResult<TessellateJsonRequest> decode_tessellate_request(std::string_view body, const Limits& limits) {
    Json root;
    if (auto error = parse(body, root)) return std::move(*error);
    if (!root.is_object())
        return invalid("", R"(the body must be an object {"patches": [...], "tolerance": t | "segments": n, "output": {...}})");
    if (auto error = check_members(root, "", {"patches", "tolerance", "segments", "output"})) return std::move(*error);

    TessellateJsonRequest request;
    const auto patches = root.find("patches");
    if (patches == root.end() || !patches->is_array() || patches->empty())
        return invalid("patches", R"(patches is required: a non-empty array of {"degree": [m, n], "points": [...]})");
    // Budgets first: nothing is copied out of the document for a request we would refuse anyway.
    if (patches->size() > limits.max_patches)
        return make_problem(Problem::BudgetExceeded,
                            "patches has " + std::to_string(patches->size()) + " patches; the limit is " +
                                std::to_string(limits.max_patches),
                            "patches");
    std::uint64_t total_points = 0;
    for (const Json& patch : *patches)
        if (patch.is_object())
            if (auto points = patch.find("points"); points != patch.end() && points->is_array())
                total_points += points->size();
    if (total_points > limits.max_input_vertices)
        return make_problem(Problem::BudgetExceeded,
                            "the patches have " + std::to_string(total_points) + " control points; the limit is " +
                                std::to_string(limits.max_input_vertices),
                            "patches");
    request.patches.patches.reserve(patches->size());
    for (std::size_t i = 0; i < patches->size(); ++i) {
        auto patch = decode_patch((*patches)[i], at("patches", i));
        if (!patch) return std::move(patch.error());
        request.patches.patches.push_back(std::move(patch.value()));
    }

    if (auto it = root.find("tolerance"); it != root.end()) {
        if (!it->is_number()) return invalid("tolerance", "tolerance must be a number (model units)");
        request.params.tolerance = it->get<double>();
    }
    if (auto it = root.find("segments"); it != root.end()) {
        auto segments = read_integer(*it, "segments");
        if (!segments) return std::move(segments.error());
        request.params.segments = segments.value();
    }
    if (auto it = root.find("output"); it != root.end()) {
        auto output = decode_output(*it);
        if (!output) return std::move(output.error());
        request.params.output = output.value();
    }
    return request;
}

}  // namespace surfaced::api
