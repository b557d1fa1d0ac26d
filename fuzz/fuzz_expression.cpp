// libFuzzer target: the implicit-surface expression language (geometry/implicit/expression.h parse_expression).
// A parsed expression is also evaluated (value and gradient) at a few points: the tree walk must stay within the
// depth the parser allowed. NaN values are allowed (sqrt of a negative); crashes and unbounded recursion are not.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz/fuzz_check.h"
#include "geometry/implicit/expression.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace surfaced;
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    const auto result = implicit::parse_expression(text);
    if (!result.ok()) {
        if (result.error().message.empty()) fuzz::fail("parse_expression error", "empty message");
        if (result.error().code != ErrorCode::ParseError && result.error().code != ErrorCode::BudgetExceeded)
            fuzz::fail("parse_expression error code", result.error().message);
        return 0;
    }
    const implicit::Field& field = **result;
    const Vec3 points[] = {{0, 0, 0}, {1, -2, 0.5}, {-1e3, 1e-3, 7}};
    for (const Vec3& p : points) {
        volatile double v = field.value(p);
        volatile double g = field.gradient(p).x;
        (void)v;
        (void)g;
    }
    return 0;
}
