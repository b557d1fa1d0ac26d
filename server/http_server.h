// HttpServer: the HTTP transport for the api/ route table. A pimpl facade (llama.cpp server-http.h): no HTTP-library
// type appears here; httplib_adapter.cpp is the only code that compiles httplib.h.
//
// What it adds on top of api/:
//  * bounded resources: a fixed pool of workers and a bounded queue of accepted connections; past it, connections
//    are answered 503 + Retry-After by a small shedding path (cpp-httplib 0.11's own queue is unbounded);
//    keep-alive limits (requests per connection, idle timeout, and idle connections give their worker up as soon
//    as another connection waits); a deadline for reading a request head (slowloris); a per-request compute
//    deadline handed to operations as a surfaced::Cancel; the request body limit (413 before buffering);
//    a deadline for the body (408: a client trickling its body cannot hold a worker indefinitely);
//  * graceful shutdown: stop() refuses new connections (new handshakes are dropped by a socket filter, so their
//    clients see a refused connection, never a reset request), accepts and answers what is already in the kernel's
//    listen backlog and what was accepted (with Connection: close),
//    lets in-flight work finish (cancelling it after drain_timeout), /readyz answers 503 meanwhile;
//  * observability: /metrics (Prometheus), request ids (X-Request-Id), JSON access log lines;
//  * security: optional bearer-token auth, a CORS allow-list with preflight, static files of the web client at
//    "/" confined to the web root (no "..", no symlinks out of it);
//  * problem+json for every error the HTTP library produces itself, and a fail-safe exception handler (500).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "api/limits.h"

namespace surfaced::server {

struct ServerConfig {
    std::string host = "127.0.0.1";
    int port = 8080;  //!< 0: any free port (see HttpServer::port())
    //! Worker threads. cpp-httplib holds one worker per connection for its whole keep-alive life, so this is also the
    //! number of clients served at once. 0: one per hardware thread (at least 2).
    int threads = 0;
    //! Directory served at "/" (index.html for "/"); ignored when empty or not a directory. API routes win.
    std::string web_root;
    api::Limits limits;
    int read_timeout_seconds = 30;   //!< per socket read while reading a body; also the wait for a first request
    int write_timeout_seconds = 30;  //!< per socket write
    //! A request line and headers must arrive within this many seconds of their first byte (slowloris).
    int header_timeout_seconds = 10;
    //! A request body must arrive within body_timeout_seconds of the end of its head, plus one second for every
    //! body_min_rate_bytes received (so uploads faster than that rate are never cut off, and a client trickling its
    //! body slower holds a worker for a bounded time); otherwise 408 `body_timeout` and the connection is closed.
    int body_timeout_seconds = 30;
    std::size_t body_min_rate_bytes = 16384;  //!< bytes per second; 0: the body gets body_timeout_seconds in all
    //! Accepted connections that may wait for a worker; more are answered 503 + Retry-After. 0: max(64, 8 x threads).
    int queue_capacity = 0;
    //! Requests served on one connection before it is closed (Connection: close on the last).
    int keep_alive_max_requests = 100;
    //! An idle keep-alive connection is closed after this many seconds, or as soon as another connection waits.
    int keep_alive_timeout_seconds = 5;
    //! stop(): in-flight work still running after this long is cancelled (its requests get 503 `cancelled`).
    int drain_timeout_seconds = 30;
    //! stop(): keep accepting (while /readyz answers 503) this long before closing the listening socket, so that a
    //! load balancer notices first. 0 in tests.
    int drain_delay_ms = 0;
    enum class AccessLog { Off, Stdout, Stderr };
    AccessLog access_log = AccessLog::Off;  //!< one JSON line per request
    //! When non-empty, every route except the probes (/livez, /readyz, /healthz), /openapi.json, static files and
    //! CORS preflights needs "Authorization: Bearer <token>" (compared in constant time); otherwise 401.
    std::string auth_token;
    //! Origins allowed to call the API from a browser ("https://app.example"; "*" for any). Empty: no CORS headers.
    std::vector<std::string> cors_origins;
};

//! A snapshot of the server's load, for tests and operators.
struct ServerStats {
    std::int64_t in_flight = 0;
    std::int64_t queue_depth = 0;
    std::int64_t busy_workers = 0;
    std::uint64_t shed_total = 0;
    bool draining = false;
};

class HttpServer {
public:
    explicit HttpServer(ServerConfig config);
    ~HttpServer();  //!< stops the server if it is running
    HttpServer(const HttpServer&) = delete;
    HttpServer& operator=(const HttpServer&) = delete;

    //! Binds host:port and serves on a background thread; returns once connections are being accepted.
    //! False (with a reason in *error) when the address cannot be bound. Call at most once.
    bool start(std::string* error = nullptr);
    //! The bound port (the chosen one when config.port was 0); -1 before start().
    int port() const;
    //! Whether static files are served (web_root exists).
    bool serves_web_root() const;
    //! Worker threads in use.
    int threads() const;
    //! Marks the server as draining (/readyz answers 503) without stopping it; stop() does this first.
    void begin_drain();
    //! Graceful shutdown: begin_drain(), wait drain_delay_ms, stop accepting, answer the connections already
    //! accepted, finish in-flight requests (cancelling those still running after drain_timeout_seconds), join the
    //! threads. Idempotent; safe before start().
    void stop();
    ServerStats stats() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

//! GET http://host:port/path with the given timeout (seconds, for connecting and for the answer): true when the
//! answer is 200. `detail` gets the status or the connection error. For `surfaced healthcheck`; defined in
//! httplib_adapter.cpp with the rest of the code that uses the HTTP library.
bool probe_http(const std::string& host, int port, const std::string& path, double timeout_seconds,
                std::string* detail = nullptr);

}  // namespace surfaced::server
