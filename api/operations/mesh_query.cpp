// POST /mesh/query (see mesh_query.h): decode, check budgets, index the mesh (geometry/spatial), answer, encode.
#include "api/operations/mesh_query.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "api/json_codec.h"
#include "api/json_util.h"
#include "api/operations/json_request.h"
#include "api/operations/query_forms.h"
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

ApiResponse run(const ApiRequest& request, const ApiContext& context) {
    const Limits& limits = context.limits;
    QueryIntake in;
    if (auto error = take_query_request(request, limits, "POST /mesh/query", "the points, rays", in))
        return error_response(std::move(*error));
    const Json& root = in.root;
    if (!root.is_object()) return error_response(invalid("", "the body must be a JSON object"));
    const auto& spec = *options::operation_options("mesh_query");
    std::vector<std::string_view> members = options::json_members(spec);
    if (in.multipart) std::erase(members, std::string_view("mesh"));
    if (auto error = check_members(root, "", members)) return error_response(std::move(*error));
    auto values = options::read_json(spec, root);
    if (!values) return error_response(std::move(values.error()));
    WindingNumberOptions winding;
    values->get("exact", winding.exact);
    values->get("accuracy", winding.accuracy);
    Encoding encoding = Encoding::Json;
    values->get("encoding", kEncodingNames, encoding);

    // Shapes and budgets first, before any number is decoded or the mesh is read.
    constexpr std::string_view kPoint = "[x, y, z]", kRay = "[ox, oy, oz, dx, dy, dz]";
    Batch point_batch, ray_batch;
    const auto points_it = root.find("points");
    const auto rays_it = root.find("rays");
    if (points_it != root.end()) {
        auto shape = batch_shape(*points_it, "points", 3, kPoint);
        if (!shape) return error_response(std::move(shape.error()));
        point_batch = std::move(shape.value());
    }
    if (rays_it != root.end()) {
        auto shape = batch_shape(*rays_it, "rays", 6, kRay);
        if (!shape) return error_response(std::move(shape.error()));
        ray_batch = std::move(shape.value());
    }
    const std::size_t point_count = point_batch.count;
    const std::size_t ray_count = ray_batch.count;
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

    if (points_it != root.end())
        if (auto error = decode_packed(*points_it, "points", 3, point_batch)) return error_response(std::move(*error));
    if (rays_it != root.end())
        if (auto error = decode_packed(*rays_it, "rays", 6, ray_batch)) return error_response(std::move(*error));
    std::vector<Vec3> points;
    points.reserve(point_count);
    for (std::size_t i = 0; i < point_count; ++i) {
        double c[3];
        if (auto error = batch_item(point_batch, i, "points", 3, kPoint, c)) return error_response(std::move(*error));
        points.push_back(Vec3{c[0], c[1], c[2]});
    }
    std::vector<Ray> rays;
    rays.reserve(ray_count);
    for (std::size_t i = 0; i < ray_count; ++i) {
        const std::string field = index_path("rays", i);
        double c[6];
        if (auto error = batch_item(ray_batch, i, "rays", 6, kRay, c)) return error_response(std::move(*error));
        const Vec3 direction{c[3], c[4], c[5]};
        const double length = norm(direction);
        if (!(length > 0) || !std::isfinite(length))
            return error_response(
                json::geometry_error(ErrorCode::InvalidArgument, field,
                                     field + ": the direction (its last three numbers) must be a non-zero vector"));
        rays.emplace_back(Vec3{c[0], c[1], c[2]}, direction);
    }

    Source source = Source::Json;
    auto mesh = query_mesh(in, limits, MeshRules::Strict, source);
    if (!mesh) return error_response(std::move(mesh.error()));
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
    if (!bvh) return error_response(geometry_error(bvh.error(), source));
    WindingTree tree;
    if (point_count > 0 && want.needs_winding()) tree = build_winding_tree(bvh.value());
    if (auto error = deadline_passed(context.cancel)) return error_response(std::move(*error));

    constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
    Json out = Json::object();
    if (encoding != Encoding::Json) out["encoding"] = std::string(enum_name(kEncodingNames, encoding));
    if (point_count > 0) {
        Column inside{Column::Bool, {}}, number{Column::Real, {}}, distance{Column::Real, {}},
            closest{Column::Vector, {}}, face{Column::Index, {}};
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
            if (want.inside) inside.values.push_back(w->value >= 0.5 ? 1 : 0);
            if (want.winding_number) number.values.push_back(w->value);
            if (want.distance) distance.values.push_back(signed_value);
            if (want.closest) {
                const Vec3 p = near ? near->point : Vec3{kNone, kNone, kNone};
                closest.values.insert(closest.values.end(), {p.x, p.y, p.z});
                face.values.push_back(near ? static_cast<double>(near->face) : -1.0);
            }
        }
        Json answers = Json::object();
        if (want.inside) answers["inside"] = encode_column(inside, encoding);
        if (want.winding_number) answers["winding_number"] = encode_column(number, encoding);
        if (want.distance) answers["distance"] = encode_column(distance, encoding);
        if (want.closest) {
            answers["closest"] = encode_column(closest, encoding);
            answers["face"] = encode_column(face, encoding);
        }
        out["points"] = std::move(answers);
    }
    if (ray_count > 0) {
        Column hit{Column::Bool, {}}, t{Column::Real, {}}, face{Column::Index, {}}, point{Column::Vector, {}},
            normal{Column::Vector, {}};
        for (std::size_t i = 0; i < ray_count; ++i) {
            if (i % kBatch == 0)
                if (auto error = deadline_passed(context.cancel)) return error_response(std::move(*error));
            const auto h = ray_first_hit(bvh.value(), rays[i]);
            const Vec3 none{kNone, kNone, kNone};
            const Vec3 p = h ? h->point : none, n = h ? h->normal : none;
            hit.values.push_back(h ? 1 : 0);
            t.values.push_back(h ? h->t : kNone);
            face.values.push_back(h ? static_cast<double>(h->face) : -1.0);
            point.values.insert(point.values.end(), {p.x, p.y, p.z});
            normal.values.insert(normal.values.end(), {n.x, n.y, n.z});
        }
        out["rays"] = {{"hit", encode_column(hit, encoding)},
                       {"t", encode_column(t, encoding)},
                       {"face", encode_column(face, encoding)},
                       {"point", encode_column(point, encoding)},
                       {"normal", encode_column(normal, encoding)}};
    }
    if (auto error = check_deadline_before_encoding(context.cancel)) return error_response(std::move(*error));
    return json_response(out);
}

}  // namespace

ApiResponse mesh_query(const ApiRequest& request, const ApiContext& context) noexcept {
    return guarded([&] { return run(request, context); });
}

}  // namespace surfaced::api::operations
