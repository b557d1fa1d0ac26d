// Internal to geo_gltf: the steps every glTF writer of ours ends with (mesh, points, polylines), on a tinygltf::Model.
#pragma once

#include <cstdint>
#include <exception>
#include <limits>
#include <new>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>

#include "geometry/core/result.h"
#include "geometry/io/json_text.h"
#include "geometry/io/tinygltf_config.h"

namespace surfaced::gltf_detail {

//! Pads buffer 0 to a multiple of 4 bytes (the GLB BIN chunk is padded anyway; byteLength then equals the chunk) and
//! checks it against GLB's uint32 lengths, leaving 1 MiB for the JSON chunk.
inline Status pad_and_check_buffer(tinygltf::Model& model) {
    auto& data = model.buffers[0].data;
    data.resize((data.size() + 3) & ~std::size_t{3}, 0);
    if (data.size() > std::numeric_limits<std::uint32_t>::max() - (std::size_t{1} << 20))
        return make_error(ErrorCode::BudgetExceeded,
                          "GLB would exceed 4 GiB (" + std::to_string(data.size()) + " bytes of data)");
    return Ok{};
}

//! Makes `mesh` the model's only mesh, in one node of the default scene.
inline void add_single_mesh_scene(tinygltf::Model& model, tinygltf::Mesh mesh) {
    model.meshes.push_back(std::move(mesh));
    tinygltf::Node node;
    node.mesh = static_cast<int>(model.meshes.size() - 1);
    model.nodes.push_back(std::move(node));
    tinygltf::Scene scene;
    scene.nodes.push_back(static_cast<int>(model.nodes.size() - 1));
    model.scenes.push_back(std::move(scene));
    model.defaultScene = 0;
}

//! The glTF JSON of `text` again, numbers printed as every output prints them (json_text.h): tinygltf writes
//! accessor bounds as 1.0 and -0.0.
inline Result<std::string> reprint_json(std::string_view text) {
    const nlohmann::json document = nlohmann::json::parse(text, nullptr, false);
    if (document.is_discarded()) return make_error(ErrorCode::Internal, "tinygltf wrote a glTF that is not JSON");
    return json_text(document);
}

inline void store_u32_le(std::string& out, std::size_t at, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) out[at + i] = static_cast<char>((v >> (8 * i)) & 0xff);
}

inline std::uint32_t load_u32_le(std::string_view bytes, std::size_t at) {
    std::uint32_t v = 0;
    for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(bytes[at + i]);
    return v;
}

//! GLB, or text glTF with the buffer embedded as a base64 data URI (tinygltf does so for buffers without a uri).
//! The JSON (a GLB's JSON chunk) is printed through json_text.h.
inline Result<std::string> serialise(tinygltf::Model& model, bool binary) {
    std::ostringstream stream;
    tinygltf::TinyGLTF writer;
    if (!writer.WriteGltfSceneToStream(&model, stream, /*prettyPrint=*/false, /*writeBinary=*/binary) || !stream)
        return make_error(ErrorCode::Internal, "tinygltf failed to serialise the glTF");
    std::string out = std::move(stream).str();
    if (!binary) return reprint_json(out);
    // GLB: 12-byte header, then the JSON chunk (length, type, text padded with spaces to 4 bytes), then the rest
    if (out.size() < 20) return make_error(ErrorCode::Internal, "tinygltf wrote a GLB shorter than its header");
    const std::size_t json_length = load_u32_le(out, 12);
    if (20 + json_length > out.size()) return make_error(ErrorCode::Internal, "tinygltf wrote a truncated GLB");
    auto json = reprint_json(std::string_view(out).substr(20, json_length));
    if (!json) return json.error();
    std::string& text = json.value();
    text.resize((text.size() + 3) & ~std::size_t{3}, ' ');
    std::string glb = out.substr(0, 20) + text + out.substr(20 + json_length);
    store_u32_le(glb, 8, static_cast<std::uint32_t>(glb.size()));
    store_u32_le(glb, 12, static_cast<std::uint32_t>(text.size()));
    return glb;
}

//! Runs a writer: tinygltf and nlohmann::json report failures by throwing, and nothing may cross the public API.
template <class Write>
Result<std::string> guarded(Write&& write, std::string_view what) {
    try {
        return write();
    } catch (const std::bad_alloc&) {
        return make_error(ErrorCode::BudgetExceeded, "out of memory while writing the " + std::string(what));
    } catch (const std::exception&) {
        return make_error(ErrorCode::Internal, std::string(what) + " writer failed");
    }
}

}  // namespace surfaced::gltf_detail
