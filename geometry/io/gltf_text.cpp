// glTF JSON (.gltf) output: the GLB's JSON chunk with its binary chunk embedded as a base64 data URI, so the
// result is one self-contained text file that every glTF loader reads.
#include <cstdint>
#include <cstring>
#include <string>

#include <nlohmann/json.hpp>

#include "geometry/io/base64.h"
#include "geometry/io/gltf.h"
#include "geometry/io/json_text.h"

namespace surfaced {

namespace {

std::uint32_t read_u32(std::string_view bytes, std::size_t at) {
    std::uint32_t v;
    std::memcpy(&v, bytes.data() + at, 4);  // GLB is little-endian, as is every platform we build for
    return v;
}

}  // namespace

Result<std::string> write_gltf(const PolygonMesh& mesh, const GltfOptions& options) {
    auto glb = write_glb(mesh, options);
    if (!glb) return glb.error();
    return gltf_from_glb(*glb);
}

Result<std::string> gltf_from_glb(std::string_view bytes) {
    // our own GLB: header, JSON chunk, BIN chunk (checked anyway: a mistake here must not read out of bounds)
    if (bytes.size() < 20) return make_error(ErrorCode::Internal, "GLB too short");
    const std::uint32_t json_length = read_u32(bytes, 12);
    if (20 + std::size_t{json_length} > bytes.size())
        return make_error(ErrorCode::Internal, "GLB JSON chunk truncated");
    nlohmann::json document = nlohmann::json::parse(bytes.substr(20, json_length), nullptr, false);
    if (document.is_discarded()) return make_error(ErrorCode::Internal, "GLB JSON chunk is not JSON");
    const std::size_t bin_header = 20 + std::size_t{json_length};
    if (bin_header + 8 <= bytes.size()) {
        const std::uint32_t bin_length = read_u32(bytes, bin_header);
        if (bin_header + 8 + bin_length > bytes.size())
            return make_error(ErrorCode::Internal, "GLB BIN chunk truncated");
        if (!document.contains("buffers") || document["buffers"].empty())
            return make_error(ErrorCode::Internal, "GLB has a BIN chunk but no buffer");
        auto& buffer = document["buffers"][0];
        const auto byte_length = buffer.value("byteLength", std::uint64_t{0});
        if (byte_length > bin_length) return make_error(ErrorCode::Internal, "GLB buffer longer than its BIN chunk");
        // the BIN chunk is padded to 4 bytes; the buffer is byteLength long
        buffer["uri"] =
            "data:application/octet-stream;base64," + encode_base64(bytes.substr(bin_header + 8, byte_length));
    }
    return json_text(document);  // numbers (accessor min/max) as every text output prints them
}

}  // namespace surfaced
