// libFuzzer target: the JSON request codecs for POST /subdivide and /simplify (mesh, tags, options, output).
// Errors must be 4xx with a detail. The codec only decodes: topology (a face repeating a vertex, ...) is checked by
// validate() in the operation's intake (request_forms), so a decoded mesh that validate() refuses must be refused
// with a user-facing error, never Internal.
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
        if (!valid.ok() && valid.error().code == ErrorCode::Internal)
            fuzz::fail("validate() failed internally on a decoded subdivide mesh", valid.error().message);
    }
    const auto simplify = api::decode_simplify_request(body, limits);
    fuzz::check_api_result(simplify);
    if (simplify.ok()) {
        const Status valid = validate(simplify->mesh);
        if (!valid.ok() && valid.error().code == ErrorCode::Internal)
            fuzz::fail("validate() failed internally on a decoded simplify mesh", valid.error().message);
    }
    return 0;
}
