// Base64 (RFC 4648, standard alphabet, '=' padding): how glTF JSON embeds its buffers and how JSON answers carry
// packed binary arrays. Decoding is strict (the alphabet, padding to whole groups of four, zero stray bits, nothing
// else), so damaged data is an error that says where rather than silently shorter data.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "geometry/core/result.h"

namespace surfaced {

//! The base64 text of `bytes`, padded.
std::string encode_base64(std::string_view bytes);

//! The decoded bytes, or a ParseError naming the first bad character (and its index in `text`) or the padding
//! problem. The output is 3/4 of the input, so it is bounded by what was received.
Result<std::vector<unsigned char>> decode_base64(std::string_view text);

//! The number of bytes `text` decodes to when it is well-formed (for budgets before decoding).
inline std::size_t decoded_base64_size(std::string_view text) {
    std::size_t padding = 0;
    if (!text.empty() && text.back() == '=') ++padding;
    if (text.size() >= 2 && text[text.size() - 2] == '=') ++padding;
    return text.size() / 4 * 3 - (text.size() % 4 == 0 ? padding : 0);
}

}  // namespace surfaced
