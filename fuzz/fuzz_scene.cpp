// libFuzzer target: scene JSON (api/scene_codec.h parse_scene), including the expression language inside scenes.
// Errors must be 4xx with a detail; a parsed scene is evaluated at a few points.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "api/scene_codec.h"
#include "fuzz/fuzz_api_check.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace surfaced;
    const std::string_view body(reinterpret_cast<const char*>(data), size);
    api::json::Json document;
    if (api::json::parse(body, document)) return 0;  // not JSON: json_util's parser is covered by the other targets
    const auto scene = api::parse_scene(document, api::Limits{});
    fuzz::check_api_result(scene);
    if (scene.ok()) {  // a parsed scene must evaluate anywhere without crashing (NaN allowed)
        for (const Vec3& p : {Vec3{0, 0, 0}, Vec3{0.3, -0.7, 1.1}, Vec3{-50, 20, 1e-3}}) {
            volatile double v = scene.value()->value(p);
            (void)v;
        }
    }
    return 0;
}
