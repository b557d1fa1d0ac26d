// The Accept header (RFC 9110 section 12.5.1): which of the media types an endpoint can answer with a client prefers.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string_view>

namespace surfaced::api {

//! The index into `offered` (lower-case "type/subtype" names) of the type `accept` prefers: each offered type takes
//! the quality (q, default 1) of the most specific range that matches it (type/subtype over type/* over */*; media
//! type parameters other than q are ignored), the highest quality above 0 wins, and a tie goes to `preferred`, else
//! to the earlier offered type. nullopt when `accept` accepts none of them. A header without a single well-formed
//! range (empty, or only "text", "*/json" or a bad q) accepts everything: `preferred`.
std::optional<std::size_t> negotiate_media_type(std::string_view accept, std::span<const std::string_view> offered,
                                                std::size_t preferred);

}  // namespace surfaced::api
