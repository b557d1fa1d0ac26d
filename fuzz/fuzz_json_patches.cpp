// libFuzzer target: the JSON request codec for POST /tessellate. Decoded patches and B-spline surfaces must pass
// validate(), and a decoded surface must decompose into its predicted number of Bézier patches.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "api/patch_codec.h"
#include "fuzz/fuzz_api_check.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace surfaced;
    const std::string_view body(reinterpret_cast<const char*>(data), size);
    const auto result = api::decode_tessellate_request(body, api::Limits{});
    fuzz::check_api_result(result);
    if (result.ok()) {
        const Status valid = validate(std::span<const BezierPatch>(result->patches.patches));
        if (!valid.ok()) fuzz::fail("decode_tessellate_request returned invalid patches", valid.error().message);
        for (const BSplineSurface& surface : result->surfaces) {
            const Status ok = validate(surface);
            if (!ok.ok()) fuzz::fail("decode_tessellate_request returned an invalid surface", ok.error().message);
            if (bezier_patch_count(surface) > 10'000) continue;  // the operation's budget would refuse it
            auto patches = to_bezier(surface);
            if (!patches.ok()) fuzz::fail("to_bezier failed on a valid surface", patches.error().message);
            if (patches->patches.size() != bezier_patch_count(surface))
                fuzz::fail("to_bezier", "patch count differs from bezier_patch_count");
            if (const Status p = validate(std::span<const BezierPatch>(patches->patches)); !p.ok())
                fuzz::fail("to_bezier returned invalid patches", p.error().message);
        }
    }
    return 0;
}
