// Request metrics of the HTTP server, rendered in the Prometheus text exposition format (version 0.0.4).
// Labels are bounded: `route` is a route template from api::routes() ("/patches/{name}"), "static" or "unmatched",
// never a raw path, so a client cannot grow the series set.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <string_view>
#include <tuple>

namespace surfaced::server {

//! Instantaneous values the server reads when rendering (not stored here).
struct MetricsGauges {
    std::int64_t in_flight = 0;       //!< requests being read, computed or written
    std::int64_t queue_depth = 0;     //!< accepted connections waiting for a worker
    std::int64_t queue_capacity = 0;  //!< the bound beyond which connections are shed (503)
    std::int64_t workers = 0;         //!< worker threads
    std::int64_t busy_workers = 0;    //!< workers holding a connection
    bool draining = false;
};

class Metrics {
public:
    //! Upper bounds of the latency histogram buckets, in seconds (+Inf is implicit).
    static constexpr std::array<double, 13> kBuckets = {0.005, 0.01, 0.025, 0.05, 0.1,  0.25, 0.5,
                                                        1.0,   2.5,  5.0,   10.0, 30.0, 60.0};

    //! One answered request. `output_faces` comes from the response's X-Output-Faces header (0 when absent).
    void observe(std::string_view route, std::string_view method, int status, double seconds, std::uint64_t bytes_in,
                 std::uint64_t bytes_out, std::uint64_t output_faces);
    //! One connection answered 503 by the shedding path (the queue was full).
    void shed();
    std::uint64_t shed_total() const;

    std::string render(const MetricsGauges& gauges) const;

private:
    struct RouteStats {
        std::array<std::uint64_t, kBuckets.size()> buckets{};  // non-cumulative here; cumulated when rendered
        std::uint64_t count = 0;
        double sum = 0.0;
        std::uint64_t bytes_in = 0;
        std::uint64_t bytes_out = 0;
        std::uint64_t output_faces = 0;
    };
    mutable std::mutex mutex_;
    std::map<std::tuple<std::string, std::string, int>, std::uint64_t> requests_;  // (route, method, status)
    std::map<std::string, RouteStats> routes_;
    std::uint64_t shed_ = 0;
};

}  // namespace surfaced::server
