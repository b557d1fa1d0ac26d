#include "server/router.h"

#include <charconv>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <system_error>
#include <utility>

#include "api/routes.h"
#include "server/access_control.h"
#include "server/httplib_adapter.h"
#include "server/problems.h"
#include "server/request_id.h"

namespace surfaced::server {
namespace {

//! The route template `path` belongs to (whatever the method), or "".
std::string route_template(std::string_view path) {
    for (const api::Route& route : api::routes())
        if (api::match_path(route.path, path)) return std::string(route.path);
    return {};
}

//! Whether a route answers `method` at `path` (cpp-httplib answers HEAD with a GET route).
bool has_route(std::string_view method, std::string_view path) {
    for (const api::Route& route : api::routes())
        if ((route.method == method || (method == "HEAD" && route.method == "GET")) &&
            api::match_path(route.path, path))
            return true;
    return false;
}

//! The value of a Content-Length header, or nullopt when it is absent or not a number.
std::optional<std::uint64_t> content_length(const HttpRequest& req) {
    if (!req.has_header("Content-Length")) return std::nullopt;
    const std::string text = req.header("Content-Length");
    std::uint64_t value = 0;
    const auto result = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || result.ec != std::errc() || result.ptr != text.data() + text.size()) return std::nullopt;
    return value;
}

}  // namespace

Router::Router(const ServerConfig& config, api::ApiContext context, const std::atomic<bool>& abort)
    : config_(config), context_(std::move(context)), abort_(abort), static_files_(config.web_root) {}

void Router::mount(HttplibAdapter& adapter) const {
    for (const api::Route& route : api::routes()) {
        const api::Operation operation = route.handler;
        const std::string_view path = route.path;
        adapter.add_route(route.method, path,
                          [this, operation, path](const HttpRequest& req, HttpResponse& res, RequestRecord& record) {
                              handle(operation, path, req, res, record);
                          });
    }
}

void Router::handle(api::Operation operation, std::string_view route, const HttpRequest& req, HttpResponse& res,
                    const RequestRecord& record) const {
    if (!authorized(config_, req, route)) {
        write_response(unauthorized_problem(req.has_header("Authorization")), res);
        return;
    }
    api::ApiRequest request = req.to_api();
    api::match_path(route, request.path, &request.path_params);
    api::ApiContext request_context = context_;
    request_context.request_id = record.id;
    request_context.cancel.flag = &abort_;
    if (config_.limits.compute_deadline_ms > 0)
        request_context.cancel.deadline = record.start + std::chrono::milliseconds(config_.limits.compute_deadline_ms);
    write_response(operation(request, request_context), res);
}

// Request id, route label (for the metrics), OPTIONS and static files, before the body is read.
bool Router::before_routing(const HttpRequest& req, HttpResponse& res, RequestRecord& record) {
    record.method = req.method();
    record.path = req.path();
    const std::string incoming = req.header("X-Request-Id");
    record.id = sane_request_id(incoming) ? incoming : new_request_id();
    record.route = route_template(req.path());
    const bool has_body = req.has_header("Transfer-Encoding") ||
                          (req.has_header("Content-Length") && req.header("Content-Length") != "0");
    if (req.method() == "OPTIONS") {
        options(req, res);
        record.force_close = has_body;
        return true;
    }
    if (record.route.empty() && (req.method() == "GET" || req.method() == "HEAD")) {
        if (auto file = static_files_.load(req.path())) {
            res.set_body(std::move(file->body));
            res.set_status(200);
            res.add_header("Content-Type", file->content_type);
            record.route = "static";
            record.force_close = has_body;
            return true;
        }
    }
    // What can be refused from the head alone is refused before the body is read (which could take until the body
    // deadline): no route for this method (404, or 405 with Allow), or a Content-Length over the limit (413). The
    // body stays unread, so the connection is closed after the answer.
    if (!has_route(req.method(), req.path())) {
        write_response(api::route_not_found(req.method(), req.path()), res);
        record.force_close = has_body;
        return true;
    }
    if (const auto length = content_length(req); length && *length > config_.limits.max_body_bytes) {
        write_response(declared_body_too_large_problem(*length, config_.limits.max_body_bytes), res);
        record.force_close = true;
        return true;
    }
    return false;
}

void Router::options(const HttpRequest& req, HttpResponse& res) const {
    std::string allow = api::allowed_methods(req.path());
    if (allow.empty() && static_files_.has(req.path())) allow = "GET, HEAD";
    if (allow.empty()) {
        write_response(api::route_not_found(req.method(), req.path()), res);
        return;
    }
    answer_options(config_, req, allow + ", OPTIONS", res);
}

// Called for every status >= 400, including the problem+json our operations wrote: those have a body and are left
// alone. The rest are the library's own (no route, body too large, unparsable request) and get the same envelope;
// the body may be unread, so the connection is closed after.
bool Router::on_error_status(const HttpRequest& req, HttpResponse& res, RequestRecord& record) {
    if (res.has_body()) return false;
    record.force_close = true;
    if (record.body_timed_out) {
        write_response(body_timeout_problem(config_.body_timeout_seconds, config_.body_min_rate_bytes), res);
        return true;
    }
    write_response(library_error_problem(res.status(), req.method(), req.path(), config_.limits.max_body_bytes), res);
    return true;
}

// Operations never throw; this is the fail-safe for bugs in the server or the HTTP library.
void Router::on_exception(HttpResponse& res) { write_response(internal_error_problem(), res); }

void Router::before_sending(const HttpRequest& req, HttpResponse& res, RequestRecord& record) {
    if (record.id.empty()) record.id = new_request_id();  // the head could not be parsed: no before_routing
    if (record.force_close) {
        // The connection loop closes the connection after this response; say so. cpp-httplib adds Keep-Alive to
        // every response whose request did not ask for close, after the error hook has run.
        res.remove_header("Keep-Alive");
        res.remove_header("Connection");
        res.add_header("Connection", "close");
    }
    if (record.method.empty()) record.method = req.method();
    record.status = res.status();
    res.add_header("X-Request-Id", record.id);
    if (res.status() == 503 && !res.has_header("Retry-After")) res.add_header("Retry-After", "1");
    add_cors_headers(config_, req, res);
    const std::string faces = res.header("X-Output-Faces");
    std::uint64_t value = 0;
    if (!faces.empty() && std::from_chars(faces.data(), faces.data() + faces.size(), value).ec == std::errc())
        record.output_faces = value;
}

}  // namespace surfaced::server
