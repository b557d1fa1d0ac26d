#include "api/routes.h"

#include "api/openapi.h"
#include "api/operations/subdivide.h"
#include "api/operations/simplify.h"
#include "api/operations/remesh.h"
#include "api/operations/repair.h"
#include "api/operations/curves.h"
#include "api/operations/surfaces.h"
#include "api/operations/tessellate.h"
#include "api/operations/implicit_query.h"
#include "api/operations/mesh_query.h"
#include "api/operations/pointcloud.h"
#include "api/operations/implicit_mesh.h"
#include "api/operations/implicit_grid.h"
#include "api/operations/limit_evaluate.h"
#include "api/operations/reconstruct.h"

namespace surfaced::api {
namespace {

constexpr Route kRoutes[] = {
    {"GET", "/healthz", &healthz, "Liveness: {\"status\":\"ok\"} (alias of /livez)"},
    {"GET", "/livez", &livez, "Liveness probe: 200 while the process answers"},
    {"GET", "/readyz", &readyz, "Readiness probe: 200, or 503 once shutdown (draining) has begun"},
    {"GET", "/metrics", &metrics, "Prometheus text metrics: requests, latency, in-flight, queue, bytes, output faces"},
    {"GET", "/openapi.json", &openapi, "The OpenAPI 3.1 description of every endpoint"},
    {"POST", "/subdivide", &operations::subdivide,
     "Catmull-Clark or Loop subdivision of a JSON or uploaded mesh (OBJ, OFF, PLY, STL, GLB) -> "
     "GLB/glTF/OBJ/PLY/JSON/STL/OFF"},
    {"POST", "/simplify", &operations::simplify,
     "QEM edge-collapse simplification to target_faces / ratio / max_error (repairs the input first), optional "
     "Hausdorff/RMS report -> GLB/glTF/OBJ/PLY/JSON/STL/OFF"},
    {"POST", "/remesh", &operations::remesh,
     "Isotropic remeshing to edge_length (split, collapse, flip, relax, project), features and boundary kept, quality "
     "report (repairs the input first) -> GLB/glTF/OBJ/PLY/JSON/STL/OFF"},
    {"POST", "/repair", &operations::repair,
     "Mesh repair: weld, drop degenerate and duplicate faces, orient, cut non-manifold edges and vertices, fill small "
     "holes, with a report -> GLB/glTF/OBJ/PLY/JSON/STL/OFF"},
    {"POST", "/tessellate", &operations::tessellate,
     "Bezier patches (JSON or geomview BEZ/BBP) tessellated by tolerance or segments, crack-free -> "
     "GLB/glTF/OBJ/PLY/JSON/STL/OFF"},
    {"GET", "/patches/{name}", &operations::patch_sample,
     "A built-in patch sample (teapot) tessellated, ?tolerance=T or ?segments=N (?format=patches: its control points); "
     "ETag / If-None-Match -> 304"},
    {"POST", "/curves", &operations::curves,
     "Bezier curve queries (evaluate, derivatives, split, elevate, length, closest point, tessellate) -> JSON"},
    {"POST", "/surfaces", &operations::surfaces,
     "B-spline/NURBS surface queries (evaluate, derivatives, closest point, knot insertion, degree elevation, Bezier "
     "patches, bounding box) -> JSON"},
    {"POST", "/implicit/query", &operations::implicit_query,
     "Implicit scene queries: points inside/on/outside, value and gradient; rays by sphere tracing -> JSON"},
    {"POST", "/mesh/query", &operations::mesh_query,
     "Mesh queries (BVH): inside (generalized winding number), signed distance, closest point and face; first ray "
     "hits -> JSON"},
    {"POST", "/pointcloud", &operations::pointcloud,
     "Point clouds: convert PLY/OBJ/XYZ/JSON points, sample a mesh or implicit scene, estimate oriented normals "
     "(kNN PCA) -> GLB POINTS (Draco)/glTF/PLY/JSON"},
    {"POST", "/reconstruct", &operations::reconstruct,
     "Screened Poisson surface reconstruction of a point cloud (PLY/OBJ/XYZ/JSON points; normals estimated when "
     "missing) -> closed mesh as GLB/glTF/OBJ/PLY/JSON/STL/OFF"},
    {"POST", "/implicit/mesh", &operations::implicit_mesh,
     "Implicit scene meshed in bounds (dual marching cubes, QEF vertices; closed, manifold, sharp) -> "
     "GLB/glTF/OBJ/PLY/JSON/STL/OFF"},
    {"POST", "/implicit/grid", &operations::implicit_grid,
     "Mesh (exact distances, winding-number signs) or implicit scene as a narrow-band signed distance grid -> a "
     "level_set scene node (JSON)"},
    {"POST", "/limit/evaluate", &operations::limit_evaluate,
     "Exact Catmull-Clark limit surface at (face, u, v) points: position, derivatives, normal, limit UVs -> JSON"},
};

}  // namespace

std::span<const Route> routes() { return kRoutes; }

bool match_path(std::string_view pattern, std::string_view path, std::map<std::string, std::string>* params) {
    if (pattern.find('{') == std::string_view::npos) return pattern == path;
    std::map<std::string, std::string> found;
    while (!pattern.empty() || !path.empty()) {
        if (pattern.empty() || path.empty() || pattern[0] != '/' || path[0] != '/') return false;
        pattern.remove_prefix(1);
        path.remove_prefix(1);
        const std::string_view want = pattern.substr(0, pattern.find('/'));
        const std::string_view got = path.substr(0, path.find('/'));
        pattern.remove_prefix(want.size());
        path.remove_prefix(got.size());
        if (want.size() >= 2 && want.front() == '{' && want.back() == '}') {
            if (got.empty()) return false;
            found[std::string(want.substr(1, want.size() - 2))] = std::string(got);
        } else if (want != got) {
            return false;
        }
    }
    if (params) *params = std::move(found);
    return true;
}

ApiResponse healthz(const ApiRequest&, const ApiContext&) noexcept {
    ApiResponse response;
    response.content_type = "application/json";
    response.body = R"({"status":"ok"})";
    return response;
}

ApiResponse livez(const ApiRequest& request, const ApiContext& context) noexcept { return healthz(request, context); }

ApiResponse readyz(const ApiRequest&, const ApiContext& context) noexcept {
    if (context.service && context.service->draining()) {
        ApiError error = make_transport_problem(503, "the server is shutting down and accepts no new work");
        error.code = "draining";
        error.title = "Server draining";
        ApiResponse response = error_response(std::move(error));
        response.headers.emplace_back("Retry-After", "1");
        return response;
    }
    ApiResponse response;
    response.content_type = "application/json";
    response.body = R"({"status":"ready"})";
    return response;
}

ApiResponse metrics(const ApiRequest&, const ApiContext& context) noexcept {
    ApiResponse response;
    response.content_type = "text/plain; version=0.0.4; charset=utf-8";
    try {
        if (context.service) response.body = context.service->metrics_text();
    } catch (...) {
        return error_response(make_problem(Problem::Internal, "metrics could not be rendered"));
    }
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
        if (!match_path(route.path, path)) continue;
        if (!out.empty()) out += ", ";
        out += route.method;
        if (route.method == "GET") out += ", HEAD";  // cpp-httplib answers HEAD with the GET handler
    }
    return out;
}

ApiResponse route_not_found(std::string_view method, std::string_view path) {
    const std::string allow = allowed_methods(path);
    if (allow.empty()) return error_response(make_problem(Problem::NotFound, "no endpoint at " + std::string(path)));
    ApiResponse response =
        error_response(make_problem(Problem::MethodNotAllowed, std::string(path) + " does not accept " +
                                                                   std::string(method) + "; allowed: " + allow));
    response.headers.emplace_back("Allow", allow);
    return response;
}

ApiResponse dispatch(const ApiRequest& request, const ApiContext& context) {
    for (const Route& route : kRoutes) {
        if (route.method != request.method) continue;
        if (route.path == request.path) return route.handler(request, context);
        std::map<std::string, std::string> params;
        if (match_path(route.path, request.path, &params)) {
            ApiRequest with_params = request;
            with_params.path_params = std::move(params);
            return route.handler(with_params, context);
        }
    }
    return route_not_found(request.method, request.path);
}

}  // namespace surfaced::api
