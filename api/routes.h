// The endpoint table: every operation the service offers, with no HTTP-library types. The server mounts each row;
// the CLI and tests can call dispatch() without a socket. Adding an endpoint = one row in routes.cpp.
#pragma once

#include <map>
#include <span>
#include <string>
#include <string_view>

#include "api/operation.h"

namespace surfaced::api {

struct Route {
    std::string_view method;  //!< "GET", "POST", ...
    std::string_view path;    //!< exact path ("/subdivide"), or with `{name}` segments ("/patches/{name}")
    Operation handler;
    std::string_view description;  //!< one line, for --help and a future index page
};

//! Whether `path` matches the route path `pattern`: literal segments equal, a `{name}` segment matches one
//! non-empty segment (no '/'), whose value goes to (*params)[name] when params is given.
bool match_path(std::string_view pattern, std::string_view path, std::map<std::string, std::string>* params = nullptr);

//! All routes, in a fixed order.
std::span<const Route> routes();

//! The route for (method, path), or 404 not_found / 405 method_not_allowed (with an Allow header) problems.
ApiResponse dispatch(const ApiRequest& request, const ApiContext& context);

//! 404 for an unknown path, or 405 with Allow when the path exists under another method.
ApiResponse route_not_found(std::string_view method, std::string_view path);

//! "GET, HEAD" style list of the methods `path` answers to; empty when the path is unknown.
std::string allowed_methods(std::string_view path);

//! GET /healthz (an alias of /livez): {"status":"ok"}.
ApiResponse healthz(const ApiRequest& request, const ApiContext& context) noexcept;

//! GET /livez: 200 {"status":"ok"} while the process can answer at all.
ApiResponse livez(const ApiRequest& request, const ApiContext& context) noexcept;

//! GET /readyz: 200 {"status":"ready"}, or 503 `draining` once shutdown has begun.
ApiResponse readyz(const ApiRequest& request, const ApiContext& context) noexcept;

//! GET /metrics: the server's Prometheus text exposition (empty without a server).
ApiResponse metrics(const ApiRequest& request, const ApiContext& context) noexcept;

}  // namespace surfaced::api
