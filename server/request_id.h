// Request ids (X-Request-Id): a client's own id is kept when it is sane, otherwise the server makes a random one.
#pragma once

#include <string>
#include <string_view>

namespace surfaced::server {

//! Whether an incoming X-Request-Id may be kept: 1..128 characters of [A-Za-z0-9._:-].
bool sane_request_id(std::string_view id);

//! A new random id: 32 lowercase hex digits.
std::string new_request_id();

}  // namespace surfaced::server
