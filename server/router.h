// Router: what the server does with each request, around the endpoint table of api/routes.cpp. It mounts every route
// on the HTTP adapter with a handler that checks the bearer token, builds the ApiRequest and ApiContext (limits,
// request id, compute deadline, shutdown flag) and calls the operation; and it implements the hooks around the
// handlers: request ids and route labels, OPTIONS, static files, problem+json for the errors the HTTP library
// produces itself, and the headers every response gets (X-Request-Id, Retry-After, CORS).
#pragma once

#include <atomic>
#include <string_view>

#include "api/operation.h"
#include "server/http_exchange.h"
#include "server/http_server.h"
#include "server/static_files.h"

namespace surfaced::server {

class HttplibAdapter;

class Router final : public HttpHooks {
public:
    //! `context`: limits and the service state every operation gets; `abort`: set when in-flight work is to be
    //! cancelled. `config` and `abort` must outlive the router.
    Router(const ServerConfig& config, api::ApiContext context, const std::atomic<bool>& abort);

    //! Mounts every route of api::routes() on `adapter`.
    void mount(HttplibAdapter& adapter) const;
    //! Whether static files are served (the web root exists).
    bool serves_static_files() const { return static_files_.enabled(); }

    bool before_routing(const HttpRequest& req, HttpResponse& res, RequestRecord& record) override;
    bool on_error_status(const HttpRequest& req, HttpResponse& res, RequestRecord& record) override;
    void on_exception(HttpResponse& res) override;
    void before_sending(const HttpRequest& req, HttpResponse& res, RequestRecord& record) override;

private:
    void handle(api::Operation operation, std::string_view route, const HttpRequest& req, HttpResponse& res,
                const RequestRecord& record) const;
    void options(const HttpRequest& req, HttpResponse& res) const;

    const ServerConfig& config_;
    const api::ApiContext context_;
    const std::atomic<bool>& abort_;
    const StaticFiles static_files_;
};

}  // namespace surfaced::server
