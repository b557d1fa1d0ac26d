// Production behaviour of the server: probes, metrics, request ids, bounded queue (503 shedding), compute deadline,
// keep-alive limits, idle connections, auth, CORS, static-file confinement, healthcheck and SIGTERM draining.
// Statuses and counters are asserted, never durations; waits for a state poll for it with a generous bound.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "server/http_server.h"
#include "tests/support/http_test_server.h"

namespace surfaced::server {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using testing::connect_to;
using testing::eventually;
using testing::read_until_close;
using testing::status_of;

constexpr const char* kCubeObj =
    "v -0.5 -0.5 -0.5\nv 0.5 -0.5 -0.5\nv 0.5 0.5 -0.5\nv -0.5 0.5 -0.5\n"
    "v -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv 0.5 0.5 0.5\nv -0.5 0.5 0.5\n"
    "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

//! An n x n grid of quads as OBJ: big enough that refining it takes far longer than a millisecond.
std::string grid_obj(int n) {
    std::ostringstream out;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) out << "v " << i << ' ' << j << " 0\n";
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const int a = j * (n + 1) + i + 1;
            out << "f " << a << ' ' << a + 1 << ' ' << a + n + 2 << ' ' << a + n + 1 << "\n";
        }
    return out.str();
}

fs::path make_temp_dir(const std::string& tag) {
    std::random_device rd;
    const fs::path dir = fs::temp_directory_path() / ("surfaced-" + tag + "-" + std::to_string(rd()));
    fs::create_directories(dir);
    return dir;
}

// ---- raw sockets, for what a well-behaved client library will not send --------------------------------------

void send_text(int fd, const std::string& text) {
    ASSERT_EQ(send(fd, text.data(), text.size(), MSG_NOSIGNAL), static_cast<ssize_t>(text.size()));
}

//! Reads one response (head + Content-Length body) from a kept-alive connection.
std::string read_response(int fd) {
    std::string out;
    char c = 0;
    while (out.find("\r\n\r\n") == std::string::npos) {
        pollfd pfd{fd, POLLIN, 0};
        if (poll(&pfd, 1, 20'000) <= 0 || recv(fd, &c, 1, 0) != 1) return out;
        out += c;
    }
    std::smatch m;
    std::size_t length = 0;
    if (std::regex_search(out, m, std::regex("Content-Length: *([0-9]+)", std::regex::icase)))
        length = std::stoul(m[1]);
    std::string body(length, '\0');
    std::size_t got = 0;
    while (got < length) {
        pollfd pfd{fd, POLLIN, 0};
        if (poll(&pfd, 1, 20'000) <= 0) break;
        const ssize_t n = recv(fd, body.data() + got, length - got, 0);
        if (n <= 0) break;
        got += static_cast<std::size_t>(n);
    }
    return out + body.substr(0, got);
}

// ---- Prometheus text ----------------------------------------------------------------------------------------

//! Parses the text exposition; every sample line must be `name{labels} value`. Key: the line's name and labels.
std::map<std::string, double> parse_prometheus(const std::string& text) {
    static const std::regex sample(
        R"(^([a-zA-Z_:][a-zA-Z0-9_:]*(\{([a-zA-Z_][a-zA-Z0-9_]*="([^"\\]|\\.)*",?)*\})?) (\S+)$)");
    static const std::regex comment(R"(^# (HELP|TYPE) [a-zA-Z_:][a-zA-Z0-9_:]* .+$)");
    std::map<std::string, double> out;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty()) continue;
        if (line[0] == '#') {
            EXPECT_TRUE(std::regex_match(line, comment)) << line;
            continue;
        }
        std::smatch m;
        EXPECT_TRUE(std::regex_match(line, m, sample)) << line;
        if (!m.empty()) out[m[1]] = std::stod(m[5]);
    }
    return out;
}

double value_or_zero(const std::map<std::string, double>& metrics, const std::string& key) {
    const auto it = metrics.find(key);
    return it == metrics.end() ? 0.0 : it->second;
}

// ---- an in-process server per test ----------------------------------------------------------------------------

struct Running {
    explicit Running(ServerConfig config) : server(std::move(config)) {
        std::string error;
        EXPECT_TRUE(server.start(&error)) << error;
    }
    httplib::Client client() const {
        httplib::Client c("127.0.0.1", server.port());
        c.set_read_timeout(30, 0);
        return c;
    }
    std::map<std::string, double> metrics() const {
        auto res = client().Get("/metrics");
        EXPECT_TRUE(res);
        if (!res) return {};
        EXPECT_EQ(res->status, 200);
        EXPECT_EQ(res->get_header_value("Content-Type").rfind("text/plain; version=0.0.4", 0), 0u);
        return parse_prometheus(res->body);
    }
    //! The metrics once `ready` holds for them: a request is counted after its last byte is written, so a client
    //! can see its answer a moment before the counters do.
    std::map<std::string, double> metrics_when(
        const std::function<bool(const std::map<std::string, double>&)>& ready) const {
        std::map<std::string, double> out;
        EXPECT_TRUE(eventually([&] {
            out = metrics();
            return ready(out);
        }));
        return out;
    }
    HttpServer server;
};

ServerConfig base_config() {
    ServerConfig config;
    config.port = 0;
    config.threads = 2;
    config.web_root = "";
    return config;
}

nlohmann::json problem_of(const httplib::Result& res) {
    EXPECT_EQ(res->get_header_value("Content-Type"), "application/problem+json");
    return nlohmann::json::parse(res->body);
}

TEST(Production, ProbesAndReadinessWhileDraining) {
    Running s(base_config());
    for (const char* path : {"/livez", "/readyz", "/healthz"}) {
        auto res = s.client().Get(path);
        ASSERT_TRUE(res) << path;
        EXPECT_EQ(res->status, 200) << path;
    }
    s.server.begin_drain();
    EXPECT_TRUE(s.server.stats().draining);
    auto ready = s.client().Get("/readyz");
    ASSERT_TRUE(ready);
    EXPECT_EQ(ready->status, 503);
    EXPECT_EQ(problem_of(ready)["code"], "draining");
    EXPECT_FALSE(ready->get_header_value("Retry-After").empty());
    auto live = s.client().Get("/livez");
    ASSERT_TRUE(live);
    EXPECT_EQ(live->status, 200);
    EXPECT_EQ(s.metrics().at("surfaced_draining"), 1.0);
}

TEST(Production, RequestIdIsEchoedWhenSaneAndGeneratedOtherwise) {
    Running s(base_config());
    auto kept = s.client().Get("/livez", {{"X-Request-Id", "trace-42.a:b_c"}});
    ASSERT_TRUE(kept);
    EXPECT_EQ(kept->get_header_value("X-Request-Id"), "trace-42.a:b_c");
    for (const std::string& bad : {std::string("has space"), std::string(200, 'x'), std::string("{\"json\":1}")}) {
        auto replaced = s.client().Get("/livez", {{"X-Request-Id", bad}});
        ASSERT_TRUE(replaced);
        const std::string id = replaced->get_header_value("X-Request-Id");
        EXPECT_TRUE(std::regex_match(id, std::regex("[0-9a-f]{32}"))) << id;
    }
    auto error = s.client().Get("/no/such/route");  // errors carry an id too
    ASSERT_TRUE(error);
    EXPECT_EQ(error->status, 404);
    EXPECT_EQ(error->get_header_value("X-Request-Id").size(), 32u);
}

TEST(Production, MetricsCountRequestsBytesAndFaces) {
    Running s(base_config());
    const auto before = s.metrics();
    const std::string key = R"(surfaced_http_requests_total{route="/subdivide",method="POST",status="200"})";
    EXPECT_EQ(value_or_zero(before, key), 0.0);
    double faces = 0;
    for (int i = 0; i < 3; ++i) {
        auto res = s.client().Post("/subdivide?levels=2&format=obj", kCubeObj, "model/obj");
        ASSERT_TRUE(res);
        ASSERT_EQ(res->status, 200);
        faces += std::stod(res->get_header_value("X-Output-Faces"));
    }
    auto bad = s.client().Post("/subdivide?levels=oops", kCubeObj, "model/obj");
    ASSERT_TRUE(bad);
    ASSERT_EQ(bad->status, 400);
    auto missing = s.client().Get("/nowhere/../x");
    ASSERT_TRUE(missing);
    {  // an unparsable request line with a made-up method: 400, counted under method "other"
        const int fd = connect_to(s.server.port());
        send_text(fd, "BREW /pot HTTP/1.1\r\nHost: x\r\n\r\n");
        EXPECT_EQ(status_of(read_until_close(fd)), 400);
        close(fd);
    }

    const auto after = s.metrics_when([&](const auto& m) {
        return value_or_zero(m, key) == 3.0 &&
               value_or_zero(m, R"(surfaced_http_requests_total{route="unmatched",method="other",status="400"})") ==
                   1.0 &&
               value_or_zero(m, R"(surfaced_http_requests_total{route="unmatched",method="GET",status="404"})") ==
                   1.0 &&
               value_or_zero(m, R"(surfaced_http_requests_total{route="/subdivide",method="POST",status="400"})") ==
                   1.0;
    });
    EXPECT_EQ(after.at(key), 3.0);
    EXPECT_EQ(after.at(R"(surfaced_http_requests_total{route="/subdivide",method="POST",status="400"})"), 1.0);
    EXPECT_EQ(after.at(R"(surfaced_http_requests_total{route="unmatched",method="GET",status="404"})"), 1.0);
    EXPECT_EQ(after.at(R"(surfaced_output_faces_total{route="/subdivide"})"), faces);
    EXPECT_EQ(faces, 3 * 96.0);
    EXPECT_GT(after.at(R"(surfaced_http_request_bytes_total{route="/subdivide"})"), 4 * std::string(kCubeObj).size());
    EXPECT_GT(after.at(R"(surfaced_http_response_bytes_total{route="/subdivide"})"), 0.0);
    // histogram: cumulative buckets, +Inf == count
    const std::string prefix = R"(surfaced_http_request_duration_seconds_bucket{route="/subdivide",le=")";
    double previous = 0;
    for (const char* le : {"0.005", "0.01", "0.1", "1", "10", "60", "+Inf"}) {
        const double v = after.at(prefix + le + "\"}");
        EXPECT_GE(v, previous) << le;
        previous = v;
    }
    EXPECT_EQ(previous, 4.0);
    EXPECT_EQ(after.at(R"(surfaced_http_request_duration_seconds_count{route="/subdivide"})"), 4.0);
    // the /metrics request being answered is in flight
    EXPECT_GE(after.at("surfaced_http_requests_in_flight"), 1.0);
    EXPECT_EQ(after.at("surfaced_http_workers"), 2.0);
    EXPECT_EQ(after.at("surfaced_http_shed_total"), 0.0);
}

TEST(Production, FullQueueIsShedWith503AndRetryAfter) {
    ServerConfig config = base_config();
    config.threads = 1;
    config.queue_capacity = 1;
    Running s(config);
    // A: a request whose body has not arrived yet holds the only worker.
    const int a = connect_to(s.server.port());
    ASSERT_GE(a, 0);
    send_text(a,
              "POST /subdivide?format=obj HTTP/1.1\r\nHost: x\r\nContent-Type: model/obj\r\nConnection: close\r\n"
              "Content-Length: " +
                  std::to_string(std::string(kCubeObj).size()) + "\r\n\r\n");
    ASSERT_TRUE(eventually([&] { return s.server.stats().busy_workers == 1 && s.server.stats().in_flight == 1; }));
    // B waits in the queue.
    const int b = connect_to(s.server.port());
    ASSERT_GE(b, 0);
    send_text(b, "GET /livez HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
    ASSERT_TRUE(eventually([&] { return s.server.stats().queue_depth == 1; }));
    // C finds the queue full: 503 at once.
    const int c = connect_to(s.server.port());
    ASSERT_GE(c, 0);
    send_text(c, "POST /subdivide HTTP/1.1\r\nHost: x\r\nContent-Type: model/obj\r\nContent-Length: 4\r\n\r\nv 0\n");
    const std::string shed = read_until_close(c);
    close(c);
    EXPECT_EQ(status_of(shed), 503) << shed;
    EXPECT_NE(shed.find("Retry-After: 1\r\n"), std::string::npos);
    EXPECT_NE(shed.find("Content-Type: application/problem+json"), std::string::npos);
    const auto body = nlohmann::json::parse(shed.substr(shed.find("\r\n\r\n") + 4));
    EXPECT_EQ(body["code"], "overloaded");
    EXPECT_EQ(body["status"], 503);
    EXPECT_EQ(s.server.stats().shed_total, 1u);
    // A completes, then B is served: nothing accepted into the queue is lost.
    send_text(a, kCubeObj);
    EXPECT_EQ(status_of(read_until_close(a)), 200);
    EXPECT_EQ(status_of(read_until_close(b)), 200);
    close(a);
    close(b);
    EXPECT_EQ(s.metrics().at("surfaced_http_shed_total"), 1.0);
}

TEST(Production, IdleConnectionGivesItsWorkerUpToAWaitingOne) {
    ServerConfig config = base_config();
    config.threads = 1;
    config.read_timeout_seconds = 60;  // far longer than the test's client waits
    Running s(config);
    const int idle = connect_to(s.server.port());  // connects, never sends
    ASSERT_GE(idle, 0);
    ASSERT_TRUE(eventually([&] { return s.server.stats().busy_workers == 1; }));
    auto res = s.client().Get("/livez");
    ASSERT_TRUE(res) << httplib::to_string(res.error());
    EXPECT_EQ(res->status, 200);
    close(idle);
}

TEST(Production, SlowHeadIsAnswered503WhenAnotherConnectionWaits) {
    ServerConfig config = base_config();
    config.threads = 1;
    Running s(config);
    const int slow = connect_to(s.server.port());  // slowloris: half a head, then nothing
    ASSERT_GE(slow, 0);
    send_text(slow, "GET /livez HTTP/1.1\r\nHost: x\r\n");
    ASSERT_TRUE(eventually([&] { return s.server.stats().busy_workers == 1; }));
    const int other = connect_to(s.server.port());
    ASSERT_GE(other, 0);
    send_text(other, "GET /livez HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
    EXPECT_EQ(status_of(read_until_close(slow)), 503);  // gives the worker up instead of holding it
    EXPECT_EQ(status_of(read_until_close(other)), 200);
    close(slow);
    close(other);
    EXPECT_EQ(s.server.stats().shed_total, 1u);
}

TEST(Production, SlowRequestHeadIsCutOffAtTheHeaderDeadline) {
    ServerConfig config = base_config();
    config.header_timeout_seconds = 1;
    Running s(config);
    const int fd = connect_to(s.server.port());
    ASSERT_GE(fd, 0);
    send_text(fd, "GET /livez HTTP/1.1\r\nX-Slow: ");
    // never finishes the head: the server closes the connection (answering 400) instead of waiting forever
    const std::string answer = read_until_close(fd);
    close(fd);
    EXPECT_TRUE(answer.empty() || status_of(answer) == 400) << answer;
    EXPECT_TRUE(eventually([&] { return s.server.stats().busy_workers == 0; }));  // the worker is free again
}

TEST(Production, KeepAliveLimitClosesAfterMaxRequests) {
    ServerConfig config = base_config();
    config.keep_alive_max_requests = 2;
    Running s(config);
    const int fd = connect_to(s.server.port());
    ASSERT_GE(fd, 0);
    send_text(fd, "GET /livez HTTP/1.1\r\nHost: x\r\n\r\n");
    const std::string first = read_response(fd);
    EXPECT_EQ(status_of(first), 200);
    EXPECT_EQ(first.find("Connection: close"), std::string::npos);
    send_text(fd, "GET /livez HTTP/1.1\r\nHost: x\r\n\r\n");
    const std::string second = read_response(fd);
    EXPECT_EQ(status_of(second), 200);
    EXPECT_NE(second.find("Connection: close"), std::string::npos) << second;
    EXPECT_EQ(read_until_close(fd), "");  // and the server closed it
    close(fd);
}

TEST(Production, ComputeDeadlineCancelsWith503) {
    ServerConfig config = base_config();
    config.limits.compute_deadline_ms = 1;
    Running s(config);
    // Decoding 10k quads alone takes longer than 1 ms; refining them to level 3 (640k faces) far longer.
    auto res = s.client().Post("/subdivide?levels=3&format=obj", grid_obj(100), "model/obj");
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 503);
    EXPECT_EQ(problem_of(res)["code"], "cancelled");
    EXPECT_FALSE(res->get_header_value("Retry-After").empty());
    // cheap endpoints are unaffected (no work polls the deadline)
    auto live = s.client().Get("/livez");
    ASSERT_TRUE(live);
    EXPECT_EQ(live->status, 200);
    const std::string key = R"(surfaced_http_requests_total{route="/subdivide",method="POST",status="503"})";
    s.metrics_when([&](const auto& m) { return value_or_zero(m, key) == 1.0; });
}

TEST(Production, BearerTokenAuth) {
    ServerConfig config = base_config();
    config.auth_token = "s3cret-token";
    Running s(config);
    auto none = s.client().Post("/subdivide?format=obj", kCubeObj, "model/obj");
    ASSERT_TRUE(none);
    EXPECT_EQ(none->status, 401);
    EXPECT_EQ(problem_of(none)["code"], "unauthorized");
    EXPECT_EQ(none->get_header_value("WWW-Authenticate"), R"(Bearer realm="surfaced")");

    auto wrong =
        s.client().Post("/subdivide?format=obj", {{"Authorization", "Bearer s3cret-tokeN"}}, kCubeObj, "model/obj");
    ASSERT_TRUE(wrong);
    EXPECT_EQ(wrong->status, 401);
    EXPECT_NE(wrong->get_header_value("WWW-Authenticate").find("invalid_token"), std::string::npos);
    auto prefix = s.client().Post("/subdivide?format=obj", {{"Authorization", "Bearer s3cret"}}, kCubeObj, "model/obj");
    ASSERT_TRUE(prefix);
    EXPECT_EQ(prefix->status, 401);

    auto right =
        s.client().Post("/subdivide?format=obj", {{"Authorization", "bearer s3cret-token"}}, kCubeObj, "model/obj");
    ASSERT_TRUE(right);
    EXPECT_EQ(right->status, 200);

    for (const char* open : {"/livez", "/readyz", "/healthz", "/openapi.json"}) {
        auto res = s.client().Get(open);
        ASSERT_TRUE(res);
        EXPECT_EQ(res->status, 200) << open;
    }
    auto metrics = s.client().Get("/metrics");
    ASSERT_TRUE(metrics);
    EXPECT_EQ(metrics->status, 401);
    auto metrics_ok = s.client().Get("/metrics", {{"Authorization", "Bearer s3cret-token"}});
    ASSERT_TRUE(metrics_ok);
    EXPECT_EQ(metrics_ok->status, 200);
}

TEST(Production, NoAuthTokenMeansNoAuth) {
    Running s(base_config());
    auto res = s.client().Post("/subdivide?format=obj", {{"Authorization", "Bearer anything"}}, kCubeObj, "model/obj");
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 200);
}

TEST(Production, CorsAllowListAndPreflight) {
    ServerConfig config = base_config();
    config.cors_origins = {"https://app.example"};
    Running s(config);
    const httplib::Headers preflight = {{"Origin", "https://app.example"},
                                        {"Access-Control-Request-Method", "POST"},
                                        {"Access-Control-Request-Headers", "content-type, authorization"}};
    auto ok = s.client().Options("/subdivide", preflight);
    ASSERT_TRUE(ok);
    EXPECT_EQ(ok->status, 204);
    EXPECT_EQ(ok->get_header_value("Access-Control-Allow-Origin"), "https://app.example");
    EXPECT_NE(ok->get_header_value("Access-Control-Allow-Methods").find("POST"), std::string::npos);
    EXPECT_NE(ok->get_header_value("Access-Control-Allow-Headers").find("Authorization"), std::string::npos);
    EXPECT_EQ(ok->get_header_value("Vary"), "Origin");

    auto other = s.client().Options("/subdivide",
                                    {{"Origin", "https://evil.example"}, {"Access-Control-Request-Method", "POST"}});
    ASSERT_TRUE(other);
    EXPECT_EQ(other->status, 403);
    EXPECT_FALSE(other->has_header("Access-Control-Allow-Origin"));

    auto unknown = s.client().Options("/no/such", preflight);
    ASSERT_TRUE(unknown);
    EXPECT_EQ(unknown->status, 404);

    auto post = s.client().Post("/subdivide?format=obj", {{"Origin", "https://app.example"}}, kCubeObj, "model/obj");
    ASSERT_TRUE(post);
    EXPECT_EQ(post->status, 200);
    EXPECT_EQ(post->get_header_value("Access-Control-Allow-Origin"), "https://app.example");
    EXPECT_NE(post->get_header_value("Access-Control-Expose-Headers").find("X-Output-Faces"), std::string::npos);
    EXPECT_EQ(post->get_header_value("Vary"), "Origin");
    auto foreign =
        s.client().Post("/subdivide?format=obj", {{"Origin", "https://evil.example"}}, kCubeObj, "model/obj");
    ASSERT_TRUE(foreign);
    EXPECT_FALSE(foreign->has_header("Access-Control-Allow-Origin"));
}

TEST(Production, PreflightNeedsNoTokenButTheRequestDoes) {
    ServerConfig config = base_config();
    config.cors_origins = {"*"};
    config.auth_token = "t";
    Running s(config);
    auto preflight = s.client().Options(
        "/simplify", {{"Origin", "http://localhost:5173"}, {"Access-Control-Request-Method", "POST"}});
    ASSERT_TRUE(preflight);
    EXPECT_EQ(preflight->status, 204);
    EXPECT_EQ(preflight->get_header_value("Access-Control-Allow-Origin"), "http://localhost:5173");
    auto post = s.client().Post("/simplify?ratio=0.5", {{"Origin", "http://localhost:5173"}}, kCubeObj, "model/obj");
    ASSERT_TRUE(post);
    EXPECT_EQ(post->status, 401);
    EXPECT_EQ(post->get_header_value("Access-Control-Allow-Origin"), "http://localhost:5173");  // readable 401
}

TEST(Production, StaticFilesStayInsideTheWebRoot) {
    const fs::path dir = make_temp_dir("static");
    const fs::path root = dir / "www";
    fs::create_directories(root / "sub");
    std::ofstream(root / "index.html") << "<!doctype html><title>root</title>";
    std::ofstream(root / "sub" / "ok.txt") << "inside";
    std::ofstream(dir / "secret.txt") << "SECRET";
    fs::create_symlink(dir / "secret.txt", root / "link.txt");
    fs::create_directory_symlink(dir, root / "up");
    fs::create_symlink(root / "sub" / "ok.txt", root / "alias.txt");  // a symlink inside the root is fine

    ServerConfig config = base_config();
    config.web_root = root.string();
    Running s(config);
    ASSERT_TRUE(s.server.serves_web_root());
    auto get_raw = [&](const std::string& target) {
        const int fd = connect_to(s.server.port());
        send_text(fd, "GET " + std::string(target) + " HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
        std::string out = read_until_close(fd);
        close(fd);
        return out;
    };
    EXPECT_EQ(status_of(get_raw("/")), 200);
    const std::string ok = get_raw("/sub/ok.txt");
    EXPECT_EQ(status_of(ok), 200);
    EXPECT_NE(ok.find("inside"), std::string::npos);
    EXPECT_EQ(status_of(get_raw("/alias.txt")), 200);
    for (const char* attack : {"/../secret.txt", "/sub/../../secret.txt", "/%2e%2e/secret.txt", "/%2E%2E/secret.txt",
                               "/sub/%2e%2e/%2e%2e/secret.txt", "/..%2fsecret.txt", "/link.txt", "/up/secret.txt",
                               "/sub/..%5c..%5csecret.txt", "/%00/../secret.txt"}) {
        const std::string answer = get_raw(attack);
        const int status = status_of(answer);
        EXPECT_TRUE(status == 404 || status == 400) << attack << " -> " << status;
        EXPECT_EQ(answer.find("SECRET"), std::string::npos) << attack;
    }
    std::error_code ec;
    fs::remove_all(dir, ec);
}

// ---- the binary: healthcheck and SIGTERM ---------------------------------------------------------------------

//! Runs `surfaced ARGS` (or, with binary false, the command line ARGS as it is) and returns its exit status.
int run_cli(const std::string& args, bool binary = true) {
    const std::string command =
        (binary ? std::string("'") + SURFACED_CLI_PATH + "' " + args : args) + " >/dev/null 2>&1";
    const int status = std::system(command.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// A token file whose first line is blank, or a token variable of blanks, is a usage error (exit 2 before anything
// listens): the service must never start without authentication when a token was meant.
TEST(Production, ServeRefusesABlankAuthToken) {
    const fs::path dir = fs::temp_directory_path() / ("surfaced-token-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    // `timeout`: a server that wrongly starts is stopped (status 124) instead of hanging the test
    const std::string serve = "timeout 20 '" + std::string(SURFACED_CLI_PATH) + "' serve --port 0";
    for (const std::string text : {"", "\n", "   \t\nsecond-line-token\n", "  "}) {
        std::ofstream(dir / "token") << text;
        EXPECT_EQ(run_cli(serve + " --auth-token-file '" + (dir / "token").string() + "'", false), 2)
            << "token file " << ::testing::PrintToString(text);
    }
    EXPECT_EQ(run_cli(serve + " --auth-token-file '" + (dir / "missing").string() + "'", false), 2);
    EXPECT_EQ(run_cli("SURFACED_AUTH_TOKEN='   ' " + serve, false), 2);
    std::error_code ec;
    fs::remove_all(dir, ec);
}

TEST(Production, HealthcheckCommand) {
    Running s(base_config());
    const std::string port = std::to_string(s.server.port());
    EXPECT_EQ(run_cli("healthcheck --port " + port), 0);
    EXPECT_EQ(run_cli("healthcheck --host 0.0.0.0 --port=" + port + " --timeout 5"), 0);
    EXPECT_EQ(run_cli("healthcheck --port " + port + " --path /no/such"), 1);  // 404
    s.server.begin_drain();
    EXPECT_EQ(run_cli("healthcheck --port " + port + " --path /readyz"), 1);  // 503 while draining
    EXPECT_EQ(run_cli("healthcheck --port " + port), 0);                      // still alive
    s.server.stop();
    EXPECT_EQ(run_cli("healthcheck --port " + port + " --timeout 1"), 1);  // nobody listening
    EXPECT_EQ(run_cli("healthcheck --port 0"), 2);
    EXPECT_EQ(run_cli("healthcheck --timeout -1"), 2);
    EXPECT_EQ(run_cli("healthcheck --bogus"), 2);
}

//! `surfaced serve --port 0 --threads 2 --access-log off EXTRA...` in a child process, and the port it announced on
//! its first line (0 when it did not start).
struct ServeProcess {
    pid_t pid = -1;
    int port = 0;
    int out = -1;  //!< the read end of its standard output
    std::string first_line;
};

ServeProcess spawn_serve(const std::vector<std::string>& extra = {}) {
    ServeProcess p;
    int out_pipe[2];
    if (pipe(out_pipe) != 0) return p;
    std::vector<std::string> args = {SURFACED_CLI_PATH, "serve", "--port",       "0",
                                     "--threads",       "2",     "--access-log", "off"};
    args.insert(args.end(), extra.begin(), extra.end());
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    p.pid = fork();
    if (p.pid == 0) {
        dup2(out_pipe[1], STDOUT_FILENO);
        close(out_pipe[0]);
        close(out_pipe[1]);
        execv(SURFACED_CLI_PATH, argv.data());
        _exit(127);
    }
    close(out_pipe[1]);
    p.out = out_pipe[0];
    char c = 0;
    pollfd pfd{p.out, POLLIN, 0};
    while (p.first_line.find('\n') == std::string::npos && poll(&pfd, 1, 10'000) > 0 && read(p.out, &c, 1) == 1)
        p.first_line += c;
    const auto at = p.first_line.find("http://127.0.0.1:");
    p.port = at == std::string::npos ? 0 : std::atoi(p.first_line.c_str() + at + 17);
    return p;
}

//! SIGTERM, then the exit status (-1 when it was killed by a signal).
int stop_serve(ServeProcess& p) {
    kill(p.pid, SIGTERM);
    int status = 0;
    if (waitpid(p.pid, &status, 0) != p.pid) return -1;
    close(p.out);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// The budget flags of `serve` reach the operations: each request below is within the default budgets and over the
// one given on the command line.
TEST(Production, ServeBudgetFlagsApplyToRequests) {
    ServeProcess p = spawn_serve(
        {"--max-grid-cells", "1000", "--max-mesh-queries", "2", "--max-input-faces", "5", "--max-scene-nodes", "2"});
    ASSERT_GT(p.port, 0) << p.first_line;
    httplib::Client cl("127.0.0.1", p.port);
    cl.set_read_timeout(60, 0);
    const std::string cube = R"({"positions":[[0,0,0],[1,0,0],[1,1,0],[0,1,0],[0,0,1],[1,0,1],[1,1,1],[0,1,1]],)"
                             R"("faces":[[0,3,2,1],[4,5,6,7],[0,1,5,4],[1,2,6,5],[2,3,7,6],[3,0,4,7]]})";
    auto expect_budget = [](const httplib::Result& res, const std::string& what) {
        ASSERT_TRUE(res) << what;
        EXPECT_EQ(res->status, 422) << what << ": " << res->body;
        EXPECT_NE(res->body.find("budget_exceeded"), std::string::npos) << what << ": " << res->body;
    };
    expect_budget(cl.Post("/implicit/mesh",
                          R"({"scene":{"op":"sphere","radius":1},"bounds":[[-2,-2,-2],[2,2,2]],"resolution":16})",
                          "application/json"),
                  "grid cells");
    expect_budget(cl.Post("/implicit/query",
                          R"({"scene":{"op":"union","args":[{"op":"sphere","radius":1},{"op":"sphere","radius":2}]},)"
                          R"("points":[[0,0,0]]})",
                          "application/json"),
                  "scene nodes");
    expect_budget(
        cl.Post("/mesh/query", R"({"mesh":)" + cube + R"(,"points":[[0,0,0],[1,1,1],[2,2,2]]})", "application/json"),
        "mesh queries");
    expect_budget(cl.Post("/subdivide", R"({"mesh":)" + cube + R"(,"levels":1})", "application/json"), "input faces");
    // within them: answered
    auto small = cl.Post("/implicit/mesh",
                         R"({"scene":{"op":"sphere","radius":1},"bounds":[[-2,-2,-2],[2,2,2]],"resolution":8})",
                         "application/json");
    ASSERT_TRUE(small);
    EXPECT_EQ(small->status, 200) << small->body;
    EXPECT_EQ(stop_serve(p), 0);
}

TEST(Production, SigtermFinishesTheRequestInFlightAndExitsZero) {
    ServeProcess p = spawn_serve();
    const int port = p.port;
    ASSERT_GT(port, 0) << p.first_line;

    // A request that takes a while (10k quads to level 3, 640k faces, Draco-encoded).
    int slow_status = -1;
    std::string slow_error, slow_faces, slow_magic;
    std::thread client([&] {
        httplib::Client cl("127.0.0.1", port);
        cl.set_read_timeout(120, 0);
        auto res = cl.Post("/subdivide?levels=3", grid_obj(100), "model/obj");
        if (!res) {
            slow_error = httplib::to_string(res.error());
            return;
        }
        slow_status = res->status;
        slow_faces = res->get_header_value("X-Output-Faces");
        slow_magic = res->body.substr(0, 4);
    });
    // Wait until the server has it in flight (the /metrics request itself is the other one).
    httplib::Client probe("127.0.0.1", port);
    const bool in_flight = eventually([&] {
        auto res = probe.Get("/metrics");
        if (!res) return false;
        std::smatch m;
        return std::regex_search(res->body, m, std::regex("\nsurfaced_http_requests_in_flight ([0-9]+)")) &&
               std::stoi(m[1]) >= 2;
    });
    EXPECT_TRUE(in_flight);
    kill(p.pid, SIGTERM);
    client.join();
    EXPECT_EQ(slow_status, 200) << slow_error;
    EXPECT_EQ(slow_faces, "640000");
    EXPECT_EQ(slow_magic, "glTF");
    int status = 0;
    ASSERT_EQ(waitpid(p.pid, &status, 0), p.pid);
    EXPECT_TRUE(WIFEXITED(status)) << "killed by a signal instead of stopping cleanly";
    EXPECT_EQ(WEXITSTATUS(status), 0);
    // and it no longer listens
    httplib::Client after("127.0.0.1", port);
    after.set_connection_timeout(1, 0);
    EXPECT_FALSE(after.Get("/livez"));
    close(p.out);
}

}  // namespace
}  // namespace surfaced::server
