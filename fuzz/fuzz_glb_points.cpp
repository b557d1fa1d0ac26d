// libFuzzer target: read_glb_points and read_gltf_points (gltf_points.h: POINTS primitives or a mesh's vertices,
// NORMAL and COLOR_0, node transforms, KHR_draco_mesh_compression). Input starting with '{' goes to the glTF JSON
// reader, the rest to the GLB reader. An accepted cloud must pass validate(); an error must carry a message and
// never be Internal.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz/fuzz_check.h"
#include "geometry/io/gltf_points.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace surfaced;
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    PointReadOptions options;
    options.max_points = 1'000'000;  // the fuzzer's 2 GiB: a cloud of the default 20 M points is 1.2 GB alone
    const auto result =
        !bytes.empty() && bytes.front() == '{' ? read_gltf_points(bytes, options) : read_glb_points(bytes, options);
    if (!result.ok()) {
        if (result.error().message.empty()) fuzz::fail("read_glb_points error", "empty message");
        if (result.error().code == ErrorCode::Internal)
            fuzz::fail("read_glb_points error is Internal", result.error().message);
        return 0;
    }
    if (result->empty()) fuzz::fail("read_glb_points returned an empty cloud", "");
    const Status valid = validate(*result);
    if (!valid.ok()) fuzz::fail("read_glb_points returned a cloud that validate() rejects", valid.error().message);
    for (const Vec3& n : result->normals)
        if (std::abs(norm(n) - 1.0) > 1e-9) fuzz::fail("read_glb_points returned a normal that is not unit", "");
    return 0;
}
