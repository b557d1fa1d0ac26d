// Fault behaviour of the server over real loopback sockets: stopping under a burst of
// connections answers every connection the kernel completed, a client trickling its request body cannot hold the
// only worker, clients that disconnect mid-request leave no in-flight or busy worker behind. Statuses, counts and
// bytes are asserted, never durations; every wait is bounded (seconds) so a regression fails instead of hanging.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "server/http_server.h"
#include "tests/support/http_test_server.h"

namespace surfaced::server {
namespace {

using namespace std::chrono_literals;
using testing::body_of;
using testing::complete_response;
using testing::connect_to;
using testing::eventually;
using testing::LoopbackServer;
using testing::raw_header;
using testing::read_until_close;
using testing::send_all_text;
using testing::status_of;

constexpr const char* kCubeObj =
    "v -0.5 -0.5 -0.5\nv 0.5 -0.5 -0.5\nv 0.5 0.5 -0.5\nv -0.5 0.5 -0.5\n"
    "v -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv 0.5 0.5 0.5\nv -0.5 0.5 0.5\n"
    "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

const std::string kLivez = "GET /livez HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n";

//! A POST /subdivide head for the cube, without its body.
std::string cube_head(const std::string& query = "format=obj") {
    return "POST /subdivide?" + query +
           " HTTP/1.1\r\nHost: x\r\nContent-Type: model/obj\r\nConnection: close\r\n"
           "Content-Length: " +
           std::to_string(std::string(kCubeObj).size()) + "\r\n\r\n";
}

//! A non-blocking loopback connect that waits at most `bound_ms` for the handshake: the socket (blocking again)
//! once connected, -1 when refused or not completed in time.
int connect_within(int port, int bound_ms) {
    const int fd = socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK, 0);
    if (fd < 0) return -1;
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<std::uint16_t>(port));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
        if (errno != EINPROGRESS) {
            close(fd);
            return -1;
        }
        pollfd pfd{fd, POLLOUT, 0};
        int error = 0;
        socklen_t length = sizeof error;
        if (poll(&pfd, 1, bound_ms) <= 0 || getsockopt(fd, SOL_SOCKET, SO_ERROR, &error, &length) != 0 || error != 0) {
            close(fd);
            return -1;
        }
    }
    fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) & ~O_NONBLOCK);
    return fd;
}

ServerConfig one_worker() {
    ServerConfig config;
    config.threads = 1;
    config.web_root = "";
    return config;
}

// While the only worker is busy, a burst of clients connects and sends complete requests; stop() starts in the
// middle of the burst. Every connection the kernel completed (connect() succeeded) must get a complete response:
// cpp-httplib's own stop() reset those still in the listen backlog (wrk counted them as read errors).
TEST(Faults, StopAnswersEveryConnectionTheKernelCompleted) {
    ServerConfig config = one_worker();
    config.queue_capacity = 512;  // nothing is shed: every completed connection is served, 200
    LoopbackServer s(config);
    ASSERT_TRUE(s.started());
    const std::string expected_body = [&] {
        auto res = s.client().Get("/livez");
        return res ? res->body : std::string();
    }();
    ASSERT_FALSE(expected_body.empty());

    // A holds the only worker: its head is in, its body is not.
    const int a = connect_to(s.port());
    ASSERT_GE(a, 0);
    ASSERT_TRUE(send_all_text(a, cube_head()));
    ASSERT_TRUE(eventually([&] { return s.server().stats().busy_workers == 1 && s.server().stats().in_flight == 1; }));

    // 100 clients connect and send one at a time (all accepted into the queue), then stop() is signalled and 300
    // more connect without waiting for each other: the kernel completes handshakes faster than one thread accepts
    // them, so some are still in the listen backlog when the drain begins.
    constexpr int kBefore = 100, kBurst = 300;
    std::vector<int> connected;
    std::atomic<bool> stop_now{false};
    // (a jthread: should an assertion end the test early, its destructor still stops the server and joins)
    std::jthread stopper([&](std::stop_token token) {
        while (!stop_now.load() && !token.stop_requested()) std::this_thread::sleep_for(1ms);
        s.server().stop();
    });
    for (int i = 0; i < kBefore; ++i) {
        const int fd = connect_within(s.port(), 3000);
        ASSERT_GE(fd, 0);
        connected.push_back(fd);
        ASSERT_TRUE(send_all_text(fd, kLivez));
    }
    stop_now = true;
    std::vector<int> pending;
    int refused = 0;
    for (int i = 0; i < kBurst; ++i) {
        const int fd = socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK, 0);
        ASSERT_GE(fd, 0);
        sockaddr_in addr{};
        addr.sin_family = AF_INET;
        addr.sin_port = htons(static_cast<std::uint16_t>(s.port()));
        addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        if (connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0 || errno == EINPROGRESS) {
            pending.push_back(fd);
        } else {
            close(fd);
            ++refused;
        }
    }
    // Each either completes (then it must be answered) or is refused once the listening socket has closed (its
    // client knows the request was never sent). A SYN dropped while draining is retried after ~1 s and refused.
    const auto resolve_by = std::chrono::steady_clock::now() + 10s;
    for (const int fd : pending) {
        pollfd pfd{fd, POLLOUT, 0};
        const auto left =
            std::chrono::duration_cast<std::chrono::milliseconds>(resolve_by - std::chrono::steady_clock::now());
        int error = 0;
        socklen_t length = sizeof error;
        if (poll(&pfd, 1, static_cast<int>(std::max<long long>(0, left.count()))) <= 0 ||
            getsockopt(fd, SOL_SOCKET, SO_ERROR, &error, &length) != 0 || error != 0) {
            close(fd);
            ++refused;
            continue;
        }
        fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) & ~O_NONBLOCK);
        connected.push_back(fd);
        send_all_text(fd, kLivez);  // may fail if the server reset it: then the read below fails the test
    }
    stop_now = true;
    ASSERT_TRUE(eventually([&] { return s.server().stats().draining; }));
    // Now free the worker: A's body arrives and it is answered, then everything queued behind it.
    ASSERT_TRUE(send_all_text(a, kCubeObj));
    const std::string a_answer = read_until_close(a);
    close(a);
    EXPECT_EQ(status_of(a_answer), 200) << a_answer.substr(0, 200);
    EXPECT_TRUE(complete_response(a_answer));

    int complete = 0, resets = 0;
    for (const int& fd : connected) {
        bool reset = false;
        const std::string answer = read_until_close(fd, 20'000, &reset);
        close(fd);
        resets += reset ? 1 : 0;
        if (status_of(answer) == 200 && complete_response(answer) && body_of(answer) == expected_body &&
            raw_header(answer, "Connection") == "close")
            ++complete;
        else
            ADD_FAILURE() << "connection " << &fd - connected.data() << (reset ? " was reset" : "") << ": "
                          << answer.substr(0, 200);
    }
    stopper.join();
    EXPECT_GE(connected.size(), static_cast<std::size_t>(kBefore));
    EXPECT_EQ(complete, static_cast<int>(connected.size())) << resets << " resets, " << refused << " refused";
    EXPECT_EQ(resets, 0);
    // and nobody listens any more
    EXPECT_LT(connect_within(s.port(), 1000), 0);
}

// A client sends its head, then trickles its body a byte at a time. With one worker and a 1 s body timeout, it is
// answered 408 problem+json and closed, and a second client waiting for the worker gets its 200.
TEST(Faults, TricklingBodyIsCutOffWith408AndFreesTheWorker) {
    ServerConfig config = one_worker();
    config.body_timeout_seconds = 1;
    config.body_min_rate_bytes = 1024;  // a byte per 100 ms earns 10 ms per second: the deadline stays near 1 s
    config.read_timeout_seconds = 60;   // the per-read timeout alone would never end it
    LoopbackServer s(config);
    ASSERT_TRUE(s.started());
    const int slow = connect_to(s.port());
    ASSERT_GE(slow, 0);
    ASSERT_TRUE(send_all_text(slow, cube_head()));
    ASSERT_TRUE(eventually([&] { return s.server().stats().in_flight == 1; }));
    std::atomic<bool> done{false};
    std::thread trickle([&] {
        // at most 15 s of trickling (far past the 1 s body timeout), ending early once the server closes
        const std::string body = kCubeObj;
        for (std::size_t i = 0; i < body.size() && !done.load() && i < 150; ++i) {
            if (send(slow, body.data() + i, 1, MSG_NOSIGNAL) != 1) break;
            std::this_thread::sleep_for(100ms);
        }
    });
    httplib::Client other = s.client(15);
    auto res = other.Get("/livez");  // waits in the queue behind the trickler
    const std::string answer = read_until_close(slow);
    done = true;
    trickle.join();
    close(slow);

    ASSERT_TRUE(res) << "the second client was not served: " << httplib::to_string(res.error());
    EXPECT_EQ(res->status, 200);
    EXPECT_EQ(status_of(answer), 408) << answer.substr(0, 300);
    EXPECT_EQ(raw_header(answer, "Content-Type"), "application/problem+json");
    EXPECT_EQ(raw_header(answer, "Connection"), "close");
    EXPECT_EQ(raw_header(answer, "Keep-Alive"), "");
    const auto problem = nlohmann::json::parse(body_of(answer), nullptr, false);
    ASSERT_FALSE(problem.is_discarded()) << answer;
    EXPECT_EQ(problem.value("status", 0), 408);
    EXPECT_EQ(problem.value("code", ""), "body_timeout");
    EXPECT_TRUE(eventually([&] { return s.server().stats().in_flight == 0 && s.server().stats().busy_workers == 0; }));
}

// A body that arrives steadily faster than the minimum rate is never cut off, however long it takes in total.
TEST(Faults, BodyFasterThanTheMinimumRateIsServed) {
    ServerConfig config = one_worker();
    config.body_timeout_seconds = 1;
    config.body_min_rate_bytes = 16;  // 16 bytes earn a second
    LoopbackServer s(config);
    ASSERT_TRUE(s.started());
    const int fd = connect_to(s.port());
    ASSERT_GE(fd, 0);
    ASSERT_TRUE(send_all_text(fd, cube_head()));
    // 64-byte pieces every 200 ms (320 B/s, 20x the minimum): about 2 s in all, twice the bare body timeout
    const std::string body = kCubeObj;
    for (std::size_t at = 0; at < body.size(); at += 64) {
        ASSERT_TRUE(send_all_text(fd, body.substr(at, 64)));
        std::this_thread::sleep_for(200ms);
    }
    const std::string answer = read_until_close(fd);
    close(fd);
    EXPECT_EQ(status_of(answer), 200) << answer.substr(0, 300);
    EXPECT_TRUE(complete_response(answer));
}

// Clients that send half a body, or a whole request, and close without reading leave nothing behind: the in-flight
// and busy-worker gauges return to 0 (/metrics then shows only its own request) and the server still answers.
TEST(Faults, ClientsThatDisconnectMidRequestDoNotLeak) {
    ServerConfig config = one_worker();
    config.threads = 2;
    LoopbackServer s(config);
    ASSERT_TRUE(s.started());
    constexpr int kClients = 12;
    const std::string half = std::string(kCubeObj).substr(0, std::string(kCubeObj).size() / 2);
    for (int i = 0; i < kClients; ++i) {
        const int fd = connect_to(s.port());
        ASSERT_GE(fd, 0);
        switch (i % 3) {
            case 0: send_all_text(fd, cube_head() + half); break;                           // half a body
            case 1: send_all_text(fd, cube_head("levels=5&format=obj") + kCubeObj); break;  // a whole request
            default: send_all_text(fd, "POST /subdivide HTTP/1.1\r\nHost: x\r\n"); break;   // half a head
        }
        close(fd);
    }
    // The accept loop and the workers take connections in order: once a later request is answered, every one of
    // them has been taken up (and the gauges below cannot read 0 merely because one still waits in the backlog).
    const int marker = connect_to(s.port());
    ASSERT_GE(marker, 0);
    ASSERT_TRUE(send_all_text(marker, kLivez));
    EXPECT_EQ(status_of(read_until_close(marker)), 200);
    close(marker);
    ASSERT_TRUE(eventually([&] {
        const ServerStats stats = s.server().stats();
        return stats.in_flight == 0 && stats.busy_workers == 0 && stats.queue_depth == 0;
    }));
    auto metrics = s.client().Get("/metrics");
    ASSERT_TRUE(metrics);
    ASSERT_EQ(metrics->status, 200);
    EXPECT_NE(metrics->body.find("\nsurfaced_http_requests_in_flight 1\n"), std::string::npos) << metrics->body;
    EXPECT_NE(metrics->body.find("\nsurfaced_http_workers_busy 1\n"), std::string::npos) << metrics->body;
    EXPECT_NE(metrics->body.find("\nsurfaced_http_queue_depth 0\n"), std::string::npos) << metrics->body;
    for (int i = 0; i < 4; ++i) {
        auto res = s.client().Post("/subdivide?format=obj", kCubeObj, "model/obj");
        ASSERT_TRUE(res) << httplib::to_string(res.error());
        EXPECT_EQ(res->status, 200);
        EXPECT_EQ(res->get_header_value("X-Output-Faces"), "24");
    }
    EXPECT_EQ(s.server().stats().shed_total, 0u);
}

}  // namespace
}  // namespace surfaced::server
