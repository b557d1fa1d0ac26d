// HttpServer: the HTTP transport for the api/ route table. A pimpl facade (llama.cpp server-http.h): no HTTP-library
// type appears here, so only http_server.cpp compiles httplib.h.
//
// What it adds on top of api/: a worker pool, the request body limit (413 before the body is buffered), socket
// timeouts, problem+json for every error the HTTP library produces itself (404, 405, 413, malformed requests) and a
// fail-safe exception handler (500), and static files of the web client at "/".
#pragma once

#include <memory>
#include <string>

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
    int read_timeout_seconds = 30;   //!< per socket read, not per request (cpp-httplib semantics)
    int write_timeout_seconds = 30;
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
    //! Stops accepting, finishes in-flight requests, joins the threads. Idempotent; safe before start().
    void stop();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace surfaced::server
