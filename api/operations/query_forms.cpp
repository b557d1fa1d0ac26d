// Request intake and batch encodings shared by the JSON query endpoints (see query_forms.h).
#include "api/operations/query_forms.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <utility>

#include "api/json_codec.h"
#include "api/multipart.h"
#include "geometry/io/base64.h"

namespace surfaced::api::operations {

using namespace json;  // the shared readers (api/json_util.h)

namespace {

std::size_t bytes_per_value(Encoding e) { return e == Encoding::Float32 ? 4 : 8; }

void append_le(std::string& out, std::uint64_t bits, std::size_t bytes) {
    for (std::size_t b = 0; b < bytes; ++b) out += static_cast<char>((bits >> (8 * b)) & 0xff);
}

std::size_t column_width(const Column& column) {
    return column.kind == Column::Vector ? 3 : column.kind == Column::Vector2 ? 2 : 1;
}

}  // namespace

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

std::optional<ApiError> decode_packed(const Json& value, const std::string& field, std::size_t components, Batch& batch,
                                      bool finite_only) {
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
        if (finite_only && !std::isfinite(x))
            return invalid(path, path + ": number " + std::to_string(i % components) + " of item " +
                                     std::to_string(i / components) + " is not finite");
        batch.packed[i] = x;
    }
    return std::nullopt;
}

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

Json column_item(const Column& column, std::size_t i) {
    switch (column.kind) {
        case Column::Bool: return Json(column.values[i] != 0);
        case Column::Real: return std::isnan(column.values[i]) ? Json(nullptr) : Json(column.values[i]);
        case Column::Index:
            return column.values[i] < 0 ? Json(nullptr) : Json(static_cast<std::int64_t>(column.values[i]));
        case Column::Vector: {
            const double* v = &column.values[3 * i];
            return std::isnan(v[0]) ? Json(nullptr) : vec3_json(Vec3{v[0], v[1], v[2]});
        }
        case Column::Vector2: {
            const double* v = &column.values[2 * i];
            return std::isnan(v[0]) ? Json(nullptr) : Json::array({v[0], v[1]});
        }
    }
    return Json(nullptr);
}

Json encode_column(const Column& column, Encoding encoding) {
    if (encoding == Encoding::Json) {
        Json out = Json::array();
        const std::size_t n = column.values.size() / column_width(column);
        for (std::size_t i = 0; i < n; ++i) out.push_back(column_item(column, i));
        return out;
    }
    std::string bytes;
    for (const double x : column.values) {
        switch (column.kind) {
            case Column::Bool: bytes += static_cast<char>(x != 0 ? 1 : 0); break;
            case Column::Index: append_le(bytes, static_cast<std::uint32_t>(static_cast<std::int32_t>(x)), 4); break;
            case Column::Real:
            case Column::Vector:
            case Column::Vector2:
                if (encoding == Encoding::Float32)
                    append_le(bytes, std::bit_cast<std::uint32_t>(static_cast<float>(x)), 4);
                else
                    append_le(bytes, std::bit_cast<std::uint64_t>(x), 8);
                break;
        }
    }
    return encode_base64(bytes);
}

std::optional<ApiError> deadline_passed(const Cancel& cancel) {
    if (!cancel.requested()) return std::nullopt;
    return from_geo_error(GeoError{ErrorCode::Cancelled, "the request's compute deadline passed while answering"});
}

std::optional<ApiError> take_query_request(const ApiRequest& request, const Limits& limits, std::string_view endpoint,
                                           std::string_view items, QueryIntake& in) {
    std::string media_type;
    if (auto error = check_body(request, limits, media_type, "application/json, multipart/form-data")) return error;
    if (media_type == "application/json") {
        if (auto error = reject_query_with_json(request)) return error;
        return parse(request.body, in.root);
    }
    if (media_type != "multipart/form-data")
        return make_problem(Problem::UnsupportedMediaType,
                            std::string(endpoint) +
                                " takes application/json, or multipart/form-data with a mesh file part "
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
                                "unknown part \"" + part.name + "\": send the mesh file as the part \"file\" and " +
                                    std::string(items) + " and the options as the JSON part \"request\"");
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

ApiResult<PolygonMesh> query_mesh(const QueryIntake& in, const Limits& limits, MeshRules rules, Source& source) {
    ApiResult<PolygonMesh> mesh = PolygonMesh{};
    source = Source::Json;
    if (!in.multipart) {
        const auto mesh_it = in.root.find("mesh");
        if (mesh_it == in.root.end()) return invalid("mesh", "mesh is required");
        mesh = decode_mesh_json(*mesh_it, limits, "mesh");
    } else if (in.file_media_type == "application/json") {
        mesh = decode_mesh(in.file.body, limits, "mesh");
    } else {
        source = Source::File;
        mesh = read_uploaded_mesh(in.file, in.file_media_type, limits, rules);
    }
    if (!mesh) return std::move(mesh.error());
    if (auto error = check_mesh_input(mesh.value(), limits, source, rules)) return std::move(*error);
    return mesh;
}

}  // namespace surfaced::api::operations
