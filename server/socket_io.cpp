#include "server/socket_io.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>

#include <algorithm>
#include <array>
#include <cerrno>

namespace surfaced::server {

using Clock = std::chrono::steady_clock;

int millis_until(Clock::time_point deadline) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    return left <= 0 ? 0 : static_cast<int>(std::min<long long>(left, 1'000'000));
}

void discard_input(int fd, std::chrono::milliseconds budget, std::size_t max_bytes, bool until_head) {
    const auto deadline = Clock::now() + budget;
    std::array<char, 4096> buffer;
    std::string tail;
    std::size_t total = 0;
    while (total < max_bytes) {
        pollfd pfd{fd, POLLIN, 0};
        if (poll(&pfd, 1, millis_until(deadline)) <= 0) return;
        const ssize_t n = recv(fd, buffer.data(), buffer.size(), MSG_DONTWAIT);
        if (n <= 0) return;
        total += static_cast<std::size_t>(n);
        if (until_head) {
            tail.append(buffer.data(), static_cast<std::size_t>(n));
            if (tail.find("\r\n\r\n") != std::string::npos) return;
            if (tail.size() > 4) tail.erase(0, tail.size() - 4);
        }
    }
}

bool send_all(int fd, std::string_view bytes, std::chrono::milliseconds budget) {
    const auto deadline = Clock::now() + budget;
    while (!bytes.empty()) {
        pollfd pfd{fd, POLLOUT, 0};
        if (poll(&pfd, 1, millis_until(deadline)) <= 0) return false;
        const ssize_t n = send(fd, bytes.data(), bytes.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
        if (n < 0 && (errno == EAGAIN || errno == EINTR)) continue;
        if (n <= 0) return false;
        bytes.remove_prefix(static_cast<std::size_t>(n));
    }
    return true;
}

void address_and_port(int fd, bool local, std::string& ip, int& port) {
    sockaddr_storage addr{};
    socklen_t len = sizeof addr;
    const int rc = local ? getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len)
                         : getpeername(fd, reinterpret_cast<sockaddr*>(&addr), &len);
    if (rc != 0) return;
    char text[INET6_ADDRSTRLEN] = {};
    if (addr.ss_family == AF_INET) {
        const auto* in = reinterpret_cast<sockaddr_in*>(&addr);
        inet_ntop(AF_INET, &in->sin_addr, text, sizeof text);
        port = ntohs(in->sin_port);
    } else if (addr.ss_family == AF_INET6) {
        const auto* in6 = reinterpret_cast<sockaddr_in6*>(&addr);
        inet_ntop(AF_INET6, &in6->sin6_addr, text, sizeof text);
        port = ntohs(in6->sin6_port);
    }
    ip = text;
}

std::string peer_address(int fd) {
    std::string ip;
    int port = 0;
    address_and_port(fd, false, ip, port);
    return ip;
}

}  // namespace surfaced::server
