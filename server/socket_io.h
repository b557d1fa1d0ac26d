// Socket helpers of the connection handling, bounded in time with poll(): reading and discarding what a peer sends,
// sending a whole answer, and the addresses of a connected socket.
#pragma once

#include <chrono>
#include <cstddef>
#include <string>
#include <string_view>

namespace surfaced::server {

//! Milliseconds from now until `deadline`, for poll(): 0 once it has passed, at most 1'000'000.
int millis_until(std::chrono::steady_clock::time_point deadline);

//! Reads and discards what the peer sends for up to `budget` (or until EOF / `max_bytes`); with `until_head`,
//! stops once a blank line ends a request head.
void discard_input(int fd, std::chrono::milliseconds budget, std::size_t max_bytes, bool until_head);

//! Sends all of `bytes` within `budget`; false when the time runs out or the peer is gone.
bool send_all(int fd, std::string_view bytes, std::chrono::milliseconds budget);

//! The IP address and port of the socket's own end (`local`) or of its peer; left unchanged when the socket has
//! none, `ip` empty for a family other than IPv4/IPv6.
void address_and_port(int fd, bool local, std::string& ip, int& port);

//! The peer's IP address, "" when unknown.
std::string peer_address(int fd);

}  // namespace surfaced::server
