#include "api/operations/simplify.h"

#include <cstdint>
#include <string>

#include "api/dto.h"
#include "api/json_codec.h"
#include "api/operations/request_forms.h"
#include "geometry/simplify/mesh_distance.h"
#include "geometry/simplify/qem.h"

namespace surfaced::api::operations {
namespace {

ApiResult<SimplifyParams> params_from_query(const std::multimap<std::string, std::string>& query) {
    if (auto error = check_query_names(query, {"target_faces", "ratio", "max_error", "lock_border", "report_error",
                                                "format", "compression", "quantize_position", "normals"}))
        return std::move(*error);

    SimplifyParams params;
    for (const auto& [name, text] : query) {
        std::optional<ApiError> error;
        if (name == "target_faces") error = read_parameter(name, text, params.target_faces);
        else if (name == "ratio") error = read_parameter(name, text, params.ratio);
        else if (name == "max_error") error = read_parameter(name, text, params.max_error);
        else if (name == "lock_border") error = read_parameter(name, text, params.lock_border);
        else if (name == "report_error") error = read_parameter(name, text, params.report_error);
        else if (auto output = parse_output_parameter(name, text, params.output); !output) error = std::move(output.error());
        if (error) return std::move(*error);
    }
    return params;
}

std::optional<ApiError> check_params(const SimplifyParams& params, Source source) {
    if (!params.target_faces && !params.ratio && !params.max_error)
        return make_problem(Problem::InvalidField,
                            "one of target_faces, ratio or max_error is required (simplification stops at whichever "
                            "is reached first)",
                            "target_faces");
    if (params.target_faces && *params.target_faces < 0)
        return make_problem(Problem::InvalidField,
                            "target_faces must be >= 0, got " + std::to_string(*params.target_faces), "target_faces");
    if (params.ratio && !(*params.ratio > 0 && *params.ratio <= 1))
        return make_problem(Problem::InvalidField, "ratio must be in (0, 1], got " + format_double(*params.ratio),
                            "ratio");
    if (params.max_error && !(*params.max_error >= 0))
        return make_problem(Problem::InvalidField,
                            "max_error must be a distance >= 0, got " + format_double(*params.max_error), "max_error");
    return check_output_options(params.output, source);
}

ApiResponse run(const ApiRequest& request, const ApiContext& context) {
    const Limits& limits = context.limits;
    const auto t_start = Clock::now();

    // 1-3. size and media type, options and mesh (for uploads the options are checked before the file is parsed),
    // budgets and validity, before any work
    auto decoded = decode_mesh_request<SimplifyParams>(request, limits, decode_simplify_request, params_from_query,
                                                       check_params);
    if (!decoded) return error_response(std::move(decoded.error()));
    auto& [source, params, mesh, t_decoded] = decoded.value();
    if (auto error = check_triangulated_budget(mesh, limits)) return error_response(std::move(*error));

    // 4. simplify
    SimplifyOptions options;
    if (params.target_faces) options.target_faces = static_cast<std::size_t>(*params.target_faces);
    options.ratio = params.ratio;
    options.max_error = params.max_error;
    options.lock_border = params.lock_border;
    options.cancel = context.cancel;
    auto simplified = simplify_qem(mesh, options);
    if (!simplified) return error_response(geometry_error(simplified.error(), source));
    if (auto error = check_deadline_before_encoding(context.cancel)) return error_response(std::move(*error));
    SimplifyResult& result = simplified.value();
    const auto t_simplified = Clock::now();

    SimplifyStats stats;
    stats.input_vertices = mesh.vertex_count();
    stats.input_faces = mesh.face_count();
    stats.output_vertices = result.mesh.vertex_count();
    stats.output_faces = result.faces;
    stats.triangulated = result.triangulated;
    stats.achieved_error = result.achieved_error;
    stats.relative_error = result.relative_error;
    if (params.report_error) {
        const MeshDistance distance = mesh_distance(mesh, result.mesh);
        stats.hausdorff = distance.hausdorff;
        stats.rms = distance.rms;
    }
    const auto t_measured = Clock::now();
    stats.elapsed_ms = ms_between(t_start, t_measured);

    // 5. encode
    Headers headers =
        mesh_count_headers(stats.input_vertices, stats.input_faces, stats.output_vertices, stats.output_faces);
    headers.emplace_back("X-Triangulated", stats.triangulated ? "true" : "false");
    headers.emplace_back("X-Achieved-Error", format_double(stats.achieved_error));
    headers.emplace_back("X-Relative-Error", format_double(stats.relative_error));
    if (stats.hausdorff) headers.emplace_back("X-Hausdorff", format_double(*stats.hausdorff));
    if (stats.rms) headers.emplace_back("X-RMS", format_double(*stats.rms));
    return mesh_response(result.mesh, params.output, source,
                         [&](const PolygonMesh& m) { return encode_simplify_response(m, stats); }, std::move(headers),
                         Timing{t_start, {{"decode", t_decoded}, {"simplify", t_simplified}, {"measure", t_measured}}});
}

}  // namespace

ApiResponse simplify(const ApiRequest& request, const ApiContext& context) noexcept {
    return guarded([&] { return run(request, context); });
}

}  // namespace surfaced::api::operations
