// multipart/form-data (RFC 7578 over the framing of RFC 2046 section 5.1): the parts of a body, as views into it.
// Pure and bounded: the number of parts and the size of each part's header block are limited, nothing is copied but
// names and header values, and every malformed input is a 400 `malformed_multipart` naming what is wrong.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "api/errors.h"

namespace surfaced::api {

struct MultipartPart {
    std::string name;                     //!< Content-Disposition: form-data; name="..."
    std::optional<std::string> filename;  //!< its filename parameter, when given (an empty one included)
    std::string content_type;             //!< the part's Content-Type as sent; empty when absent
    std::string_view body;                //!< the part's content: a view into the parsed body
};

struct MultipartLimits {
    std::size_t max_parts = 64;           //!< parts in one body
    std::size_t max_header_bytes = 8192;  //!< the header block of one part, up to its blank line
};

//! The boundary parameter of a multipart Content-Type ("multipart/form-data; boundary=xyz", quoted or not):
//! 1 to 70 characters as RFC 2046 allows; otherwise 400 malformed_multipart.
ApiResult<std::string> multipart_boundary(std::string_view content_type);

//! The parts of `body` delimited by "--" + `boundary`: an optional preamble, each delimiter line ending in CRLF (after
//! optional blanks), the part's headers up to a blank line, its content up to CRLF and the next delimiter, and the
//! close delimiter "--boundary--" (an epilogue after it is ignored). Each part needs a Content-Disposition of type
//! form-data with a name.
ApiResult<std::vector<MultipartPart>> parse_multipart(std::string_view body, std::string_view boundary,
                                                      const MultipartLimits& limits = {});

}  // namespace surfaced::api
