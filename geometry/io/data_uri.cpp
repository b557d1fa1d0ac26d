// Base64 data: URIs: see data_uri.h.
#include "geometry/io/data_uri.h"

#include <array>
#include <cstdint>
#include <string>

namespace surfaced::io_detail {

namespace {

constexpr unsigned char kInvalid = 0xff;

constexpr std::array<unsigned char, 256> make_table() {
    std::array<unsigned char, 256> table{};
    table.fill(kInvalid);
    constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    for (unsigned char i = 0; i < 64; ++i) table[static_cast<unsigned char>(kAlphabet[i])] = i;
    return table;
}
constexpr std::array<unsigned char, 256> kTable = make_table();

bool iequals_ascii(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i) {
        char x = a[i], y = b[i];
        if (x >= 'A' && x <= 'Z') x = static_cast<char>(x - 'A' + 'a');
        if (y >= 'A' && y <= 'Z') y = static_cast<char>(y - 'A' + 'a');
        if (x != y) return false;
    }
    return true;
}

//! A character for an error message: itself when printable, else its code.
std::string describe(char c) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x21 && u < 0x7f) return std::string("'") + c + "'";
    static constexpr char kHex[] = "0123456789abcdef";
    return std::string("byte 0x") + kHex[u >> 4] + kHex[u & 15];
}

}  // namespace

bool is_data_uri(std::string_view uri) { return uri.size() >= 5 && iequals_ascii(uri.substr(0, 5), "data:"); }

Result<std::vector<unsigned char>> decode_base64(std::string_view text) {
    if (text.size() % 4 != 0)
        return make_error(ErrorCode::ParseError, "base64 data of " + std::to_string(text.size()) +
                                                     " characters is not padded to a multiple of 4 with '='");
    std::size_t padding = 0;
    if (!text.empty() && text.back() == '=') ++padding;
    if (text.size() >= 2 && text[text.size() - 2] == '=') ++padding;
    std::vector<unsigned char> out;
    out.reserve(text.size() / 4 * 3);
    std::uint32_t group = 0;
    for (std::size_t i = 0; i < text.size() - padding; ++i) {
        const unsigned char value = kTable[static_cast<unsigned char>(text[i])];
        if (value == kInvalid)
            return make_error(ErrorCode::ParseError, "base64 data has " + describe(text[i]) + " at character " +
                                                         std::to_string(i) +
                                                         (text[i] == '=' ? " (padding before the end)" : ""));
        group = (group << 6) | value;
        if (i % 4 == 3) {
            out.push_back(static_cast<unsigned char>(group >> 16));
            out.push_back(static_cast<unsigned char>(group >> 8));
            out.push_back(static_cast<unsigned char>(group));
            group = 0;
        }
    }
    // The last group: "xx==" holds one byte, "xxx=" two; the bits the padding leaves over must be zero.
    if (padding == 2) {
        if ((group & 0xf) != 0) return make_error(ErrorCode::ParseError, "base64 data has stray bits before its '=='");
        out.push_back(static_cast<unsigned char>(group >> 4));
    } else if (padding == 1) {
        if ((group & 0x3) != 0) return make_error(ErrorCode::ParseError, "base64 data has stray bits before its '='");
        out.push_back(static_cast<unsigned char>(group >> 10));
        out.push_back(static_cast<unsigned char>(group >> 2));
    }
    return out;
}

Result<std::vector<unsigned char>> decode_data_uri(std::string_view uri,
                                                   std::initializer_list<std::string_view> media_types) {
    if (!is_data_uri(uri)) return make_error(ErrorCode::ParseError, "is not a data: URI");
    const std::size_t comma = uri.find(',');
    if (comma == std::string_view::npos) return make_error(ErrorCode::ParseError, "data: URI has no ','");
    std::string_view header = uri.substr(5, comma - 5);
    constexpr std::string_view kBase64 = ";base64";
    if (header.size() < kBase64.size() || !iequals_ascii(header.substr(header.size() - kBase64.size()), kBase64))
        return make_error(ErrorCode::Unsupported, "data: URI is not base64 (\";base64,\" expected)");
    header.remove_suffix(kBase64.size());
    bool known = false;
    for (std::string_view type : media_types) known = known || iequals_ascii(header, type);
    if (!known) {
        std::string expected;
        for (std::string_view type : media_types) expected += (expected.empty() ? "" : " or ") + std::string(type);
        return make_error(ErrorCode::Unsupported, "data: URI has media type \"" + std::string(header.substr(0, 100)) +
                                                      "\" (expected " + expected + ")");
    }
    return decode_base64(uri.substr(comma + 1));
}

}  // namespace surfaced::io_detail
