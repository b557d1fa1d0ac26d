// libFuzzer target: read_gltf (glTF JSON, base64 data: URI buffers, accessors, node transforms,
// KHR_draco_mesh_compression), and that every accepted mesh passes validate().
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz/fuzz_check.h"
#include "geometry/io/gltf.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    surfaced::fuzz::check_mesh_result(surfaced::read_gltf(bytes));
    return 0;
}
