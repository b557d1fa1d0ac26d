// The problem+json answers the HTTP layer gives by itself (the operations build their own in api/): overload, a
// missing or wrong bearer token, a disallowed CORS origin, a body too slow, the errors the HTTP library produces
// itself (no route, body too large, unparsable request), and the fail-safe 500.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "api/operation.h"

namespace surfaced::server {

//! A problem+json response with the given status, machine-readable code, title and detail.
api::ApiResponse problem(int status, std::string code, std::string title, std::string detail);

//! 503 `overloaded`: every worker busy and the queue of waiting connections full.
api::ApiResponse overloaded_problem(int threads, std::size_t queue_capacity);

//! 401 with WWW-Authenticate; `had_token`: an Authorization header was sent but is not the token.
api::ApiResponse unauthorized_problem(bool had_token);

//! 403 `origin_not_allowed` for a CORS preflight from `origin`.
api::ApiResponse origin_not_allowed_problem(const std::string& origin);

//! 408 `body_timeout`, naming the body deadline (see ServerConfig::body_timeout_seconds).
api::ApiResponse body_timeout_problem(int body_timeout_seconds, std::size_t body_min_rate_bytes);

//! 413 `payload_too_large` for a Content-Length of `length` bytes over `max_body_bytes`, before any of it is read.
api::ApiResponse declared_body_too_large_problem(std::uint64_t length, std::size_t max_body_bytes);

//! The problem for an error status the HTTP library produced itself (404/405 for no route, 413 past
//! `max_body_bytes`, 400 for an unparsable request, another status as is).
api::ApiResponse library_error_problem(int status, std::string_view method, std::string_view path,
                                       std::size_t max_body_bytes);

//! 500 `internal`: the fail-safe for a handler that threw.
api::ApiResponse internal_error_problem();

}  // namespace surfaced::server
