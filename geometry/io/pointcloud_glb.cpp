// GLB writer for point clouds: validate -> attribute arrays -> Draco or plain buffer views -> tinygltf model -> GLB.
// Shares conventions with gltf_write.cpp (one buffer, 4-byte aligned views, accessors of the decoded Draco data).
#include "geometry/io/pointcloud_glb.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "geometry/io/draco_points.h"
#include "geometry/io/gltf_model.h"

namespace surfaced {
namespace {

constexpr const char* kDracoExtension = "KHR_draco_mesh_compression";

Status check_options(const PointGlbOptions& o) {
    auto out_of_range = [](const char* name, int value, int lo, int hi) {
        return make_error(ErrorCode::InvalidArgument, std::string(name) + " = " + std::to_string(value) +
                                                          " is out of range " + std::to_string(lo) + ".." +
                                                          std::to_string(hi));
    };
    // same caps as write_glb (gltf_write.cpp explains the cost per bit)
    if (o.quantize_position < 1 || o.quantize_position > 24)
        return out_of_range("quantize_position", o.quantize_position, 1, 24);
    if (o.quantize_normal < 2 || o.quantize_normal > 22)
        return out_of_range("quantize_normal", o.quantize_normal, 2, 22);
    if (o.encode_speed < 0 || o.encode_speed > 10) return out_of_range("encode_speed", o.encode_speed, 0, 10);
    if (o.decode_speed < 0 || o.decode_speed > 10) return out_of_range("decode_speed", o.decode_speed, 0, 10);
    return Ok{};
}

void min_max(const std::vector<float>& values, std::vector<double>& lo, std::vector<double>& hi) {
    lo.assign(3, std::numeric_limits<double>::infinity());
    hi.assign(3, -std::numeric_limits<double>::infinity());
    for (std::size_t i = 0; i < values.size(); ++i) {
        lo[i % 3] = std::min(lo[i % 3], static_cast<double>(values[i]));
        hi[i % 3] = std::max(hi[i % 3], static_cast<double>(values[i]));
    }
}

int add_buffer_view(tinygltf::Model& model, const void* bytes, std::size_t size, int target) {
    auto& data = model.buffers[0].data;
    data.resize((data.size() + 3) & ~std::size_t{3}, 0);
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = data.size();
    view.byteLength = size;
    view.target = target;
    const auto* first = static_cast<const unsigned char*>(bytes);
    data.insert(data.end(), first, first + size);
    model.bufferViews.push_back(std::move(view));
    return static_cast<int>(model.bufferViews.size() - 1);
}

int add_accessor(tinygltf::Model& model, int view, int component_type, int type, std::size_t count,
                 bool normalized = false, std::vector<double> lo = {}, std::vector<double> hi = {}) {
    tinygltf::Accessor accessor;
    accessor.bufferView = view;
    accessor.componentType = component_type;
    accessor.normalized = normalized;
    accessor.type = type;
    accessor.count = count;
    accessor.minValues = std::move(lo);
    accessor.maxValues = std::move(hi);
    model.accessors.push_back(std::move(accessor));
    return static_cast<int>(model.accessors.size() - 1);
}

Vec3 unit_or_up(const Vec3& n) {
    const double len = norm(n);
    if (!(len > 1e-12) || !std::isfinite(len)) return {0, 0, 1};  // the validator rejects non-unit normals
    return n * (1.0 / len);
}

Status add_draco_primitive(tinygltf::Model& model, tinygltf::Primitive& primitive, const PointCloud& cloud,
                           bool with_normals, bool with_colors, const PointGlbOptions& options) {
    draco_points::PointData data;
    data.positions.reserve(cloud.size() * 3);
    for (const Vec3& p : cloud.positions)
        for (int k = 0; k < 3; ++k) data.positions.push_back(static_cast<float>(p[k]));
    if (with_normals) {
        data.normals.reserve(cloud.size() * 3);
        for (const Vec3& n : cloud.normals) {
            const Vec3 u = unit_or_up(n);
            for (int k = 0; k < 3; ++k) data.normals.push_back(static_cast<float>(u[k]));
        }
    }
    if (with_colors) {
        data.color_components = cloud.has_alpha ? 4 : 3;
        data.colors.reserve(cloud.size() * static_cast<std::size_t>(data.color_components));
        for (const Color& c : cloud.colors) {
            data.colors.insert(data.colors.end(), {c.r, c.g, c.b});
            if (cloud.has_alpha) data.colors.push_back(c.a);
        }
    }
    draco_codec::EncodeOptions encode_options;
    encode_options.quantize_position = options.quantize_position;
    encode_options.quantize_normal = options.quantize_normal;
    encode_options.encode_speed = options.encode_speed;
    encode_options.decode_speed = options.decode_speed;
    auto encoded = draco_points::encode(data, encode_options);
    if (!encoded) return encoded.error();
    // accessors describe the decoded data (quantized positions, possibly reordered): decode what was written
    const auto* payload = reinterpret_cast<const std::uint8_t*>(encoded->bytes.data());
    auto decoded = draco_points::decode({payload, encoded->bytes.size()}, encoded->ids, cloud.size());
    if (!decoded)
        return make_error(ErrorCode::Internal,
                          "Draco round trip of the written points failed: " + decoded.error().message);
    const std::size_t points = decoded->point_count();

    const int view = add_buffer_view(model, encoded->bytes.data(), encoded->bytes.size(), 0);
    tinygltf::Value::Object ids;
    std::vector<double> lo, hi;
    min_max(decoded->positions, lo, hi);
    primitive.attributes["POSITION"] =
        add_accessor(model, -1, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, points, false, lo, hi);
    ids["POSITION"] = tinygltf::Value(encoded->ids.position);
    if (encoded->ids.normal >= 0) {
        primitive.attributes["NORMAL"] =
            add_accessor(model, -1, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, points);
        ids["NORMAL"] = tinygltf::Value(encoded->ids.normal);
    }
    if (encoded->ids.color >= 0) {
        primitive.attributes["COLOR_0"] =
            add_accessor(model, -1, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                         data.color_components == 4 ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3, points, true);
        ids["COLOR_0"] = tinygltf::Value(encoded->ids.color);
    }
    tinygltf::Value::Object extension;
    extension["bufferView"] = tinygltf::Value(view);
    extension["attributes"] = tinygltf::Value(std::move(ids));
    primitive.extensions[kDracoExtension] = tinygltf::Value(std::move(extension));
    model.extensionsUsed.push_back(kDracoExtension);
    model.extensionsRequired.push_back(kDracoExtension);
    return Ok{};
}

void add_plain_primitive(tinygltf::Model& model, tinygltf::Primitive& primitive, const PointCloud& cloud,
                         bool with_normals, bool with_colors) {
    const std::size_t points = cloud.size();
    std::vector<float> values;
    values.reserve(points * 4);
    for (const Vec3& p : cloud.positions)
        for (int k = 0; k < 3; ++k) values.push_back(static_cast<float>(p[k]));
    std::vector<double> lo, hi;
    min_max(values, lo, hi);
    int view = add_buffer_view(model, values.data(), values.size() * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER);
    primitive.attributes["POSITION"] =
        add_accessor(model, view, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, points, false, lo, hi);
    if (with_normals) {
        values.clear();
        for (const Vec3& n : cloud.normals) {
            const Vec3 u = unit_or_up(n);
            for (int k = 0; k < 3; ++k) values.push_back(static_cast<float>(u[k]));
        }
        view = add_buffer_view(model, values.data(), values.size() * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER);
        primitive.attributes["NORMAL"] =
            add_accessor(model, view, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, points);
    }
    if (with_colors) {
        values.clear();
        for (const Color& c : cloud.colors) {
            values.insert(values.end(), {c.r, c.g, c.b});
            if (cloud.has_alpha) values.push_back(c.a);
        }
        view = add_buffer_view(model, values.data(), values.size() * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER);
        primitive.attributes["COLOR_0"] =
            add_accessor(model, view, TINYGLTF_COMPONENT_TYPE_FLOAT,
                         cloud.has_alpha ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3, points);
    }
}

Result<std::string> write_unchecked(const PointCloud& cloud, const PointGlbOptions& options) {
    if (Status s = check_options(options); !s) return s.error();
    if (cloud.empty()) return make_error(ErrorCode::InvalidArgument, "cannot write an empty point cloud to glTF");
    if (Status s = validate(cloud); !s) return s.error();
    if (cloud.size() >= std::numeric_limits<std::uint32_t>::max() - 1)
        return make_error(ErrorCode::BudgetExceeded, "too many points for glTF: " + std::to_string(cloud.size()));
    const bool with_normals = options.normals && cloud.has_normals();
    const bool with_colors = options.colors && cloud.has_colors();

    tinygltf::Model model;
    model.asset.version = "2.0";
    model.asset.generator = "surfaced";
    model.buffers.emplace_back();
    tinygltf::Primitive primitive;
    primitive.mode = TINYGLTF_MODE_POINTS;
    if (options.draco) {
        if (Status s = add_draco_primitive(model, primitive, cloud, with_normals, with_colors, options); !s)
            return s.error();
    } else {
        add_plain_primitive(model, primitive, cloud, with_normals, with_colors);
    }
    if (Status s = gltf_detail::pad_and_check_buffer(model); !s) return s.error();
    tinygltf::Mesh mesh;
    mesh.primitives.push_back(std::move(primitive));
    gltf_detail::add_single_mesh_scene(model, std::move(mesh));
    return gltf_detail::serialise(model, /*binary=*/true);
}

}  // namespace

Result<std::string> write_points_glb(const PointCloud& cloud, const PointGlbOptions& options) {
    return gltf_detail::guarded([&] { return write_unchecked(cloud, options); }, "GLB");
}

}  // namespace surfaced
