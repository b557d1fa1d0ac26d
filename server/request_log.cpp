#include "server/request_log.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <iterator>
#include <string_view>

#include "api/errors.h"
#include "server/metrics.h"
#include "server/socket_io.h"

namespace surfaced::server {
namespace {

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

}  // namespace

RequestLog::RequestLog(ServerConfig::AccessLog where, Metrics& metrics) : where_(where), metrics_(metrics) {}

void RequestLog::finished(const RequestRecord& r) {
    if (r.status == 0) return;  // nothing was answered (the client closed or timed out before a request)
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - r.start).count();
    const std::string route = r.route.empty() ? "unmatched" : r.route;
    // the method of an unparsable request line is whatever the client sent: keep the label set bounded
    static constexpr std::string_view kMethods[] = {"GET", "HEAD", "POST", "PUT", "DELETE", "OPTIONS", "PATCH"};
    const bool known = std::find(std::begin(kMethods), std::end(kMethods), r.method) != std::end(kMethods);
    metrics_.observe(route, known ? r.method : "other", r.status, seconds, r.bytes_in, r.bytes_out, r.output_faces);
    if (where_ == ServerConfig::AccessLog::Off) return;
    std::string line = "{\"ts\":\"" + utc_timestamp() + "\",\"id\":" + api::json_quote(r.id) +
                       ",\"remote\":" + api::json_quote(peer_address(r.fd)) +
                       ",\"method\":" + api::json_quote(r.method) + ",\"path\":" + api::json_quote(r.path) +
                       ",\"route\":" + api::json_quote(route) + ",\"status\":" + std::to_string(r.status);
    char ms[32];
    std::snprintf(ms, sizeof ms, "%.3f", seconds * 1000.0);
    line += ",\"ms\":" + std::string(ms) + ",\"bytes_in\":" + std::to_string(r.bytes_in) +
            ",\"bytes_out\":" + std::to_string(r.bytes_out);
    if (r.output_faces) line += ",\"output_faces\":" + std::to_string(r.output_faces);
    line += "}\n";
    write_line(line);
}

void RequestLog::shed() { metrics_.shed(); }

void RequestLog::shed_answered(const std::string& id) {
    if (where_ != ServerConfig::AccessLog::Off)
        write_line("{\"ts\":\"" + utc_timestamp() + "\",\"id\":\"" + id + "\",\"status\":503,\"shed\":true}\n");
}

void RequestLog::write_line(const std::string& line) {
    std::FILE* out = where_ == ServerConfig::AccessLog::Stdout ? stdout : stderr;
    std::lock_guard lock(mutex_);
    std::fwrite(line.data(), 1, line.size(), out);
    std::fflush(out);
}

}  // namespace surfaced::server
