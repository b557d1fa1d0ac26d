// Internal to geo_gltf: base64 `data:` URIs (RFC 2397), the way glTF JSON embeds its buffers (the base64 itself:
// geometry/io/base64.h, strict).
#pragma once

#include <initializer_list>
#include <string_view>
#include <vector>

#include "geometry/core/result.h"

namespace surfaced::io_detail {

//! True for any `data:` URI (the scheme is case-insensitive); false for a relative path or another scheme.
bool is_data_uri(std::string_view uri);

//! The bytes of `data:MEDIA_TYPE;base64,DATA` when MEDIA_TYPE is one of `media_types`: Unsupported for another
//! media type or a data URI that is not base64, ParseError for bad base64. Messages name no owner: the caller
//! prefixes where the URI came from.
Result<std::vector<unsigned char>> decode_data_uri(std::string_view uri,
                                                   std::initializer_list<std::string_view> media_types);

}  // namespace surfaced::io_detail
