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

//! GLB, or text glTF with the buffer embedded as a base64 data URI (tinygltf does so for buffers without a uri).
inline Result<std::string> serialise(tinygltf::Model& model, bool binary) {
    std::ostringstream stream;
    tinygltf::TinyGLTF writer;
    if (!writer.WriteGltfSceneToStream(&model, stream, /*prettyPrint=*/false, /*writeBinary=*/binary) || !stream)
        return make_error(ErrorCode::Internal, "tinygltf failed to serialise the glTF");
    return std::move(stream).str();
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
