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
#include "api/options/option_reader.h"
#include "geometry/repair/repair.h"

namespace surfaced::api::operations {
namespace {

using json::Json;

struct RepairParams {
    double weld_tolerance = 0;
    bool orient = true;
    std::int64_t min_component_faces = 0;
    std::int64_t max_hole_edges = 0;
    OutputOptions output;
};

RepairParams params_from(const options::OptionValues& values) {
    RepairParams params;
    values.get("weld_tolerance", params.weld_tolerance);
    values.get("orient", params.orient);
    values.get("min_component_faces", params.min_component_faces);
    values.get("max_hole_edges", params.max_hole_edges);
    values.get_output(params.output);
    return params;
}

const options::OperationOptions& repair_options() { return *options::operation_options("repair"); }

ApiResult<RepairParams> params_from_query(const std::multimap<std::string, std::string>& query) {
    auto values = options::read_query(repair_options(), query);
    if (!values) return std::move(values.error());
    return params_from(values.value());
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
    if (auto error = json::check_members(root, "", options::json_members(repair_options()))) return std::move(*error);
    auto values = options::read_json(repair_options(), root);
    if (!values) return std::move(values.error());
    JsonRequest request;
    request.params = params_from(values.value());
    const auto mesh_it = root.find("mesh");
    if (mesh_it == root.end())
        return json::invalid("mesh", R"(mesh is required: {"positions": [[x,y,z],...], "faces": [[i,j,k,...],...]})");
    auto mesh = decode_mesh(mesh_it->dump(), limits, "mesh");
    if (!mesh) return std::move(mesh.error());
    request.mesh = std::move(mesh.value());
    return request;
}

//! Ranges were checked as the options were read: what is left is output options that do not fit the format.
std::optional<ApiError> check_params(const RepairParams& params, Source source) {
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
