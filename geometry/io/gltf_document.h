// Internal to geo_gltf: the checked glTF document both glTF readers build on (gltf_read.cpp reads triangle meshes,
// gltf_points.cpp point clouds). Input is untrusted (it arrives over HTTP), so every step checks before it trusts:
//  - the GLB container is checked first, with byte offsets in the errors (a .gltf is the JSON alone);
//  - the JSON is parsed with nlohmann::json into the small document model below, every field type-checked and
//    every cross-reference range-checked, with the JSON path in the error ("accessors[3].count"). tinygltf is not
//    used for reading: 2.7.0 rejects Draco primitives (index accessors without bufferView) unless its own Draco
//    decoding is compiled in, and that code indexes buffer views and attribute arrays without bounds checks;
//  - GLB buffers must come from the BIN chunk, .gltf buffers from data: URIs (strict base64, data_uri.h); any other
//    URI (a file name, a URL) is Unsupported and nothing is ever opened or fetched;
//  - every accessor is checked against its buffer view and the view against the buffer before it is read, so a
//    reader applies its limits to the counts the accessors announce before anything is allocated.
#pragma once

#include <array>
#include <cstdint>
#include <exception>
#include <map>
#include <new>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "geometry/core/result.h"

namespace surfaced::gltf_doc {

inline constexpr const char* kDracoExtension = "KHR_draco_mesh_compression";
inline constexpr const char* kQuantizationExtension = "KHR_mesh_quantization";

// glTF enums
inline constexpr int kByte = 5120, kUnsignedByte = 5121, kShort = 5122, kUnsignedShort = 5123, kUnsignedInt = 5125,
                     kFloat = 5126;
inline constexpr int kModePoints = 0, kModeTriangles = 4, kModeTriangleStrip = 5, kModeTriangleFan = 6;

inline GeoError parse_error(std::string message, std::int64_t offset = -1) {
    return make_error(ErrorCode::ParseError, std::move(message), -1, offset);
}

//! What the scene readers read: the glTF JSON, and where its buffers' bytes are.
struct SceneInput {
    std::string_view json;
    std::int64_t json_offset = 0;  //!< where `json` starts in the input, for error offsets
    std::string_view bin;          //!< GLB: the BIN chunk (buffer 0)
    bool embedded = false;         //!< .gltf: every buffer is a base64 data: URI
    const char* kind = "GLB";      //!< names the input in messages
};

//! A GLB's container checked (header, JSON chunk, BIN chunk), its parts as a SceneInput.
Result<SceneInput> glb_input(std::string_view bytes);
//! glTF JSON text whose buffers are embedded as data: URIs.
SceneInput gltf_input(std::string_view text);

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
inline constexpr Mat4 kIdentity{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

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

//! The document, its buffers resolved: GLB buffers point into the input, .gltf ones into `storage` (which must
//! outlive the document).
Result<Document> parse_document(const SceneInput& input, std::vector<std::vector<unsigned char>>& storage);

//! Reads accessor data, each accessor's element range checked against its buffer view first.
struct Reader {
    const Document& doc;
    bool quantization_allowed = false;  //!< KHR_mesh_quantization: integer attributes need not be normalized

    GeoError accessor_error(int index, const std::string& what) const;
    //! First element's address and the stride; nullptr base for an accessor without buffer view (all zeros).
    //! The element range is checked against the view without overflow: everything is compared as remaining room.
    Result<std::pair<const unsigned char*, std::size_t>> element_bytes(int index, std::size_t element_size) const;
    //! `components` values per element as doubles (float, or normalized / KHR_mesh_quantization integers).
    Result<std::vector<double>> read_floats(int index, int components, const char* semantic) const;
    Result<std::vector<std::uint32_t>> read_indices(int index) const;
};

//! The reader for `doc` once its extensionsRequired are known: Draco and KHR_mesh_quantization are read, any other
//! required extension is Unsupported, naming it (`kind` names the input: "GLB", "glTF").
Result<Reader> make_reader(const Document& doc, const char* kind);

Mat4 multiply(const Mat4& a, const Mat4& b);
//! Of the upper-left 3x3: negative for a mirroring transform.
double determinant3(const Mat4& m);

struct MeshInstance {
    int mesh = 0;
    Mat4 world = kIdentity;
};

//! Mesh nodes of the default scene (or of every root node when there are no scenes) with their world matrices.
//! glTF requires the node graph to be a forest: a node with two parents, a cycle, or a scene root that is someone's
//! child is an error.
Result<std::vector<MeshInstance>> collect_instances(const Document& doc);

//! Runs a read: nlohmann::json and Draco may throw (bad_alloc, type errors nobody foresaw); none of it may escape.
template <class T, class Read>
Result<T> guarded(const char* kind, Read&& read) {
    try {
        return read();
    } catch (const std::bad_alloc&) {
        return make_error(ErrorCode::BudgetExceeded, std::string("out of memory while reading the ") + kind);
    } catch (const std::exception&) {
        // nlohmann's or Draco's exception text is theirs, not a description a client can act on.
        return make_error(ErrorCode::ParseError,
                          std::string("malformed ") + kind + ": a member has an unexpected type or value");
    }
}

}  // namespace surfaced::gltf_doc
