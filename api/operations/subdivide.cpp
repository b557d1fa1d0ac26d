#include "api/operations/subdivide.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <chrono>
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
#include "geometry/subdivision/subdivide.h"

namespace surfaced::api::operations {
namespace {

//! Options of the raw-file form. Same names and values as the JSON form (output options unnested).
ApiResult<SubdivideParams> params_from_query(const std::multimap<std::string, std::string>& query) {
    if (auto error = check_query_names(query, {"scheme", "levels", "boundary", "crease_method", "triangle_rule",
                                                "uv_interpolation", "loop_weights", "limit_surface", "max_faces", "format",
                                                "compression", "quantize_position", "normals"}))
        return std::move(*error);

    SubdivideParams params;
    for (const auto& [name, text] : query) {
        if (name == "scheme") {
            auto v = parse_enum_parameter(name, text, kSchemeNames);
            if (!v) return std::move(v.error());
            params.scheme = v.value();
        } else if (name == "levels") {
            auto v = parse_integer_parameter(name, text);
            if (!v) return std::move(v.error());
            params.levels = v.value();
            params.levels_given = true;
        } else if (name == "crease_method") {
            auto v = parse_enum_parameter(name, text, kCreaseMethodNames);
            if (!v) return std::move(v.error());
            params.crease_method = v.value();
        } else if (name == "triangle_rule") {
            auto v = parse_enum_parameter(name, text, kTriangleRuleNames);
            if (!v) return std::move(v.error());
            params.triangle_rule = v.value();
        } else if (name == "loop_weights") {
            auto v = parse_enum_parameter(name, text, kLoopWeightNames);
            if (!v) return std::move(v.error());
            params.loop_weights = v.value();
        } else if (name == "uv_interpolation") {
            auto v = parse_enum_parameter(name, text, kUvInterpolationNames);
            if (!v) return std::move(v.error());
            params.uv_interpolation = v.value();
        } else if (name == "limit_surface") {
            auto v = parse_bool_parameter(name, text);
            if (!v) return std::move(v.error());
            params.limit_surface = v.value();
        } else if (name == "max_faces") {
            auto v = parse_integer_parameter(name, text);
            if (!v) return std::move(v.error());
            params.max_faces = v.value();
        } else if (name == "boundary") {
            auto v = parse_enum_parameter(name, text, kBoundaryNames);
            if (!v) return std::move(v.error());
            params.boundary = v.value();
        } else {
            auto output = parse_output_parameter(name, text, params.output);
            if (!output) return std::move(output.error());
        }
    }
    return params;
}

//! Range checks shared by both request forms. Field names: the JSON path (query parameters use the leaf name).
std::optional<ApiError> check_params(const SubdivideParams& params, const Limits& limits, Source source) {
    if (params.levels < 0)
        return make_problem(Problem::InvalidField, "levels must be >= 0, got " + std::to_string(params.levels), "levels");
    if (params.levels > limits.max_levels)
        return make_problem(Problem::BudgetExceeded,
                            "levels is " + std::to_string(params.levels) + "; this server allows at most " +
                                std::to_string(limits.max_levels),
                            "levels");
    if (params.max_faces && *params.max_faces < 1)
        return make_problem(Problem::InvalidField, "max_faces must be >= 1, got " + std::to_string(*params.max_faces),
                            "max_faces");
    return check_output_options(params.output, source);
}

ApiResponse run(const ApiRequest& request, const ApiContext& context) {
    const Limits& limits = context.limits;
    const auto t_start = Clock::now();

    // 1. size and media type: nothing is parsed for a request we would refuse anyway.
    std::string media_type;
    if (auto error = check_body(request, limits, media_type)) return error_response(std::move(*error));

    // 2. decode options and mesh (for uploads the options are checked before the file is parsed)
    Source source = Source::File;
    SubdivideParams params;
    PolygonMesh mesh;
    if (media_type == "application/json") {
        source = Source::Json;
        if (auto error = reject_query_with_json(request)) return error_response(std::move(*error));
        auto decoded = decode_subdivide_request(request.body, limits);
        if (!decoded) return error_response(std::move(decoded.error()));
        params = std::move(decoded->params);
        if (auto error = check_params(params, limits, source)) return error_response(std::move(*error));
        mesh = std::move(decoded->mesh);
    } else {
        if (!mesh_format_for(media_type, request.body)) {
            auto refused = read_uploaded_mesh(request, media_type, limits);  // the 415, worded in one place
            return error_response(std::move(refused.error()));
        }
        auto query_params = params_from_query(request.query);
        if (!query_params) return error_response(std::move(query_params.error()));
        params = std::move(query_params.value());
        if (auto error = check_params(params, limits, source)) return error_response(std::move(*error));
        auto read = read_uploaded_mesh(request, media_type, limits);
        if (!read) return error_response(std::move(read.error()));
        mesh = std::move(read.value());
    }
    const auto t_decoded = Clock::now();

    // 3. input budget and validity (readers enforce their own limits; this covers every source the same way)
    if (auto error = check_input_budget(mesh, limits)) return error_response(std::move(*error));
    if (auto valid = validate(mesh); !valid) return error_response(geometry_error(valid.error(), source));

    // 4. options, and the predicted output against the budget, before refining anything
    SubdivisionOptions options;
    options.scheme = params.scheme;
    options.crease_method = params.crease_method;
    options.triangle_rule = params.triangle_rule;
    options.limit_surface = params.limit_surface;
    options.uv_interpolation = params.uv_interpolation;
    options.loop_weights = params.loop_weights;
    if (params.boundary) {
        options.boundary = *params.boundary;
        options.use_mesh_boundary_tag = false;  // an explicit request wins over the file's tag
    }
    // The work is that of refining to levels + limit_extra_levels (exact limits refine past semi-sharp creases);
    // the output is that of `levels`.
    const auto work_faces = [&](int levels) {
        options.levels = levels;
        return predicted_face_count(mesh, params.scheme, levels + limit_extra_levels(mesh, options));
    };
    int levels = static_cast<int>(params.levels);  // range-checked above
    if (params.max_faces) {
        // the largest level whose output fits max_faces (and whose work fits the server's budget)
        const int upper = params.levels_given ? levels : limits.max_levels;
        const auto cap = static_cast<std::uint64_t>(*params.max_faces);
        int chosen = -1;
        for (int l = 0; l <= upper; ++l) {
            if (predicted_face_count(mesh, params.scheme, l) > cap || work_faces(l) > limits.max_output_faces) break;
            chosen = l;
        }
        if (chosen < 0)
            return error_response(make_problem(Problem::BudgetExceeded,
                                               "the input already has " + std::to_string(mesh.face_count()) +
                                                   " faces, more than max_faces " + std::to_string(*params.max_faces),
                                               "max_faces"));
        levels = chosen;
    }
    const std::uint64_t predicted = work_faces(levels);
    if (predicted > limits.max_output_faces)
        return error_response(make_problem(
            Problem::BudgetExceeded,
            "subdividing " + std::to_string(mesh.face_count()) + " faces " + std::to_string(levels) +
                (levels == 1 ? " time" : " times") +
                (options.limit_surface && limit_extra_levels(mesh, options) > 0
                     ? " (plus " + std::to_string(limit_extra_levels(mesh, options)) +
                           " internal levels to evaluate the limit past semi-sharp creases)"
                     : std::string()) +
                " would produce " + std::to_string(predicted) + " faces; the limit is " +
                std::to_string(limits.max_output_faces) + " (use fewer levels or a smaller mesh)",
            "levels"));

    // 5. refine
    options.levels = levels;
    auto refined = surfaced::subdivide(mesh, options);
    if (!refined) return error_response(geometry_error(refined.error(), source));
    PolygonMesh& result = refined.value();
    const auto t_refined = Clock::now();

    SubdivideStats stats;
    stats.input_vertices = mesh.vertex_count();
    stats.input_faces = mesh.face_count();
    stats.output_vertices = result.vertex_count();
    stats.output_faces = result.face_count();
    stats.scheme = params.scheme;
    stats.levels = levels;
    stats.elapsed_ms = ms_between(t_start, t_refined);

    // 6. encode
    ApiResponse response;
    response.content_type = std::string(output_media_type(params.output.format));
    auto encoded = encode_mesh_output(result, params.output, source,
                                      [&](const PolygonMesh& m) { return encode_mesh_response(m, stats); });
    if (!encoded) return error_response(std::move(encoded.error()));
    response.body = std::move(encoded.value());
    const auto t_encoded = Clock::now();

    response.headers = {
        {"X-Input-Vertices", std::to_string(stats.input_vertices)},
        {"X-Input-Faces", std::to_string(stats.input_faces)},
        {"X-Output-Vertices", std::to_string(stats.output_vertices)},
        {"X-Output-Faces", std::to_string(stats.output_faces)},
        {"X-Elapsed-Ms", format_ms(ms_between(t_start, t_encoded))},
        {"Server-Timing", "decode;dur=" + format_ms(ms_between(t_start, t_decoded)) +
                              ", subdivide;dur=" + format_ms(ms_between(t_decoded, t_refined)) +
                              ", encode;dur=" + format_ms(ms_between(t_refined, t_encoded)) +
                              ", total;dur=" + format_ms(ms_between(t_start, t_encoded))},
    };
    return response;
}

}  // namespace

ApiResponse subdivide(const ApiRequest& request, const ApiContext& context) noexcept {
    return guarded([&] { return run(request, context); });
}

}  // namespace surfaced::api::operations
