#include "server/metrics.h"

#include <cstdio>

namespace surfaced::server {
namespace {

//! A label value: route templates and methods are ours, but escape as the format requires anyway.
std::string label(std::string_view value) {
    std::string out;
    for (const char c : value) {
        if (c == '\\' || c == '"') out += '\\';
        if (c == '\n') {
            out += "\\n";
            continue;
        }
        out += c;
    }
    return out;
}

std::string number(double value) {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.17g", value);
    return buffer;
}

void header(std::string& out, const char* name, const char* type, const char* help) {
    out += "# HELP ";
    out += name;
    out += ' ';
    out += help;
    out += "\n# TYPE ";
    out += name;
    out += ' ';
    out += type;
    out += '\n';
}

}  // namespace

void Metrics::observe(std::string_view route, std::string_view method, int status, double seconds,
                      std::uint64_t bytes_in, std::uint64_t bytes_out, std::uint64_t output_faces) {
    std::lock_guard lock(mutex_);
    ++requests_[{std::string(route), std::string(method), status}];
    RouteStats& stats = routes_[std::string(route)];
    std::size_t bucket = 0;
    while (bucket < kBuckets.size() && seconds > kBuckets[bucket]) ++bucket;
    if (bucket < kBuckets.size()) ++stats.buckets[bucket];
    ++stats.count;
    stats.sum += seconds;
    stats.bytes_in += bytes_in;
    stats.bytes_out += bytes_out;
    stats.output_faces += output_faces;
}

void Metrics::shed() {
    std::lock_guard lock(mutex_);
    ++shed_;
}

std::uint64_t Metrics::shed_total() const {
    std::lock_guard lock(mutex_);
    return shed_;
}

std::string Metrics::render(const MetricsGauges& gauges) const {
    std::lock_guard lock(mutex_);
    std::string out;
    out.reserve(4096 + routes_.size() * 2048);

    header(out, "surfaced_http_requests_total", "counter",
           "HTTP requests answered, by route template, method and status.");
    for (const auto& [key, count] : requests_) {
        const auto& [route, method, status] = key;
        out += "surfaced_http_requests_total{route=\"" + label(route) + "\",method=\"" + label(method) +
               "\",status=\"" + std::to_string(status) + "\"} " + std::to_string(count) + "\n";
    }

    header(out, "surfaced_http_request_duration_seconds", "histogram",
           "Time from the first byte of a request to its last response byte, by route template.");
    for (const auto& [route, stats] : routes_) {
        const std::string prefix = "surfaced_http_request_duration_seconds_bucket{route=\"" + label(route) + "\",le=\"";
        std::uint64_t cumulative = 0;
        for (std::size_t i = 0; i < kBuckets.size(); ++i) {
            cumulative += stats.buckets[i];
            char bound[32];
            std::snprintf(bound, sizeof bound, "%g", kBuckets[i]);
            out += prefix + bound + "\"} " + std::to_string(cumulative) + "\n";
        }
        out += prefix + "+Inf\"} " + std::to_string(stats.count) + "\n";
        out += "surfaced_http_request_duration_seconds_sum{route=\"" + label(route) + "\"} " + number(stats.sum) + "\n";
        out += "surfaced_http_request_duration_seconds_count{route=\"" + label(route) + "\"} " +
               std::to_string(stats.count) + "\n";
    }

    const auto per_route = [&](const char* name, const char* help, std::uint64_t RouteStats::*field) {
        header(out, name, "counter", help);
        for (const auto& [route, stats] : routes_)
            out += std::string(name) + "{route=\"" + label(route) + "\"} " + std::to_string(stats.*field) + "\n";
    };
    per_route("surfaced_http_request_bytes_total", "Request bytes read (head and body), by route template.",
              &RouteStats::bytes_in);
    per_route("surfaced_http_response_bytes_total", "Response bytes written (head and body), by route template.",
              &RouteStats::bytes_out);
    per_route("surfaced_output_faces_total", "Faces of the meshes returned (X-Output-Faces), by route template.",
              &RouteStats::output_faces);

    header(out, "surfaced_http_shed_total", "counter",
           "Connections answered 503 with Retry-After because every worker was busy and the queue was full.");
    out += "surfaced_http_shed_total " + std::to_string(shed_) + "\n";

    const auto gauge = [&](const char* name, const char* help, std::int64_t value) {
        header(out, name, "gauge", help);
        out += std::string(name) + " " + std::to_string(value) + "\n";
    };
    gauge("surfaced_http_requests_in_flight", "Requests being read, computed or written.", gauges.in_flight);
    gauge("surfaced_http_queue_depth", "Accepted connections waiting for a worker.", gauges.queue_depth);
    gauge("surfaced_http_queue_capacity", "Waiting connections beyond which new ones are shed.", gauges.queue_capacity);
    gauge("surfaced_http_workers", "Worker threads.", gauges.workers);
    gauge("surfaced_http_workers_busy", "Workers holding a connection.", gauges.busy_workers);
    gauge("surfaced_draining", "1 once shutdown has begun (/readyz answers 503).", gauges.draining ? 1 : 0);
    return out;
}

}  // namespace surfaced::server
