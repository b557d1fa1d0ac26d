// libFuzzer target: read_obj_patches (OBJ free-form cstype [rat] bezier and [rat] bspline surfaces). Accepted patch sets must pass
// validate(); errors must carry a message and a line.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz/fuzz_check.h"
#include "geometry/io/obj_patches.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    surfaced::ObjPatchReadOptions options;
    options.max_patches = 10'000;
    options.max_vertices = 100'000;
    const auto result = surfaced::read_obj_patches(text, options);
    if (!result.ok()) {
        if (result.error().message.empty()) surfaced::fuzz::fail("read_obj_patches error", "empty message");
        if (result.error().code == surfaced::ErrorCode::Internal)
            surfaced::fuzz::fail("read_obj_patches internal error", result.error().message);
        return 0;
    }
    const surfaced::Status valid = surfaced::validate(std::span<const surfaced::BezierPatch>(result->patches));
    if (!valid.ok())
        surfaced::fuzz::fail("read_obj_patches returned patches that validate() rejects", valid.error().message);
    return 0;
}
