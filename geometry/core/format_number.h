// Numbers in messages: the shortest text that reads back as the same double ("1e-09", "0.1"), never "%f", which
// prints a small tolerance as "0.000000".
#pragma once

#include <charconv>
#include <string>

namespace surfaced {

inline std::string shortest_text(double value) {
    char buffer[32];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
    return std::string(buffer, result.ptr);
}

}  // namespace surfaced
