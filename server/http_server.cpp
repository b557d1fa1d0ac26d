// HttpServer: the server object. It derives the effective settings from ServerConfig, owns the parts (metrics and
// access log, router, HTTP adapter), runs the accept loop on a background thread, and sequences the graceful stop.
#include "server/http_server.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <utility>

#include "api/operation.h"
#include "server/httplib_adapter.h"
#include "server/metrics.h"
#include "server/request_log.h"
#include "server/router.h"
#include "server/worker_pool.h"

namespace surfaced::server {
namespace {

int default_threads() {
    const unsigned n = std::thread::hardware_concurrency();
    return n < 2 ? 2 : static_cast<int>(n);
}

}  // namespace

struct HttpServer::Impl final : public api::ServiceState {
    const ServerConfig config;
    const int threads;
    const std::size_t queue_capacity;
    Metrics metrics;
    LoadCounters counters;
    std::atomic<bool> draining_{false};
    std::atomic<bool> abort_{false};  // set when the drain timeout passes: in-flight work is cancelled
    RequestLog log;
    Router router;
    HttplibAdapter transport;
    std::thread listener;
    std::mutex done_mutex;
    std::condition_variable done_cv;
    bool listener_done = false;
    std::mutex mutex;  // start/stop
    int port = -1;

    explicit Impl(ServerConfig c)
        : config(std::move(c)),
          threads(config.threads > 0 ? config.threads : default_threads()),
          queue_capacity(
              static_cast<std::size_t>(config.queue_capacity > 0 ? config.queue_capacity : std::max(64, 8 * threads))),
          log(config.access_log, metrics),
          router(config, operation_context(), abort_),
          transport(config, router, log, counters, draining_) {
        router.mount(transport);
    }

    //! What every operation gets, before the per-request parts (request id, deadline, cancel flag).
    api::ApiContext operation_context() {
        api::ApiContext context;
        context.limits = config.limits;
        context.service = this;
        return context;
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
};

HttpServer::HttpServer(ServerConfig config) : impl_(std::make_unique<Impl>(std::move(config))) {}

HttpServer::~HttpServer() { stop(); }

bool HttpServer::start(std::string* error) {
    std::lock_guard lock(impl_->mutex);
    Impl& s = *impl_;
    if (s.listener.joinable()) {
        if (error) *error = "server already started";
        return false;
    }
    if (!s.transport.listen(s.port, error)) return false;
    // The socket is listening already: connections made from now on wait in the backlog until the loop runs, and
    // a stop() right away finds the wake-up byte.
    s.listener = std::thread([&s] {
        s.transport.run(s.threads, s.queue_capacity);
        std::lock_guard done(s.done_mutex);
        s.listener_done = true;
        s.done_cv.notify_all();
    });
    return true;
}

int HttpServer::port() const { return impl_->port; }

bool HttpServer::serves_web_root() const { return impl_->router.serves_static_files(); }

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
    s.transport.wake();
    {
        std::unique_lock done(s.done_mutex);
        if (!s.done_cv.wait_for(done, std::chrono::seconds(std::max(0, s.config.drain_timeout_seconds)),
                                [&] { return s.listener_done; }))
            s.abort_ = true;  // cancel the work still running; its requests are answered 503 `cancelled`
    }
    s.listener.join();
    s.transport.close_wake_pipe();
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

}  // namespace surfaced::server
