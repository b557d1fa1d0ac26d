// How every text output of the service prints a number (OBJ, OFF, ascii PLY, the JSON mesh and stats, response
// headers, the text glTF's JSON): the shortest decimal text that reads back as the same double, so a round trip
// through any text format is exact. Two conventions on top of std::to_chars' shortest form:
//  - an integral value prints without a fraction ("1", not "1.0"), as to_chars and JSON integers do;
//  - negative zero prints as "0" (it reads back as +0, the same point).
// Standard library only, so the writers (geo_formats) and the API layer share it.
#pragma once

#include <charconv>
#include <string>

namespace surfaced {

//! Appends the shortest round-trip text of `value` ("0.1", "1", "1e+300", "-2.5"); -0 as "0". Non-finite values
//! print as to_chars spells them ("inf", "nan"); callers that write JSON handle those before.
inline void append_number_text(std::string& out, double value) {
    if (value == 0) value = 0;  // -0 == 0: prints as "0"
    char buffer[32];
    const std::to_chars_result r = std::to_chars(buffer, buffer + sizeof(buffer), value);
    out.append(buffer, r.ptr);
}

//! append_number_text into a new string.
inline std::string number_text(double value) {
    std::string out;
    append_number_text(out, value);
    return out;
}

}  // namespace surfaced
