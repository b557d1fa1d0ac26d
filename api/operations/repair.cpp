// POST /repair (see repair.h): decode, check, repair_mesh(), encode with the report.
#include "api/operations/repair.h"

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>

#include "api/dto.h"
#include "api/json_codec.h"
#include "api/json_util.h"
#include "api/operations/mesh_repair.h"
#include "api/operations/request_forms.h"
#include "geometry/repair/repair.h"

namespace surfaced::api::operations {
namespace {

using json::Json;

//! Holes with more boundary edges than this are never filled (the fill is quadratic in the loop's length).
constexpr std::int64_t kMaxHoleEdges = 10'000;

struct RepairParams {
    double weld_tolerance = 0;
    bool orient = true;
    std::int64_t min_component_faces = 0;
    std::int64_t max_hole_edges = 0;
    OutputOptions output;
};

ApiResult<RepairParams> params_from_query(const std::multimap<std::string, std::string>& query) {
    if (auto error = check_query_names(query, {"weld_tolerance", "orient", "min_component_faces", "max_hole_edges",
                                               "format", "compression", "quantize_position", "normals"}))
        return std::move(*error);
    RepairParams params;
    for (const auto& [name, text] : query) {
        std::optional<ApiError> error;
        if (name == "weld_tolerance")
            error = read_parameter(name, text, params.weld_tolerance);
        else if (name == "orient")
            error = read_parameter(name, text, params.orient);
        else if (name == "min_component_faces")
            error = read_parameter(name, text, params.min_component_faces);
        else if (name == "max_hole_edges")
            error = read_parameter(name, text, params.max_hole_edges);
        else if (auto output = parse_output_parameter(name, text, params.output); !output)
            error = std::move(output.error());
        if (error) return std::move(*error);
    }
    return params;
}

struct JsonRequest {
    RepairParams params;
    PolygonMesh mesh;
};

ApiResult<JsonRequest> decode_request(std::string_view body, const Limits& limits) {
    Json root;
    if (auto error = json::parse(body, root)) return std::move(*error);
    if (!root.is_object())
        return make_problem(Problem::InvalidField, R"(request body must be a JSON object {"mesh": {...}, ...})");
    if (auto error = json::check_members(
            root, "", {"mesh", "weld_tolerance", "orient", "min_component_faces", "max_hole_edges", "output"}))
        return std::move(*error);
    JsonRequest request;
    RepairParams& params = request.params;
    for (auto error : {json::read_member(root, "weld_tolerance", params.weld_tolerance),
                       json::read_member(root, "orient", params.orient),
                       json::read_member(root, "min_component_faces", params.min_component_faces),
                       json::read_member(root, "max_hole_edges", params.max_hole_edges)})
        if (error) return std::move(*error);
    if (auto error = json::read_output(root, params.output)) return std::move(*error);
    const auto mesh_it = root.find("mesh");
    if (mesh_it == root.end())
        return json::invalid("mesh", R"(mesh is required: {"positions": [[x,y,z],...], "faces": [[i,j,k,...],...]})");
    auto mesh = decode_mesh(mesh_it->dump(), limits, "mesh");
    if (!mesh) return std::move(mesh.error());
    request.mesh = std::move(mesh.value());
    return request;
}

std::optional<ApiError> check_params(const RepairParams& params, Source source) {
    if (!(std::isfinite(params.weld_tolerance) && params.weld_tolerance >= 0))
        return make_problem(
            Problem::InvalidField,
            "weld_tolerance must be a finite distance >= 0, got " + format_double(params.weld_tolerance),
            "weld_tolerance");
    if (params.min_component_faces < 0)
        return make_problem(Problem::InvalidField,
                            "min_component_faces must be >= 0, got " + std::to_string(params.min_component_faces),
                            "min_component_faces");
    if (params.max_hole_edges < 0 || params.max_hole_edges > kMaxHoleEdges)
        return make_problem(Problem::InvalidField,
                            "max_hole_edges must be in 0.." + std::to_string(kMaxHoleEdges) + ", got " +
                                std::to_string(params.max_hole_edges),
                            "max_hole_edges");
    return check_output_options(params.output, source);
}

ApiResponse run(const ApiRequest& request, const ApiContext& context) {
    const Limits& limits = context.limits;
    const auto t_start = Clock::now();

    // 1-3. size and media type, options and mesh, budgets; faces that repeat a vertex are read (repair drops them)
    auto decoded = decode_mesh_request<RepairParams>(request, limits, decode_request, params_from_query, check_params,
                                                     MeshRules::Subdivision);
    if (!decoded) return error_response(std::move(decoded.error()));
    auto& [source, params, input, t_decoded, read_report] = decoded.value();

    // 4. repair
    RepairOptions options;
    options.weld_tolerance = params.weld_tolerance;
    options.orient = params.orient;
    options.min_component_faces = static_cast<std::size_t>(params.min_component_faces);
    options.max_hole_edges = static_cast<std::size_t>(params.max_hole_edges);
    options.cancel = context.cancel;
    auto repaired = repair_mesh(input, options);
    if (!repaired) return error_response(geometry_error(repaired.error(), source));
    if (auto error = check_deadline_before_encoding(context.cancel)) return error_response(std::move(*error));
    RepairResult& result = repaired.value();
    const auto t_repaired = Clock::now();

    // 5. encode
    const std::string stats = "{\"input_vertices\":" + std::to_string(input.vertex_count()) +
                              ",\"input_faces\":" + std::to_string(input.face_count()) +
                              ",\"output_vertices\":" + std::to_string(result.mesh.vertex_count()) +
                              ",\"output_faces\":" + std::to_string(result.mesh.face_count()) +
                              ",\"repairs\":" + encode_repairs(result.report) +
                              ",\"elapsed_ms\":" + format_double(ms_between(t_start, t_repaired)) + "}";
    Headers headers = mesh_count_headers(input.vertex_count(), input.face_count(), result.mesh.vertex_count(),
                                         result.mesh.face_count());
    headers.emplace_back("X-Repairs", repairs_header(result.report));
    append_read_headers(headers, read_report);
    return mesh_response(
        result.mesh, params.output, source,
        [&](const PolygonMesh& m) -> ApiResult<std::string> { return encode_mesh_with_stats(m, stats); },
        std::move(headers), Timing{t_start, {{"decode", t_decoded}, {"repair", t_repaired}}});
}

}  // namespace

ApiResponse repair(const ApiRequest& request, const ApiContext& context) noexcept {
    return guarded([&] { return run(request, context); });
}

}  // namespace surfaced::api::operations
