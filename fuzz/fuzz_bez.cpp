// libFuzzer target: read_bez (geomview BEZ/BBP patch text). Accepted patch sets must pass validate().
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz/fuzz_check.h"
#include "geometry/io/bez.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    const auto result = surfaced::read_bez(text);
    if (!result.ok()) {
        if (result.error().message.empty()) surfaced::fuzz::fail("read_bez error", "empty message");
        return 0;
    }
    const surfaced::Status valid = surfaced::validate(std::span<const surfaced::BezierPatch>(result->patches));
    if (!valid.ok()) surfaced::fuzz::fail("read_bez returned patches that validate() rejects", valid.error().message);
    return 0;
}
