// JSON text with numbers printed as number_text.h prints them: shortest round trip, integral values without ".0",
// -0 as 0. nlohmann's dump() would write 1.0, -0.0 and its own exponent thresholds; the service's JSON outputs (the
// text glTF, the mesh operations' stats) go through here so every output prints a number the same way.
#pragma once

#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "geometry/io/number_text.h"

namespace surfaced {

//! Appends `value` as compact JSON (no whitespace). Strings are escaped as nlohmann escapes them (invalid UTF-8
//! replaced); non-finite numbers, which JSON cannot hold, become null as in nlohmann.
inline void append_json(std::string& out, const nlohmann::json& value) {
    using Json = nlohmann::json;
    const auto append_string = [&](const std::string& text) {
        out += Json(text).dump(-1, ' ', false, Json::error_handler_t::replace);
    };
    switch (value.type()) {
        case Json::value_t::object: {
            out += '{';
            bool first = true;
            for (const auto& [key, member] : value.items()) {
                if (!first) out += ',';
                first = false;
                append_string(key);
                out += ':';
                append_json(out, member);
            }
            out += '}';
            return;
        }
        case Json::value_t::array: {
            out += '[';
            bool first = true;
            for (const auto& item : value) {
                if (!first) out += ',';
                first = false;
                append_json(out, item);
            }
            out += ']';
            return;
        }
        case Json::value_t::number_float: {
            const double number = value.get<double>();
            if (std::isfinite(number))
                append_number_text(out, number);
            else
                out += "null";
            return;
        }
        case Json::value_t::string: append_string(value.get_ref<const std::string&>()); return;
        default: out += value.dump(-1, ' ', false, Json::error_handler_t::replace); return;
    }
}

//! append_json into a new string.
inline std::string json_text(const nlohmann::json& value) {
    std::string out;
    append_json(out, value);
    return out;
}

}  // namespace surfaced
