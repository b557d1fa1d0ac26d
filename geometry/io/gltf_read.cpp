// glTF readers: GLB, and glTF JSON (.gltf) with its buffers embedded as base64 data: URIs, both through the same
// scene path. Input is untrusted (it arrives over HTTP), so every step checks before it trusts:
//  - the GLB container is checked first, with byte offsets in the errors (a .gltf is the JSON alone);
//  - the JSON chunk is parsed with nlohmann::json into a small document model here, every field type-checked and
//    every cross-reference range-checked, with the JSON path in the error ("accessors[3].count"). tinygltf is not
//    used for reading: 2.7.0 rejects Draco primitives (index accessors without bufferView) unless its own Draco
//    decoding is compiled in, and that code indexes buffer views and attribute arrays without bounds checks;
//  - GLB buffers must come from the BIN chunk, .gltf buffers from data: URIs (strict base64, data_uri.h); any other
//    URI (a file name, a URL) is Unsupported and nothing is ever opened or fetched;
//  - every accessor is checked against its buffer view and the view against the buffer, every index against its
//    vertex count, and the ReadOptions limits are applied to announced counts before anything is allocated.
// Steps: container (GLB) -> document -> extensionsRequired -> node world transforms -> primitives (plain or Draco;
// points and lines skipped and counted) -> weld by position -> PolygonMesh.
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <optional>
#include <unordered_map>

#include <nlohmann/json.hpp>

#include "geometry/io/data_uri.h"
#include "geometry/io/draco_codec.h"
#include "geometry/io/gltf.h"

namespace surfaced {

namespace {

using nlohmann::json;

constexpr std::uint32_t kGlbMagic = 0x46546C67;   // "glTF"
constexpr std::uint32_t kChunkJson = 0x4E4F534A;  // "JSON"
constexpr std::uint32_t kChunkBin = 0x004E4942;   // "BIN\0"
constexpr std::int64_t kJsonOffset = 20;          // where the JSON text starts in a GLB
constexpr const char* kDracoExtension = "KHR_draco_mesh_compression";
constexpr const char* kQuantizationExtension = "KHR_mesh_quantization";

// glTF enums
constexpr int kByte = 5120, kUnsignedByte = 5121, kShort = 5122, kUnsignedShort = 5123, kUnsignedInt = 5125,
              kFloat = 5126;
constexpr int kModeTriangles = 4, kModeTriangleStrip = 5, kModeTriangleFan = 6;

std::uint32_t read_u32(std::string_view bytes, std::size_t offset) {
    std::uint32_t v = 0;
    for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(bytes[offset + static_cast<std::size_t>(i)]);
    return v;
}

GeoError parse_error(std::string message, std::int64_t offset = -1) {
    return make_error(ErrorCode::ParseError, std::move(message), -1, offset);
}

// ---- container ---------------------------------------------------------------------------------------------------

struct Chunks {
    std::string_view json;
    std::string_view bin;  //!< empty when the GLB has no BIN chunk
};

Result<Chunks> split_container(std::string_view bytes) {
    if (bytes.size() < 12)
        return parse_error("not a GLB: " + std::to_string(bytes.size()) + " bytes, the header alone needs 12", 0);
    if (read_u32(bytes, 0) != kGlbMagic) return parse_error("not a GLB: bad magic (expected \"glTF\")", 0);
    if (const std::uint32_t version = read_u32(bytes, 4); version != 2)
        return make_error(ErrorCode::Unsupported, "GLB version " + std::to_string(version) + " (only 2 is supported)",
                          -1, 4);
    const std::size_t length = read_u32(bytes, 8);
    if (length > bytes.size())
        return parse_error("truncated GLB: header declares " + std::to_string(length) + " bytes but only " +
                               std::to_string(bytes.size()) + " are present",
                           8);
    if (length < 20)
        return parse_error("GLB length " + std::to_string(length) + " leaves no room for the JSON chunk", 8);
    const std::size_t json_length = read_u32(bytes, 12);
    if (read_u32(bytes, 16) != kChunkJson) return parse_error("first GLB chunk is not JSON", 16);
    if (json_length == 0 || json_length > length - 20)
        return parse_error("JSON chunk length " + std::to_string(json_length) + " exceeds the GLB (" +
                               std::to_string(length - 20) + " bytes available)",
                           12);
    Chunks chunks;
    chunks.json = bytes.substr(20, json_length);
    // Chunks start on 4-byte boundaries; the JSON chunk's padding is part of its length.
    const std::size_t bin_offset = 20 + json_length;
    if (bin_offset < length) {
        if (length - bin_offset < 8)
            return parse_error("truncated chunk header after the JSON chunk", static_cast<std::int64_t>(bin_offset));
        const std::size_t bin_length = read_u32(bytes, bin_offset);
        if (bin_length > length - bin_offset - 8)
            return parse_error("BIN chunk length " + std::to_string(bin_length) + " exceeds the GLB (" +
                                   std::to_string(length - bin_offset - 8) + " bytes available)",
                               static_cast<std::int64_t>(bin_offset));
        // Chunks of unknown type after the JSON must be ignored (spec); only a BIN chunk there carries data.
        if (read_u32(bytes, bin_offset + 4) == kChunkBin) chunks.bin = bytes.substr(bin_offset + 8, bin_length);
    }
    return chunks;
}

//! What the scene reader reads: the glTF JSON, and where its buffers' bytes are.
struct SceneInput {
    std::string_view json;
    std::int64_t json_offset = 0;  //!< where `json` starts in the input, for error offsets
    std::string_view bin;          //!< GLB: the BIN chunk (buffer 0)
    bool embedded = false;         //!< .gltf: every buffer is a base64 data: URI
    const char* kind = "GLB";      //!< names the input in messages
};

// ---- document model --------------------------------------------------------------------------------------------
// Only what geometry needs, every index already range-checked against its array.

struct Accessor {
    int buffer_view = -1;  //!< -1: all zeros (or data from Draco)
    std::uint64_t byte_offset = 0;
    int component_type = 0;
    int components = 0;
    std::uint64_t count = 0;
    bool normalized = false;
    bool sparse = false;
};

struct BufferView {
    std::uint64_t byte_offset = 0;
    std::uint64_t byte_length = 0;
    std::uint64_t byte_stride = 0;
    std::span<const unsigned char> bytes;  //!< the view's bytes, bounds already checked against its buffer
};

struct DracoPrimitive {
    int buffer_view = -1;
    std::map<std::string, int> attributes;  //!< semantic -> Draco unique id
};

struct Primitive {
    std::map<std::string, int> attributes;  //!< semantic -> accessor
    int indices = -1;
    int mode = kModeTriangles;
    std::optional<DracoPrimitive> draco;
};

using Mat4 = std::array<double, 16>;  // column-major, as glTF stores it
constexpr Mat4 kIdentity{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

struct Node {
    int mesh = -1;
    std::vector<int> children;
    Mat4 local = kIdentity;
};

struct Document {
    std::vector<Accessor> accessors;
    std::vector<BufferView> views;
    std::vector<std::vector<Primitive>> meshes;
    std::vector<Node> nodes;
    std::vector<std::vector<int>> scenes;
    int scene = -1;
    std::vector<std::string> extensions_required;
    std::vector<std::string> extensions_used;
    std::int64_t json_offset = 0;  //!< where the JSON text starts in the input: the offset of document errors
};

//! Typed field access with the JSON path in every error.
class Fields {
public:
    Fields(const json& object, std::string path, std::int64_t json_offset)
        : object_(object), path_(std::move(path)), json_offset_(json_offset) {}

    const std::string& path() const { return path_; }
    std::int64_t json_offset() const { return json_offset_; }
    const json* find(const char* key) const {
        auto it = object_.find(key);
        return it == object_.end() ? nullptr : &*it;
    }
    GeoError error(const char* key, const std::string& what) const {
        return parse_error("glTF " + path_ + "." + key + " " + what, json_offset_);
    }

    //! Non-negative integer; `fallback` when absent, error when absent and `fallback` is empty.
    Result<std::uint64_t> uint(const char* key, std::optional<std::uint64_t> fallback = std::nullopt) const {
        const json* v = find(key);
        if (!v) {
            if (fallback) return *fallback;
            return error(key, "is missing");
        }
        if (v->is_number_unsigned()) return v->get<std::uint64_t>();
        if (v->is_number_integer()) return error(key, "must not be negative");
        return error(key, "must be an integer");
    }
    //! An index into an array of `size` elements; -1 when absent and optional.
    Result<int> index(const char* key, std::size_t size, bool required = false) const {
        if (!find(key)) {
            if (required) return error(key, "is missing");
            return -1;
        }
        auto v = uint(key);
        if (!v) return v.error();
        if (*v >= size)
            return error(key, "= " + std::to_string(*v) + " is out of range (" + std::to_string(size) + " elements)");
        return static_cast<int>(*v);
    }
    Result<std::vector<double>> numbers(const char* key, std::size_t expected) const {
        std::vector<double> out;
        const json* v = find(key);
        if (!v) return out;
        if (!v->is_array() || v->size() != expected)
            return error(key, "must be an array of " + std::to_string(expected) + " numbers");
        for (const json& x : *v) {
            if (!x.is_number()) return error(key, "must be an array of " + std::to_string(expected) + " numbers");
            out.push_back(x.get<double>());
        }
        return out;
    }

private:
    const json& object_;
    std::string path_;
    std::int64_t json_offset_;
};

//! The named top-level array (absent = empty); each element must be an object.
Result<const json*> array_of_objects(const json& root, const char* key, std::int64_t json_offset) {
    static const json kEmpty = json::array();
    auto it = root.find(key);
    if (it == root.end()) return &kEmpty;
    if (!it->is_array()) return parse_error(std::string("glTF ") + key + " must be an array", json_offset);
    for (std::size_t i = 0; i < it->size(); ++i)
        if (!(*it)[i].is_object())
            return parse_error("glTF " + std::string(key) + "[" + std::to_string(i) + "] must be an object",
                               json_offset);
    return &*it;
}

Result<std::vector<std::string>> string_list(const json& root, const char* key, std::int64_t json_offset) {
    std::vector<std::string> out;
    auto it = root.find(key);
    if (it == root.end()) return out;
    if (!it->is_array()) return parse_error(std::string("glTF ") + key + " must be an array of strings", json_offset);
    for (const json& s : *it) {
        if (!s.is_string())
            return parse_error(std::string("glTF ") + key + " must be an array of strings", json_offset);
        out.push_back(s.get<std::string>());
    }
    return out;
}

int component_size(int component_type) {
    switch (component_type) {
        case kByte:
        case kUnsignedByte: return 1;
        case kShort:
        case kUnsignedShort: return 2;
        case kUnsignedInt:
        case kFloat: return 4;
        default: return 0;
    }
}

int component_count(const std::string& type) {
    if (type == "SCALAR") return 1;
    if (type == "VEC2") return 2;
    if (type == "VEC3") return 3;
    if (type == "VEC4") return 4;
    return 0;  // matrices: never a geometry attribute we read
}

//! A GLB buffer: buffer 0 without a uri is the BIN chunk; a uri is refused, never opened (nor decoded: a GLB keeps
//! its data in the BIN chunk).
Result<std::span<const unsigned char>> glb_buffer(const Fields& f, std::size_t index, std::string_view bin) {
    if (const json* uri = f.find("uri")) {
        const std::string text = uri->is_string() ? uri->get<std::string>() : std::string("(not a string)");
        if (text.rfind("data:", 0) == 0)
            return make_error(ErrorCode::Unsupported,
                              "glTF " + f.path() +
                                  " is a base64 data URI: only data in "
                                  "the GLB's BIN chunk is supported",
                              -1, f.json_offset());
        // Never opened: a server must not read files named by its input.
        return make_error(ErrorCode::Unsupported,
                          "glTF " + f.path() + " refers to an external resource \"" + text.substr(0, 200) +
                              "\": only self-contained GLB files (data in the BIN chunk) "
                              "are supported",
                          -1, f.json_offset());
    }
    if (index != 0) return f.error("uri", "is missing: only buffer 0 can live in the GLB's BIN chunk");
    auto length = f.uint("byteLength");
    if (!length) return length.error();
    if (*length > bin.size())
        return f.error("byteLength", "= " + std::to_string(*length) + " exceeds the BIN chunk (" +
                                         std::to_string(bin.size()) + " bytes)");
    return std::span<const unsigned char>(reinterpret_cast<const unsigned char*>(bin.data()),
                                          static_cast<std::size_t>(*length));
}

//! What a uri that is not a data: URI names, for the refusal: nothing it names is ever opened or fetched.
std::string external_uri_error(const Fields& f, const std::string& uri, const char* what) {
    const bool url = uri.find("://") != std::string::npos;
    return "glTF " + f.path() + ".uri \"" + uri.substr(0, 200) + "\" is " + (url ? "a URL" : "an external file") +
           ": embed the " + what + " (data: URI) or send a GLB";
}

//! A .gltf buffer: its base64 data: URI decoded into `storage` (3/4 of the URI's length, so bounded by the input).
Result<std::span<const unsigned char>> embedded_buffer(const Fields& f,
                                                       std::vector<std::vector<unsigned char>>& storage) {
    const json* uri = f.find("uri");
    if (!uri) return f.error("uri", "is missing: a .gltf's buffers must be embedded as data: URIs (or send a GLB)");
    if (!uri->is_string()) return f.error("uri", "must be a string");
    const std::string& text = uri->get_ref<const std::string&>();
    if (!io_detail::is_data_uri(text))
        return make_error(ErrorCode::Unsupported, external_uri_error(f, text, "buffer"), -1, f.json_offset());
    auto bytes = io_detail::decode_data_uri(text, {"application/octet-stream", "application/gltf-buffer"});
    if (!bytes) {
        GeoError error = bytes.error();
        error.message = "glTF " + f.path() + ".uri: " + error.message;
        error.offset = f.json_offset();
        return error;
    }
    auto length = f.uint("byteLength");
    if (!length) return length.error();
    if (*length > bytes->size())
        return f.error("byteLength", "= " + std::to_string(*length) + " exceeds its data: URI (" +
                                         std::to_string(bytes->size()) + " bytes)");
    // The outer vector may move its elements; their heap blocks, which the span points into, stay where they are.
    storage.push_back(std::move(*bytes));
    return std::span<const unsigned char>(storage.back().data(), static_cast<std::size_t>(*length));
}

//! A .gltf's images may be embedded (and are ignored, as in a GLB); one named by a path or URL is refused.
Status check_images_embedded(const json& root, std::int64_t json_offset) {
    auto images = array_of_objects(root, "images", json_offset);
    if (!images) return images.error();
    for (std::size_t i = 0; i < (*images)->size(); ++i) {
        const Fields f((**images)[i], "images[" + std::to_string(i) + "]", json_offset);
        const json* uri = f.find("uri");
        if (!uri) continue;  // in a buffer view
        if (!uri->is_string()) return f.error("uri", "must be a string");
        const std::string& text = uri->get_ref<const std::string&>();
        if (!io_detail::is_data_uri(text))
            return make_error(ErrorCode::Unsupported, external_uri_error(f, text, "image"), -1, json_offset);
    }
    return Ok{};
}

Status parse_buffers_and_views(const json& root, const SceneInput& input,
                               std::vector<std::vector<unsigned char>>& storage, Document& doc) {
    auto buffers = array_of_objects(root, "buffers", doc.json_offset);
    if (!buffers) return buffers.error();
    std::vector<std::span<const unsigned char>> buffer_bytes;
    for (std::size_t i = 0; i < (*buffers)->size(); ++i) {
        const Fields f((**buffers)[i], "buffers[" + std::to_string(i) + "]", doc.json_offset);
        auto bytes = input.embedded ? embedded_buffer(f, storage) : glb_buffer(f, i, input.bin);
        if (!bytes) return bytes.error();
        buffer_bytes.push_back(*bytes);
    }

    auto views = array_of_objects(root, "bufferViews", doc.json_offset);
    if (!views) return views.error();
    for (std::size_t i = 0; i < (*views)->size(); ++i) {
        const Fields f((**views)[i], "bufferViews[" + std::to_string(i) + "]", doc.json_offset);
        BufferView view;
        auto buffer = f.index("buffer", buffer_bytes.size(), true);
        auto offset = f.uint("byteOffset", 0);
        auto length = f.uint("byteLength");
        auto stride = f.uint("byteStride", 0);
        if (!buffer) return buffer.error();
        if (!offset) return offset.error();
        if (!length) return length.error();
        if (!stride) return stride.error();
        const auto data = buffer_bytes[static_cast<std::size_t>(*buffer)];
        if (*offset > data.size() || *length > data.size() - *offset)
            return parse_error("glTF " + f.path() + " (byteOffset " + std::to_string(*offset) + ", byteLength " +
                                   std::to_string(*length) + ") exceeds buffer " + std::to_string(*buffer) + " (" +
                                   std::to_string(data.size()) + " bytes)",
                               doc.json_offset);
        view.byte_offset = *offset;
        view.byte_length = *length;
        view.byte_stride = *stride;
        view.bytes = data.subspan(static_cast<std::size_t>(*offset), static_cast<std::size_t>(*length));
        doc.views.push_back(view);
    }
    return Ok{};
}

Status parse_accessors(const json& root, Document& doc) {
    auto accessors = array_of_objects(root, "accessors", doc.json_offset);
    if (!accessors) return accessors.error();
    for (std::size_t i = 0; i < (*accessors)->size(); ++i) {
        const json& a = (**accessors)[i];
        const Fields f(a, "accessors[" + std::to_string(i) + "]", doc.json_offset);
        Accessor acc;
        auto view = f.index("bufferView", doc.views.size());
        auto offset = f.uint("byteOffset", 0);
        auto type = f.uint("componentType");
        auto count = f.uint("count");
        if (!view) return view.error();
        if (!offset) return offset.error();
        if (!type) return type.error();
        if (!count) return count.error();
        acc.buffer_view = *view;
        acc.byte_offset = *offset;
        acc.component_type = static_cast<int>(std::min<std::uint64_t>(*type, 1u << 30));
        acc.count = *count;
        const json* t = f.find("type");
        if (!t || !t->is_string()) return f.error("type", "must be a string");
        acc.components = component_count(t->get<std::string>());
        if (const json* n = f.find("normalized")) {
            if (!n->is_boolean()) return f.error("normalized", "must be a boolean");
            acc.normalized = n->get<bool>();
        }
        acc.sparse = f.find("sparse") != nullptr;
        doc.accessors.push_back(acc);
    }
    return Ok{};
}

Result<std::map<std::string, int>> index_map(const Fields& f, const char* key, std::size_t size) {
    std::map<std::string, int> out;
    const json* m = f.find(key);
    if (!m || !m->is_object()) return f.error(key, "must be an object");
    for (auto it = m->begin(); it != m->end(); ++it) {
        if (!it.value().is_number_unsigned() || it.value().get<std::uint64_t>() >= size)
            return f.error(key, "." + it.key() + " must be an index below " + std::to_string(size));
        out[it.key()] = static_cast<int>(it.value().get<std::uint64_t>());
    }
    return out;
}

Status parse_meshes(const json& root, Document& doc) {
    auto meshes = array_of_objects(root, "meshes", doc.json_offset);
    if (!meshes) return meshes.error();
    for (std::size_t m = 0; m < (*meshes)->size(); ++m) {
        const json& mesh = (**meshes)[m];
        auto prims = mesh.find("primitives");
        if (prims == mesh.end() || !prims->is_array())
            return parse_error("glTF meshes[" + std::to_string(m) + "].primitives must be an array", doc.json_offset);
        std::vector<Primitive> out;
        for (std::size_t p = 0; p < prims->size(); ++p) {
            const json& pj = (*prims)[p];
            const std::string path = "meshes[" + std::to_string(m) + "].primitives[" + std::to_string(p) + "]";
            if (!pj.is_object()) return parse_error("glTF " + path + " must be an object", doc.json_offset);
            const Fields f(pj, path, doc.json_offset);
            Primitive prim;
            auto attributes = index_map(f, "attributes", doc.accessors.size());
            auto indices = f.index("indices", doc.accessors.size());
            auto mode = f.uint("mode", kModeTriangles);
            if (!attributes) return attributes.error();
            if (!indices) return indices.error();
            if (!mode) return mode.error();
            prim.attributes = std::move(*attributes);
            prim.indices = *indices;
            prim.mode = static_cast<int>(std::min<std::uint64_t>(*mode, 255));
            if (const json* ext = f.find("extensions"); ext && ext->is_object()) {
                auto d = ext->find(kDracoExtension);
                if (d != ext->end()) {
                    if (!d->is_object())
                        return parse_error("glTF " + path + ".extensions." + kDracoExtension + " must be an object",
                                           doc.json_offset);
                    const Fields df(*d, path + ".extensions." + kDracoExtension, doc.json_offset);
                    DracoPrimitive draco;
                    auto view = df.index("bufferView", doc.views.size(), true);
                    auto ids = index_map(df, "attributes", std::numeric_limits<std::uint32_t>::max());
                    if (!view) return view.error();
                    if (!ids) return ids.error();
                    draco.buffer_view = *view;
                    draco.attributes = std::move(*ids);
                    prim.draco = std::move(draco);
                }
            }
            out.push_back(std::move(prim));
        }
        doc.meshes.push_back(std::move(out));
    }
    return Ok{};
}

Result<Mat4> local_matrix(const Fields& f) {
    auto matrix = f.numbers("matrix", 16);
    if (!matrix) return matrix.error();
    if (!matrix->empty()) {
        Mat4 m;
        std::copy(matrix->begin(), matrix->end(), m.begin());
        return m;
    }
    auto t = f.numbers("translation", 3);
    auto r = f.numbers("rotation", 4);
    auto s = f.numbers("scale", 3);
    if (!t) return t.error();
    if (!r) return r.error();
    if (!s) return s.error();
    // M = T * R * S, rotation as a unit quaternion (x, y, z, w)
    const double tx = t->empty() ? 0 : (*t)[0], ty = t->empty() ? 0 : (*t)[1], tz = t->empty() ? 0 : (*t)[2];
    double x = 0, y = 0, z = 0, w = 1;
    if (!r->empty()) {
        x = (*r)[0], y = (*r)[1], z = (*r)[2], w = (*r)[3];
        const double len = std::sqrt(x * x + y * y + z * z + w * w);
        if (len > 0) x /= len, y /= len, z /= len, w /= len;
    }
    const double sx = s->empty() ? 1 : (*s)[0], sy = s->empty() ? 1 : (*s)[1], sz = s->empty() ? 1 : (*s)[2];
    return Mat4{(1 - 2 * (y * y + z * z)) * sx,
                2 * (x * y + z * w) * sx,
                2 * (x * z - y * w) * sx,
                0,
                2 * (x * y - z * w) * sy,
                (1 - 2 * (x * x + z * z)) * sy,
                2 * (y * z + x * w) * sy,
                0,
                2 * (x * z + y * w) * sz,
                2 * (y * z - x * w) * sz,
                (1 - 2 * (x * x + y * y)) * sz,
                0,
                tx,
                ty,
                tz,
                1};
}

Status parse_nodes_and_scenes(const json& root, Document& doc) {
    auto nodes = array_of_objects(root, "nodes", doc.json_offset);
    if (!nodes) return nodes.error();
    const std::size_t n = (*nodes)->size();
    for (std::size_t i = 0; i < n; ++i) {
        const Fields f((**nodes)[i], "nodes[" + std::to_string(i) + "]", doc.json_offset);
        Node node;
        auto mesh = f.index("mesh", doc.meshes.size());
        if (!mesh) return mesh.error();
        node.mesh = *mesh;
        auto local = local_matrix(f);
        if (!local) return local.error();
        node.local = *local;
        if (const json* children = f.find("children")) {
            if (!children->is_array()) return f.error("children", "must be an array");
            for (const json& c : *children) {
                if (!c.is_number_unsigned() || c.get<std::uint64_t>() >= n)
                    return f.error("children", "must hold node indices below " + std::to_string(n));
                node.children.push_back(static_cast<int>(c.get<std::uint64_t>()));
            }
        }
        doc.nodes.push_back(std::move(node));
    }
    auto scenes = array_of_objects(root, "scenes", doc.json_offset);
    if (!scenes) return scenes.error();
    for (std::size_t s = 0; s < (*scenes)->size(); ++s) {
        const Fields f((**scenes)[s], "scenes[" + std::to_string(s) + "]", doc.json_offset);
        std::vector<int> roots;
        if (const json* list = f.find("nodes")) {
            if (!list->is_array()) return f.error("nodes", "must be an array");
            for (const json& r : *list) {
                if (!r.is_number_unsigned() || r.get<std::uint64_t>() >= n)
                    return f.error("nodes", "must hold node indices below " + std::to_string(n));
                roots.push_back(static_cast<int>(r.get<std::uint64_t>()));
            }
        }
        doc.scenes.push_back(std::move(roots));
    }
    auto scene = Fields(root, "", doc.json_offset).index("scene", doc.scenes.size());
    if (!scene) return scene.error();
    doc.scene = *scene;
    return Ok{};
}

//! The document, its buffers resolved: GLB buffers point into the input, .gltf ones into `storage`.
Result<Document> parse_document(const SceneInput& input, std::vector<std::vector<unsigned char>>& storage) {
    // The spec pads with spaces; some exporters pad with NUL bytes, which are not JSON whitespace.
    std::string_view text = input.json;
    while (!text.empty() && text.back() == '\0') text.remove_suffix(1);
    json root;
    try {
        root = json::parse(text.begin(), text.end());
    } catch (const json::parse_error& e) {
        // e.byte is 1-based within the JSON text.
        const auto at = input.json_offset + static_cast<std::int64_t>(e.byte > 0 ? e.byte - 1 : 0);
        return parse_error(
            std::string(input.embedded ? "invalid glTF JSON" : "invalid JSON chunk") + " at byte " + std::to_string(at),
            at);
    } catch (const json::out_of_range&) {  // a number beyond a double; nlohmann gives no position
        return parse_error(std::string(input.embedded ? "glTF JSON" : "the JSON chunk") +
                               " holds a number beyond the range of a double",
                           input.json_offset);
    }
    if (!root.is_object()) return parse_error("glTF JSON must be an object", input.json_offset);
    const auto asset = root.find("asset");
    if (asset == root.end() || !asset->is_object() || !asset->contains("version") || !(*asset)["version"].is_string())
        return parse_error("glTF asset.version is missing", input.json_offset);
    const std::string version = (*asset)["version"].get<std::string>();
    if (version.rfind("2.", 0) != 0)
        return make_error(ErrorCode::Unsupported, "glTF version " + version + " (need 2.x)");

    Document doc;
    doc.json_offset = input.json_offset;
    auto required = string_list(root, "extensionsRequired", doc.json_offset);
    auto used = string_list(root, "extensionsUsed", doc.json_offset);
    if (!required) return required.error();
    if (!used) return used.error();
    doc.extensions_required = std::move(*required);
    doc.extensions_used = std::move(*used);
    if (Status s = parse_buffers_and_views(root, input, storage, doc); !s) return s.error();
    if (input.embedded)
        if (Status s = check_images_embedded(root, doc.json_offset); !s) return s.error();
    if (Status s = parse_accessors(root, doc); !s) return s.error();
    if (Status s = parse_meshes(root, doc); !s) return s.error();
    if (Status s = parse_nodes_and_scenes(root, doc); !s) return s.error();
    return doc;
}

// ---- accessor data -----------------------------------------------------------------------------------------------

//! One component as a double; normalized integers map to [0, 1] / [-1, 1] as the glTF spec defines.
double load_component(const unsigned char* p, int component_type, bool normalized) {
    switch (component_type) {
        case kFloat: {
            float f;
            std::memcpy(&f, p, 4);
            return f;
        }
        case kUnsignedByte: return normalized ? p[0] / 255.0 : p[0];
        case kByte: {
            const auto v = static_cast<std::int8_t>(p[0]);
            return normalized ? std::max(v / 127.0, -1.0) : v;
        }
        case kUnsignedShort: {
            std::uint16_t v;
            std::memcpy(&v, p, 2);
            return normalized ? v / 65535.0 : v;
        }
        case kShort: {
            std::int16_t v;
            std::memcpy(&v, p, 2);
            return normalized ? std::max(v / 32767.0, -1.0) : v;
        }
        case kUnsignedInt: {
            std::uint32_t v;
            std::memcpy(&v, p, 4);
            return v;
        }
        default: return 0;
    }
}

struct Reader {
    const Document& doc;
    const ReadOptions& options;
    bool quantization_allowed = false;

    GeoError accessor_error(int index, const std::string& what) const {
        return parse_error("glTF accessors[" + std::to_string(index) + "] " + what, doc.json_offset);
    }

    //! First element's address and the stride; nullptr base for an accessor without buffer view (all zeros).
    //! The element range is checked against the view without overflow: everything is compared as remaining room.
    Result<std::pair<const unsigned char*, std::size_t>> element_bytes(int index, std::size_t element_size) const {
        const Accessor& a = doc.accessors[static_cast<std::size_t>(index)];
        if (a.sparse)
            return make_error(ErrorCode::Unsupported, "glTF accessors[" + std::to_string(index) + "] is sparse");
        if (a.count == 0) return accessor_error(index, "has count 0");
        if (a.buffer_view < 0) return std::pair<const unsigned char*, std::size_t>{nullptr, element_size};
        const BufferView& view = doc.views[static_cast<std::size_t>(a.buffer_view)];
        const std::uint64_t stride = view.byte_stride == 0 ? element_size : view.byte_stride;
        if (stride < element_size)
            return accessor_error(index, "is read with byteStride " + std::to_string(stride) +
                                             ", smaller than its element (" + std::to_string(element_size) + " bytes)");
        const std::uint64_t available = view.bytes.size();
        if (a.byte_offset > available || element_size > available - a.byte_offset ||
            (a.count - 1) > (available - a.byte_offset - element_size) / stride)
            return accessor_error(index, "(" + std::to_string(a.count) + " elements at byteOffset " +
                                             std::to_string(a.byte_offset) + ", stride " + std::to_string(stride) +
                                             ") does not fit in bufferViews[" + std::to_string(a.buffer_view) + "] (" +
                                             std::to_string(available) + " bytes)");
        return std::pair<const unsigned char*, std::size_t>{view.bytes.data() + a.byte_offset,
                                                            static_cast<std::size_t>(stride)};
    }

    //! `components` values per element as doubles (float, or normalized / KHR_mesh_quantization integers).
    Result<std::vector<double>> read_floats(int index, int components, const char* semantic) const {
        const Accessor& a = doc.accessors[static_cast<std::size_t>(index)];
        if (a.components != components)
            return accessor_error(
                index, std::string("(") + semantic + ") must have " + std::to_string(components) + " components");
        const int csize = component_size(a.component_type);
        if (csize == 0 || a.component_type == kUnsignedInt)
            return accessor_error(index, std::string("(") + semantic + ") has unsupported componentType " +
                                             std::to_string(a.component_type));
        if (a.component_type != kFloat && !a.normalized && !quantization_allowed)
            return make_error(ErrorCode::Unsupported,
                              "glTF accessors[" + std::to_string(index) + "] (" + semantic +
                                  ") has integer components but KHR_mesh_quantization is not used");
        auto raw = element_bytes(index, static_cast<std::size_t>(csize * components));
        if (!raw) return raw.error();
        const auto [base, stride] = *raw;
        std::vector<double> out(a.count * static_cast<std::size_t>(components), 0.0);
        if (base != nullptr)
            for (std::size_t i = 0; i < a.count; ++i)
                for (int k = 0; k < components; ++k)
                    out[i * static_cast<std::size_t>(components) + static_cast<std::size_t>(k)] = load_component(
                        base + i * stride + static_cast<std::size_t>(k * csize), a.component_type, a.normalized);
        return out;
    }

    Result<std::vector<std::uint32_t>> read_indices(int index) const {
        const Accessor& a = doc.accessors[static_cast<std::size_t>(index)];
        if (a.components != 1) return accessor_error(index, "(indices) must be SCALAR");
        if (a.component_type != kUnsignedByte && a.component_type != kUnsignedShort && a.component_type != kUnsignedInt)
            return accessor_error(index, "(indices) must have an unsigned integer componentType");
        const int csize = component_size(a.component_type);
        auto raw = element_bytes(index, static_cast<std::size_t>(csize));
        if (!raw) return raw.error();
        const auto [base, stride] = *raw;
        std::vector<std::uint32_t> out(a.count, 0);
        if (base != nullptr)
            for (std::size_t i = 0; i < a.count; ++i)
                out[i] = static_cast<std::uint32_t>(load_component(base + i * stride, a.component_type, false));
        return out;
    }
};

Mat4 multiply(const Mat4& a, const Mat4& b) {
    Mat4 r{};
    for (int c = 0; c < 4; ++c)
        for (int row = 0; row < 4; ++row) {
            double s = 0;
            for (int k = 0; k < 4; ++k)
                s += a[static_cast<std::size_t>(k * 4 + row)] * b[static_cast<std::size_t>(c * 4 + k)];
            r[static_cast<std::size_t>(c * 4 + row)] = s;
        }
    return r;
}

double determinant3(const Mat4& m) {
    return m[0] * (m[5] * m[10] - m[9] * m[6]) - m[4] * (m[1] * m[10] - m[9] * m[2]) +
           m[8] * (m[1] * m[6] - m[5] * m[2]);
}

struct MeshInstance {
    int mesh = 0;
    Mat4 world = kIdentity;
};

//! Mesh nodes of the default scene (or of every root node when there are no scenes) with their world matrices.
//! glTF requires the node graph to be a forest: a node with two parents, a cycle, or a scene root that is someone's
//! child is an error.
Result<std::vector<MeshInstance>> collect_instances(const Document& doc) {
    std::vector<MeshInstance> out;
    const std::size_t n = doc.nodes.size();
    if (n == 0) {
        // A file with meshes but no nodes (a mesh library): take each mesh as it is.
        for (std::size_t m = 0; m < doc.meshes.size(); ++m) out.push_back({static_cast<int>(m), kIdentity});
        return out;
    }
    std::vector<int> parent(n, -1);
    for (std::size_t i = 0; i < n; ++i)
        for (int child : doc.nodes[i].children) {
            if (parent[static_cast<std::size_t>(child)] != -1 || static_cast<std::size_t>(child) == i)
                return parse_error("glTF nodes[" + std::to_string(child) + "] has more than one parent",
                                   doc.json_offset);
            parent[static_cast<std::size_t>(child)] = static_cast<int>(i);
        }
    std::vector<int> roots;
    if (!doc.scenes.empty()) {
        roots = doc.scenes[doc.scene >= 0 ? static_cast<std::size_t>(doc.scene) : 0];
        for (int r : roots)
            if (parent[static_cast<std::size_t>(r)] != -1)
                return parse_error("glTF nodes[" + std::to_string(r) + "] is a scene root but also a child",
                                   doc.json_offset);
    } else {
        for (std::size_t i = 0; i < n; ++i)
            if (parent[i] == -1) roots.push_back(static_cast<int>(i));
    }
    // Iterative walk (no recursion depth for an attacker to exploit).
    std::vector<char> visited(n, 0);
    std::vector<std::pair<int, Mat4>> stack;
    for (int r : roots) stack.push_back({r, kIdentity});
    while (!stack.empty()) {
        auto [index, parent_world] = stack.back();
        stack.pop_back();
        const auto i = static_cast<std::size_t>(index);
        if (visited[i])
            return parse_error("glTF nodes[" + std::to_string(i) + "] is reached twice (a cycle?)", doc.json_offset);
        visited[i] = 1;
        const Node& node = doc.nodes[i];
        const Mat4 world = multiply(parent_world, node.local);
        if (node.mesh >= 0) out.push_back({node.mesh, world});
        for (int child : node.children) stack.push_back({child, world});
    }
    return out;
}

// ---- assembling the mesh -----------------------------------------------------------------------------------------

//! Exact-position key for welding: glTF duplicates vertices at uv seams and normal creases, our topology must not.
struct PositionKey {
    std::array<std::uint64_t, 3> bits;
    bool operator==(const PositionKey&) const = default;
};
struct PositionKeyHash {
    std::size_t operator()(const PositionKey& k) const {
        std::uint64_t h = 1469598103934665603ull;
        for (std::uint64_t b : k.bits) h = (h ^ b) * 1099511628211ull ^ (b >> 29);
        return static_cast<std::size_t>(h);
    }
};
PositionKey key_of(const Vec3& p) {
    PositionKey key{};
    for (int k = 0; k < 3; ++k) {
        const double v = p[k] == 0.0 ? 0.0 : p[k];  // -0 and +0 are the same place
        std::memcpy(&key.bits[static_cast<std::size_t>(k)], &v, sizeof v);
    }
    return key;
}

struct Builder {
    PolygonMesh mesh;
    std::unordered_map<PositionKey, Index, PositionKeyHash> welded;
    std::vector<Vec2> uvs;  //!< one per corner, deduplicated at the end
    bool all_have_uvs = true;
};

//! Triangle corner lists for the three triangle modes (strips and fans keep a consistent winding).
Result<std::vector<std::uint32_t>> triangles_of(int mode, std::vector<std::uint32_t> idx, const std::string& where,
                                                std::int64_t json_offset) {
    if (mode == kModeTriangles) {
        if (idx.size() % 3 != 0)
            return parse_error(
                "glTF " + where + ": TRIANGLES index count " + std::to_string(idx.size()) + " is not a multiple of 3",
                json_offset);
        return idx;
    }
    std::vector<std::uint32_t> out;
    if (idx.size() < 3) return out;
    out.reserve((idx.size() - 2) * 3);
    for (std::size_t i = 0; i + 2 < idx.size(); ++i) {
        if (mode == kModeTriangleFan)
            out.insert(out.end(), {idx[0], idx[i + 1], idx[i + 2]});
        else if (i % 2 == 0)
            out.insert(out.end(), {idx[i], idx[i + 1], idx[i + 2]});
        else
            out.insert(out.end(), {idx[i + 1], idx[i], idx[i + 2]});
    }
    return out;
}

//! One primitive's vertex data as decoded, before transforming and welding: xyz, uv (empty when absent) and
//! triangle corners.
struct PrimitiveData {
    std::vector<double> positions, texcoords;
    std::vector<std::uint32_t> indices;
};

//! Limits on what the accessors announce, before anything is decoded or allocated.
Status check_announced_counts(const Reader& reader, const Builder& b, const Primitive& prim, int position_accessor,
                              const std::string& where) {
    const ReadOptions& limits = reader.options;
    const std::uint64_t announced = reader.doc.accessors[static_cast<std::size_t>(position_accessor)].count;
    if (announced > limits.max_vertices || b.mesh.positions.size() > limits.max_vertices - announced)
        return make_error(ErrorCode::BudgetExceeded, where + ": " + std::to_string(announced) +
                                                         " more vertices exceed the limit of " +
                                                         std::to_string(limits.max_vertices));
    const std::uint64_t announced_corners =
        prim.indices >= 0 ? reader.doc.accessors[static_cast<std::size_t>(prim.indices)].count : announced;
    if (announced_corners / 3 > limits.max_faces || b.mesh.face_count() > limits.max_faces - announced_corners / 3)
        return make_error(ErrorCode::BudgetExceeded, where + ": " + std::to_string(announced_corners / 3) +
                                                         " more triangles exceed the limit of " +
                                                         std::to_string(limits.max_faces));
    return Ok{};
}

//! A KHR_draco_mesh_compression primitive: its buffer view decoded by Draco (within the limits left).
Status decode_draco_primitive(const Reader& reader, const Builder& b, const DracoPrimitive& draco, bool has_uv,
                              const std::string& where, PrimitiveData& out) {
    const ReadOptions& limits = reader.options;
    draco_codec::AttributeIds ids;
    const auto pos_id = draco.attributes.find("POSITION");
    if (pos_id == draco.attributes.end())
        return parse_error("glTF " + where + ": " + kDracoExtension + " has no POSITION attribute",
                           reader.doc.json_offset);
    ids.position = pos_id->second;
    if (const auto uv_id = draco.attributes.find("TEXCOORD_0"); has_uv && uv_id != draco.attributes.end())
        ids.texcoord = uv_id->second;
    const auto bytes = reader.doc.views[static_cast<std::size_t>(draco.buffer_view)].bytes;
    const draco_codec::DecodeLimits decode_limits{limits.max_vertices - b.mesh.positions.size(),
                                                  limits.max_faces - b.mesh.face_count()};
    auto decoded = draco_codec::decode({bytes.data(), bytes.size()}, ids, decode_limits);
    if (!decoded) {
        GeoError e = decoded.error();
        e.message = where + ": " + e.message;
        return e;
    }
    out.positions.assign(decoded->positions.begin(), decoded->positions.end());
    out.texcoords.assign(decoded->texcoords.begin(), decoded->texcoords.end());
    out.indices = std::move(decoded->indices);
    return Ok{};
}

//! A plain primitive: POSITION, TEXCOORD_0 and indices read from their accessors, strips and fans made triangles.
Status read_accessor_primitive(const Reader& reader, const Primitive& prim, int position_accessor,
                               std::optional<int> uv_accessor, const std::string& where, PrimitiveData& out) {
    auto p = reader.read_floats(position_accessor, 3, "POSITION");
    if (!p) return p.error();
    out.positions = std::move(*p);
    if (uv_accessor) {
        auto t = reader.read_floats(*uv_accessor, 2, "TEXCOORD_0");
        if (!t) return t.error();
        out.texcoords = std::move(*t);
        if (out.texcoords.size() / 2 != out.positions.size() / 3)
            return parse_error("glTF " + where + ": TEXCOORD_0 and POSITION counts differ", reader.doc.json_offset);
    }
    std::vector<std::uint32_t> corners;
    if (prim.indices >= 0) {
        auto i = reader.read_indices(prim.indices);
        if (!i) return i.error();
        corners = std::move(*i);
    } else {
        // No indices: vertices are used in order.
        corners.resize(out.positions.size() / 3);
        for (std::size_t k = 0; k < corners.size(); ++k) corners[k] = static_cast<std::uint32_t>(k);
    }
    auto tris = triangles_of(prim.mode, std::move(corners), where, reader.doc.json_offset);
    if (!tris) return tris.error();
    out.indices = std::move(*tris);
    return Ok{};
}

//! The primitive's vertices transformed by `world` and welded into the mesh being built, its triangles added (with
//! the winding flipped under a mirroring transform) and their corner uvs kept for finish_uvs().
Status append_primitive(Builder& b, const PrimitiveData& data, const Mat4& world, const std::string& where) {
    const std::size_t count = data.positions.size() / 3;
    std::vector<Index> remap(count);
    for (std::size_t v = 0; v < count; ++v) {
        const double x = data.positions[3 * v], y = data.positions[3 * v + 1], z = data.positions[3 * v + 2];
        const Vec3 p{world[0] * x + world[4] * y + world[8] * z + world[12],
                     world[1] * x + world[5] * y + world[9] * z + world[13],
                     world[2] * x + world[6] * y + world[10] * z + world[14]};
        if (!is_finite(p))
            return make_error(ErrorCode::NonFinite, where + ": vertex " + std::to_string(v) + " is not finite", -1, -1,
                              static_cast<std::int64_t>(v));
        auto [it, inserted] = b.welded.try_emplace(key_of(p), static_cast<Index>(b.mesh.positions.size()));
        if (inserted) b.mesh.positions.push_back(p);
        remap[v] = it->second;
    }

    // A mirroring transform turns the triangles inside out; glTF says to flip the winding then.
    const bool flip = determinant3(world) < 0;
    const std::vector<double>& uv = data.texcoords;
    for (std::size_t t = 0; t < data.indices.size() / 3; ++t) {
        std::array<std::uint32_t, 3> c{data.indices[3 * t], data.indices[3 * t + 1], data.indices[3 * t + 2]};
        for (std::uint32_t v : c)
            if (v >= count)
                return make_error(ErrorCode::IndexOutOfRange,
                                  where + ": triangle " + std::to_string(t) + " refers to vertex " + std::to_string(v) +
                                      " of " + std::to_string(count),
                                  -1, -1, static_cast<std::int64_t>(t));
        if (flip) std::swap(c[1], c[2]);
        const Index a = remap[c[0]], bb = remap[c[1]], cc = remap[c[2]];
        if (a == bb || bb == cc || a == cc) continue;  // collapsed by welding: no longer a polygon
        b.mesh.add_face({a, bb, cc});
        for (std::uint32_t v : c) b.uvs.push_back(uv.empty() ? Vec2{} : Vec2{uv[2 * v], 1.0 - uv[2 * v + 1]});
    }
    return Ok{};
}

Status add_primitive(const Reader& reader, Builder& b, const Primitive& prim, const Mat4& world, std::size_t mesh_index,
                     std::size_t prim_index) {
    const std::string where =
        "meshes[" + std::to_string(mesh_index) + "].primitives[" + std::to_string(prim_index) + "]";
    const auto pos_it = prim.attributes.find("POSITION");
    if (pos_it == prim.attributes.end())
        return parse_error("glTF " + where + " has no POSITION", reader.doc.json_offset);
    const auto uv_it = prim.attributes.find("TEXCOORD_0");
    const bool has_uv = uv_it != prim.attributes.end();
    const ReadOptions& limits = reader.options;
    if (auto status = check_announced_counts(reader, b, prim, pos_it->second, where); !status) return status;

    PrimitiveData data;
    Status decoded =
        prim.draco ? decode_draco_primitive(reader, b, *prim.draco, has_uv, where, data)
                   : read_accessor_primitive(reader, prim, pos_it->second,
                                             has_uv ? std::optional<int>(uv_it->second) : std::nullopt, where, data);
    if (!decoded) return decoded;
    // Strips and fans make up to one triangle per index: check the real count too.
    if (data.indices.size() / 3 > limits.max_faces - b.mesh.face_count())
        return make_error(ErrorCode::BudgetExceeded, where + ": " + std::to_string(data.indices.size() / 3) +
                                                         " more triangles exceed the limit of " +
                                                         std::to_string(limits.max_faces));
    if (data.texcoords.empty()) b.all_have_uvs = false;
    for (std::size_t k = 0; k < data.texcoords.size(); ++k)
        if (!std::isfinite(data.texcoords[k]))
            return make_error(ErrorCode::NonFinite,
                              where + ": TEXCOORD_0 of vertex " + std::to_string(k / 2) + " is not finite");
    return append_primitive(b, data, world, where);
}

//! Face-varying uvs with exact duplicates shared (the per-corner list would repeat every seam-free vertex).
void finish_uvs(Builder& b) {
    if (!b.all_have_uvs || b.uvs.empty()) return;
    std::unordered_map<PositionKey, Index, PositionKeyHash> seen;
    b.mesh.uv_indices.reserve(b.uvs.size());
    for (const Vec2& uv : b.uvs) {
        auto [it, inserted] = seen.try_emplace(key_of(Vec3{uv.x, uv.y, 0}), static_cast<Index>(b.mesh.uvs.size()));
        if (inserted) b.mesh.uvs.push_back(uv);
        b.mesh.uv_indices.push_back(it->second);
    }
}

//! Every triangle primitive of every mesh instance of the default scene, as one mesh.
Result<PolygonMesh> read_scene(const SceneInput& input, const ReadOptions& options, GltfReadReport& report) {
    std::vector<std::vector<unsigned char>> embedded;  // .gltf buffers, decoded; the document's views point here
    auto doc = parse_document(input, embedded);
    if (!doc) return doc.error();

    Reader reader{*doc, options};
    for (const std::string& ext : doc->extensions_required) {
        if (ext == kQuantizationExtension)
            reader.quantization_allowed = true;
        else if (ext != kDracoExtension)
            return make_error(ErrorCode::Unsupported,
                              std::string(input.kind) + " requires unsupported extension " + ext);
    }
    for (const std::string& ext : doc->extensions_used)
        if (ext == kQuantizationExtension) reader.quantization_allowed = true;

    auto instances = collect_instances(*doc);
    if (!instances) return instances.error();

    // primitives
    Builder builder;
    for (const MeshInstance& inst : *instances) {
        const auto& primitives = doc->meshes[static_cast<std::size_t>(inst.mesh)];
        for (std::size_t p = 0; p < primitives.size(); ++p) {
            const Primitive& prim = primitives[p];
            if (prim.mode != kModeTriangles && prim.mode != kModeTriangleStrip && prim.mode != kModeTriangleFan) {
                ++report.skipped_primitives;  // points and lines carry no surface
                continue;
            }
            if (Status s = add_primitive(reader, builder, prim, inst.world, static_cast<std::size_t>(inst.mesh), p); !s)
                return s.error();
        }
    }
    if (builder.mesh.face_count() == 0)
        return make_error(ErrorCode::Unsupported,
                          std::string(input.kind) + (report.skipped_primitives > 0
                                                         ? " has only point or line primitives, no triangles"
                                                         : " contains no triangles"));
    finish_uvs(builder);
    return std::move(builder.mesh);
}

//! Runs a reader: nlohmann::json and Draco may throw (bad_alloc, type errors we did not foresee); none of it may
//! escape. The report is reset first and keeps what the read counted.
template <class Read>
Result<PolygonMesh> guarded(const char* kind, GltfReadReport* report, Read&& read) {
    GltfReadReport local;
    GltfReadReport& counts = report ? *report : local;
    counts = GltfReadReport{};
    try {
        return read(counts);
    } catch (const std::bad_alloc&) {
        return make_error(ErrorCode::BudgetExceeded, std::string("out of memory while reading the ") + kind);
    } catch (const std::exception&) {
        // nlohmann's or Draco's exception text is theirs, not a description a client can act on.
        return make_error(ErrorCode::ParseError,
                          std::string("malformed ") + kind + ": a member has an unexpected type or value");
    }
}

}  // namespace

Result<PolygonMesh> read_glb(std::string_view bytes, const ReadOptions& options, GltfReadReport* report) {
    return guarded("GLB", report, [&](GltfReadReport& counts) -> Result<PolygonMesh> {
        auto chunks = split_container(bytes);
        if (!chunks) return chunks.error();
        return read_scene({chunks->json, kJsonOffset, chunks->bin, false, "GLB"}, options, counts);
    });
}

Result<PolygonMesh> read_gltf(std::string_view text, const ReadOptions& options, GltfReadReport* report) {
    return guarded("glTF", report, [&](GltfReadReport& counts) {
        return read_scene({text, 0, {}, true, "glTF"}, options, counts);
    });
}

}  // namespace surfaced
