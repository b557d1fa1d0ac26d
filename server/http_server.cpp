#include "server/http_server.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <linux/filter.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <deque>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <mutex>
#include <optional>
#include <random>
#include <thread>

#include <httplib.h>

#include "api/errors.h"
#include "api/operation.h"
#include "api/routes.h"
#include "server/metrics.h"

namespace surfaced::server {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// ---- per-thread request state ----------------------------------------------------------------------------------
// A connection is served start to end by one worker thread and its requests one after another, so what the hooks
// (pre-routing, handler, post-routing) learn about the current request lives in thread-local state.

struct RequestState {
    Clock::time_point start;
    std::string id;
    std::string route;  // route template, "static" or "unmatched"
    std::string method;
    std::string path;
    std::string remote;
    int status = 0;  // 0: no response was produced (the client went away)
    std::uint64_t output_faces = 0;
    bool force_close = false;     // the request body may be unread: do not parse another request from this stream
    bool body_timed_out = false;  // the body did not arrive in time (set by ConnectionStream::read): answer 408
};

//! How the current thread runs a connection handed to it by the task queue.
enum class ConnectionMode { Serve, Shed, Reject };

thread_local RequestState t_request;
thread_local ConnectionMode t_mode = ConnectionMode::Serve;

// ---- small helpers ---------------------------------------------------------------------------------------------

//! Removes every Accept-Encoding token mentioning "br" (httplib 0.11 picks brotli when the header merely contains
//! that substring).
void without_brotli(httplib::Request& req) {
    const auto range = req.headers.equal_range("Accept-Encoding");
    for (auto it = range.first; it != range.second; ++it) {
        std::string kept;
        std::string_view rest = it->second;
        while (!rest.empty()) {
            const std::size_t comma = rest.find(',');
            std::string_view token = rest.substr(0, comma);
            rest = comma == std::string_view::npos ? std::string_view() : rest.substr(comma + 1);
            while (!token.empty() && token.front() == ' ') token.remove_prefix(1);
            if (token.empty() || token.find("br") != std::string_view::npos) continue;
            if (!kept.empty()) kept += ", ";
            kept += token;
        }
        it->second = std::move(kept);
    }
}

api::ApiRequest to_api_request(const httplib::Request& req) {
    api::ApiRequest out;
    out.method = req.method;
    out.path = req.path;
    out.query.insert(req.params.begin(), req.params.end());
    out.content_type = req.get_header_value("Content-Type");
    out.body = req.body;
    for (const auto& [name, value] : req.headers) {
        std::string lower = name;
        for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        out.headers.emplace(std::move(lower), value);
    }
    return out;
}

void write_response(api::ApiResponse&& response, httplib::Response& res) {
    res.status = response.status;
    for (auto& [name, value] : response.headers) res.set_header(name, value);
    // Response::set_content copies; bodies can be tens of MB.
    res.body = std::move(response.body);
    res.set_header("Content-Type", response.content_type);
}

api::ApiResponse problem(int status, std::string code, std::string title, std::string detail) {
    api::ApiError error = api::make_transport_problem(status, std::move(detail));
    error.code = std::move(code);
    error.title = std::move(title);
    return api::error_response(std::move(error));
}

//! cpp-httplib route patterns are regular expressions; our paths are literal except for `{name}` segments, which
//! match one path segment (api::match_path extracts their values).
std::string literal_pattern(std::string_view path) {
    std::string out;
    for (std::size_t i = 0; i < path.size(); ++i) {
        const char c = path[i];
        if (const std::size_t close = path.find('}', i); c == '{' && close != std::string_view::npos) {
            out += "[^/]+";
            i = close;
            continue;
        }
        if (std::string_view(R"(\^$.|?*+()[]{})").find(c) != std::string_view::npos) out += '\\';
        out += c;
    }
    return out;
}

int default_threads() {
    const unsigned n = std::thread::hardware_concurrency();
    return n < 2 ? 2 : static_cast<int>(n);
}

//! An incoming X-Request-Id is kept when it is 1..128 characters of [A-Za-z0-9._:-]; anything else is replaced.
bool sane_request_id(std::string_view id) {
    if (id.empty() || id.size() > 128) return false;
    return std::all_of(id.begin(), id.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.' || c == ':';
    });
}

std::string new_request_id() {
    thread_local std::mt19937_64 rng{std::random_device{}() ^
                                     static_cast<std::uint64_t>(Clock::now().time_since_epoch().count())};
    static constexpr char kHex[] = "0123456789abcdef";
    std::string id(32, '0');
    for (int half = 0; half < 2; ++half) {
        std::uint64_t bits = rng();
        for (int i = 0; i < 16; ++i, bits >>= 4) id[static_cast<std::size_t>(half * 16 + i)] = kHex[bits & 15];
    }
    return id;
}

//! Compares in time that depends only on the lengths, not on where the strings differ.
bool constant_time_equal(std::string_view a, std::string_view b) {
    unsigned char diff = a.size() == b.size() ? 0 : 1;
    const std::size_t n = std::max(a.size(), b.size());
    for (std::size_t i = 0; i < n; ++i) {
        const unsigned char x = i < a.size() ? static_cast<unsigned char>(a[i]) : 0;
        const unsigned char y = i < b.size() ? static_cast<unsigned char>(b[i]) : 0;
        diff = static_cast<unsigned char>(diff | (x ^ y));
    }
    return diff == 0;
}

bool iequals(std::string_view a, std::string_view b) {
    return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
               return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
           });
}

std::string utc_timestamp() {
    const auto now = std::chrono::system_clock::now();
    const std::time_t seconds = std::chrono::system_clock::to_time_t(now);
    const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count() % 1000;
    std::tm tm{};
    gmtime_r(&seconds, &tm);
    char buffer[96];
    std::snprintf(buffer, sizeof buffer, "%04d-%02d-%02dT%02d:%02d:%02d.%03dZ", tm.tm_year + 1900, tm.tm_mon + 1,
                  tm.tm_mday, tm.tm_hour, tm.tm_min, tm.tm_sec, static_cast<int>(ms));
    return buffer;
}

std::string peer_address(int fd) {
    sockaddr_storage addr{};
    socklen_t len = sizeof addr;
    if (getpeername(fd, reinterpret_cast<sockaddr*>(&addr), &len) != 0) return {};
    char text[INET6_ADDRSTRLEN] = {};
    if (addr.ss_family == AF_INET)
        inet_ntop(AF_INET, &reinterpret_cast<sockaddr_in*>(&addr)->sin_addr, text, sizeof text);
    else if (addr.ss_family == AF_INET6)
        inet_ntop(AF_INET6, &reinterpret_cast<sockaddr_in6*>(&addr)->sin6_addr, text, sizeof text);
    return text;
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

int millis_until(Clock::time_point deadline) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    return left <= 0 ? 0 : static_cast<int>(std::min<long long>(left, 1'000'000));
}

//! Reads and discards what the peer sends for up to `budget` (or until EOF / `max_bytes`); with `until_head`,
//! stops once a blank line ends a request head.
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

// ---- the socket stream -----------------------------------------------------------------------------------------

//! httplib::Stream over an accepted socket, with the deadlines cpp-httplib 0.11 lacks: the request head must
//! arrive within a total time (not only per read), and byte counts for the metrics.
class ConnectionStream final : public httplib::Stream {
public:
    ConnectionStream(int fd, const ServerConfig& config) : fd_(fd), config_(config) {}

    //! Called before each request: restarts the head deadline and the byte counts.
    void begin_request() {
        head_done_ = false;
        head_tail_ = 0;
        head_deadline_ = Clock::now() + std::chrono::seconds(config_.header_timeout_seconds);
        bytes_in_ = 0;
        bytes_out_ = 0;
        body_bytes_ = 0;
    }
    bool has_buffered() const { return offset_ < size_; }
    //! Whether the buffered bytes hold a whole request head (up to the blank line), or cannot hold more.
    bool head_buffered() const {
        if (size_ == buffer_.size() && offset_ == 0) return true;  // full: let the parser refuse an oversized head
        return std::string_view(buffer_.data() + offset_, size_ - offset_).find("\r\n\r\n") != std::string_view::npos;
    }
    //! Reads what the socket has now into the buffer without blocking; false when the peer closed or failed.
    bool fill_once() {
        if (offset_ > 0) {
            std::memmove(buffer_.data(), buffer_.data() + offset_, size_ - offset_);
            size_ -= offset_;
            offset_ = 0;
        }
        if (size_ == buffer_.size()) return true;
        const ssize_t n = recv(fd_, buffer_.data() + size_, buffer_.size() - size_, MSG_DONTWAIT);
        if (n > 0) size_ += static_cast<std::size_t>(n);
        return n > 0 || (n < 0 && (errno == EAGAIN || errno == EINTR));
    }
    std::uint64_t bytes_in() const { return bytes_in_; }
    std::uint64_t bytes_out() const { return bytes_out_; }

    bool is_readable() const override { return has_buffered() || wait(POLLIN, read_wait_ms()); }
    bool is_writable() const override { return wait(POLLOUT, config_.write_timeout_seconds * 1000); }

    ssize_t read(char* ptr, size_t size) override {
        if (!has_buffered()) {
            if (head_done_) {
                // Past the body deadline nothing more is read, however steadily a trickle still arrives.
                for (;;) {
                    if (body_deadline_passed()) return body_timeout();
                    const int per_read = config_.read_timeout_seconds * 1000;
                    const int left = millis_until(body_deadline()) + 1;  // poll may wake a fraction of a ms early
                    if (wait(POLLIN, std::min(per_read, left))) break;
                    if (left > per_read) return -1;  // the per-read timeout
                }
            } else if (!wait(POLLIN, read_wait_ms())) {
                return -1;
            }
            const ssize_t n = recv(fd_, buffer_.data(), buffer_.size(), 0);
            if (n <= 0) return n;
            offset_ = 0;
            size_ = static_cast<std::size_t>(n);
        }
        const std::size_t n = std::min(size, size_ - offset_);
        std::memcpy(ptr, buffer_.data() + offset_, n);
        offset_ += n;
        bytes_in_ += n;
        if (head_done_)
            body_bytes_ += n;
        else
            track_head(ptr, n);
        return static_cast<ssize_t>(n);
    }

    ssize_t write(const char* ptr, size_t size) override {
        if (!is_writable()) return -1;
        const ssize_t n = send(fd_, ptr, size, MSG_NOSIGNAL);
        if (n > 0) bytes_out_ += static_cast<std::uint64_t>(n);
        return n;
    }

    void get_remote_ip_and_port(std::string& ip, int& port) const override { address_and_port(fd_, false, ip, port); }
    void get_local_ip_and_port(std::string& ip, int& port) const override { address_and_port(fd_, true, ip, port); }
    socket_t socket() const override { return fd_; }

private:
    // While the head is being read the total head deadline applies, afterwards the body deadline; both are capped
    // by the per-read timeout.
    int read_wait_ms() const {
        const int per_read = config_.read_timeout_seconds * 1000;
        return std::min(per_read, millis_until(head_done_ ? body_deadline() : head_deadline_));
    }
    //! body_timeout after the head, plus one second per body_min_rate_bytes received since.
    Clock::time_point body_deadline() const {
        auto credit = std::chrono::milliseconds(0);
        if (config_.body_min_rate_bytes > 0)
            credit = std::chrono::milliseconds(body_bytes_ * 1000 / config_.body_min_rate_bytes);
        return body_start_ + std::chrono::seconds(std::max(1, config_.body_timeout_seconds)) + credit;
    }
    bool body_deadline_passed() const { return Clock::now() >= body_deadline(); }
    ssize_t body_timeout() const {
        t_request.body_timed_out = true;
        return -1;
    }
    bool wait(short events, int timeout_ms) const {
        pollfd pfd{fd_, events, 0};
        for (;;) {
            const int rc = poll(&pfd, 1, timeout_ms);
            if (rc < 0 && errno == EINTR) continue;
            return rc > 0 && (pfd.revents & (events | POLLHUP)) != 0;
        }
    }
    // Watches the bytes handed out for the blank line that ends the head ("\r\n\r\n").
    void track_head(const char* ptr, std::size_t n) {
        static constexpr char kEnd[] = "\r\n\r\n";
        for (std::size_t i = 0; i < n && !head_done_; ++i) {
            head_tail_ = ptr[i] == kEnd[head_tail_] ? head_tail_ + 1 : (ptr[i] == '\r' ? 1 : 0);
            if (head_tail_ == 4) {
                head_done_ = true;
                body_start_ = Clock::now();
                body_bytes_ = n - i - 1;  // the rest of this read is body
            }
        }
    }

    int fd_;
    const ServerConfig& config_;
    std::array<char, 16384> buffer_{};  // a request head must fit (cpp-httplib refuses longer lines anyway)
    std::size_t offset_ = 0;
    std::size_t size_ = 0;
    bool head_done_ = false;
    int head_tail_ = 0;
    Clock::time_point head_deadline_;
    Clock::time_point body_start_;
    std::uint64_t body_bytes_ = 0;
    std::uint64_t bytes_in_ = 0;
    std::uint64_t bytes_out_ = 0;
};

// ---- the bounded worker pool -----------------------------------------------------------------------------------

//! Counters shared by the pool and the server (the pool is created and destroyed by httplib's accept loop).
struct LoadCounters {
    std::atomic<std::int64_t> queued{0};
    std::atomic<std::int64_t> busy{0};
    std::atomic<std::int64_t> in_flight{0};
};

//! cpp-httplib's TaskQueue with a bound. Each task is "serve this accepted socket" and owns the socket, so every
//! task must run: beyond the bound it runs on a shedding thread (which answers 503 and closes), and if even that
//! thread's queue is full, at once on the accept thread in Reject mode (close without an answer).
class BoundedPool final : public httplib::TaskQueue {
public:
    static constexpr std::size_t kShedCapacity = 256;

    BoundedPool(std::size_t workers, std::size_t capacity, LoadCounters& counters)
        : capacity_(capacity), counters_(counters) {
        for (std::size_t i = 0; i < workers; ++i) workers_.emplace_back([this] { work(); });
        shedder_ = std::thread([this] { shed(); });
    }
    ~BoundedPool() override { shutdown(); }

    void enqueue(std::function<void()> fn) override {
        {
            std::lock_guard lock(mutex_);
            if (jobs_.size() < capacity_) {
                jobs_.push_back(std::move(fn));
                counters_.queued.store(static_cast<std::int64_t>(jobs_.size()));
                job_ready_.notify_one();
                return;
            }
            if (shed_jobs_.size() < kShedCapacity) {
                shed_jobs_.push_back(std::move(fn));
                shed_ready_.notify_one();
                return;
            }
        }
        t_mode = ConnectionMode::Reject;
        fn();
        t_mode = ConnectionMode::Serve;
    }

    //! Runs what is queued, then joins every thread (httplib calls this once the accept loop has ended).
    void shutdown() override {
        {
            std::lock_guard lock(mutex_);
            if (stopping_) return;
            stopping_ = true;
        }
        job_ready_.notify_all();
        shed_ready_.notify_all();
        for (std::thread& t : workers_) t.join();
        shedder_.join();
    }

private:
    void work() {
        for (;;) {
            std::function<void()> fn;
            {
                std::unique_lock lock(mutex_);
                job_ready_.wait(lock, [&] { return stopping_ || !jobs_.empty(); });
                if (jobs_.empty()) return;  // stopping and nothing left
                fn = std::move(jobs_.front());
                jobs_.pop_front();
                counters_.queued.store(static_cast<std::int64_t>(jobs_.size()));
            }
            ++counters_.busy;
            fn();
            --counters_.busy;
        }
    }
    void shed() {
        t_mode = ConnectionMode::Shed;
        for (;;) {
            std::function<void()> fn;
            {
                std::unique_lock lock(mutex_);
                shed_ready_.wait(lock, [&] { return stopping_ || !shed_jobs_.empty(); });
                if (shed_jobs_.empty()) return;
                fn = std::move(shed_jobs_.front());
                shed_jobs_.pop_front();
            }
            fn();
        }
    }

    const std::size_t capacity_;
    LoadCounters& counters_;
    std::mutex mutex_;
    std::condition_variable job_ready_;
    std::condition_variable shed_ready_;
    std::deque<std::function<void()>> jobs_;
    std::deque<std::function<void()>> shed_jobs_;
    bool stopping_ = false;
    std::vector<std::thread> workers_;
    std::thread shedder_;
};

// ---- static files ----------------------------------------------------------------------------------------------

const char* mime_type(const fs::path& file) {
    std::string ext = file.extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (ext == ".html" || ext == ".htm") return "text/html; charset=utf-8";
    if (ext == ".js" || ext == ".mjs") return "text/javascript; charset=utf-8";
    if (ext == ".css") return "text/css; charset=utf-8";
    if (ext == ".json" || ext == ".map") return "application/json";
    if (ext == ".wasm") return "application/wasm";
    if (ext == ".glb") return "model/gltf-binary";
    if (ext == ".gltf") return "model/gltf+json";
    if (ext == ".svg") return "image/svg+xml";
    if (ext == ".png") return "image/png";
    if (ext == ".jpg" || ext == ".jpeg") return "image/jpeg";
    if (ext == ".ico") return "image/x-icon";
    if (ext == ".txt") return "text/plain; charset=utf-8";
    return "application/octet-stream";
}

//! The file under `root` (canonical) that the decoded URL path names, or nothing: segments "..", backslashes and
//! NULs are refused outright, and the canonical target (symlinks resolved) must still lie under the root.
std::optional<fs::path> resolve_static(const fs::path& root, std::string_view url_path) {
    if (url_path.empty() || url_path.front() != '/') return std::nullopt;
    fs::path relative;
    std::size_t begin = 1;
    while (begin <= url_path.size()) {
        const std::size_t end = std::min(url_path.find('/', begin), url_path.size());
        const std::string_view segment = url_path.substr(begin, end - begin);
        if (segment == ".." || segment.find('\\') != std::string_view::npos ||
            segment.find('\0') != std::string_view::npos)
            return std::nullopt;
        if (!segment.empty() && segment != ".") relative /= std::string(segment);
        begin = end + 1;
    }
    if (url_path.back() == '/') relative /= "index.html";
    std::error_code ec;
    const fs::path target = fs::canonical(root / relative, ec);
    if (ec || !fs::is_regular_file(target, ec)) return std::nullopt;
    const auto [root_end, target_it] = std::mismatch(root.begin(), root.end(), target.begin(), target.end());
    if (root_end != root.end()) return std::nullopt;  // resolved outside the web root (a symlink out of it)
    (void)target_it;
    return target;
}

//! The route template `path` belongs to (whatever the method), or "".
std::string route_template(std::string_view path) {
    for (const api::Route& route : api::routes())
        if (api::match_path(route.path, path)) return std::string(route.path);
    return {};
}

bool is_open_route(std::string_view route) {
    return route == "/livez" || route == "/readyz" || route == "/healthz" || route == "/openapi.json";
}

constexpr std::string_view kCorsAllowHeaders = "Authorization, Content-Type, If-None-Match, X-Request-Id";
constexpr std::string_view kCorsExposeHeaders =
    "X-Request-Id, X-Output-Faces, X-Output-Vertices, X-Levels, X-Error-Bound, X-Hausdorff, X-RMS, X-Triangulated, "
    "X-Elapsed-Ms, ETag, Retry-After";

}  // namespace

// ---- the server ------------------------------------------------------------------------------------------------

struct HttpServer::Impl final : public api::ServiceState {
    //! httplib::Server with our connection loop: process_and_close_socket is httplib's (private, virtual) hook for
    //! one accepted socket; overriding it gives the socket to us, so the keep-alive loop, deadlines, draining and
    //! the shedding answer are ours while request parsing, routing and response writing stay httplib's.
    class CoreServer final : public httplib::Server {
    public:
        explicit CoreServer(Impl& owner) : owner_(owner) {}

        //! The listening socket bound by bind_to_port / bind_to_any_port, handed over to the caller (our accept
        //! loop owns it from then on; httplib's listen loop is never run).
        int take_listening_socket() { return svr_sock_.exchange(INVALID_SOCKET); }

        //! Serves one accepted socket (in the mode the calling thread runs in) and closes it.
        void serve_connection(int sock) { process_and_close_socket(sock); }

    private:
        bool process_and_close_socket(socket_t sock) override {
            switch (t_mode) {
                case ConnectionMode::Reject:
                    owner_.metrics.shed();
                    ::close(sock);
                    return false;
                case ConnectionMode::Shed: owner_.shed_connection(sock); return false;
                case ConnectionMode::Serve: break;
            }
            // Responses go out as two writes (head, body): without TCP_NODELAY the second waits for the peer's
            // delayed ACK (40 ms on Linux).
            const int one = 1;
            setsockopt(sock, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
            ConnectionStream stream(sock, owner_.config);
            const int max_requests = std::max(1, owner_.config.keep_alive_max_requests);
            for (int served = 0; served < max_requests; ++served) {
                const Next next = owner_.wait_for_request(sock, stream, served == 0);
                if (next == Next::Shed) {
                    owner_.metrics.shed();
                    send_all(sock, owner_.overloaded_response(new_request_id()), std::chrono::milliseconds(200));
                }
                if (next != Next::Serve) break;
                // Connection: close on the last allowed request, when draining, and while other connections wait
                // for a worker (one request per turn then: fair, and no idle-close race with the client).
                const bool last =
                    served + 1 == max_requests || owner_.draining_.load() || owner_.counters.queued.load() > 0;
                stream.begin_request();
                t_request = RequestState{};
                t_request.start = Clock::now();
                ++owner_.counters.in_flight;
                bool closed = false;
                const bool ok = process_request(stream, last, closed, nullptr);
                --owner_.counters.in_flight;
                owner_.finish_request(stream, sock);
                if (!ok || closed || last || t_request.force_close) break;
            }
            // Half-close, then read what is left so that close() does not turn into a reset that could destroy the
            // answer before the client has read it.
            ::shutdown(sock, SHUT_WR);
            discard_input(sock, std::chrono::milliseconds(100), std::size_t{1} << 16, false);
            ::close(sock);
            return true;
        }

        Impl& owner_;
    };

    ServerConfig config;
    api::ApiContext context;
    CoreServer server{*this};
    Metrics metrics;
    LoadCounters counters;
    std::atomic<bool> draining_{false};
    std::atomic<bool> abort_{false};  // set when the drain timeout passes: in-flight work is cancelled
    int listen_fd = -1;               // owned by the accept loop once it runs
    int wake_pipe[2] = {-1, -1};      // stop() writes a byte: the accept loop drains and ends
    std::thread listener;
    std::mutex done_mutex;
    std::condition_variable done_cv;
    bool listener_done = false;
    std::mutex mutex;  // start/stop
    std::mutex log_mutex;
    int port = -1;
    int threads = 0;
    std::size_t queue_capacity = 0;
    std::optional<fs::path> web_root;  // canonical

    explicit Impl(ServerConfig c) : config(std::move(c)) {
        context.limits = config.limits;
        context.service = this;
        threads = config.threads > 0 ? config.threads : default_threads();
        queue_capacity =
            static_cast<std::size_t>(config.queue_capacity > 0 ? config.queue_capacity : std::max(64, 8 * threads));
        if (!config.web_root.empty()) {
            std::error_code ec;
            const fs::path root = fs::canonical(config.web_root, ec);
            if (!ec && fs::is_directory(root, ec)) web_root = root;
        }
        configure();
    }

    // api::ServiceState
    bool draining() const override { return draining_.load(); }
    std::string metrics_text() const override {
        MetricsGauges gauges;
        gauges.in_flight = counters.in_flight.load();
        gauges.queue_depth = counters.queued.load();
        gauges.queue_capacity = static_cast<std::int64_t>(queue_capacity);
        gauges.workers = threads;
        gauges.busy_workers = counters.busy.load();
        gauges.draining = draining_.load();
        return metrics.render(gauges);
    }

    enum class Next { Serve, Close, Shed };

    //! What to do with this connection next. A request is handed to the parser only once its whole head is
    //! buffered, so a worker never blocks on a slow head. The first request gets read_timeout to start arriving,
    //! later ones keep_alive_timeout, a started head header_timeout. When another connection waits for a worker,
    //! an idle connection gives its worker up (after 1 s for a new connection, 250 ms between keep-alive requests)
    //! and a connection still sending its head after 1 s is answered 503 (slowloris). Draining closes idle
    //! keep-alive connections.
    Next wait_for_request(int fd, ConnectionStream& stream, bool first) {
        const auto begin = Clock::now();
        const auto idle_deadline =
            begin + std::chrono::seconds(first ? config.read_timeout_seconds : config.keep_alive_timeout_seconds);
        const auto yield_after = first ? std::chrono::milliseconds(1000) : std::chrono::milliseconds(250);
        std::optional<Clock::time_point> head_deadline;
        for (;;) {
            if (stream.has_buffered()) {
                if (stream.head_buffered()) return Next::Serve;
                if (!head_deadline) head_deadline = Clock::now() + std::chrono::seconds(config.header_timeout_seconds);
            }
            const auto deadline = head_deadline ? *head_deadline : idle_deadline;
            pollfd pfd{fd, POLLIN, 0};
            const int rc = poll(&pfd, 1, std::min(50, millis_until(deadline)));
            if (rc > 0) {
                if (!stream.fill_once()) return Next::Close;  // closed by the client
                continue;
            }
            if (rc < 0 && errno != EINTR) return Next::Close;
            const auto now = Clock::now();
            if (now >= deadline) return Next::Close;
            if (!stream.has_buffered() && !first && draining_.load()) return Next::Close;
            if (now - begin >= (stream.has_buffered() ? std::chrono::milliseconds(1000) : yield_after) &&
                counters.queued.load() > 0)
                return stream.has_buffered() ? Next::Shed : Next::Close;
        }
    }

    //! Accepts every connection the kernel has completed (non-blocking, until EAGAIN) into the pool.
    void accept_pending(BoundedPool& pool) {
        for (;;) {
            const int sock = ::accept4(listen_fd, nullptr, nullptr, SOCK_CLOEXEC);
            if (sock < 0) {
                if (errno == EINTR || errno == ECONNABORTED) continue;
                // EMFILE/ENFILE: the connection stays in the backlog; poll() reports it again after a pause.
                if (errno == EMFILE || errno == ENFILE || errno == ENOBUFS || errno == ENOMEM)
                    std::this_thread::sleep_for(std::chrono::milliseconds(10));
                return;  // EAGAIN: nothing more queued
            }
            // As cpp-httplib's own loop does: a blocking send() of a large response to a client that stops reading
            // (poll() only says some space is free) gives up after write_timeout instead of holding the worker.
            const timeval read_timeout{static_cast<time_t>(config.read_timeout_seconds), 0};
            const timeval write_timeout{static_cast<time_t>(config.write_timeout_seconds), 0};
            setsockopt(sock, SOL_SOCKET, SO_RCVTIMEO, &read_timeout, sizeof read_timeout);
            setsockopt(sock, SOL_SOCKET, SO_SNDTIMEO, &write_timeout, sizeof write_timeout);
            pool.enqueue([this, sock] { server.serve_connection(sock); });
        }
    }

    //! The accept loop (our own: cpp-httplib's stop() shuts the listening socket down, which resets every
    //! connection still in the kernel's listen backlog; those clients had already sent their requests).
    //! On stop: a socket filter drops new SYNs (a client that was not yet connected sees its connection refused once
    //! the socket closes, and may retry elsewhere), handshakes already under way complete, everything the kernel
    //! queued is accepted and answered like any accepted connection (with Connection: close while draining), then
    //! the socket is closed and the pool drained.
    void accept_loop() {
        BoundedPool pool(static_cast<std::size_t>(threads), queue_capacity, counters);
        for (;;) {
            pollfd fds[2] = {{listen_fd, POLLIN, 0}, {wake_pipe[0], POLLIN, 0}};
            const int rc = poll(fds, 2, -1);
            if (rc < 0) {
                if (errno == EINTR) continue;
                break;
            }
            if (fds[1].revents != 0) break;
            if ((fds[0].revents & (POLLERR | POLLNVAL)) != 0) break;
            if ((fds[0].revents & POLLIN) != 0) accept_pending(pool);
        }
        refuse_new_handshakes(listen_fd);
        accept_pending(pool);
        // A handshake whose final ACK passed the filter while it was being attached lands in the queue a moment
        // later; loopback delivers it within microseconds, a network path within a round trip.
        for (int round = 0; round < 5; ++round) {
            pollfd pfd{listen_fd, POLLIN, 0};
            if (poll(&pfd, 1, 20) > 0) accept_pending(pool);
        }
        ::close(listen_fd);
        listen_fd = -1;
        pool.shutdown();  // serves what is queued, joins the workers
    }

    //! Attaches a classic BPF filter to the listening socket that drops every segment carrying SYN (new
    //! connections) and keeps the rest (the ACKs that complete handshakes already under way). For TCP the filter
    //! sees the segment from its TCP header: byte 13 holds the flags, SYN is 0x02.
    static void refuse_new_handshakes(int fd) {
        sock_filter code[] = {
            BPF_STMT(BPF_LD | BPF_B | BPF_ABS, 13),
            BPF_JUMP(BPF_JMP | BPF_JSET | BPF_K, 0x02, 0, 1),
            BPF_STMT(BPF_RET | BPF_K, 0),
            BPF_STMT(BPF_RET | BPF_K, 0xffffffffu),
        };
        sock_fprog program{static_cast<unsigned short>(std::size(code)), code};
        // Best effort: without the filter, connections arriving in the last moment are reset as before.
        (void)setsockopt(fd, SOL_SOCKET, SO_ATTACH_FILTER, &program, sizeof program);
    }

    //! The 503 + Retry-After problem+json answer of the shedding paths, as raw bytes.
    std::string overloaded_response(const std::string& id) const {
        const api::ApiResponse response =
            problem(503, "overloaded", "Server overloaded",
                    "all " + std::to_string(threads) + " workers are busy and " + std::to_string(queue_capacity) +
                        " connections are waiting; retry later");
        return "HTTP/1.1 503 Service Unavailable\r\nContent-Type: " + response.content_type +
               "\r\nRetry-After: 1\r\nConnection: close\r\nX-Request-Id: " + id +
               "\r\nContent-Length: " + std::to_string(response.body.size()) + "\r\n\r\n" + response.body;
    }

    //! Metrics and the access log line for the request the current thread just answered.
    void finish_request(const ConnectionStream& stream, int fd) {
        RequestState& r = t_request;
        if (r.status == 0) return;  // nothing was answered (the client closed or timed out before a request)
        const double seconds = std::chrono::duration<double>(Clock::now() - r.start).count();
        const std::string route = r.route.empty() ? "unmatched" : r.route;
        // the method of an unparsable request line is whatever the client sent: keep the label set bounded
        static constexpr std::string_view kMethods[] = {"GET", "HEAD", "POST", "PUT", "DELETE", "OPTIONS", "PATCH"};
        const bool known = std::find(std::begin(kMethods), std::end(kMethods), r.method) != std::end(kMethods);
        metrics.observe(route, known ? r.method : "other", r.status, seconds, stream.bytes_in(), stream.bytes_out(),
                        r.output_faces);
        if (config.access_log == ServerConfig::AccessLog::Off) return;
        std::string line = "{\"ts\":\"" + utc_timestamp() + "\",\"id\":" + api::json_quote(r.id) +
                           ",\"remote\":" + api::json_quote(peer_address(fd)) +
                           ",\"method\":" + api::json_quote(r.method) + ",\"path\":" + api::json_quote(r.path) +
                           ",\"route\":" + api::json_quote(route) + ",\"status\":" + std::to_string(r.status);
        char ms[32];
        std::snprintf(ms, sizeof ms, "%.3f", seconds * 1000.0);
        line += ",\"ms\":" + std::string(ms) + ",\"bytes_in\":" + std::to_string(stream.bytes_in()) +
                ",\"bytes_out\":" + std::to_string(stream.bytes_out());
        if (r.output_faces) line += ",\"output_faces\":" + std::to_string(r.output_faces);
        line += "}\n";
        log_line(line);
    }

    void log_line(const std::string& line) {
        std::FILE* out = config.access_log == ServerConfig::AccessLog::Stdout ? stdout : stderr;
        std::lock_guard lock(log_mutex);
        std::fwrite(line.data(), 1, line.size(), out);
        std::fflush(out);
    }

    //! The shedding path: every worker is busy and the queue is full. Reads the request head (briefly), answers
    //! 503 + Retry-After with problem+json, and closes; about 0.3 s at most per connection, on one thread.
    void shed_connection(int fd) {
        metrics.shed();
        discard_input(fd, std::chrono::milliseconds(200), std::size_t{1} << 16, true);
        const std::string id = new_request_id();
        send_all(fd, overloaded_response(id), std::chrono::milliseconds(200));
        ::shutdown(fd, SHUT_WR);
        discard_input(fd, std::chrono::milliseconds(100), std::size_t{1} << 16, false);
        ::close(fd);
        if (config.access_log != ServerConfig::AccessLog::Off)
            log_line("{\"ts\":\"" + utc_timestamp() + "\",\"id\":\"" + id + "\",\"status\":503,\"shed\":true}\n");
    }

    //! Whether the request may run: no token configured, an open route, or a matching bearer token.
    bool authorized(const httplib::Request& req, std::string_view route) const {
        if (config.auth_token.empty() || is_open_route(route)) return true;
        const std::string value = req.get_header_value("Authorization");
        constexpr std::string_view kScheme = "bearer ";
        if (value.size() < kScheme.size() || !iequals(std::string_view(value).substr(0, kScheme.size()), kScheme))
            return false;
        std::string_view token = std::string_view(value).substr(kScheme.size());
        while (!token.empty() && token.front() == ' ') token.remove_prefix(1);
        return constant_time_equal(token, config.auth_token);
    }

    api::ApiResponse unauthorized(const httplib::Request& req) const {
        const bool had_token = req.has_header("Authorization");
        api::ApiResponse response = problem(
            401, "unauthorized", "Authentication required",
            had_token ? "the bearer token is not valid" : "this endpoint needs \"Authorization: Bearer <token>\"");
        response.headers.emplace_back("WWW-Authenticate", had_token
                                                              ? R"(Bearer realm="surfaced", error="invalid_token")"
                                                              : R"(Bearer realm="surfaced")");
        return response;
    }

    bool origin_allowed(std::string_view origin) const {
        if (origin.empty()) return false;
        return std::any_of(config.cors_origins.begin(), config.cors_origins.end(),
                           [&](const std::string& allowed) { return allowed == "*" || allowed == origin; });
    }

    //! OPTIONS: CORS preflight for an allowed Origin (204), 403 for another Origin, 204 + Allow without one.
    void options(const httplib::Request& req, httplib::Response& res) {
        const std::string origin = req.get_header_value("Origin");
        std::string allow = api::allowed_methods(req.path);
        if (allow.empty() && web_root && resolve_static(*web_root, req.path)) allow = "GET, HEAD";
        if (allow.empty()) {
            write_response(api::route_not_found(req.method, req.path), res);
            return;
        }
        allow += ", OPTIONS";
        if (!origin.empty() && !config.cors_origins.empty()) {
            if (!origin_allowed(origin)) {
                write_response(problem(403, "origin_not_allowed", "Origin not allowed",
                                       "cross-origin requests from " + origin + " are not allowed"),
                               res);
                return;
            }
            res.set_header("Access-Control-Allow-Methods", allow);
            res.set_header("Access-Control-Allow-Headers", std::string(kCorsAllowHeaders));
            res.set_header("Access-Control-Max-Age", "600");
        }
        res.status = 204;
        res.set_header("Allow", allow);
    }

    void configure() {
        // Not used by our connection loop (CoreServer), but keeps httplib's own bookkeeping consistent.
        server.set_keep_alive_max_count(static_cast<std::size_t>(std::max(1, config.keep_alive_max_requests)));
        server.set_keep_alive_timeout(config.keep_alive_timeout_seconds);
        // Without a limit cpp-httplib buffers bodies of any size; with it, an oversized Content-Length is refused
        // (413, rendered by the error handler below) before the body is read.
        server.set_payload_max_length(config.limits.max_body_bytes);
        server.set_read_timeout(config.read_timeout_seconds, 0);
        server.set_write_timeout(config.write_timeout_seconds, 0);

        for (const api::Route& route : api::routes()) {
            const api::Operation operation = route.handler;
            const std::string_view route_path = route.path;
            auto handler = [this, operation, route_path](const httplib::Request& req, httplib::Response& res) {
                if (!authorized(req, route_path)) {
                    write_response(unauthorized(req), res);
                    return;
                }
                api::ApiRequest request = to_api_request(req);
                api::match_path(route_path, request.path, &request.path_params);
                api::ApiContext request_context = context;
                request_context.request_id = t_request.id;
                request_context.cancel.flag = &abort_;
                if (config.limits.compute_deadline_ms > 0)
                    request_context.cancel.deadline =
                        t_request.start + std::chrono::milliseconds(config.limits.compute_deadline_ms);
                write_response(operation(request, request_context), res);
            };
            const std::string pattern = literal_pattern(route.path);
            if (route.method == "GET")
                server.Get(pattern, handler);
            else if (route.method == "POST")
                server.Post(pattern, handler);
            else if (route.method == "PUT")
                server.Put(pattern, handler);
            else if (route.method == "PATCH")
                server.Patch(pattern, handler);
            else if (route.method == "DELETE")
                server.Delete(pattern, handler);
        }

        // Runs after the head is parsed and before the body is read: request id, route label, OPTIONS, static files.
        server.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
            // Debian's libcpp-httplib is built with brotli, which it prefers and runs at quality 11: 5-13 s for
            // three.js's 2 MB modules, seconds for large JSON/OBJ results, where gzip (zlib level 6) takes ~0.15 s.
            // Hide "br" from the library's choice of encoding. The Request is a non-const local of httplib's
            // process_request, so changing it through this const reference is well defined.
            without_brotli(const_cast<httplib::Request&>(req));
            RequestState& r = t_request;
            r.method = req.method;
            r.path = req.path;
            const std::string incoming = req.get_header_value("X-Request-Id");
            r.id = sane_request_id(incoming) ? incoming : new_request_id();
            r.route = route_template(req.path);
            const bool has_body = req.has_header("Transfer-Encoding") ||
                                  (req.has_header("Content-Length") && req.get_header_value("Content-Length") != "0");
            if (req.method == "OPTIONS") {
                options(req, res);
                r.force_close = has_body;
                return httplib::Server::HandlerResponse::Handled;
            }
            if (r.route.empty() && web_root && (req.method == "GET" || req.method == "HEAD")) {
                if (const auto file = resolve_static(*web_root, req.path)) {
                    std::error_code ec;
                    const auto size = fs::file_size(*file, ec);
                    std::ifstream in(*file, std::ios::binary);
                    if (!ec && in && size <= (std::uintmax_t{256} << 20)) {
                        res.body.resize(static_cast<std::size_t>(size));
                        in.read(res.body.data(), static_cast<std::streamsize>(size));
                        res.status = 200;
                        res.set_header("Content-Type", mime_type(*file));
                        r.route = "static";
                        r.force_close = has_body;
                        return httplib::Server::HandlerResponse::Handled;
                    }
                }
            }
            return httplib::Server::HandlerResponse::Unhandled;
        });

        // Runs for every response just before its head is written, errors included.
        server.set_post_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
            RequestState& r = t_request;
            if (r.id.empty()) r.id = new_request_id();  // the head could not be parsed: no pre-routing
            if (r.method.empty()) r.method = req.method;
            r.status = res.status;
            res.set_header("X-Request-Id", r.id);
            if (res.status == 503 && !res.has_header("Retry-After")) res.set_header("Retry-After", "1");
            if (!config.cors_origins.empty()) {
                res.set_header("Vary", "Origin");
                const std::string origin = req.get_header_value("Origin");
                if (origin_allowed(origin)) {
                    res.set_header("Access-Control-Allow-Origin", origin);
                    res.set_header("Access-Control-Expose-Headers", std::string(kCorsExposeHeaders));
                }
            }
            const std::string faces = res.get_header_value("X-Output-Faces");
            std::uint64_t value = 0;
            if (!faces.empty() && std::from_chars(faces.data(), faces.data() + faces.size(), value).ec == std::errc())
                r.output_faces = value;
        });

        // cpp-httplib calls this for every response with status >= 400, including the problem+json our operations
        // wrote: those have a body and are left alone. The rest are the library's own (no route, body too large,
        // unparsable request) and get the same envelope; the body may be unread, so the connection is closed after.
        server.set_error_handler(httplib::Server::HandlerWithResponse(
            [this](const httplib::Request& req, httplib::Response& res) -> httplib::Server::HandlerResponse {
                if (!res.body.empty()) return httplib::Server::HandlerResponse::Unhandled;
                t_request.force_close = true;
                api::ApiResponse problem_response;
                if (t_request.body_timed_out) {
                    res.headers.erase("Keep-Alive");
                    res.headers.erase("Connection");
                    res.set_header("Connection", "close");
                    write_response(problem(408, "body_timeout", "Request body too slow",
                                           "the request body did not arrive within " +
                                               std::to_string(config.body_timeout_seconds) + " s plus 1 s per " +
                                               std::to_string(config.body_min_rate_bytes) + " bytes received"),
                                   res);
                    return httplib::Server::HandlerResponse::Handled;
                }
                switch (res.status) {
                    case 404: problem_response = api::route_not_found(req.method, req.path); break;
                    case 413:
                        problem_response = api::error_response(api::make_problem(
                            api::Problem::PayloadTooLarge, "request body is larger than the limit of " +
                                                               std::to_string(config.limits.max_body_bytes) +
                                                               " bytes"));
                        break;
                    case 400:
                        problem_response = api::error_response(
                            api::make_problem(api::Problem::BadRequest, "the HTTP request could not be parsed"));
                        break;
                    default:
                        problem_response = api::error_response(
                            api::make_transport_problem(res.status, "the HTTP layer rejected the request"));
                }
                write_response(std::move(problem_response), res);
                return httplib::Server::HandlerResponse::Handled;
            }));

        // Operations never throw; this is the fail-safe for bugs in this file or the library.
        server.set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr) {
            write_response(api::error_response(api::make_problem(api::Problem::Internal, "internal error")), res);
        });
    }
};

HttpServer::HttpServer(ServerConfig config) : impl_(std::make_unique<Impl>(std::move(config))) {}

HttpServer::~HttpServer() { stop(); }

bool HttpServer::start(std::string* error) {
    std::lock_guard lock(impl_->mutex);
    Impl& s = *impl_;
    const std::string where = s.config.host + ":" + std::to_string(s.config.port);
    if (s.listener.joinable()) {
        if (error) *error = "server already started";
        return false;
    }
    if (s.config.port == 0) {
        s.port = s.server.bind_to_any_port(s.config.host);
    } else if (s.server.bind_to_port(s.config.host, s.config.port)) {
        s.port = s.config.port;
    } else {
        s.port = -1;
    }
    if (s.port < 0) {
        if (error) *error = "cannot listen on " + where + " (address in use, not local, or not permitted)";
        return false;
    }
    s.listen_fd = s.server.take_listening_socket();
    // httplib listens with a backlog of 5: under a burst of connections the kernel would drop SYNs (clients retry
    // after a second). The kernel caps this at net.core.somaxconn.
    if (s.listen_fd < 0 || ::listen(s.listen_fd, SOMAXCONN) != 0 ||
        fcntl(s.listen_fd, F_SETFL, fcntl(s.listen_fd, F_GETFL) | O_NONBLOCK) != 0 ||
        pipe2(s.wake_pipe, O_CLOEXEC | O_NONBLOCK) != 0) {
        if (s.listen_fd >= 0) ::close(s.listen_fd);
        s.listen_fd = -1;
        if (error) *error = "cannot listen on " + where + ": " + std::strerror(errno);
        return false;
    }
    // The socket is listening already: connections made from now on wait in the backlog until the loop runs, and
    // a stop() right away finds the wake-up byte.
    s.listener = std::thread([&s] {
        s.accept_loop();
        std::lock_guard done(s.done_mutex);
        s.listener_done = true;
        s.done_cv.notify_all();
    });
    return true;
}

int HttpServer::port() const { return impl_->port; }

bool HttpServer::serves_web_root() const { return impl_->web_root.has_value(); }

int HttpServer::threads() const { return impl_->threads; }

void HttpServer::begin_drain() { impl_->draining_ = true; }

void HttpServer::stop() {
    std::lock_guard lock(impl_->mutex);
    Impl& s = *impl_;
    if (!s.listener.joinable()) return;
    s.draining_ = true;
    if (s.config.drain_delay_ms > 0) std::this_thread::sleep_for(std::chrono::milliseconds(s.config.drain_delay_ms));
    // Wakes the accept loop: it refuses new handshakes, accepts the listen backlog, closes the listening socket and
    // shuts the pool down, which serves everything accepted.
    const char byte = 1;
    while (::write(s.wake_pipe[1], &byte, 1) < 0 && errno == EINTR) {}
    {
        std::unique_lock done(s.done_mutex);
        if (!s.done_cv.wait_for(done, std::chrono::seconds(std::max(0, s.config.drain_timeout_seconds)),
                                [&] { return s.listener_done; }))
            s.abort_ = true;  // cancel the work still running; its requests are answered 503 `cancelled`
    }
    s.listener.join();
    for (int& fd : s.wake_pipe) {
        if (fd >= 0) ::close(fd);
        fd = -1;
    }
}

ServerStats HttpServer::stats() const {
    ServerStats out;
    out.in_flight = impl_->counters.in_flight.load();
    out.queue_depth = impl_->counters.queued.load();
    out.busy_workers = impl_->counters.busy.load();
    out.shed_total = impl_->metrics.shed_total();
    out.draining = impl_->draining_.load();
    return out;
}

bool probe_http(const std::string& host, int port, const std::string& path, double timeout_seconds,
                std::string* detail) {
    const double timeout = timeout_seconds > 0 ? timeout_seconds : 1.0;
    const auto sec = static_cast<time_t>(timeout);
    const auto usec = static_cast<time_t>((timeout - static_cast<double>(sec)) * 1e6);
    // Listening on every interface means the probe (run next to the server) reaches it on loopback.
    const std::string target = host.empty() || host == "0.0.0.0" ? "127.0.0.1" : (host == "::" ? "::1" : host);
    httplib::Client client(target, port);
    client.set_connection_timeout(sec, usec);
    client.set_read_timeout(sec, usec);
    client.set_write_timeout(sec, usec);
    client.set_keep_alive(false);
    const auto result = client.Get(path);
    if (!result) {
        if (detail)
            *detail =
                "no answer from " + target + ":" + std::to_string(port) + ": " + httplib::to_string(result.error());
        return false;
    }
    if (detail) *detail = "HTTP " + std::to_string(result->status) + " from " + path;
    return result->status == 200;
}

}  // namespace surfaced::server
