#include "api/routes.h"

#include "api/openapi.h"
#include "api/operations/subdivide.h"

namespace surfaced::api {
namespace {

constexpr Route kRoutes[] = {
    {"GET", "/healthz", &healthz, "Liveness: {\"status\":\"ok\"}"},
    {"GET", "/openapi.json", &openapi, "The OpenAPI 3.1 description of every endpoint"},
    {"POST", "/subdivide", &operations::subdivide,
     "Catmull-Clark or Loop subdivision of a JSON or uploaded mesh (OBJ, OFF, PLY, STL, GLB) -> GLB/OBJ/PLY/JSON"},
};

}  // namespace

std::span<const Route> routes() { return kRoutes; }

ApiResponse healthz(const ApiRequest&, const ApiContext&) noexcept {
    ApiResponse response;
    response.content_type = "application/json";
    response.body = R"({"status":"ok"})";
    return response;
}

ApiResponse openapi(const ApiRequest&, const ApiContext&) noexcept {
    ApiResponse response;
    response.content_type = "application/json";
    response.body = std::string(openapi_document());
    return response;
}

std::string allowed_methods(std::string_view path) {
    std::string out;
    for (const Route& route : kRoutes) {
        if (route.path != path) continue;
        if (!out.empty()) out += ", ";
        out += route.method;
        if (route.method == "GET") out += ", HEAD";  // cpp-httplib answers HEAD with the GET handler
    }
    return out;
}

ApiResponse route_not_found(std::string_view method, std::string_view path) {
    const std::string allow = allowed_methods(path);
    if (allow.empty())
        return error_response(make_problem(Problem::NotFound, "no endpoint at " + std::string(path)));
    ApiResponse response = error_response(make_problem(
        Problem::MethodNotAllowed, std::string(path) + " does not accept " + std::string(method) + "; allowed: " + allow));
    response.headers.emplace_back("Allow", allow);
    return response;
}

ApiResponse dispatch(const ApiRequest& request, const ApiContext& context) {
    for (const Route& route : kRoutes)
        if (route.method == request.method && route.path == request.path) return route.handler(request, context);
    return route_not_found(request.method, request.path);
}

}  // namespace surfaced::api
