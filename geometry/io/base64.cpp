// Base64: see base64.h.
#include "geometry/io/base64.h"

#include <array>
#include <cstdint>

namespace surfaced {

namespace {

constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

constexpr unsigned char kInvalid = 0xff;

constexpr std::array<unsigned char, 256> make_table() {
    std::array<unsigned char, 256> table{};
    table.fill(kInvalid);
    for (unsigned char i = 0; i < 64; ++i) table[static_cast<unsigned char>(kAlphabet[i])] = i;
    return table;
}
constexpr std::array<unsigned char, 256> kTable = make_table();

//! A character for an error message: itself when printable, else its code.
std::string describe(char c) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x21 && u < 0x7f) return std::string("'") + c + "'";
    static constexpr char kHex[] = "0123456789abcdef";
    return std::string("byte 0x") + kHex[u >> 4] + kHex[u & 15];
}

}  // namespace

std::string encode_base64(std::string_view bytes) {
    std::string out;
    out.reserve((bytes.size() + 2) / 3 * 4);
    std::size_t i = 0;
    for (; i + 2 < bytes.size(); i += 3) {
        const std::uint32_t n = (std::uint32_t(std::uint8_t(bytes[i])) << 16) |
                                (std::uint32_t(std::uint8_t(bytes[i + 1])) << 8) | std::uint8_t(bytes[i + 2]);
        out += kAlphabet[(n >> 18) & 63];
        out += kAlphabet[(n >> 12) & 63];
        out += kAlphabet[(n >> 6) & 63];
        out += kAlphabet[n & 63];
    }
    if (i < bytes.size()) {
        std::uint32_t n = std::uint32_t(std::uint8_t(bytes[i])) << 16;
        if (i + 1 < bytes.size()) n |= std::uint32_t(std::uint8_t(bytes[i + 1])) << 8;
        out += kAlphabet[(n >> 18) & 63];
        out += kAlphabet[(n >> 12) & 63];
        out += i + 1 < bytes.size() ? kAlphabet[(n >> 6) & 63] : '=';
        out += '=';
    }
    return out;
}

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

}  // namespace surfaced
