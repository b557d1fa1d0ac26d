// What the server's request handling sees of one HTTP exchange, with no HTTP-library types: the request and the
// response being built (views that the HTTP adapter implements over its library's), the record kept of the request
// for its handlers, the metrics and the access log, and the hooks the adapter calls while answering.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>

#include "api/operation.h"

namespace surfaced::server {

//! What the server learns about one request while answering it. The connection loop starts a fresh record for each
//! request (start time), the hooks fill it in, the connection loop adds the byte counts once it is answered.
struct RequestRecord {
    std::chrono::steady_clock::time_point start;
    std::string id;
    std::string route;  //!< route template, "static", or "" (unmatched)
    std::string method;
    std::string path;
    int status = 0;  //!< 0: no response was produced (the client went away)
    std::uint64_t output_faces = 0;
    std::uint64_t bytes_in = 0;
    std::uint64_t bytes_out = 0;
    int fd = -1;                  //!< the connection's socket (the access log reads the peer's address from it)
    bool force_close = false;     //!< the request body may be unread: do not parse another request from this stream
    bool body_timed_out = false;  //!< the body did not arrive in time: answer 408
};

//! The request being answered. Header names compare case-insensitively.
class HttpRequest {
public:
    virtual ~HttpRequest() = default;
    virtual const std::string& method() const = 0;
    virtual const std::string& path() const = 0;  //!< decoded, without the query
    virtual bool has_header(const std::string& name) const = 0;
    //! The first value of header `name`; "" when absent.
    virtual std::string header(const std::string& name) const = 0;
    //! The request as api/ operations take it (header names in lower case). Its body views this request's body.
    virtual api::ApiRequest to_api() const = 0;
};

//! The response being built. Header names compare case-insensitively; adding a header keeps the values it already
//! has under that name.
class HttpResponse {
public:
    virtual ~HttpResponse() = default;
    virtual int status() const = 0;
    virtual void set_status(int status) = 0;
    virtual bool has_body() const = 0;
    virtual void set_body(std::string body) = 0;
    virtual bool has_header(const std::string& name) const = 0;
    //! The first value of header `name`; "" when absent.
    virtual std::string header(const std::string& name) const = 0;
    virtual void add_header(const std::string& name, const std::string& value) = 0;
    //! Removes every value of header `name`.
    virtual void remove_header(const std::string& name) = 0;
};

//! The handler of one route, called once the request body has been read.
using RouteHandler = std::function<void(const HttpRequest&, HttpResponse&, RequestRecord&)>;

//! What the HTTP adapter calls around the route handlers, on the worker thread that serves the connection.
class HttpHooks {
public:
    virtual ~HttpHooks() = default;
    //! Once the request head is parsed, before the body is read. True: `res` is the answer, no route handler runs.
    virtual bool before_routing(const HttpRequest& req, HttpResponse& res, RequestRecord& record) = 0;
    //! For every response with status >= 400, the route handlers' included. True: `res` was rewritten.
    virtual bool on_error_status(const HttpRequest& req, HttpResponse& res, RequestRecord& record) = 0;
    //! A route handler threw: `res` is to be the answer.
    virtual void on_exception(HttpResponse& res) = 0;
    //! For every response just before its head is written, errors included.
    virtual void before_sending(const HttpRequest& req, HttpResponse& res, RequestRecord& record) = 0;
};

//! Writes an api/ response: status, its headers, body and Content-Type.
inline void write_response(api::ApiResponse&& response, HttpResponse& res) {
    res.set_status(response.status);
    for (auto& [name, value] : response.headers) res.add_header(name, value);
    res.set_body(std::move(response.body));  // moved, not copied: bodies can be tens of MB
    res.add_header("Content-Type", response.content_type);
}

}  // namespace surfaced::server
