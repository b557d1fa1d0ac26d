// The point-cloud intake shared by POST /pointcloud and POST /reconstruct (point_input.h).
#include "api/operations/point_input.h"

#include <cmath>
#include <string>

#include "api/json_util.h"
#include "geometry/pointcloud/normals.h"

namespace surfaced::api::operations {
namespace {

using namespace json;  // the shared readers (api/json_util.h)

// The default k of normal estimation: the points x k budget is max_points x this.
constexpr std::uint64_t kBudgetK = 16;

}  // namespace

bool reads_point_media_type(std::string_view media_type) {
    return media_type == "application/json" || media_type == "application/octet-stream" || media_type == "text/plain" ||
           point_format_from_media_type(media_type);
}

ApiError point_error(const GeoError& error, Source source, const char* array) {
    ApiError out = from_geo_error(error);
    if (source == Source::Json && error.element >= 0 && error.element_kind == ElementKind::Vertex)
        out.field = std::string(array) + "[" + std::to_string(error.element) + "]";
    return out;
}

ApiResult<PointCloud> decode_json_points(const Json& root, const Limits& limits, bool keep_normal_lengths) {
    const Json& points = root["points"];
    if (!points.is_array() || points.empty()) return invalid("points", "points must be a non-empty array of [x, y, z]");
    if (points.size() > limits.max_points)
        return make_problem(
            Problem::BudgetExceeded,
            std::to_string(points.size()) + " points; the limit is " + std::to_string(limits.max_points), "points");
    PointCloud cloud;
    cloud.positions.reserve(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        auto p = read_vec3(points[i], index_path("points", i));
        if (!p) return std::move(p.error());
        cloud.positions.push_back(p.value());
    }
    if (auto it = root.find("normals"); it != root.end()) {
        if (!it->is_array() || it->size() != points.size())
            return invalid("normals", "normals must be an array with one [nx, ny, nz] per point (" +
                                          std::to_string(points.size()) + ")");
        cloud.normals.reserve(points.size());
        for (std::size_t i = 0; i < it->size(); ++i) {
            const std::string field = index_path("normals", i);
            auto n = read_vec3((*it)[i], field);
            if (!n) return std::move(n.error());
            const double len = norm(n.value());
            if (keep_normal_lengths) {
                if (!std::isfinite(len)) return invalid(field, field + " is too long to have a finite length");
                cloud.normals.push_back(n.value());
                continue;
            }
            if (!(len > 0)) return invalid(field, field + " has zero length");
            cloud.normals.push_back(n.value() * (1.0 / len));
        }
    }
    if (auto it = root.find("colors"); it != root.end()) {
        if (!it->is_array() || it->size() != points.size())
            return invalid("colors", "colors must be an array with one [r, g, b] or [r, g, b, a] per point (" +
                                         std::to_string(points.size()) + ")");
        cloud.colors.reserve(points.size());
        std::size_t arity = 0;
        for (std::size_t i = 0; i < it->size(); ++i) {
            const std::string field = index_path("colors", i);
            const Json& c = (*it)[i];
            if (!c.is_array() || (c.size() != 3 && c.size() != 4))
                return invalid(field, field + " must be [r, g, b] or [r, g, b, a] with channels in 0..1");
            if (arity == 0) arity = c.size();
            if (c.size() != arity)
                return invalid(field, field + " has " + std::to_string(c.size()) + " channels, colors[0] has " +
                                          std::to_string(arity));
            float channels[4] = {0, 0, 0, 1};
            for (std::size_t k = 0; k < c.size(); ++k) {
                auto v = read_number(c[k], index_path(field, k));
                if (!v) return std::move(v.error());
                if (!(v.value() >= 0 && v.value() <= 1))
                    return invalid(index_path(field, k), index_path(field, k) + " must be in 0..1");
                channels[k] = static_cast<float>(v.value());
            }
            cloud.colors.push_back({channels[0], channels[1], channels[2], channels[3]});
        }
        cloud.has_alpha = arity == 4;
    }
    return cloud;
}

ApiResult<PointFormat> uploaded_point_format(std::string_view media_type, std::string_view body) {
    std::optional<PointFormat> format = point_format_from_media_type(media_type);
    const bool sniffed = media_type == "application/octet-stream" || media_type == "text/plain";
    if (!format && sniffed) format = sniff_point_format(body);
    if (format) return *format;
    return make_problem(Problem::UnsupportedMediaType,
                        sniffed ? "could not recognise the point format from the content; send Content-Type "
                                  "application/json, application/ply, model/obj, text/x-xyz or model/gltf-binary"
                                : "Content-Type \"" + std::string(media_type) +
                                      "\" is not accepted; accepted: " + std::string(kPointMediaTypes));
}

ApiResult<PointCloud> read_uploaded_points(std::string_view body, PointFormat format, const Limits& limits) {
    PointReadOptions read_options;
    read_options.max_points = static_cast<std::size_t>(limits.max_points);
    auto read = read_points(body, format, read_options);
    if (!read) return point_error(read.error(), Source::File);
    return std::move(read.value());
}

std::optional<ApiError> estimate_point_normals(PointCloud& cloud, std::int64_t k, const Limits& limits,
                                               const Cancel& cancel, Source source, const std::string& k_field,
                                               std::optional<std::string> estimate_field) {
    // Orientation keeps the kNN graph (~12 bytes an edge): bound points x k like max_points x the default k.
    const std::uint64_t edges = static_cast<std::uint64_t>(cloud.size()) * static_cast<std::uint64_t>(k);
    if (edges > limits.max_points * kBudgetK)
        return make_problem(Problem::BudgetExceeded,
                            "normal estimation for " + std::to_string(cloud.size()) +
                                " points with k = " + std::to_string(k) + " needs " + std::to_string(edges) +
                                " neighbour links; the limit is " + std::to_string(limits.max_points * kBudgetK) +
                                " (points x k)",
                            k_field);
    NormalEstimationOptions options;
    options.k = static_cast<std::size_t>(k);
    options.cancel = cancel;
    if (Status s = estimate_normals(cloud, options); !s) {
        ApiError error = point_error(s.error(), source);
        if (s.error().code == ErrorCode::InvalidArgument && !error.field && estimate_field)
            error.field = std::move(*estimate_field);
        return error;
    }
    return std::nullopt;
}

}  // namespace surfaced::api::operations
