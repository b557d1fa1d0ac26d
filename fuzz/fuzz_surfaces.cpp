// libFuzzer target: POST /surfaces and POST /tessellate's trimmed surfaces end to end (the surface and trim codecs,
// every query, validate_trims, the trimmed tessellator, the encoders), called as the server calls them. A body with a
// "surfaces" member goes to POST /tessellate, any other to POST /surfaces. Any answer but a 2xx, a 4xx with a
// problem body, or 503 when the compute deadline passed is a bug. Budgets are lowered so that one input stays well
// inside libFuzzer's per-input timeout.
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "api/operations/surfaces.h"
#include "api/operations/tessellate.h"
#include "fuzz/fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace surfaced;
    api::ApiRequest request;
    request.method = "POST";
    request.content_type = "application/json";
    request.body = std::string_view(reinterpret_cast<const char*>(data), size);
    const bool tessellate = request.body.find("\"surfaces\"") != std::string::npos;
    request.path = tessellate ? "/tessellate" : "/surfaces";
    api::ApiContext context;
    context.limits.max_patches = 2'000;
    context.limits.max_input_vertices = 50'000;
    context.limits.max_patch_segments = 64;
    context.limits.max_output_faces = 200'000;
    context.cancel.deadline = Cancel::Clock::now() + std::chrono::seconds(2);
    const api::ApiResponse response =
        tessellate ? api::operations::tessellate(request, context) : api::operations::surfaces(request, context);
    const std::string what = "POST " + request.path;
    if (response.status >= 200 && response.status < 300) {
        if (response.body.empty()) fuzz::fail(what.c_str(), "2xx with an empty body");
        return 0;
    }
    if (response.status == 503) return 0;  // the deadline above
    if (response.status < 400 || response.status >= 500)
        fuzz::fail((what + " answered an unexpected status").c_str(),
                   std::to_string(response.status) + ": " + response.body);
    if (response.content_type != "application/problem+json" || response.body.find("\"detail\"") == std::string::npos)
        fuzz::fail((what + " error without a problem+json detail").c_str(), response.body);
    return 0;
}
