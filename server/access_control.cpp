#include "server/access_control.h"

#include <algorithm>
#include <cctype>

#include "server/problems.h"

namespace surfaced::server {
namespace {

constexpr std::string_view kCorsAllowHeaders = "Authorization, Content-Type, If-None-Match, X-Request-Id";
constexpr std::string_view kCorsExposeHeaders =
    "X-Request-Id, X-Output-Faces, X-Output-Vertices, X-Levels, X-Error-Bound, X-Hausdorff, X-RMS, X-Triangulated, "
    "X-Repairs, X-Elapsed-Ms, ETag, Retry-After";

bool is_open_route(std::string_view route) {
    return route == "/livez" || route == "/readyz" || route == "/healthz" || route == "/openapi.json";
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

}  // namespace

bool authorized(const ServerConfig& config, const HttpRequest& req, std::string_view route) {
    if (config.auth_token.empty() || is_open_route(route)) return true;
    const std::string value = req.header("Authorization");
    constexpr std::string_view kScheme = "bearer ";
    if (value.size() < kScheme.size() || !iequals(std::string_view(value).substr(0, kScheme.size()), kScheme))
        return false;
    std::string_view token = std::string_view(value).substr(kScheme.size());
    while (!token.empty() && token.front() == ' ') token.remove_prefix(1);
    return constant_time_equal(token, config.auth_token);
}

bool origin_allowed(const ServerConfig& config, std::string_view origin) {
    if (origin.empty()) return false;
    return std::any_of(config.cors_origins.begin(), config.cors_origins.end(),
                       [&](const std::string& allowed) { return allowed == "*" || allowed == origin; });
}

void answer_options(const ServerConfig& config, const HttpRequest& req, const std::string& allow, HttpResponse& res) {
    const std::string origin = req.header("Origin");
    if (!origin.empty() && !config.cors_origins.empty()) {
        if (!origin_allowed(config, origin)) {
            write_response(origin_not_allowed_problem(origin), res);
            return;
        }
        res.add_header("Access-Control-Allow-Methods", allow);
        res.add_header("Access-Control-Allow-Headers", std::string(kCorsAllowHeaders));
        res.add_header("Access-Control-Max-Age", "600");
    }
    res.set_status(204);
    res.add_header("Allow", allow);
}

void add_cors_headers(const ServerConfig& config, const HttpRequest& req, HttpResponse& res) {
    if (config.cors_origins.empty()) return;
    res.add_header("Vary", "Origin");
    const std::string origin = req.header("Origin");
    if (origin_allowed(config, origin)) {
        res.add_header("Access-Control-Allow-Origin", origin);
        res.add_header("Access-Control-Expose-Headers", std::string(kCorsExposeHeaders));
    }
}

}  // namespace surfaced::server
