// The checked glTF document (gltf_document.h): container, JSON document model, accessor data, node transforms.
#include "geometry/io/gltf_document.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include <nlohmann/json.hpp>

#include "geometry/io/data_uri.h"

namespace surfaced::gltf_doc {

namespace {

using nlohmann::json;

constexpr std::uint32_t kGlbMagic = 0x46546C67;   // "glTF"
constexpr std::uint32_t kChunkJson = 0x4E4F534A;  // "JSON"
constexpr std::uint32_t kChunkBin = 0x004E4942;   // "BIN\0"
constexpr std::int64_t kJsonOffset = 20;          // where the JSON text starts in a GLB

std::uint32_t read_u32(std::string_view bytes, std::size_t offset) {
    std::uint32_t v = 0;
    for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(bytes[offset + static_cast<std::size_t>(i)]);
    return v;
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

}  // namespace

Result<SceneInput> glb_input(std::string_view bytes) {
    auto chunks = split_container(bytes);
    if (!chunks) return chunks.error();
    return SceneInput{chunks->json, kJsonOffset, chunks->bin, false, "GLB"};
}

SceneInput gltf_input(std::string_view text) { return SceneInput{text, 0, {}, true, "glTF"}; }

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

GeoError Reader::accessor_error(int index, const std::string& what) const {
    return parse_error("glTF accessors[" + std::to_string(index) + "] " + what, doc.json_offset);
}

Result<std::pair<const unsigned char*, std::size_t>> Reader::element_bytes(int index, std::size_t element_size) const {
    const Accessor& a = doc.accessors[static_cast<std::size_t>(index)];
    if (a.sparse) return make_error(ErrorCode::Unsupported, "glTF accessors[" + std::to_string(index) + "] is sparse");
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

Result<std::vector<double>> Reader::read_floats(int index, int components, const char* semantic) const {
    const Accessor& a = doc.accessors[static_cast<std::size_t>(index)];
    if (a.components != components)
        return accessor_error(
            index, std::string("(") + semantic + ") must have " + std::to_string(components) + " components");
    const int csize = component_size(a.component_type);
    if (csize == 0 || a.component_type == kUnsignedInt)
        return accessor_error(
            index, std::string("(") + semantic + ") has unsupported componentType " + std::to_string(a.component_type));
    if (a.component_type != kFloat && !a.normalized && !quantization_allowed)
        return make_error(ErrorCode::Unsupported, "glTF accessors[" + std::to_string(index) + "] (" + semantic +
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

Result<std::vector<std::uint32_t>> Reader::read_indices(int index) const {
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

Result<Reader> make_reader(const Document& doc, const char* kind) {
    Reader reader{doc};
    for (const std::string& ext : doc.extensions_required) {
        if (ext == kQuantizationExtension)
            reader.quantization_allowed = true;
        else if (ext != kDracoExtension)
            return make_error(ErrorCode::Unsupported, std::string(kind) + " requires unsupported extension " + ext);
    }
    for (const std::string& ext : doc.extensions_used)
        if (ext == kQuantizationExtension) reader.quantization_allowed = true;
    return reader;
}

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

}  // namespace surfaced::gltf_doc
