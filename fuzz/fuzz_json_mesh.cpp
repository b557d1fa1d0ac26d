// libFuzzer target: the JSON request codecs for POST /subdivide and /simplify (mesh, tags, options, output).
// A decoded mesh must pass validate(); errors must be 4xx with a detail.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "api/json_codec.h"
#include "fuzz/fuzz_api_check.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace surfaced;
    const std::string_view body(reinterpret_cast<const char*>(data), size);
    const api::Limits limits;
    const auto subdivide = api::decode_subdivide_request(body, limits);
    fuzz::check_api_result(subdivide);
    if (subdivide.ok()) {
        const Status valid = validate(subdivide->mesh);
        if (!valid.ok()) fuzz::fail("decode_subdivide_request returned an invalid mesh", valid.error().message);
    }
    const auto simplify = api::decode_simplify_request(body, limits);
    fuzz::check_api_result(simplify);
    if (simplify.ok()) {
        const Status valid = validate(simplify->mesh);
        if (!valid.ok()) fuzz::fail("decode_simplify_request returned an invalid mesh", valid.error().message);
    }
    return 0;
}
