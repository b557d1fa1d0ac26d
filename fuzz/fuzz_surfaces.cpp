// libFuzzer target: POST /surfaces end to end (the surface codec, every query, the encoders), called as the server
// calls it. Any answer but a 2xx, a 4xx with a problem body, or 503 when the compute deadline passed is a bug. Budgets
// are lowered so that one input stays well inside libFuzzer's per-input timeout.
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "api/operations/surfaces.h"
#include "fuzz/fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace surfaced;
    api::ApiRequest request;
    request.method = "POST";
    request.path = "/surfaces";
    request.content_type = "application/json";
    request.body = std::string_view(reinterpret_cast<const char*>(data), size);
    api::ApiContext context;
    context.limits.max_patches = 2'000;
    context.limits.max_input_vertices = 50'000;
    context.cancel.deadline = Cancel::Clock::now() + std::chrono::seconds(2);
    const api::ApiResponse response = api::operations::surfaces(request, context);
    if (response.status >= 200 && response.status < 300) {
        if (response.body.empty()) fuzz::fail("POST /surfaces", "2xx with an empty body");
        return 0;
    }
    if (response.status == 503) return 0;  // the deadline above
    if (response.status < 400 || response.status >= 500)
        fuzz::fail("POST /surfaces answered an unexpected status",
                   std::to_string(response.status) + ": " + response.body);
    if (response.content_type != "application/problem+json" || response.body.find("\"detail\"") == std::string::npos)
        fuzz::fail("POST /surfaces error without a problem+json detail", response.body);
    return 0;
}
