#include "server/http_server.h"

#include <atomic>
#include <cctype>
#include <chrono>
#include <exception>
#include <filesystem>
#include <mutex>
#include <thread>

#include <httplib.h>

#include "api/errors.h"
#include "api/operation.h"
#include "api/routes.h"

namespace surfaced::server {
namespace {

api::ApiRequest to_api_request(const httplib::Request& req) {
    api::ApiRequest out;
    out.method = req.method;
    out.path = req.path;
    out.query.insert(req.params.begin(), req.params.end());
    out.content_type = req.get_header_value("Content-Type");
    out.body = req.body;
    for (const auto& [name, value] : req.headers) {
        std::string lower = name;
        for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        out.headers.emplace(std::move(lower), value);
    }
    return out;
}

void write_response(api::ApiResponse&& response, httplib::Response& res) {
    res.status = response.status;
    for (auto& [name, value] : response.headers) res.set_header(name, value);
    // Response::set_content copies; bodies can be tens of MB.
    res.body = std::move(response.body);
    res.set_header("Content-Type", response.content_type);
}

//! cpp-httplib route patterns are regular expressions; our paths are literal except for `{name}` segments, which
//! match one path segment (api::match_path extracts their values).
std::string literal_pattern(std::string_view path) {
    std::string out;
    for (std::size_t i = 0; i < path.size(); ++i) {
        const char c = path[i];
        if (const std::size_t close = path.find('}', i); c == '{' && close != std::string_view::npos) {
            out += "[^/]+";
            i = close;
            continue;
        }
        if (std::string_view(R"(\^$.|?*+()[]{})").find(c) != std::string_view::npos) out += '\\';
        out += c;
    }
    return out;
}

int default_threads() {
    const unsigned n = std::thread::hardware_concurrency();
    return n < 2 ? 2 : static_cast<int>(n);
}

}  // namespace

struct HttpServer::Impl {
    ServerConfig config;
    api::ApiContext context;
    httplib::Server server;
    std::thread listener;
    std::atomic<bool> listener_done{false};
    std::mutex mutex;  // start/stop
    int port = -1;
    int threads = 0;
    bool static_files = false;

    explicit Impl(ServerConfig c) : config(std::move(c)) {
        context.limits = config.limits;
        threads = config.threads > 0 ? config.threads : default_threads();
        configure();
    }

    void configure() {
        const int pool_size = threads;
        server.new_task_queue = [pool_size] { return new httplib::ThreadPool(static_cast<std::size_t>(pool_size)); };
        // Without a limit cpp-httplib buffers bodies of any size; with it, an oversized Content-Length is refused
        // (413, rendered by the error handler below) before the body is read.
        server.set_payload_max_length(config.limits.max_body_bytes);
        server.set_read_timeout(config.read_timeout_seconds, 0);
        server.set_write_timeout(config.write_timeout_seconds, 0);

        for (const api::Route& route : api::routes()) {
            const api::Operation operation = route.handler;
            const std::string_view route_path = route.path;
            auto handler = [this, operation, route_path](const httplib::Request& req, httplib::Response& res) {
                api::ApiRequest request = to_api_request(req);
                api::match_path(route_path, request.path, &request.path_params);
                write_response(operation(request, context), res);
            };
            const std::string pattern = literal_pattern(route.path);
            if (route.method == "GET") server.Get(pattern, handler);
            else if (route.method == "POST") server.Post(pattern, handler);
            else if (route.method == "PUT") server.Put(pattern, handler);
            else if (route.method == "PATCH") server.Patch(pattern, handler);
            else if (route.method == "DELETE") server.Delete(pattern, handler);
        }

        // cpp-httplib calls this for every response with status >= 400, including the problem+json our operations
        // wrote: those have a body and are left alone. The rest are the library's own (no route, body too large,
        // unparsable request) and get the same envelope.
        server.set_error_handler(httplib::Server::HandlerWithResponse(
            [this](const httplib::Request& req, httplib::Response& res) -> httplib::Server::HandlerResponse {
            if (!res.body.empty()) return httplib::Server::HandlerResponse::Unhandled;
            api::ApiResponse problem;
            switch (res.status) {
                case 404: problem = api::route_not_found(req.method, req.path); break;
                case 413:
                    problem = api::error_response(api::make_problem(
                        api::Problem::PayloadTooLarge, "request body is larger than the limit of " +
                                                           std::to_string(config.limits.max_body_bytes) + " bytes"));
                    break;
                case 400:
                    problem = api::error_response(
                        api::make_problem(api::Problem::BadRequest, "the HTTP request could not be parsed"));
                    break;
                default:
                    problem = api::error_response(
                        api::make_transport_problem(res.status, "the HTTP layer rejected the request"));
            }
            write_response(std::move(problem), res);
            return httplib::Server::HandlerResponse::Handled;
        }));

        // Operations never throw; this is the fail-safe for bugs in this file or the library.
        server.set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr) {
            write_response(api::error_response(api::make_problem(api::Problem::Internal, "internal error")), res);
        });

        if (!config.web_root.empty()) {
            std::error_code ec;
            if (std::filesystem::is_directory(config.web_root, ec)) {
                static_files = server.set_mount_point("/", config.web_root);
                server.set_file_extension_and_mimetype_mapping("mjs", "text/javascript");
                server.set_file_extension_and_mimetype_mapping("wasm", "application/wasm");
                server.set_file_extension_and_mimetype_mapping("glb", "model/gltf-binary");
            }
        }
    }
};

HttpServer::HttpServer(ServerConfig config) : impl_(std::make_unique<Impl>(std::move(config))) {}

HttpServer::~HttpServer() { stop(); }

bool HttpServer::start(std::string* error) {
    std::lock_guard lock(impl_->mutex);
    Impl& s = *impl_;
    const std::string where = s.config.host + ":" + std::to_string(s.config.port);
    if (s.listener.joinable()) {
        if (error) *error = "server already started";
        return false;
    }
    if (s.config.port == 0) {
        s.port = s.server.bind_to_any_port(s.config.host);
    } else if (s.server.bind_to_port(s.config.host, s.config.port)) {
        s.port = s.config.port;
    } else {
        s.port = -1;
    }
    if (s.port < 0) {
        if (error) *error = "cannot listen on " + where + " (address in use, not local, or not permitted)";
        return false;
    }
    s.listener = std::thread([&s] {
        s.server.listen_after_bind();
        s.listener_done = true;
    });
    // httplib's stop() does nothing until the accept loop runs, so a stop() right after start() would be lost and
    // the join would hang: return only once the loop is running.
    while (!s.server.is_running() && !s.listener_done) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    if (!s.server.is_running()) {
        s.listener.join();
        if (error) *error = "the server on " + where + " stopped immediately";
        return false;
    }
    return true;
}

int HttpServer::port() const { return impl_->port; }

bool HttpServer::serves_web_root() const { return impl_->static_files; }

int HttpServer::threads() const { return impl_->threads; }

void HttpServer::stop() {
    std::lock_guard lock(impl_->mutex);
    if (!impl_->listener.joinable()) return;
    impl_->server.stop();
    impl_->listener.join();
}

}  // namespace surfaced::server
