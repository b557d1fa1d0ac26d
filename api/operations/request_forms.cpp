#include "api/operations/request_forms.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>

namespace surfaced::api::operations {

double ms_between(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
}

std::string format_ms(double ms) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3f", ms);
    return buf;
}

std::string format_double(double value) {
    char buf[32];
    const auto result = std::to_chars(buf, buf + sizeof buf, value);
    return std::string(buf, result.ptr);
}

std::string media_type_of(std::string_view content_type) {
    const auto semicolon = content_type.find(';');
    std::string_view type = content_type.substr(0, semicolon);
    while (!type.empty() && std::isspace(static_cast<unsigned char>(type.front()))) type.remove_prefix(1);
    while (!type.empty() && std::isspace(static_cast<unsigned char>(type.back()))) type.remove_suffix(1);
    std::string out(type);
    std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return std::tolower(c); });
    return out;
}

std::string accepted_mesh_media_types() {
    std::string out = "application/json";
    for (const auto& entry : kMeshMediaTypes) out += ", " + std::string(entry.name);
    return out + ", application/octet-stream (format detected from the content)";
}

std::optional<MeshFormat> mesh_format_for(const std::string& media_type, std::string_view body) {
    if (media_type == "application/octet-stream") return sniff_format(body);
    if (auto format = format_from_media_type(media_type)) return format;
    return enum_from_name(kMeshMediaTypes, media_type);
}

std::string_view output_media_type(OutputFormat format) {
    switch (format) {
        case OutputFormat::Glb: return "model/gltf-binary";
        case OutputFormat::Gltf: return "model/gltf+json";
        case OutputFormat::Obj: return "model/obj";
        case OutputFormat::Ply: return "application/ply";
        case OutputFormat::Json: return "application/json";
    }
    return "application/octet-stream";
}

ApiError geometry_error(const GeoError& error, Source source) {
    ApiError out = from_geo_error(error);
    if (source != Source::Json || error.element < 0) return out;
    const std::string index = "[" + std::to_string(error.element) + "]";
    switch (error.element_kind) {
        case ElementKind::Vertex: out.field = "mesh.positions" + index; break;
        case ElementKind::Face: out.field = "mesh.faces" + index; break;
        case ElementKind::Crease: out.field = "creases" + index; break;
        case ElementKind::Corner: out.field = "corners" + index; break;
        case ElementKind::Hole: out.field = "holes" + index; break;
        case ElementKind::None: break;
    }
    return out;
}

ApiResult<std::int64_t> parse_integer_parameter(const std::string& name, const std::string& text) {
    std::int64_t value = 0;
    const auto result = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || result.ec != std::errc() || result.ptr != text.data() + text.size())
        return make_problem(Problem::InvalidField, "query parameter " + name + " must be an integer, got \"" + text + "\"",
                            name);
    return value;
}

ApiResult<double> parse_number_parameter(const std::string& name, const std::string& text) {
    double value = 0;
    const auto result = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || result.ec != std::errc() || result.ptr != text.data() + text.size() || !std::isfinite(value))
        return make_problem(Problem::InvalidField,
                            "query parameter " + name + " must be a finite number, got \"" + text + "\"", name);
    return value;
}

ApiResult<bool> parse_bool_parameter(const std::string& name, const std::string& text) {
    if (text == "true" || text == "1") return true;
    if (text == "false" || text == "0") return false;
    return make_problem(Problem::InvalidField, "query parameter " + name + " must be true or false, got \"" + text + "\"",
                        name);
}

}  // namespace surfaced::api::operations
