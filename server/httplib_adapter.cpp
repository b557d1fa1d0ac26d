#include "server/httplib_adapter.h"

#include <fcntl.h>
#include <linux/filter.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <strings.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <ctime>
#include <exception>
#include <optional>
#include <thread>
#include <utility>

#include <httplib.h>

#include "server/problems.h"
#include "server/request_id.h"
#include "server/request_log.h"
#include "server/socket_io.h"
#include "server/worker_pool.h"

namespace surfaced::server {
namespace {

using Clock = std::chrono::steady_clock;

// A connection is served start to end by one worker thread and its requests one after another, so the record of the
// current request, which the library's hooks (pre-routing, handler, error, post-routing) fill in, is thread-local.
thread_local RequestRecord t_request;
// The Content-Type of the current request when it names a form (see hide_form_content_type), else empty.
thread_local std::string t_form_content_type;

// ---- requests and responses ------------------------------------------------------------------------------------

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

//! The media type of a Content-Type value, lower-cased, without parameters.
std::string media_type_of(std::string_view content_type) {
    std::string_view type = content_type.substr(0, content_type.find(';'));
    while (!type.empty() && type.front() == ' ') type.remove_prefix(1);
    while (!type.empty() && type.back() == ' ') type.remove_suffix(1);
    std::string out(type);
    for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

//! cpp-httplib decodes form bodies itself while reading them: application/x-www-form-urlencoded into query
//! parameters (and refuses one over 8 KiB with 413, whatever the body limit), multipart/form-data into files (the
//! body stays empty). So the header is taken off the library's request and kept in t_form_content_type: the body is
//! read as plain bytes within the body limit, like any other, and reaches the API unchanged with its Content-Type;
//! the upload operations parse a multipart/form-data body themselves (api/multipart.h), and answer 415 with the
//! types they accept for a urlencoded one.
void hide_form_content_type(httplib::Request& req) {
    t_form_content_type.clear();
    const std::string type = media_type_of(req.get_header_value("Content-Type"));
    if (type != "application/x-www-form-urlencoded" && type != "multipart/form-data") return;
    t_form_content_type = req.get_header_value("Content-Type");
    req.headers.erase("Content-Type");
}

//! A request that expects a body but has neither Content-Length nor Transfer-Encoding has an empty body (RFC 9112
//! section 6.3); cpp-httplib would read it until the client closes, so the emptiness is made explicit.
void empty_body_without_length(httplib::Request& req) {
    const bool takes_body =
        req.method == "POST" || req.method == "PUT" || req.method == "PATCH" || req.method == "DELETE";
    if (takes_body && !req.has_header("Content-Length") && !req.has_header("Transfer-Encoding"))
        req.set_header("Content-Length", "0");
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

class LibraryRequest final : public HttpRequest {
public:
    explicit LibraryRequest(const httplib::Request& req) : req_(req) {}

    const std::string& method() const override { return req_.method; }
    const std::string& path() const override { return req_.path; }
    bool has_header(const std::string& name) const override { return is_hidden(name) || req_.has_header(name); }
    std::string header(const std::string& name) const override {
        return is_hidden(name) ? t_form_content_type : req_.get_header_value(name);
    }
    api::ApiRequest to_api() const override {
        api::ApiRequest out;
        out.method = req_.method;
        out.path = req_.path;
        out.query.insert(req_.params.begin(), req_.params.end());
        out.content_type = header("Content-Type");
        out.body = req_.body;
        for (const auto& [name, value] : req_.headers) {
            std::string lower = name;
            for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
            out.headers.emplace(std::move(lower), value);
        }
        if (!t_form_content_type.empty()) out.headers.emplace("content-type", t_form_content_type);
        return out;
    }

private:
    static bool is_hidden(const std::string& name) {
        return !t_form_content_type.empty() && name.size() == 12 && strncasecmp(name.c_str(), "content-type", 12) == 0;
    }
    const httplib::Request& req_;
};

class LibraryResponse final : public HttpResponse {
public:
    explicit LibraryResponse(httplib::Response& res) : res_(res) {}

    int status() const override { return res_.status; }
    void set_status(int status) override { res_.status = status; }
    bool has_body() const override { return !res_.body.empty(); }
    void set_body(std::string body) override { res_.body = std::move(body); }  // set_content would copy
    bool has_header(const std::string& name) const override { return res_.has_header(name); }
    std::string header(const std::string& name) const override { return res_.get_header_value(name); }
    void add_header(const std::string& name, const std::string& value) override { res_.set_header(name, value); }
    void remove_header(const std::string& name) override { res_.headers.erase(name); }

private:
    httplib::Response& res_;
};

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

// ---- draining --------------------------------------------------------------------------------------------------

//! Attaches a classic BPF filter to the listening socket that drops every segment carrying SYN (new connections)
//! and keeps the rest (the ACKs that complete handshakes already under way). For TCP the filter sees the segment
//! from its TCP header: byte 13 holds the flags, SYN is 0x02.
void refuse_new_handshakes(int fd) {
    sock_filter code[] = {
        BPF_STMT(BPF_LD | BPF_B | BPF_ABS, 13),
        BPF_JUMP(BPF_JMP | BPF_JSET | BPF_K, 0x02, 0, 1),
        BPF_STMT(BPF_RET | BPF_K, 0),
        BPF_STMT(BPF_RET | BPF_K, 0xffffffffu),
    };
    sock_fprog program{static_cast<unsigned short>(std::size(code)), code};
    // Best effort: without the filter, connections arriving in the last moment are reset when the socket closes.
    (void)setsockopt(fd, SOL_SOCKET, SO_ATTACH_FILTER, &program, sizeof program);
}

}  // namespace

// ---- the adapter -----------------------------------------------------------------------------------------------

struct HttplibAdapter::Impl {
    //! httplib::Server with our connection loop: process_and_close_socket is httplib's (private, virtual) hook for
    //! one accepted socket; overriding it gives the socket to us, so the keep-alive loop, deadlines, draining and
    //! the shedding answer are ours while request parsing, routing and response writing (process_request) stay
    //! httplib's. Our accept loop hands each socket over through serve_connection.
    class CoreServer final : public httplib::Server {
    public:
        explicit CoreServer(Impl& owner) : owner_(owner) {}

        //! The listening socket bound by bind_to_port / bind_to_any_port, handed over to the caller (our accept
        //! loop owns it from then on; httplib's listen loop is never run).
        int take_listening_socket() { return svr_sock_.exchange(INVALID_SOCKET); }

        //! Serves one accepted socket as the pool admitted it, and closes it.
        void serve_connection(int sock, Admission admission) {
            switch (admission) {
                case Admission::Reject:
                    owner_.log.shed();
                    ::close(sock);
                    return;
                case Admission::Shed: owner_.shed_connection(sock); return;
                case Admission::Serve: process_and_close_socket(sock); return;
            }
        }

    private:
        // The keep-alive loop of one connection.
        bool process_and_close_socket(socket_t sock) override {
            // Responses go out as two writes (head, body): without TCP_NODELAY the second waits for the peer's
            // delayed ACK (40 ms on Linux).
            const int one = 1;
            setsockopt(sock, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
            ConnectionStream stream(sock, owner_.config);
            const int max_requests = std::max(1, owner_.config.keep_alive_max_requests);
            for (int served = 0; served < max_requests; ++served) {
                const Next next = owner_.wait_for_request(sock, stream, served == 0);
                if (next == Next::Shed) {
                    owner_.log.shed();
                    send_all(sock, owner_.overloaded_response(new_request_id()), std::chrono::milliseconds(200));
                }
                if (next != Next::Serve) break;
                // Connection: close on the last allowed request, when draining, and while other connections wait
                // for a worker (one request per turn then: fair, and no idle-close race with the client).
                const bool last =
                    served + 1 == max_requests || owner_.draining.load() || owner_.counters.queued.load() > 0;
                stream.begin_request();
                t_request = RequestRecord{};
                t_form_content_type.clear();
                t_request.start = Clock::now();
                ++owner_.counters.in_flight;
                bool closed = false;
                const bool ok = process_request(stream, last, closed, nullptr);
                --owner_.counters.in_flight;
                t_request.bytes_in = stream.bytes_in();
                t_request.bytes_out = stream.bytes_out();
                t_request.fd = sock;
                owner_.log.finished(t_request);
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

    const ServerConfig& config;
    HttpHooks& hooks;
    RequestLog& log;
    LoadCounters& counters;
    const std::atomic<bool>& draining;
    CoreServer server{*this};
    api::ApiResponse overloaded;  // the 503 of the shedding paths (set by run())
    int listen_fd = -1;           // owned by the accept loop once it runs
    int wake_pipe[2] = {-1, -1};  // wake() writes a byte: the accept loop drains and ends

    Impl(const ServerConfig& c, HttpHooks& h, RequestLog& l, LoadCounters& n, const std::atomic<bool>& d)
        : config(c), hooks(h), log(l), counters(n), draining(d) {
        apply_limits();
        install_hooks();
    }

    void apply_limits() {
        // Not used by our connection loop (CoreServer), but keeps httplib's own bookkeeping consistent.
        server.set_keep_alive_max_count(static_cast<std::size_t>(std::max(1, config.keep_alive_max_requests)));
        server.set_keep_alive_timeout(config.keep_alive_timeout_seconds);
        // Without a limit cpp-httplib buffers bodies of any size; with it, an oversized Content-Length is refused
        // (413, rendered by the error hook) before the body is read.
        server.set_payload_max_length(config.limits.max_body_bytes);
        server.set_read_timeout(config.read_timeout_seconds, 0);
        server.set_write_timeout(config.write_timeout_seconds, 0);
    }

    void install_hooks() {
        // Runs after the head is parsed and before the body is read.
        server.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
            // Debian's libcpp-httplib is built with brotli, which it prefers and runs at quality 11: 5-13 s for
            // three.js's 2 MB modules, seconds for large JSON/OBJ results, where gzip (zlib level 6) takes ~0.15 s.
            // Hide "br" from the library's choice of encoding; forms likewise (see hide_form_content_type), and make
            // a missing body length explicit (see empty_body_without_length). The
            // Request is a non-const local of httplib's process_request, so changing it through this const
            // reference is well defined.
            auto& request_head = const_cast<httplib::Request&>(req);
            without_brotli(request_head);
            hide_form_content_type(request_head);
            empty_body_without_length(request_head);
            const LibraryRequest request(req);
            LibraryResponse response(res);
            return hooks.before_routing(request, response, t_request) ? httplib::Server::HandlerResponse::Handled
                                                                      : httplib::Server::HandlerResponse::Unhandled;
        });
        // Runs for every response just before its head is written, errors included.
        server.set_post_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
            const LibraryRequest request(req);
            LibraryResponse response(res);
            hooks.before_sending(request, response, t_request);
        });
        // cpp-httplib calls this for every response with status >= 400.
        server.set_error_handler(httplib::Server::HandlerWithResponse(
            [this](const httplib::Request& req, httplib::Response& res) -> httplib::Server::HandlerResponse {
                const LibraryRequest request(req);
                LibraryResponse response(res);
                return hooks.on_error_status(request, response, t_request)
                           ? httplib::Server::HandlerResponse::Handled
                           : httplib::Server::HandlerResponse::Unhandled;
            }));
        server.set_exception_handler([this](const httplib::Request&, httplib::Response& res, std::exception_ptr) {
            LibraryResponse response(res);
            hooks.on_exception(response);
        });
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
            if (!stream.has_buffered() && !first && draining.load()) return Next::Close;
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
            pool.enqueue([this, sock](Admission admission) { server.serve_connection(sock, admission); });
        }
    }

    //! The accept loop (our own: cpp-httplib's stop() shuts the listening socket down, which resets every
    //! connection still in the kernel's listen backlog; those clients had already sent their requests).
    //! On wake(): a socket filter drops new SYNs (a client that was not yet connected sees its connection refused
    //! once the socket closes, and may retry elsewhere), handshakes already under way complete, everything the
    //! kernel queued is accepted and answered like any accepted connection (with Connection: close while
    //! draining), then the socket is closed and the pool drained.
    void accept_loop(int threads, std::size_t queue_capacity) {
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

    //! The 503 + Retry-After problem+json answer of the shedding paths, as raw bytes.
    std::string overloaded_response(const std::string& id) const {
        return "HTTP/1.1 503 Service Unavailable\r\nContent-Type: " + overloaded.content_type +
               "\r\nRetry-After: 1\r\nConnection: close\r\nX-Request-Id: " + id +
               "\r\nContent-Length: " + std::to_string(overloaded.body.size()) + "\r\n\r\n" + overloaded.body;
    }

    //! The shedding path: every worker is busy and the queue is full. Reads the request head (briefly), answers
    //! 503 + Retry-After with problem+json, and closes; about 0.3 s at most per connection, on one thread.
    void shed_connection(int fd) {
        log.shed();
        discard_input(fd, std::chrono::milliseconds(200), std::size_t{1} << 16, true);
        const std::string id = new_request_id();
        send_all(fd, overloaded_response(id), std::chrono::milliseconds(200));
        ::shutdown(fd, SHUT_WR);
        discard_input(fd, std::chrono::milliseconds(100), std::size_t{1} << 16, false);
        ::close(fd);
        log.shed_answered(id);
    }
};

HttplibAdapter::HttplibAdapter(const ServerConfig& config, HttpHooks& hooks, RequestLog& log, LoadCounters& counters,
                               const std::atomic<bool>& draining)
    : impl_(std::make_unique<Impl>(config, hooks, log, counters, draining)) {}

HttplibAdapter::~HttplibAdapter() = default;

void HttplibAdapter::add_route(std::string_view method, std::string_view path, RouteHandler handler) {
    auto on_request = [handler = std::move(handler)](const httplib::Request& req, httplib::Response& res) {
        const LibraryRequest request(req);
        LibraryResponse response(res);
        handler(request, response, t_request);
    };
    httplib::Server& server = impl_->server;
    const std::string pattern = literal_pattern(path);
    if (method == "GET")
        server.Get(pattern, on_request);
    else if (method == "POST")
        server.Post(pattern, on_request);
    else if (method == "PUT")
        server.Put(pattern, on_request);
    else if (method == "PATCH")
        server.Patch(pattern, on_request);
    else if (method == "DELETE")
        server.Delete(pattern, on_request);
}

bool HttplibAdapter::listen(int& port, std::string* error) {
    Impl& s = *impl_;
    const std::string where = s.config.host + ":" + std::to_string(s.config.port);
    if (s.config.port == 0) {
        port = s.server.bind_to_any_port(s.config.host);
    } else if (s.server.bind_to_port(s.config.host, s.config.port)) {
        port = s.config.port;
    } else {
        port = -1;
    }
    if (port < 0) {
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
    return true;
}

void HttplibAdapter::run(int threads, std::size_t queue_capacity) {
    impl_->overloaded = overloaded_problem(threads, queue_capacity);
    impl_->accept_loop(threads, queue_capacity);
}

void HttplibAdapter::wake() {
    const char byte = 1;
    while (::write(impl_->wake_pipe[1], &byte, 1) < 0 && errno == EINTR) {}
}

void HttplibAdapter::close_wake_pipe() {
    for (int& fd : impl_->wake_pipe) {
        if (fd >= 0) ::close(fd);
        fd = -1;
    }
}

// ---- the health probe (http_server.h) --------------------------------------------------------------------------

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
