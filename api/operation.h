// The shape every endpoint has: a plain request struct in, a plain response struct out (as llama.cpp's handler_t).
// No HTTP-library types, so operations run without a socket: from the server, the CLI and tests alike.
#pragma once

#include <map>
#include <set>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "api/errors.h"
#include "api/limits.h"
#include "geometry/core/cancel.h"

namespace surfaced::api {

struct ApiRequest {
    std::string method = "GET";
    std::string path;
    //! Decoded query parameters; a name may repeat (operations reject repeats of single-valued options).
    std::multimap<std::string, std::string> query;
    //! The Content-Type header as sent, parameters included ("application/json; charset=utf-8"); empty if absent.
    std::string content_type;
    //! Request body. Not owned: the caller keeps the bytes alive for the duration of the call.
    std::string_view body;
    //! Values of the route's `{name}` path segments ("/patches/{name}" matched by "/patches/teapot": name=teapot).
    std::map<std::string, std::string> path_params;
    //! Request headers the operations consult (If-None-Match, ...), names in lower case.
    std::multimap<std::string, std::string> headers;
    //! The names in `query` that came from multipart/form-data fields (an upload's form), for errors that name them.
    std::set<std::string> form_fields;

    //! First value of header `name` (lower case), or "" when absent.
    std::string header(std::string_view name) const {
        const auto it = headers.find(std::string(name));
        return it == headers.end() ? std::string() : it->second;
    }
};

struct ApiResponse {
    int status = 200;
    std::string content_type;
    std::string body;
    std::vector<std::pair<std::string, std::string>> headers;  //!< extra headers (X-Output-Faces, Allow, ...)
    //! Set exactly when status >= 400: the error `body` renders, so in-process callers (the CLI) need not parse it.
    std::optional<ApiError> error;
};

//! What the server running an operation can tell it about itself (GET /readyz, GET /metrics). Implemented by the
//! HTTP layer; operations called without a server (CLI, tests) see none.
class ServiceState {
public:
    virtual ~ServiceState() = default;
    //! True once shutdown has begun: /readyz answers 503 so that load balancers stop sending traffic.
    virtual bool draining() const = 0;
    //! The Prometheus text exposition (format 0.0.4) of the server's counters.
    virtual std::string metrics_text() const = 0;
};

//! What every operation may consult besides the request: budgets, the request's compute deadline, and the server.
struct ApiContext {
    Limits limits;
    //! The compute deadline / shutdown abort for this request (Limits::compute_deadline_ms from its start).
    //! Operations pass it to the algorithms' options; a fired Cancel becomes 503 `cancelled`.
    Cancel cancel;
    //! The request id the server logs and echoes in X-Request-Id; empty outside a server.
    std::string request_id;
    //! Null when there is no server (CLI, in-process tests).
    const ServiceState* service = nullptr;
};

//! An endpoint implementation. Contract: never throws; every failure is an error response.
using Operation = ApiResponse (*)(const ApiRequest&, const ApiContext&);

//! The problem+json response for `error`.
inline ApiResponse error_response(ApiError error) {
    ApiResponse response;
    response.status = error.status;
    response.content_type = std::string(kProblemJsonMediaType);
    response.body = to_problem_json(error);
    response.error = std::move(error);
    return response;
}

}  // namespace surfaced::api
