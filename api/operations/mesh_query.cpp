// POST /mesh/query (see mesh_query.h): decode, check budgets, index the mesh (geometry/spatial), answer, encode.
#include "api/operations/mesh_query.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "api/json_codec.h"
#include "api/json_util.h"
#include "api/operations/request_forms.h"
#include "api/options/option_reader.h"
#include "geometry/spatial/bvh.h"
#include "geometry/spatial/closest_point.h"
#include "geometry/spatial/ray_cast.h"
#include "geometry/spatial/signed_distance.h"
#include "geometry/spatial/winding_number.h"

namespace surfaced::api::operations {
namespace {

using namespace json;  // the shared readers (api/json_util.h)

//! Queries answered between two looks at the deadline.
constexpr std::size_t kBatch = 1024;

constexpr std::string_view kWantNames[] = {"inside", "winding_number", "distance", "closest"};

struct Want {
    bool inside = true, winding_number = true, distance = true, closest = true;
    bool needs_winding() const { return inside || winding_number || distance; }
};

//! [ox, oy, oz, dx, dy, dz] with a non-zero direction.
ApiResult<Ray> read_ray(const Json& value, const std::string& field) {
    if (!value.is_array() || value.size() != 6)
        return invalid(field, field + " must be [ox, oy, oz, dx, dy, dz] (origin, then direction)");
    double c[6];
    for (std::size_t k = 0; k < 6; ++k) {
        auto x = read_number(value[k], index_path(field, k));
        if (!x) return std::move(x.error());
        c[k] = x.value();
    }
    const Vec3 direction{c[3], c[4], c[5]};
    const double length = norm(direction);
    if (!(length > 0) || !std::isfinite(length))
        return json::geometry_error(ErrorCode::InvalidArgument, field,
                                    field + ": the direction (its last three numbers) must be a non-zero vector");
    return Ray(Vec3{c[0], c[1], c[2]}, direction);
}

//! "want": an array of kWantNames, each at most once; an unknown name is named with the nearest known one.
ApiResult<Want> read_want(const Json& value) {
    if (!value.is_array() || value.empty())
        return invalid("want",
                       R"(want must be a non-empty array of "inside", "winding_number", "distance", "closest")");
    const std::vector<std::string_view> names(std::begin(kWantNames), std::end(kWantNames));
    Want want{false, false, false, false};
    bool* flags[] = {&want.inside, &want.winding_number, &want.distance, &want.closest};
    for (std::size_t i = 0; i < value.size(); ++i) {
        const std::string field = index_path("want", i);
        if (!value[i].is_string()) return invalid(field, field + R"( must be a string ("inside", "distance", ...))");
        const auto& text = value[i].get_ref<const std::string&>();
        const auto it = std::find(names.begin(), names.end(), text);
        if (it == names.end()) {
            std::string detail = field + ": unknown value \"" + text + "\"";
            if (auto near = options::nearest_name(text, names))
                detail += " (did you mean \"" + std::string(*near) + "\"?)";
            return invalid(field, detail + R"( (allowed: "inside", "winding_number", "distance", "closest"))");
        }
        bool& flag = *flags[it - names.begin()];
        if (flag) return invalid(field, field + ": \"" + text + "\" is listed twice");
        flag = true;
    }
    return want;
}

std::optional<ApiError> deadline_passed(const Cancel& cancel) {
    if (!cancel.requested()) return std::nullopt;
    return from_geo_error(GeoError{ErrorCode::Cancelled, "the request's compute deadline passed while answering"});
}

ApiResponse run(const ApiRequest& request, const ApiContext& context) {
    const Limits& limits = context.limits;
    if (auto error = check_json_only_body(request, limits, "POST /mesh/query"))
        return error_response(std::move(*error));
    Json root;
    if (auto error = parse(request.body, root)) return error_response(std::move(*error));
    if (!root.is_object()) return error_response(invalid("", "the body must be a JSON object"));
    const auto& spec = *options::operation_options("mesh_query");
    if (auto error = check_members(root, "", options::json_members(spec))) return error_response(std::move(*error));
    auto values = options::read_json(spec, root);
    if (!values) return error_response(std::move(values.error()));
    WindingNumberOptions winding;
    values->get("exact", winding.exact);
    values->get("accuracy", winding.accuracy);

    // Shapes and budgets first, before the mesh is decoded or indexed.
    const auto points_it = root.find("points");
    const auto rays_it = root.find("rays");
    if (points_it != root.end() && !points_it->is_array())
        return error_response(invalid("points", "points must be an array of [x, y, z]"));
    if (rays_it != root.end() && !rays_it->is_array())
        return error_response(invalid("rays", "rays must be an array of [ox, oy, oz, dx, dy, dz]"));
    const std::size_t point_count = points_it == root.end() ? 0 : points_it->size();
    const std::size_t ray_count = rays_it == root.end() ? 0 : rays_it->size();
    if (point_count == 0 && ray_count == 0)
        return error_response(invalid("points", "give at least one of points and rays"));
    if (point_count + ray_count > limits.max_mesh_queries)
        return error_response(make_problem(Problem::BudgetExceeded,
                                           std::to_string(point_count) + " points + " + std::to_string(ray_count) +
                                               " rays; the limit is " + std::to_string(limits.max_mesh_queries) +
                                               " in one request",
                                           point_count > ray_count ? "points" : "rays"));
    Want want;
    if (const auto it = root.find("want"); it != root.end()) {
        auto read = read_want(*it);
        if (!read) return error_response(std::move(read.error()));
        want = read.value();
    }

    std::vector<Vec3> points;
    points.reserve(point_count);
    for (std::size_t i = 0; i < point_count; ++i) {
        auto p = read_vec3((*points_it)[i], index_path("points", i));
        if (!p) return error_response(std::move(p.error()));
        points.push_back(p.value());
    }
    std::vector<Ray> rays;
    rays.reserve(ray_count);
    for (std::size_t i = 0; i < ray_count; ++i) {
        auto r = read_ray((*rays_it)[i], index_path("rays", i));
        if (!r) return error_response(std::move(r.error()));
        rays.push_back(r.value());
    }

    const auto mesh_it = root.find("mesh");
    if (mesh_it == root.end()) return error_response(invalid("mesh", "mesh is required"));
    auto mesh = decode_mesh(mesh_it->dump(), limits, "mesh");
    if (!mesh) return error_response(std::move(mesh.error()));
    if (auto error = check_mesh_input(mesh.value(), limits, Source::Json)) return error_response(std::move(*error));
    if (auto error = check_triangulated_budget(mesh.value(), limits)) return error_response(std::move(*error));
    if (mesh->face_count() == 0)
        return error_response(
            json::geometry_error(ErrorCode::InvalidArgument, "mesh.faces",
                                 "mesh.faces is empty: a mesh without faces has no surface to query"));
    const std::uint64_t triangles = mesh->face_indices.size() - 2 * mesh->face_count();
    if (winding.exact && want.needs_winding() && point_count > 0 &&
        static_cast<double>(point_count) * static_cast<double>(triangles) >
            static_cast<double>(limits.max_exact_winding_work))
        return error_response(make_problem(
            Problem::BudgetExceeded,
            "exact winding numbers of " + std::to_string(point_count) + " points on " + std::to_string(triangles) +
                " triangles are " + format_double(static_cast<double>(point_count) * static_cast<double>(triangles)) +
                " terms; the limit is " + std::to_string(limits.max_exact_winding_work) +
                " (winding.exact false uses the hierarchy)",
            "winding.exact"));

    BvhOptions bvh_options;
    bvh_options.cancel = context.cancel;
    bvh_options.ray_nodes = ray_count > 0;  // the ray layout serves rays only
    auto bvh = build_bvh(mesh.value(), bvh_options);
    if (!bvh) return error_response(geometry_error(bvh.error(), Source::Json));
    WindingTree tree;
    if (point_count > 0 && want.needs_winding()) tree = build_winding_tree(bvh.value());
    if (auto error = deadline_passed(context.cancel)) return error_response(std::move(*error));

    Json out = Json::object();
    if (point_count > 0) {
        Json inside = Json::array(), number = Json::array(), distance = Json::array(), closest = Json::array(),
             face = Json::array();
        for (std::size_t i = 0; i < point_count; ++i) {
            if (i % kBatch == 0)
                if (auto error = deadline_passed(context.cancel)) return error_response(std::move(*error));
            const std::string field = index_path("points", i);
            std::optional<SurfacePoint> near;
            std::optional<WindingNumber> w;
            double signed_value = 0;
            if (want.distance) {
                auto d = signed_distance(bvh.value(), tree, points[i], SignedDistanceOptions{winding});
                if (!d) return error_response(json::geometry_error(d.error().code, field, d.error().message));
                near = d->closest;
                w = d->winding;
                signed_value = d->distance;
            } else {
                if (want.inside || want.winding_number) {
                    auto wn = winding_number(bvh.value(), tree, points[i], winding);
                    if (!wn) return error_response(json::geometry_error(wn.error().code, field, wn.error().message));
                    w = wn.value();
                }
                if (want.closest) near = closest_point(bvh.value(), points[i]);
            }
            if (want.inside) inside.push_back(w->value >= 0.5);
            if (want.winding_number) number.push_back(w->value);
            if (want.distance) distance.push_back(signed_value);
            if (want.closest) {
                closest.push_back(near ? vec3_json(near->point) : Json(nullptr));
                face.push_back(near ? Json(near->face) : Json(nullptr));
            }
        }
        Json answers = Json::object();
        if (want.inside) answers["inside"] = std::move(inside);
        if (want.winding_number) answers["winding_number"] = std::move(number);
        if (want.distance) answers["distance"] = std::move(distance);
        if (want.closest) {
            answers["closest"] = std::move(closest);
            answers["face"] = std::move(face);
        }
        out["points"] = std::move(answers);
    }
    if (ray_count > 0) {
        Json hit = Json::array(), t = Json::array(), face = Json::array(), point = Json::array(),
             normal = Json::array();
        for (std::size_t i = 0; i < ray_count; ++i) {
            if (i % kBatch == 0)
                if (auto error = deadline_passed(context.cancel)) return error_response(std::move(*error));
            const auto h = ray_first_hit(bvh.value(), rays[i]);
            hit.push_back(h.has_value());
            t.push_back(h ? Json(h->t) : Json(nullptr));
            face.push_back(h ? Json(h->face) : Json(nullptr));
            point.push_back(h ? vec3_json(h->point) : Json(nullptr));
            normal.push_back(h ? vec3_json(h->normal) : Json(nullptr));
        }
        out["rays"] = {{"hit", std::move(hit)},
                       {"t", std::move(t)},
                       {"face", std::move(face)},
                       {"point", std::move(point)},
                       {"normal", std::move(normal)}};
    }
    if (auto error = check_deadline_before_encoding(context.cancel)) return error_response(std::move(*error));
    ApiResponse response;
    response.content_type = "application/json";
    response.body = json_text(out);
    return response;
}

}  // namespace

ApiResponse mesh_query(const ApiRequest& request, const ApiContext& context) noexcept {
    return guarded([&] { return run(request, context); });
}

}  // namespace surfaced::api::operations
