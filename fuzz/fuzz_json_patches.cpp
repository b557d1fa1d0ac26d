// libFuzzer target: the JSON request codec for POST /tessellate. Decoded patches must pass validate().
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
    }
    return 0;
}
