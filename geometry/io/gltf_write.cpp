// GLB writer: one scene / node / mesh / TRIANGLES primitive, optionally KHR_draco_mesh_compression.
// Steps: validate -> triangulate -> split vertices into glTF vertices (position, uv) -> attribute arrays ->
// Draco or plain buffer views -> tinygltf model -> GLB bytes.
// Conventions: glTF's texture origin is the top-left corner, OBJ's (and ours) bottom-left, so v is written as 1 - v
// (as obj2gltf and Blender do); read_glb undoes it.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>

#include "geometry/io/draco_codec.h"
#include "geometry/io/gltf.h"
#include "geometry/io/gltf_model.h"
#include "geometry/mesh/normals.h"
#include "geometry/mesh/triangulate.h"

namespace surfaced {

namespace {

constexpr const char* kDracoExtension = "KHR_draco_mesh_compression";
// Draco accepts up to 30 bits, but its encoder sizes entropy-coding tables by the largest quantized value, so time
// and memory double per bit whatever the mesh size (measured on 12 vertices: 24 bits 70 MB / 0.3 s, 26 bits 270 MB / 0.8 s,
// 30 bits 17 s and, extrapolated, ~4 GB): a denial of service for a server taking options from requests. 24 bits already match
// float32 precision over the bounding box. Normals use octahedral coding, 4x per bit (22 bits: 20 MB), and 22 bits
// resolve ~1e-6 rad, the precision of a float32 normal; Draco needs at least 2 bits there.
constexpr int kMaxQuantizationBits = 24;
constexpr int kMaxNormalBits = 22;

Status check_options(const GltfOptions& o) {
    auto out_of_range = [](const char* name, int value, int lo, int hi) {
        return make_error(ErrorCode::InvalidArgument, std::string(name) + " = " + std::to_string(value) +
                                                          " is out of range " + std::to_string(lo) + ".." +
                                                          std::to_string(hi));
    };
    if (o.quantize_position < 1 || o.quantize_position > kMaxQuantizationBits)
        return out_of_range("quantize_position", o.quantize_position, 1, kMaxQuantizationBits);
    if (o.quantize_normal < 2 || o.quantize_normal > kMaxNormalBits)
        return out_of_range("quantize_normal", o.quantize_normal, 2, kMaxNormalBits);
    if (o.quantize_texcoord < 1 || o.quantize_texcoord > kMaxQuantizationBits)
        return out_of_range("quantize_texcoord", o.quantize_texcoord, 1, kMaxQuantizationBits);
    if (o.encode_speed < 0 || o.encode_speed > 10) return out_of_range("encode_speed", o.encode_speed, 0, 10);
    if (o.decode_speed < 0 || o.decode_speed > 10) return out_of_range("decode_speed", o.decode_speed, 0, 10);
    return Ok{};
}

//! glTF attributes are per vertex, ours are face-varying for uvs: a glTF vertex is a (position, uv) pair. Sorting the
//! pairs keeps glTF vertices in position order, so read_glb's welding restores the original vertex order.
struct VertexSplit {
    std::vector<std::uint64_t> keys;     //!< unique (position << 32 | uv) pairs, sorted; one per glTF vertex
    std::vector<std::uint32_t> indices;  //!< per triangle corner: glTF vertex
};

VertexSplit split_vertices(const PolygonMesh& tri, bool with_uvs) {
    VertexSplit split;
    const std::size_t corners = tri.face_indices.size();
    auto key_of = [&](std::size_t c) {
        const std::uint64_t uv = with_uvs ? tri.uv_indices[c] : 0;
        return (static_cast<std::uint64_t>(tri.face_indices[c]) << 32) | uv;
    };
    split.keys.reserve(corners);
    for (std::size_t c = 0; c < corners; ++c) split.keys.push_back(key_of(c));
    std::sort(split.keys.begin(), split.keys.end());
    split.keys.erase(std::unique(split.keys.begin(), split.keys.end()), split.keys.end());
    split.indices.resize(corners);
    for (std::size_t c = 0; c < corners; ++c)
        split.indices[c] = static_cast<std::uint32_t>(
            std::lower_bound(split.keys.begin(), split.keys.end(), key_of(c)) - split.keys.begin());
    return split;
}

Vec3 unit_or_up(const Vec3& n) {
    const double len = norm(n);
    // The validator rejects non-unit normals; a zero or broken normal has no direction to keep.
    if (!(len > 1e-12) || !std::isfinite(len)) return {0, 0, 1};
    return n * (1.0 / len);
}

draco_codec::MeshData build_vertex_data(const PolygonMesh& mesh, const PolygonMesh& tri, const VertexSplit& split,
                                        bool with_normals, bool with_uvs, std::span<const Color> colors, bool alpha) {
    draco_codec::MeshData data;
    const std::size_t n = split.keys.size();
    data.positions.resize(n * 3);
    std::vector<Vec3> computed;
    const std::vector<Vec3>* normals = nullptr;
    if (with_normals) {
        if (mesh.has_normals()) {
            normals = &mesh.normals;
        } else {
            computed = compute_vertex_normals(mesh);  // on the polygons: same area weights as the triangles
            normals = &computed;
        }
        data.normals.resize(n * 3);
    }
    if (with_uvs) data.texcoords.resize(n * 2);
    data.color_components = alpha ? 4 : 3;
    if (!colors.empty()) data.colors.reserve(n * static_cast<std::size_t>(data.color_components));
    for (std::size_t i = 0; i < n; ++i) {
        const auto v = static_cast<std::size_t>(split.keys[i] >> 32);
        const Vec3& p = tri.positions[v];
        for (int k = 0; k < 3; ++k) data.positions[3 * i + static_cast<std::size_t>(k)] = static_cast<float>(p[k]);
        if (with_normals) {
            const Vec3 nrm = unit_or_up((*normals)[v]);
            for (int k = 0; k < 3; ++k) data.normals[3 * i + static_cast<std::size_t>(k)] = static_cast<float>(nrm[k]);
        }
        if (with_uvs) {
            const Vec2& uv = tri.uvs[static_cast<std::size_t>(split.keys[i] & 0xffffffffu)];
            data.texcoords[2 * i] = static_cast<float>(uv.x);
            data.texcoords[2 * i + 1] = static_cast<float>(1.0 - uv.y);
        }
        if (!colors.empty()) {
            const Color& c = colors[v];
            const auto channel = [](float x) { return std::isfinite(x) ? std::clamp(x, 0.0f, 1.0f) : 0.0f; };
            data.colors.insert(data.colors.end(), {channel(c.r), channel(c.g), channel(c.b)});
            if (alpha) data.colors.push_back(channel(c.a));
        }
    }
    data.indices = split.indices;
    return data;
}

void min_max(const std::vector<float>& values, int components, std::vector<double>& lo, std::vector<double>& hi) {
    lo.assign(static_cast<std::size_t>(components), std::numeric_limits<double>::infinity());
    hi.assign(static_cast<std::size_t>(components), -std::numeric_limits<double>::infinity());
    for (std::size_t i = 0; i < values.size(); ++i) {
        const std::size_t k = i % static_cast<std::size_t>(components);
        lo[k] = std::min(lo[k], static_cast<double>(values[i]));
        hi[k] = std::max(hi[k], static_cast<double>(values[i]));
    }
}

//! Appends `bytes` to the single buffer at a 4-byte boundary (accessor alignment rule) and returns the view index.
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
                 std::vector<double> lo = {}, std::vector<double> hi = {}, bool normalized = false) {
    tinygltf::Accessor accessor;
    accessor.bufferView = view;  // -1 for Draco: the data comes from the extension
    accessor.componentType = component_type;
    accessor.normalized = normalized;
    accessor.type = type;
    accessor.count = count;
    accessor.minValues = std::move(lo);
    accessor.maxValues = std::move(hi);
    model.accessors.push_back(std::move(accessor));
    return static_cast<int>(model.accessors.size() - 1);
}

//! Index accessor data in the narrowest type glTF allows for this vertex count. 0xFFFF / 0xFFFFFFFF are primitive
//! restart values, which the validator rejects as indices: hence "< 65536 vertices" (max index 65534).
int index_component_type(std::size_t vertex_count) {
    return vertex_count < 65536 ? TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT : TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
}

Status add_draco_primitive(tinygltf::Model& model, tinygltf::Primitive& primitive, const draco_codec::MeshData& data,
                           const GltfOptions& options) {
    draco_codec::EncodeOptions encode_options;
    encode_options.quantize_position = options.quantize_position;
    encode_options.quantize_normal = options.quantize_normal;
    encode_options.quantize_texcoord = options.quantize_texcoord;
    encode_options.encode_speed = options.encode_speed;
    encode_options.decode_speed = options.decode_speed;
    auto encoded = draco_codec::encode(data, encode_options);
    if (!encoded) return encoded.error();

    // Accessors describe the *decoded* data (counts, POSITION min/max after quantization), and Draco may reorder
    // or split points, so decode what we wrote instead of guessing. This also proves the payload decodes.
    const auto* payload = reinterpret_cast<const std::uint8_t*>(encoded->bytes.data());
    draco_codec::DecodeLimits limits;
    limits.max_points = std::numeric_limits<std::uint32_t>::max() - 1;
    limits.max_triangles = std::numeric_limits<std::uint32_t>::max() / 3;
    auto decoded = draco_codec::decode({payload, encoded->bytes.size()}, encoded->ids, limits);
    if (!decoded)
        return make_error(ErrorCode::Internal,
                          "Draco round trip of the written mesh failed: " + decoded.error().message);
    const std::size_t points = decoded->point_count();

    const int view = add_buffer_view(model, encoded->bytes.data(), encoded->bytes.size(), 0);
    tinygltf::Value::Object attribute_ids;
    std::vector<double> lo, hi;
    min_max(decoded->positions, 3, lo, hi);
    primitive.attributes["POSITION"] =
        add_accessor(model, -1, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, points, lo, hi);
    attribute_ids["POSITION"] = tinygltf::Value(encoded->ids.position);
    if (encoded->ids.normal >= 0) {
        primitive.attributes["NORMAL"] =
            add_accessor(model, -1, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, points);
        attribute_ids["NORMAL"] = tinygltf::Value(encoded->ids.normal);
    }
    if (encoded->ids.texcoord >= 0) {
        primitive.attributes["TEXCOORD_0"] =
            add_accessor(model, -1, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, points);
        attribute_ids["TEXCOORD_0"] = tinygltf::Value(encoded->ids.texcoord);
    }
    if (encoded->ids.color >= 0) {
        primitive.attributes["COLOR_0"] =
            add_accessor(model, -1, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                         data.color_components == 4 ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3, points, {}, {}, true);
        attribute_ids["COLOR_0"] = tinygltf::Value(encoded->ids.color);
    }
    primitive.indices =
        add_accessor(model, -1, index_component_type(points), TINYGLTF_TYPE_SCALAR, decoded->indices.size());

    tinygltf::Value::Object extension;
    extension["bufferView"] = tinygltf::Value(view);
    extension["attributes"] = tinygltf::Value(std::move(attribute_ids));
    primitive.extensions[kDracoExtension] = tinygltf::Value(std::move(extension));
    model.extensionsUsed.push_back(kDracoExtension);
    model.extensionsRequired.push_back(kDracoExtension);  // no uncompressed fallback is written
    return Ok{};
}

void add_plain_primitive(tinygltf::Model& model, tinygltf::Primitive& primitive, const draco_codec::MeshData& data) {
    const std::size_t points = data.point_count();
    std::vector<double> lo, hi;
    min_max(data.positions, 3, lo, hi);
    int view = add_buffer_view(model, data.positions.data(), data.positions.size() * sizeof(float),
                               TINYGLTF_TARGET_ARRAY_BUFFER);
    primitive.attributes["POSITION"] =
        add_accessor(model, view, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, points, lo, hi);
    if (!data.normals.empty()) {
        view = add_buffer_view(model, data.normals.data(), data.normals.size() * sizeof(float),
                               TINYGLTF_TARGET_ARRAY_BUFFER);
        primitive.attributes["NORMAL"] =
            add_accessor(model, view, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, points);
    }
    if (!data.texcoords.empty()) {
        view = add_buffer_view(model, data.texcoords.data(), data.texcoords.size() * sizeof(float),
                               TINYGLTF_TARGET_ARRAY_BUFFER);
        primitive.attributes["TEXCOORD_0"] =
            add_accessor(model, view, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, points);
    }
    if (!data.colors.empty()) {
        view = add_buffer_view(model, data.colors.data(), data.colors.size() * sizeof(float),
                               TINYGLTF_TARGET_ARRAY_BUFFER);
        primitive.attributes["COLOR_0"] =
            add_accessor(model, view, TINYGLTF_COMPONENT_TYPE_FLOAT,
                         data.color_components == 4 ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3, points);
    }
    const int index_type = index_component_type(points);
    if (index_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
        std::vector<std::uint16_t> narrow(data.indices.begin(), data.indices.end());
        view = add_buffer_view(model, narrow.data(), narrow.size() * sizeof(std::uint16_t),
                               TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    } else {
        view = add_buffer_view(model, data.indices.data(), data.indices.size() * sizeof(std::uint32_t),
                               TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    }
    primitive.indices = add_accessor(model, view, index_type, TINYGLTF_TYPE_SCALAR, data.indices.size());
}

Result<std::string> write_glb_unchecked(const PolygonMesh& mesh, const GltfOptions& options) {
    if (Status s = check_options(options); !s) return s.error();
    if (mesh.positions.empty() || mesh.face_count() == 0)
        return make_error(ErrorCode::InvalidArgument, "cannot write an empty mesh to glTF (no vertices or no faces)");
    if (Status s = validate(mesh); !s) return s.error();
    if (!options.vertex_colors.empty() && options.vertex_colors.size() != mesh.positions.size())
        return make_error(ErrorCode::InvalidArgument, std::to_string(options.vertex_colors.size()) +
                                                          " vertex colours for " +
                                                          std::to_string(mesh.positions.size()) + " vertices");

    // triangulate
    const PolygonMesh tri = triangulate(mesh);
    // Index values must stay below the uint32 primitive-restart value and counts must fit glTF's uint32 fields.
    if (tri.face_indices.size() >= std::numeric_limits<std::uint32_t>::max() ||
        tri.positions.size() >= std::numeric_limits<std::uint32_t>::max() - 1)
        return make_error(ErrorCode::BudgetExceeded,
                          "mesh too large for glTF: " + std::to_string(tri.face_indices.size()) + " triangle corners");

    // glTF vertices and attributes
    const bool with_uvs = options.texcoords && tri.has_uvs();
    const VertexSplit split = split_vertices(tri, with_uvs);
    const draco_codec::MeshData data =
        build_vertex_data(mesh, tri, split, options.normals, with_uvs, options.vertex_colors, options.vertex_alpha);

    // model
    tinygltf::Model model;
    model.asset.version = "2.0";
    model.asset.generator = "surfaced";
    model.buffers.emplace_back();
    tinygltf::Primitive primitive;
    primitive.mode = TINYGLTF_MODE_TRIANGLES;
    if (options.draco) {
        if (Status s = add_draco_primitive(model, primitive, data, options); !s) return s.error();
    } else {
        add_plain_primitive(model, primitive, data);
    }
    if (Status s = gltf_detail::pad_and_check_buffer(model); !s) return s.error();
    tinygltf::Mesh gltf_mesh;
    gltf_mesh.primitives.push_back(std::move(primitive));
    gltf_detail::add_single_mesh_scene(model, std::move(gltf_mesh));
    return gltf_detail::serialise(model, /*binary=*/true);
}

}  // namespace

Result<std::string> write_glb(const PolygonMesh& mesh, const GltfOptions& options) {
    return gltf_detail::guarded([&] { return write_glb_unchecked(mesh, options); }, "GLB");
}

}  // namespace surfaced
