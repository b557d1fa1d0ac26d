// POST /mesh/query (see mesh_query.h): decode, check budgets, index the mesh (geometry/spatial), answer, encode.
#include "api/operations/mesh_query.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "api/json_codec.h"
#include "api/json_util.h"
#include "api/multipart.h"
#include "api/operations/request_forms.h"
#include "api/options/option_reader.h"
#include "geometry/io/base64.h"
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

//! How number arrays travel: JSON numbers, or base64 of packed little-endian float32 / float64.
enum class Encoding { Json, Float32, Float64 };
constexpr EnumName<Encoding> kEncodingNames[] = {
    {"json", Encoding::Json}, {"float32", Encoding::Float32}, {"float64", Encoding::Float64}};

std::size_t bytes_per_value(Encoding e) { return e == Encoding::Float32 ? 4 : 8; }

//! A batch of points (3 numbers each) or rays (6): a JSON array of arrays, or {"float32" | "float64": base64} of
//! packed little-endian numbers.
struct Batch {
    const Json* array = nullptr;  //!< the JSON form
    std::vector<double> packed;   //!< the packed form, decoded
    std::size_t count = 0;
};

//! The shape and count of `field` (no numbers decoded yet, so that the budget is checked first): `components`
//! numbers per item. `what` is "[x, y, z]" or "[ox, oy, oz, dx, dy, dz]" for messages.
ApiResult<Batch> batch_shape(const Json& value, const std::string& field, std::size_t components,
                             std::string_view what) {
    Batch batch;
    if (value.is_array()) {
        batch.array = &value;
        batch.count = value.size();
        return batch;
    }
    const std::string usage = field + " must be an array of " + std::string(what) +
                              R"(, or {"float32": base64} / {"float64": base64} of packed little-endian numbers)";
    if (!value.is_object() || value.size() != 1) return invalid(field, usage);
    // (the object's own iterator: items() yields proxies that do not outlive the statement)
    const auto member = value.begin();
    const std::string& key = member.key();
    const Json& text = member.value();
    const auto encoding = enum_from_name(kEncodingNames, key);
    if (!encoding || *encoding == Encoding::Json || !text.is_string()) return invalid(field, usage);
    const std::size_t item_bytes = components * bytes_per_value(*encoding);
    const std::size_t bytes = decoded_base64_size(text.get_ref<const std::string&>());
    if (bytes % item_bytes != 0)
        return invalid(member_path(field, key), field + "." + key + ": " + std::to_string(bytes) +
                                                    " bytes are not a whole number of " + std::string(what) + " (" +
                                                    std::to_string(item_bytes) + " bytes each)");
    batch.count = bytes / item_bytes;
    return batch;
}

//! Decodes a packed batch's numbers (after the budget check); each must be finite.
std::optional<ApiError> decode_packed(const Json& value, const std::string& field, std::size_t components,
                                      Batch& batch) {
    if (batch.array) return std::nullopt;
    // (the object's own iterator: items() yields proxies that do not outlive the statement)
    const auto member = value.begin();
    const std::string& key = member.key();
    const Json& text = member.value();
    const std::string path = member_path(field, key);
    auto bytes = decode_base64(text.get_ref<const std::string&>());
    if (!bytes) return invalid(path, path + ": " + bytes.error().message);
    const bool single = key == "float32";
    const std::size_t size = single ? 4 : 8;
    batch.packed.resize(bytes->size() / size);
    for (std::size_t i = 0; i < batch.packed.size(); ++i) {
        std::uint64_t bits = 0;
        for (std::size_t b = 0; b < size; ++b) bits |= std::uint64_t((*bytes)[i * size + b]) << (8 * b);
        const double x =
            single ? double(std::bit_cast<float>(static_cast<std::uint32_t>(bits))) : std::bit_cast<double>(bits);
        if (!std::isfinite(x))
            return invalid(path, path + ": number " + std::to_string(i % components) + " of item " +
                                     std::to_string(i / components) + " is not finite");
        batch.packed[i] = x;
    }
    return std::nullopt;
}

//! Item i of a batch as `components` numbers into `out` (JSON items are read, with field paths, here).
std::optional<ApiError> batch_item(const Batch& batch, std::size_t i, const std::string& field, std::size_t components,
                                   std::string_view what, double* out) {
    if (!batch.array) {
        std::copy_n(batch.packed.begin() + static_cast<std::ptrdiff_t>(i * components), components, out);
        return std::nullopt;
    }
    const Json& item = (*batch.array)[i];
    const std::string path = index_path(field, i);
    if (!item.is_array() || item.size() != components) return invalid(path, path + " must be " + std::string(what));
    for (std::size_t k = 0; k < components; ++k) {
        auto x = read_number(item[k], index_path(path, k));
        if (!x) return std::move(x.error());
        out[k] = x.value();
    }
    return std::nullopt;
}

//! Answers collected before encoding: booleans, numbers, 3-vectors (NaN where there is none) and indices (-1).
struct Column {
    enum Kind { Bool, Real, Vector, Index } kind;
    std::vector<double> values;  //!< one per item (three for Vector)
};

void append_le(std::string& out, std::uint64_t bits, std::size_t bytes) {
    for (std::size_t b = 0; b < bytes; ++b) out += static_cast<char>((bits >> (8 * b)) & 0xff);
}

//! A column as JSON: numbers (null for NaN / -1), or base64 of packed little-endian values: uint8 for booleans,
//! int32 for indices (-1 for none), float32 or float64 for numbers and vectors (NaN for none).
Json encode_column(const Column& column, Encoding encoding) {
    if (encoding == Encoding::Json) {
        Json out = Json::array();
        const std::size_t n = column.kind == Column::Vector ? column.values.size() / 3 : column.values.size();
        for (std::size_t i = 0; i < n; ++i) {
            switch (column.kind) {
                case Column::Bool: out.push_back(column.values[i] != 0); break;
                case Column::Real:
                    out.push_back(std::isnan(column.values[i]) ? Json(nullptr) : Json(column.values[i]));
                    break;
                case Column::Index:
                    out.push_back(column.values[i] < 0 ? Json(nullptr)
                                                       : Json(static_cast<std::int64_t>(column.values[i])));
                    break;
                case Column::Vector: {
                    const double* v = &column.values[3 * i];
                    out.push_back(std::isnan(v[0]) ? Json(nullptr) : vec3_json(Vec3{v[0], v[1], v[2]}));
                    break;
                }
            }
        }
        return out;
    }
    std::string bytes;
    for (const double x : column.values) {
        switch (column.kind) {
            case Column::Bool: bytes += static_cast<char>(x != 0 ? 1 : 0); break;
            case Column::Index: append_le(bytes, static_cast<std::uint32_t>(static_cast<std::int32_t>(x)), 4); break;
            case Column::Real:
            case Column::Vector:
                if (encoding == Encoding::Float32)
                    append_le(bytes, std::bit_cast<std::uint32_t>(static_cast<float>(x)), 4);
                else
                    append_le(bytes, std::bit_cast<std::uint64_t>(x), 8);
                break;
        }
    }
    return encode_base64(bytes);
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

//! The request in either form: a JSON body with the mesh in it, or a multipart/form-data body whose part "file" is a
//! mesh file and whose part "request" is the JSON body without the mesh.
struct Intake {
    Json root;
    bool multipart = false;
    ApiRequest file;  //!< multipart: the mesh part as a raw upload (body, content type)
    std::string file_media_type;
};

std::optional<ApiError> take_request(const ApiRequest& request, const Limits& limits, Intake& in) {
    std::string media_type;
    if (auto error = check_body(request, limits, media_type, "application/json, multipart/form-data")) return error;
    if (media_type == "application/json") {
        if (auto error = reject_query_with_json(request)) return error;
        return parse(request.body, in.root);
    }
    if (media_type != "multipart/form-data")
        return make_problem(Problem::UnsupportedMediaType,
                            "POST /mesh/query takes application/json, or multipart/form-data with a mesh file part "
                            "\"file\" and a JSON part \"request\"; not \"" +
                                media_type + "\"");
    if (!request.query.empty())
        return invalid(request.query.begin()->first,
                       "query parameters are not accepted: the options go in the \"request\" part, got \"" +
                           request.query.begin()->first + "\"");
    auto boundary = multipart_boundary(request.content_type);
    if (!boundary) return std::move(boundary.error());
    auto parts = parse_multipart(request.body, boundary.value());
    if (!parts) return std::move(parts.error());
    const MultipartPart *mesh = nullptr, *body = nullptr;
    for (const MultipartPart& part : parts.value()) {
        const MultipartPart*& slot = part.name == "request" ? body : mesh;
        if (part.name != "request" && part.name != "file")
            return make_problem(Problem::MalformedMultipart,
                                "unknown part \"" + part.name +
                                    "\": send the mesh file as the part \"file\" and the points, rays and options as "
                                    "the JSON part \"request\"");
        if (slot) return make_problem(Problem::MalformedMultipart, "the part \"" + part.name + "\" is given twice");
        slot = &part;
    }
    if (!mesh || !body)
        return make_problem(Problem::MalformedMultipart,
                            std::string("no \"") + (mesh ? "request" : "file") +
                                "\" part: send the mesh file as \"file\" and the JSON body without the mesh as "
                                "\"request\" (curl -F file=@part.stl -F request=@query.json)");
    if (mesh->body.empty()) return make_problem(Problem::EmptyBody, "the part \"file\" is empty");
    if (auto error = parse(body->body, in.root)) return error;
    if (in.root.is_object() && in.root.contains("mesh"))
        return invalid("mesh", "the mesh comes in the part \"file\"; the \"request\" part must not hold one too");
    in.multipart = true;
    in.file_media_type = file_part_media_type(*mesh, reads_mesh_media_type);
    in.file.method = request.method;
    in.file.path = request.path;
    in.file.headers = request.headers;
    in.file.body = mesh->body;
    in.file.content_type = in.file_media_type;
    return std::nullopt;
}

ApiResponse run(const ApiRequest& request, const ApiContext& context) {
    const Limits& limits = context.limits;
    Intake in;
    if (auto error = take_request(request, limits, in)) return error_response(std::move(*error));
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

    ApiResult<PolygonMesh> mesh = PolygonMesh{};
    Source source = Source::Json;
    if (!in.multipart) {
        const auto mesh_it = root.find("mesh");
        if (mesh_it == root.end()) return error_response(invalid("mesh", "mesh is required"));
        mesh = decode_mesh(mesh_it->dump(), limits, "mesh");
    } else if (in.file_media_type == "application/json") {
        mesh = decode_mesh(in.file.body, limits, "mesh");
    } else {
        source = Source::File;
        mesh = read_uploaded_mesh(in.file, in.file_media_type, limits);
    }
    if (!mesh) return error_response(std::move(mesh.error()));
    if (auto error = check_mesh_input(mesh.value(), limits, source)) return error_response(std::move(*error));
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
