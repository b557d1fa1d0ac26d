// Internal to geo_gltf: base64 `data:` URIs (RFC 2397), the way glTF JSON embeds its buffers. Decoding is strict
// (RFC 4648 alphabet, '=' padding to whole groups of four, nothing else), so a damaged buffer is an error that says
// where rather than a silently shorter one.
#pragma once

#include <initializer_list>
#include <string_view>
#include <vector>

#include "geometry/core/result.h"

namespace surfaced::io_detail {

//! True for any `data:` URI (the scheme is case-insensitive); false for a relative path or another scheme.
bool is_data_uri(std::string_view uri);

//! Strict base64: the decoded bytes, or a ParseError naming the first bad character (and its index in `text`) or the
//! padding problem. The output is 3/4 of the input, so it is bounded by what was received.
Result<std::vector<unsigned char>> decode_base64(std::string_view text);

//! The bytes of `data:MEDIA_TYPE;base64,DATA` when MEDIA_TYPE is one of `media_types`: Unsupported for another
//! media type or a data URI that is not base64, ParseError for bad base64. Messages name no owner: the caller
//! prefixes where the URI came from.
Result<std::vector<unsigned char>> decode_data_uri(std::string_view uri,
                                                   std::initializer_list<std::string_view> media_types);

}  // namespace surfaced::io_detail
