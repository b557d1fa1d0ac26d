// libFuzzer target: read_obj_surfaces (OBJ free-form cstype [rat] bezier and [rat] bspline surfaces, curv2 curves,
// trim and hole loops). Accepted patches must pass validate(), accepted trimmed surfaces validate() and
// validate_trims(); errors must carry a message and a line (a byte offset where the text cannot be decoded; neither
// for an empty input), and never be Internal. read_obj_patches must agree (the same patches, or Unsupported when there
// are trimmed surfaces).
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "fuzz/fuzz_check.h"
#include "geometry/io/obj_patches.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace surfaced;
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    ObjPatchReadOptions options;
    options.max_patches = 10'000;
    options.max_vertices = 100'000;
    options.max_trim_loops = 1'000;
    options.max_trim_segments = 100'000;
    const auto result = read_obj_surfaces(text, options);
    const auto patches = read_obj_patches(text, options);
    if (!result.ok()) {
        if (result.error().message.empty()) fuzz::fail("read_obj_surfaces error", "empty message");
        // an empty input has no line to name; text that cannot be decoded names its byte offset instead
        if (result.error().line <= 0 && result.error().offset < 0 && !text.empty())
            fuzz::fail("read_obj_surfaces error without a line", result.error().message);
        if (result.error().code == ErrorCode::Internal)
            fuzz::fail("read_obj_surfaces internal error", result.error().message);
        if (patches.ok()) fuzz::fail("read_obj_patches accepted what read_obj_surfaces refused", "");
        return 0;
    }
    const Status valid = validate(std::span<const BezierPatch>(result->patches.patches));
    if (!valid.ok()) fuzz::fail("read_obj_surfaces returned patches that validate() rejects", valid.error().message);
    for (const ObjTrimmedSurface& t : result->trimmed) {
        const Status surface = validate(t.trimmed.surface);
        if (!surface.ok()) fuzz::fail("read_obj_surfaces returned an invalid trimmed surface", surface.error().message);
        const TrimValidation trims = validate_trims(t.trimmed);
        if (!trims.ok()) fuzz::fail("read_obj_surfaces returned trims validate_trims rejects", trims.error->message);
    }
    if (result->trimmed.empty() != patches.ok())
        fuzz::fail("read_obj_patches disagrees with read_obj_surfaces",
                   patches.ok() ? "accepted trimmed surfaces" : patches.error().message);
    return 0;
}
