// What the real-socket server tests (tests/server/*_test.cpp) share: an HttpServer on an ephemeral loopback port per
// test suite, httplib clients for it, raw-socket helpers for what a well-behaved client library will not send, and a
// bounded poll for a state. Header-only (the server tests link geo_server and httplib; test_support does not).
#pragma once

#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <string>
#include <thread>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "server/http_server.h"

namespace surfaced::testing {

//! Polls `condition` every 5 ms for up to `bound` (a bound for a stuck test, not a timing assertion).
inline bool eventually(const std::function<bool()>& condition,
                       std::chrono::milliseconds bound = std::chrono::milliseconds(20'000)) {
    const auto deadline = std::chrono::steady_clock::now() + bound;
    while (std::chrono::steady_clock::now() < deadline) {
        if (condition()) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return condition();
}

// ---- raw sockets ---------------------------------------------------------------------------------------------

//! A blocking loopback connection to `port`, or -1.
inline int connect_to(int port) {
    const int fd = socket(AF_INET, SOCK_STREAM, 0);
    if (fd < 0) return -1;
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<std::uint16_t>(port));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
        close(fd);
        return -1;
    }
    return fd;
}

//! Sends all of `text`; false when the peer is gone.
inline bool send_all_text(int fd, const std::string& text) {
    std::size_t sent = 0;
    while (sent < text.size()) {
        const ssize_t n = send(fd, text.data() + sent, text.size() - sent, MSG_NOSIGNAL);
        if (n <= 0) return false;
        sent += static_cast<std::size_t>(n);
    }
    return true;
}

//! Reads until the peer closes, fails (a reset: `*reset` is set) or `bound_ms` pass without a byte.
inline std::string read_until_close(int fd, int bound_ms = 20'000, bool* reset = nullptr) {
    std::string out;
    char buffer[4096];
    for (;;) {
        pollfd pfd{fd, POLLIN, 0};
        if (poll(&pfd, 1, bound_ms) <= 0) break;
        const ssize_t n = recv(fd, buffer, sizeof buffer, 0);
        if (n < 0 && reset) *reset = true;
        if (n <= 0) break;
        out.append(buffer, static_cast<std::size_t>(n));
    }
    return out;
}

//! The status of a raw HTTP/1.1 response, or -1.
inline int status_of(const std::string& response) {
    return response.rfind("HTTP/1.1 ", 0) == 0 ? std::atoi(response.c_str() + 9) : -1;
}

//! The body of a raw response (after the blank line), or "" without one.
inline std::string body_of(const std::string& response) {
    const std::size_t end = response.find("\r\n\r\n");
    return end == std::string::npos ? std::string() : response.substr(end + 4);
}

//! The value of header `name` (exact case) in a raw response, or "".
inline std::string raw_header(const std::string& response, const std::string& name) {
    const std::size_t at = response.find("\r\n" + name + ": ");
    if (at == std::string::npos || at > response.find("\r\n\r\n")) return {};
    const std::size_t begin = at + name.size() + 4;
    return response.substr(begin, response.find("\r\n", begin) - begin);
}

//! Whether a raw response is complete: a head, and exactly Content-Length bytes of body after it.
inline bool complete_response(const std::string& response) {
    const std::string length = raw_header(response, "Content-Length");
    return status_of(response) > 0 && !length.empty() &&
           body_of(response).size() == static_cast<std::size_t>(std::stoull(length));
}

//! Reads one response (head, then Content-Length bytes of body) from a connection that may stay open; what arrived
//! when the peer closes or `bound_ms` pass without a byte.
inline std::string read_one_response(int fd, int bound_ms = 20'000) {
    std::string out;
    char buffer[4096];
    for (;;) {
        const std::size_t head_end = out.find("\r\n\r\n");
        if (head_end != std::string::npos) {
            const std::string length = raw_header(out, "Content-Length");
            const std::size_t want = head_end + 4 + (length.empty() ? 0 : std::stoull(length));
            if (out.size() >= want) return out;
        }
        pollfd pfd{fd, POLLIN, 0};
        if (poll(&pfd, 1, bound_ms) <= 0) return out;
        const ssize_t n = recv(fd, buffer, sizeof buffer, 0);
        if (n <= 0) return out;
        out.append(buffer, static_cast<std::size_t>(n));
    }
}

// ---- a server per suite --------------------------------------------------------------------------------------

//! An HttpServer on an ephemeral loopback port: `config.host`/`port` are overridden.
class LoopbackServer {
public:
    explicit LoopbackServer(server::ServerConfig config) : server_(with_loopback(std::move(config))) {
        std::string error;
        started_ = server_.start(&error);
        EXPECT_TRUE(started_) << error;
        EXPECT_GT(server_.port(), 0);
    }
    bool started() const { return started_; }
    int port() const { return server_.port(); }
    server::HttpServer& server() { return server_; }
    httplib::Client client(int read_timeout_seconds = 30) const {
        httplib::Client c("127.0.0.1", server_.port());
        c.set_read_timeout(read_timeout_seconds, 0);
        return c;
    }

private:
    static server::ServerConfig with_loopback(server::ServerConfig config) {
        config.host = "127.0.0.1";
        config.port = 0;
        return config;
    }
    server::HttpServer server_;
    bool started_ = false;
};

//! A fixture whose test suite shares one LoopbackServer, started before its first test and stopped after its last.
//! `Suite` (the fixture deriving from this) may declare `static server::ServerConfig suite_config()` to change the
//! configuration (two threads, no web root by default); every suite gets its own server.
template <class Suite>
class SharedServerTest : public ::testing::Test {
public:
    static server::ServerConfig suite_config() {
        server::ServerConfig config;
        config.threads = 2;
        config.web_root = "";
        return config;
    }

protected:
    static void SetUpTestSuite() { server_ = new LoopbackServer(Suite::suite_config()); }
    static void TearDownTestSuite() {
        delete server_;  // stops and joins
        server_ = nullptr;
    }
    static httplib::Client client(int read_timeout_seconds = 30) { return server_->client(read_timeout_seconds); }
    static inline LoopbackServer* server_ = nullptr;
};

//! Status, the problem+json media type, the envelope's status/code (and field, unless empty); the parsed envelope.
inline nlohmann::json expect_http_problem(const httplib::Result& res, int status, const std::string& code,
                                          const std::string& field = {}) {
    EXPECT_TRUE(res) << httplib::to_string(res.error());
    if (!res) return {};
    EXPECT_EQ(res->status, status) << res->body;
    EXPECT_EQ(res->get_header_value("Content-Type"), "application/problem+json") << res->body;
    auto json = nlohmann::json::parse(res->body, nullptr, false);
    EXPECT_FALSE(json.is_discarded()) << res->body;
    if (json.is_discarded()) return {};
    EXPECT_EQ(json.value("status", 0), status) << res->body;
    EXPECT_EQ(json.value("code", ""), code) << res->body;
    if (!field.empty()) {
        EXPECT_EQ(json.value("field", "<none>"), field) << res->body;
    }
    return json;
}

}  // namespace surfaced::testing
