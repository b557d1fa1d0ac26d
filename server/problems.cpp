#include "server/problems.h"

#include <utility>

#include "api/errors.h"
#include "api/routes.h"

namespace surfaced::server {

api::ApiResponse problem(int status, std::string code, std::string title, std::string detail) {
    api::ApiError error = api::make_transport_problem(status, std::move(detail));
    error.code = std::move(code);
    error.title = std::move(title);
    return api::error_response(std::move(error));
}

api::ApiResponse overloaded_problem(int threads, std::size_t queue_capacity) {
    return problem(503, "overloaded", "Server overloaded",
                   "all " + std::to_string(threads) + " workers are busy and " + std::to_string(queue_capacity) +
                       " connections are waiting; retry later");
}

api::ApiResponse unauthorized_problem(bool had_token) {
    api::ApiResponse response =
        problem(401, "unauthorized", "Authentication required",
                had_token ? "the bearer token is not valid" : "this endpoint needs \"Authorization: Bearer <token>\"");
    response.headers.emplace_back("WWW-Authenticate", had_token ? R"(Bearer realm="surfaced", error="invalid_token")"
                                                                : R"(Bearer realm="surfaced")");
    return response;
}

api::ApiResponse origin_not_allowed_problem(const std::string& origin) {
    return problem(403, "origin_not_allowed", "Origin not allowed",
                   "cross-origin requests from " + origin + " are not allowed");
}

api::ApiResponse body_timeout_problem(int body_timeout_seconds, std::size_t body_min_rate_bytes) {
    return problem(408, "body_timeout", "Request body too slow",
                   "the request body did not arrive within " + std::to_string(body_timeout_seconds) +
                       " s plus 1 s per " + std::to_string(body_min_rate_bytes) + " bytes received");
}

api::ApiResponse declared_body_too_large_problem(std::uint64_t length, std::size_t max_body_bytes) {
    return api::error_response(
        api::make_problem(api::Problem::PayloadTooLarge, "request body is " + std::to_string(length) +
                                                             " bytes (Content-Length); the limit is " +
                                                             std::to_string(max_body_bytes) + " bytes"));
}

api::ApiResponse library_error_problem(int status, std::string_view method, std::string_view path,
                                       std::size_t max_body_bytes) {
    switch (status) {
        case 404: return api::route_not_found(method, path);
        case 413:
            return api::error_response(api::make_problem(
                api::Problem::PayloadTooLarge,
                "request body is larger than the limit of " + std::to_string(max_body_bytes) + " bytes"));
        case 400:
            return api::error_response(
                api::make_problem(api::Problem::BadRequest, "the HTTP request could not be parsed"));
        default: return api::error_response(api::make_transport_problem(status, "the HTTP layer rejected the request"));
    }
}

api::ApiResponse internal_error_problem() {
    return api::error_response(api::make_problem(api::Problem::Internal, "internal error"));
}

}  // namespace surfaced::server
