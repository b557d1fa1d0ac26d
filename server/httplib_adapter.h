// HttplibAdapter: the HTTP transport, built on cpp-httplib 0.11 (Debian 12's). httplib_adapter.cpp is the only code
// that includes httplib.h and everything that depends on the library's internals is there, so that an upgrade of
// the library touches that one file. The library parses requests, routes them and writes responses; the
// connections are ours: an accept loop that drains on shutdown, a bounded pool of workers, and a keep-alive loop
// per connection with deadlines for the request head and body. probe_http (http_server.h) is defined there too.
#pragma once

#include <atomic>
#include <cstddef>
#include <memory>
#include <string>
#include <string_view>

#include "server/http_exchange.h"
#include "server/http_server.h"

namespace surfaced::server {

struct LoadCounters;
class RequestLog;

class HttplibAdapter {
public:
    //! Every argument must outlive the adapter. `draining`: once set, connections are closed after the request
    //! being served (and idle keep-alive ones at once).
    HttplibAdapter(const ServerConfig& config, HttpHooks& hooks, RequestLog& log, LoadCounters& counters,
                   const std::atomic<bool>& draining);
    ~HttplibAdapter();
    HttplibAdapter(const HttplibAdapter&) = delete;
    HttplibAdapter& operator=(const HttplibAdapter&) = delete;

    //! Routes requests for `method` and `path` to `handler`. `path` is literal except for `{name}` segments, which
    //! match one path segment. Routes are tried in the order they were added.
    void add_route(std::string_view method, std::string_view path, RouteHandler handler);

    //! Binds config.host:config.port (0: any free port), listens, and makes the wake-up pipe. `port` gets the bound
    //! port (-1 when binding failed). False, with the reason in *error, when the server cannot listen.
    bool listen(int& port, std::string* error);
    //! The accept loop (after listen()), on the calling thread: accepts connections into a pool of `threads`
    //! workers with `queue_capacity` waiting places until wake(); then drains (see HttpServer::stop) and returns
    //! once every accepted connection has been answered.
    void run(int threads, std::size_t queue_capacity);
    //! Makes run() drain and return. Safe from any thread.
    void wake();
    //! Closes the wake-up pipe once run() has returned.
    void close_wake_pipe();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace surfaced::server
