// POST /implicit/query (see implicit_query.h): decode, check budgets, run geometry/implicit/query, encode.
#include "api/operations/implicit_query.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <new>
#include <optional>
#include <string>
#include <vector>

#include "api/json_util.h"
#include "api/operations/json_request.h"
#include "api/operations/request_forms.h"
#include "api/options/option_reader.h"
#include "api/scene_codec.h"
#include "geometry/implicit/query.h"

namespace surfaced::api::operations {
namespace {

using namespace json;  // the shared readers (api/json_util.h)

const char* kind_name(implicit::FieldKind kind) {
    switch (kind) {
        case implicit::FieldKind::ExactDistance: return "exact_distance";
        case implicit::FieldKind::DistanceBound: return "distance_bound";
        case implicit::FieldKind::General: return "general";
    }
    return "general";
}

//! max_steps and max_distance for the rays, read by the option table; max_steps against Limits::max_ray_steps.
std::optional<ApiError> read_ray_options(const options::OptionValues& values, const Limits& limits,
                                         implicit::RayOptions& options) {
    options.max_steps = std::min(1000, limits.max_ray_steps);
    if (values.has("max_steps")) {
        std::int64_t steps = 0;
        values.get("max_steps", steps);
        if (steps > limits.max_ray_steps)
            return make_problem(
                Problem::BudgetExceeded,
                "max_steps is " + std::to_string(steps) + "; the limit is " + std::to_string(limits.max_ray_steps),
                "max_steps");
        options.max_steps = static_cast<int>(steps);
    }
    values.get("max_distance", options.max_distance);
    return std::nullopt;
}

//! "rays": [{"origin": [x, y, z], "direction": [x, y, z]}, ...] (directions non-zero).
std::optional<ApiError> read_rays(const Json& list, std::vector<implicit::Ray>& rays) {
    rays.reserve(list.size());
    for (std::size_t i = 0; i < list.size(); ++i) {
        const std::string path = index_path("rays", i);
        const Json& r = list[i];
        if (!r.is_object()) return invalid(path, path + R"( must be {"origin": [x, y, z], "direction": [x, y, z]})");
        if (auto error = check_members(r, path, {"origin", "direction"})) return error;
        if (!r.contains("origin")) return invalid(path + ".origin", path + ".origin is required");
        if (!r.contains("direction")) return invalid(path + ".direction", path + ".direction is required");
        auto o = read_vec3(r["origin"], path + ".origin");
        if (!o) return std::move(o.error());
        auto d = read_vec3(r["direction"], path + ".direction");
        if (!d) return std::move(d.error());
        const double n = norm(d.value());
        if (!(n > 0) || !std::isfinite(n))
            return json::geometry_error(ErrorCode::InvalidArgument, path + ".direction",
                                        path + ".direction must be a non-zero vector");
        rays.push_back({o.value(), d.value()});
    }
    return std::nullopt;
}

Json encode_samples(const std::vector<implicit::PointSample>& samples) {
    Json list = Json::array();
    for (const auto& s : samples) {
        Json item = {{"class", implicit::to_string(s.cls)}};
        item["value"] = std::isfinite(s.value) ? Json(s.value) : Json(nullptr);
        item["gradient"] = is_finite(s.gradient) ? vec3_json(s.gradient) : Json(nullptr);
        list.push_back(std::move(item));
    }
    return list;
}

Json encode_hits(const std::vector<implicit::RayHit>& hits) {
    Json list = Json::array();
    for (const auto& h : hits) {
        Json item = {{"hit", h.hit}};
        if (h.hit) {
            item["t"] = h.t;
            item["point"] = vec3_json(h.point);
            item["normal"] = vec3_json(h.normal);
        }
        item["steps"] = h.steps;
        list.push_back(std::move(item));
    }
    return list;
}

ApiResponse run(const ApiRequest& request, const ApiContext& context) {
    const Limits& limits = context.limits;
    if (auto error = check_json_only_body(request, limits, "POST /implicit/query"))
        return error_response(std::move(*error));
    Json root;
    if (auto error = parse(request.body, root)) return error_response(std::move(*error));
    if (!root.is_object()) return error_response(invalid("", "the body must be a JSON object"));
    const auto& spec = *options::operation_options("implicit_query");
    if (auto error = check_members(root, "", options::json_members(spec))) return error_response(std::move(*error));
    auto values = options::read_json(spec, root);
    if (!values) return error_response(std::move(values.error()));

    // Budgets and shapes first, before the scene is built or evaluated.
    const auto points_it = root.find("points");
    const auto rays_it = root.find("rays");
    if (points_it != root.end() && !points_it->is_array())
        return error_response(invalid("points", "points must be an array of [x, y, z]"));
    if (rays_it != root.end() && !rays_it->is_array())
        return error_response(
            invalid("rays", R"(rays must be an array of {"origin": [x, y, z], "direction": [x, y, z]})"));
    const std::size_t point_count = points_it == root.end() ? 0 : points_it->size();
    const std::size_t ray_count = rays_it == root.end() ? 0 : rays_it->size();
    if (point_count == 0 && ray_count == 0)
        return error_response(invalid("points", "give at least one of points and rays"));
    if (point_count + ray_count > limits.max_query_points)
        return error_response(make_problem(Problem::BudgetExceeded,
                                           std::to_string(point_count) + " points + " + std::to_string(ray_count) +
                                               " rays; the limit is " + std::to_string(limits.max_query_points) +
                                               " in one request",
                                           point_count > ray_count ? "points" : "rays"));
    implicit::RayOptions ray_options;
    ray_options.cancel = context.cancel;
    if (auto error = read_ray_options(values.value(), limits, ray_options)) return error_response(std::move(*error));
    implicit::PointQueryOptions point_options;
    point_options.cancel = context.cancel;
    values->get("tolerance", point_options.tolerance);

    std::vector<Vec3> points;
    points.reserve(point_count);
    for (std::size_t i = 0; i < point_count; ++i) {
        auto p = read_vec3((*points_it)[i], index_path("points", i));
        if (!p) return error_response(std::move(p.error()));
        points.push_back(p.value());
    }
    std::vector<implicit::Ray> rays;
    if (ray_count > 0)
        if (auto error = read_rays(*rays_it, rays)) return error_response(std::move(*error));

    const auto scene_it = root.find("scene");
    if (scene_it == root.end()) return error_response(invalid("scene", "scene is required (a scene node)"));
    auto scene = parse_scene(*scene_it, limits, "scene", context.cancel);
    if (!scene) return error_response(std::move(scene.error()));
    const implicit::Field& field = *scene.value();

    Json out = {{"kind", kind_name(field.kind())}};
    const double lipschitz = field.lipschitz();
    out["lipschitz"] = std::isfinite(lipschitz) ? Json(lipschitz) : Json(nullptr);
    if (points_it != root.end()) {
        auto samples = implicit::query_points(field, points, point_options);
        if (!samples) return error_response(from_geo_error(samples.error()));
        out["points"] = encode_samples(samples.value());
    }
    if (rays_it != root.end()) {
        auto hits = implicit::cast_rays(field, rays, ray_options);
        if (!hits) {
            ApiError error = from_geo_error(hits.error());
            if (hits.error().element >= 0)
                error.field = index_path("rays", static_cast<std::size_t>(hits.error().element));
            return error_response(std::move(error));
        }
        out["rays"] = encode_hits(hits.value());
    }
    return json_response(out);
}

}  // namespace

ApiResponse implicit_query(const ApiRequest& request, const ApiContext& context) noexcept {
    try {
        return run(request, context);
    } catch (const std::bad_alloc&) {
        return error_response(make_problem(Problem::Internal, "out of memory while answering the query"));
    } catch (...) {
        // A library's exception text says nothing useful to a client (and may show internals).
        return error_response(make_problem(Problem::Internal, "internal error"));
    }
}

}  // namespace surfaced::api::operations
