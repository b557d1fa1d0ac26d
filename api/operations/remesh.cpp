#include "api/operations/remesh.h"

#include <cmath>
#include <optional>
#include <string>

#include "api/dto.h"
#include "api/json_codec.h"
#include "api/json_util.h"
#include "api/operations/mesh_repair.h"
#include "api/operations/request_forms.h"
#include "api/options/option_reader.h"
#include "geometry/remesh/remesh.h"

namespace surfaced::api::operations {
namespace {

using json::Json;

struct RemeshParams {
    std::optional<double> edge_length;
    std::int64_t iterations = 10;
    double feature_angle = 60;
    bool lock_border = true;
    RemeshSmoothing smoothing = RemeshSmoothing::Tangential;
    RepairMode repair = RepairMode::Auto;
    OutputOptions output;
};

RemeshParams params_from(const options::OptionValues& values) {
    RemeshParams params;
    values.get("edge_length", params.edge_length);
    values.get("iterations", params.iterations);
    values.get("feature_angle", params.feature_angle);
    values.get("lock_border", params.lock_border);
    values.get("smoothing", kRemeshSmoothingNames, params.smoothing);
    values.get("repair", kRepairModeNames, params.repair);
    values.get_output(params.output);
    return params;
}

const options::OperationOptions& remesh_options() { return *options::operation_options("remesh"); }

ApiResult<RemeshParams> params_from_query(const std::multimap<std::string, std::string>& query) {
    auto values = options::read_query(remesh_options(), query);
    if (!values) return std::move(values.error());
    return params_from(values.value());
}

struct JsonRequest {
    RemeshParams params;
    PolygonMesh mesh;
};

ApiResult<JsonRequest> decode_request(std::string_view body, const Limits& limits) {
    Json root;
    if (auto error = json::parse(body, root)) return std::move(*error);
    if (!root.is_object())
        return make_problem(Problem::InvalidField,
                            R"(request body must be a JSON object {"mesh": {...}, "edge_length": L, ...})");
    if (auto error = json::check_members(root, "", options::json_members(remesh_options()))) return std::move(*error);
    auto values = options::read_json(remesh_options(), root);
    if (!values) return std::move(values.error());
    JsonRequest request;
    request.params = params_from(values.value());
    const auto mesh_it = root.find("mesh");
    if (mesh_it == root.end())
        return json::invalid("mesh", R"(mesh is required: {"positions": [[x,y,z],...], "faces": [[i,j,k,...],...]})");
    // The mesh decoder of json_codec (field paths "mesh.faces[3][1]", budgets) takes text; the member is valid JSON.
    auto mesh = decode_mesh(mesh_it->dump(), limits, "mesh");
    if (!mesh) return std::move(mesh.error());
    request.mesh = std::move(mesh.value());
    return request;
}

//! Ranges were checked as the options were read: what is left is output options that do not fit the format.
std::optional<ApiError> check_params(const RemeshParams& params, Source source) {
    return check_output_options(params.output, source);
}

Json quality_json(const MeshQuality& q) {
    Json valence = Json::object();
    for (std::size_t k = 0; k < q.valence_histogram.size(); ++k)
        if (q.valence_histogram[k] > 0) valence[std::to_string(k)] = q.valence_histogram[k];
    return Json{{"vertices", q.vertices},
                {"faces", q.faces},
                {"min_angle", q.min_angle_degrees},
                {"share_below_30", q.share_below_30},
                {"mean_radius_ratio", q.mean_radius_ratio},
                {"max_radius_ratio", q.max_radius_ratio},
                {"mean_edge_length", q.mean_edge_length},
                {"edge_length_stddev", q.edge_length_stddev},
                {"share_regular", q.share_regular},
                {"valence", std::move(valence)}};
}

//! {"mesh": ..., "stats": {...}}: the mesh through json_codec's writer (the one every endpoint uses), the stats here.
std::string encode_json_response(const PolygonMesh& mesh, const Json& stats) {
    std::string out = encode_simplify_response(mesh, SimplifyStats{});
    // the writer ends with ,"stats":{...}} and the mesh part holds only numbers, so the last ,"stats": is its own
    const auto at = out.rfind(",\"stats\":");
    if (at == std::string::npos) return out;
    out.resize(at);
    out += ",\"stats\":";
    out += json_text(stats);
    out += '}';
    return out;
}

ApiResponse run(const ApiRequest& request, const ApiContext& context) {
    const Limits& limits = context.limits;
    const auto t_start = Clock::now();

    // 1-3. size and media type, options and mesh (for uploads the options are checked before the file is parsed),
    // budgets and validity, before any work
    // (read as leniently as /subdivide reads: what repair "none" refuses is refused by run_with_repair)
    auto decoded = decode_mesh_request<RemeshParams>(request, limits, decode_request, params_from_query, check_params,
                                                     MeshRules::Subdivision);
    if (!decoded) return error_response(std::move(decoded.error()));
    auto& [source, params, input, t_decoded, read_report] = decoded.value();
    const PolygonMesh& mesh = input;
    if (mesh.face_count() == 0)
        return error_response(make_problem(Problem::InvalidField, "the mesh has no faces to remesh", "mesh"));
    if (auto error = check_triangulated_budget(mesh, limits)) return error_response(std::move(*error));
    // the target: given, or the input's mean edge length; then the predicted output, area / (sqrt(3)/4 L^2)
    double area = 0, edge_sum = 0;
    std::size_t edge_count = 0;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        auto t = mesh.face(f);
        for (std::size_t j = 0; j < t.size(); ++j) {
            edge_sum += norm(mesh.positions[t[(j + 1) % t.size()]] - mesh.positions[t[j]]);
            ++edge_count;
        }
        for (std::size_t j = 1; j + 1 < t.size(); ++j)
            area += 0.5 * norm(cross(mesh.positions[t[j]] - mesh.positions[t[0]],
                                     mesh.positions[t[j + 1]] - mesh.positions[t[0]]));
    }
    const double length = params.edge_length ? *params.edge_length : edge_sum / static_cast<double>(edge_count);
    if (!(length > 0))
        return error_response(
            make_problem(Problem::InvalidField, "the mesh's edges have zero length: give edge_length", "edge_length"));
    const double predicted = area / (std::sqrt(3.0) / 4 * length * length);
    if (!(predicted <= static_cast<double>(limits.max_output_faces)))
        return error_response(
            make_problem(Problem::BudgetExceeded,
                         "edge_length " + format_double(length) + " over a surface of area " + format_double(area) +
                             " predicts " + format_double(std::round(predicted)) +
                             " faces (area / (0.433 L^2)); the limit is " + std::to_string(limits.max_output_faces),
                         "edge_length"));

    // 4. remesh, repaired first when it must be (repair "auto")
    RemeshOptions options;
    options.target_edge_length = length;
    options.iterations = static_cast<int>(params.iterations);
    options.feature_angle_degrees = params.feature_angle;
    options.lock_border = params.lock_border;
    options.smoothing = params.smoothing;
    // intermediate meshes may briefly exceed the prediction (splits before collapses); never past twice the limit
    options.max_faces = static_cast<std::size_t>(2 * limits.max_output_faces);
    options.cancel = context.cancel;
    std::optional<PolygonMesh> repaired;
    std::optional<RepairReport> repairs;
    auto remeshed = run_with_repair(input, params.repair, source, read_report, context.cancel, repaired, repairs,
                                    [&](const PolygonMesh& m) { return surfaced::remesh(m, options); });
    if (!remeshed) return error_response(std::move(remeshed.error()));
    RemeshResult& result = remeshed.value();
    const auto t_remeshed = Clock::now();

    // 5. encode
    Json stats = {{"input_vertices", input.vertex_count()},        {"input_faces", input.face_count()},
                  {"output_vertices", result.mesh.vertex_count()}, {"output_faces", result.mesh.face_count()},
                  {"triangulated", result.triangulated},           {"edge_length", result.target_edge_length},
                  {"feature_edges", result.feature_edges},         {"boundary_edges", result.boundary_edges},
                  {"hausdorff", result.hausdorff.value_or(0.0)},   {"before", quality_json(result.before)},
                  {"after", quality_json(result.after)},           {"elapsed_ms", ms_between(t_start, t_remeshed)}};
    if (repairs) stats["repairs"] = Json::parse(encode_repairs(*repairs));
    Headers headers = mesh_count_headers(input.vertex_count(), input.face_count(), result.mesh.vertex_count(),
                                         result.mesh.face_count());
    if (repairs) headers.emplace_back("X-Repairs", repairs_header(*repairs));
    append_read_headers(headers, read_report);
    headers.insert(headers.end(), {
                                      {"X-Triangulated", result.triangulated ? "true" : "false"},
                                      {"X-Edge-Length", format_double(result.target_edge_length)},
                                      {"X-Feature-Edges", std::to_string(result.feature_edges)},
                                      {"X-Hausdorff", format_double(result.hausdorff.value_or(0.0))},
                                      {"X-Min-Angle-Before", format_double(result.before.min_angle_degrees)},
                                      {"X-Min-Angle-After", format_double(result.after.min_angle_degrees)},
                                      {"X-Below-30-Before", format_double(result.before.share_below_30)},
                                      {"X-Below-30-After", format_double(result.after.share_below_30)},
                                      {"X-Radius-Ratio-Before", format_double(result.before.mean_radius_ratio)},
                                      {"X-Radius-Ratio-After", format_double(result.after.mean_radius_ratio)},
                                      {"X-Mean-Edge-Length-After", format_double(result.after.mean_edge_length)},
                                  });
    return mesh_response(
        result.mesh, params.output, source, [&](const PolygonMesh& m) { return encode_json_response(m, stats); },
        std::move(headers), Timing{t_start, {{"decode", t_decoded}, {"remesh", t_remeshed}}});
}

}  // namespace

ApiResponse remesh(const ApiRequest& request, const ApiContext& context) noexcept {
    return guarded([&] { return run(request, context); });
}

}  // namespace surfaced::api::operations
