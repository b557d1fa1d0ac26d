// Internal to geo_formats: what a text reader accepts as its input's encoding. UTF-8 and ASCII are read as they are
// (a UTF-8 byte order mark skipped); UTF-16 with a byte order mark, as Windows tools write it, is converted to ASCII
// first by with_text(), the one entry every text reader goes through; anything else with NUL bytes is refused.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <type_traits>

#include "geometry/core/result.h"
#include "geometry/io/text_scanner.h"

namespace surfaced::io_detail {

enum class TextEncoding { Utf8, Utf16 };

//! The byte order of a UTF-16 byte order mark at the start of `bytes`, if there is one.
inline bool utf16_bom(std::string_view bytes, bool& big_endian) {
    if (bytes.size() < 2) return false;
    const auto b0 = static_cast<unsigned char>(bytes[0]), b1 = static_cast<unsigned char>(bytes[1]);
    if (b0 == 0xff && b1 == 0xfe) {
        big_endian = false;
        return true;
    }
    if (b0 == 0xfe && b1 == 0xff) {
        big_endian = true;
        return true;
    }
    return false;
}

//! UTF-16 code units (an even number of bytes, no byte order mark) as ASCII: one output byte per character, so the
//! output is at most half the input. Every non-ASCII character (a surrogate pair, or an unpaired surrogate, included)
//! becomes '?': the formats we read spell every keyword and number in ASCII, and non-ASCII text only ever appears in
//! comments and names that we skip. Line breaks map one to one, so line numbers are those of the original file.
inline std::string utf16_to_ascii(std::string_view units, bool big_endian) {
    std::string out;
    out.reserve(units.size() / 2);
    for (std::size_t i = 0; i + 1 < units.size(); i += 2) {
        const auto hi = static_cast<unsigned char>(units[i + (big_endian ? 0 : 1)]);
        const auto lo = static_cast<unsigned char>(units[i + (big_endian ? 1 : 0)]);
        const unsigned unit = (unsigned{hi} << 8) | lo;
        if (unit >= 0xd800 && unit <= 0xdbff && i + 3 < units.size()) {
            const auto next_hi = static_cast<unsigned char>(units[i + 2 + (big_endian ? 0 : 1)]);
            if (next_hi >= 0xdc && next_hi <= 0xdf) i += 2;  // the low half of a surrogate pair: one character
        }
        out += unit < 0x80 ? static_cast<char>(unit) : '?';
    }
    return out;
}

//! Calls `read(text, encoding)` on the text of `bytes`: the bytes themselves, or, when they start with a UTF-16 byte
//! order mark, their characters converted by utf16_to_ascii (the mark dropped). Returns what `read` returns, or the
//! error for UTF-16 input that is cut in the middle of a character.
template <class Read>
auto with_text(std::string_view bytes, Read&& read) -> std::invoke_result_t<Read&, std::string_view, TextEncoding> {
    bool big_endian = false;
    if (!utf16_bom(bytes, big_endian)) return read(bytes, TextEncoding::Utf8);
    if (bytes.size() % 2 != 0)
        return error_at_offset(ErrorCode::ParseError, static_cast<std::int64_t>(bytes.size() - 1),
                               "UTF-16 text (it starts with a byte order mark) ends in the middle of a character: " +
                                   std::to_string(bytes.size()) + " bytes, an odd number");
    const std::string text = utf16_to_ascii(bytes.substr(2), big_endian);
    return read(std::string_view(text), TextEncoding::Utf16);
}

//! Rejects what a text reader cannot read (empty input, NUL bytes) and returns where the text starts (after a UTF-8
//! byte order mark, if any). NUL bytes never occur in text formats: they mean UTF-16 without a byte order mark or
//! binary data, and rejecting them up front keeps the parsers from wandering through garbage. UTF-16 with a byte
//! order mark never gets here: with_text() has converted it.
inline Result<std::size_t> check_text_encoding(std::string_view bytes) {
    if (bytes.empty()) return make_error(ErrorCode::ParseError, "empty file", -1, 0);
    std::size_t start = 0;
    if (bytes.size() >= 3 && static_cast<unsigned char>(bytes[0]) == 0xef &&
        static_cast<unsigned char>(bytes[1]) == 0xbb && static_cast<unsigned char>(bytes[2]) == 0xbf)
        start = 3;
    if (start == bytes.size()) return make_error(ErrorCode::ParseError, "empty file", -1, 0);
    if (const void* nul = std::memchr(bytes.data(), 0, bytes.size())) {
        const auto offset = static_cast<std::size_t>(static_cast<const char*>(nul) - bytes.data());
        const std::int64_t line = line_of_offset(bytes, offset);
        // ASCII text in UTF-16 has a NUL next to nearly every character.
        const bool looks_utf16 =
            bytes.size() >= 4 && (bytes[1] == 0 || bytes[0] == 0) && (bytes[3] == 0 || bytes[2] == 0);
        std::string what = looks_utf16
                               ? "UTF-16 is not supported (NUL byte at offset " + std::to_string(offset) +
                                     "): save the file as UTF-8 or ASCII"
                               : "NUL byte at offset " + std::to_string(offset) + ": binary data in a text file";
        GeoError error = error_at_line(ErrorCode::ParseError, line, what);
        error.offset = static_cast<std::int64_t>(offset);
        return error;
    }
    return start;
}

}  // namespace surfaced::io_detail
