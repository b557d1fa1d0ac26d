// Who may call what: the optional bearer token (compared in constant time; the probes and /openapi.json are open),
// and the CORS allow-list of browser origins with its preflight answer and response headers.
#pragma once

#include <string>
#include <string_view>

#include "server/http_exchange.h"
#include "server/http_server.h"

namespace surfaced::server {

//! Whether a request for route template `route` may run: no token configured, an open route, or
//! "Authorization: Bearer <token>" with the configured token.
bool authorized(const ServerConfig& config, const HttpRequest& req, std::string_view route);

//! Whether `origin` is on the CORS allow-list ("*" allows any).
bool origin_allowed(const ServerConfig& config, std::string_view origin);

//! The answer to OPTIONS for a path that answers the methods `allow` (", OPTIONS" included): a CORS preflight from
//! an allowed Origin (204 with the Access-Control-Allow-* headers), 403 from another Origin, 204 + Allow without one.
void answer_options(const ServerConfig& config, const HttpRequest& req, const std::string& allow, HttpResponse& res);

//! With a CORS allow-list: Vary: Origin on every response, and for an allowed Origin the headers that let the
//! browser read the response.
void add_cors_headers(const ServerConfig& config, const HttpRequest& req, HttpResponse& res);

}  // namespace surfaced::server
