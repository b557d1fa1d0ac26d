#include "api/operations/simplify.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <new>
#include <set>

#include "api/dto.h"
#include "api/json_codec.h"
#include "api/operations/request_forms.h"
#include "geometry/io/gltf.h"
#include "geometry/io/mesh_io.h"
#include "geometry/mesh/normals.h"
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
        if (name == "target_faces") {
            auto v = parse_integer_parameter(name, text);
            if (!v) return std::move(v.error());
            params.target_faces = v.value();
        } else if (name == "ratio") {
            auto v = parse_number_parameter(name, text);
            if (!v) return std::move(v.error());
            params.ratio = v.value();
        } else if (name == "max_error") {
            auto v = parse_number_parameter(name, text);
            if (!v) return std::move(v.error());
            params.max_error = v.value();
        } else if (name == "lock_border") {
            auto v = parse_bool_parameter(name, text);
            if (!v) return std::move(v.error());
            params.lock_border = v.value();
        } else if (name == "report_error") {
            auto v = parse_bool_parameter(name, text);
            if (!v) return std::move(v.error());
            params.report_error = v.value();
        } else {
            auto output = parse_output_parameter(name, text, params.output);
            if (!output) return std::move(output.error());
        }
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

    // 1. size and media type
    std::string media_type;
    if (auto error = check_body(request, limits, media_type)) return error_response(std::move(*error));

    // 2. options and mesh (for uploads the options are checked before the file is parsed)
    Source source = Source::File;
    SimplifyParams params;
    PolygonMesh mesh;
    if (media_type == "application/json") {
        source = Source::Json;
        if (auto error = reject_query_with_json(request)) return error_response(std::move(*error));
        auto decoded = decode_simplify_request(request.body, limits);
        if (!decoded) return error_response(std::move(decoded.error()));
        params = std::move(decoded->params);
        if (auto error = check_params(params, source)) return error_response(std::move(*error));
        mesh = std::move(decoded->mesh);
    } else {
        if (!mesh_format_for(media_type, request.body)) {
            auto refused = read_uploaded_mesh(request, media_type, limits);  // the 415, worded in one place
            return error_response(std::move(refused.error()));
        }
        auto query_params = params_from_query(request.query);
        if (!query_params) return error_response(std::move(query_params.error()));
        params = std::move(query_params.value());
        if (auto error = check_params(params, source)) return error_response(std::move(*error));
        auto read = read_uploaded_mesh(request, media_type, limits);
        if (!read) return error_response(std::move(read.error()));
        mesh = std::move(read.value());
    }
    const auto t_decoded = Clock::now();

    // 3. budgets and validity, before any work
    if (auto error = check_input_budget(mesh, limits)) return error_response(std::move(*error));
    if (auto valid = validate(mesh); !valid) return error_response(geometry_error(valid.error(), source));
    // Triangulation turns an n-gon into n - 2 triangles: the simplifier's work is proportional to those.
    const std::uint64_t triangles = mesh.face_indices.size() - 2 * mesh.face_count();
    if (triangles > limits.max_input_faces)
        return error_response(make_problem(Problem::BudgetExceeded,
                                           "the mesh triangulates to " + std::to_string(triangles) +
                                               " triangles; the limit is " + std::to_string(limits.max_input_faces)));

    // 4. simplify
    SimplifyOptions options;
    if (params.target_faces) options.target_faces = static_cast<std::size_t>(*params.target_faces);
    options.ratio = params.ratio;
    options.max_error = params.max_error;
    options.lock_border = params.lock_border;
    auto simplified = simplify_qem(mesh, options);
    if (!simplified) return error_response(geometry_error(simplified.error(), source));
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
    ApiResponse response;
    response.content_type = std::string(output_media_type(params.output.format));
    auto encoded = encode_mesh_output(result.mesh, params.output, source,
                                      [&](const PolygonMesh& m) { return encode_simplify_response(m, stats); });
    if (!encoded) return error_response(std::move(encoded.error()));
    response.body = std::move(encoded.value());
    const auto t_encoded = Clock::now();

    response.headers = {
        {"X-Input-Vertices", std::to_string(stats.input_vertices)},
        {"X-Input-Faces", std::to_string(stats.input_faces)},
        {"X-Output-Vertices", std::to_string(stats.output_vertices)},
        {"X-Output-Faces", std::to_string(stats.output_faces)},
        {"X-Triangulated", stats.triangulated ? "true" : "false"},
        {"X-Achieved-Error", format_double(stats.achieved_error)},
        {"X-Relative-Error", format_double(stats.relative_error)},
    };
    if (stats.hausdorff) response.headers.emplace_back("X-Hausdorff", format_double(*stats.hausdorff));
    if (stats.rms) response.headers.emplace_back("X-RMS", format_double(*stats.rms));
    response.headers.emplace_back("X-Elapsed-Ms", format_ms(ms_between(t_start, t_encoded)));
    response.headers.emplace_back("Server-Timing", "decode;dur=" + format_ms(ms_between(t_start, t_decoded)) +
                                                       ", simplify;dur=" + format_ms(ms_between(t_decoded, t_simplified)) +
                                                       ", measure;dur=" + format_ms(ms_between(t_simplified, t_measured)) +
                                                       ", encode;dur=" + format_ms(ms_between(t_measured, t_encoded)) +
                                                       ", total;dur=" + format_ms(ms_between(t_start, t_encoded)));
    return response;
}

}  // namespace

ApiResponse simplify(const ApiRequest& request, const ApiContext& context) noexcept {
    return guarded([&] { return run(request, context); });
}

}  // namespace surfaced::api::operations
