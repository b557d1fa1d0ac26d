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
    static constexpr std::string_view kAllowed[] = {"scheme",        "levels",        "boundary",  "crease_method",
                                                    "triangle_rule", "uv_interpolation", "loop_weights", "limit_surface", "max_faces", "format",
                                                    "compression",   "quantize_position", "normals"};
    std::set<std::string> unknown;
    for (const auto& [name, value] : query)
        if (std::find(std::begin(kAllowed), std::end(kAllowed), name) == std::end(kAllowed)) unknown.insert(name);
    if (!unknown.empty()) {
        std::string names, allowed;
        for (const auto& name : unknown) names += (names.empty() ? "\"" : ", \"") + name + "\"";
        for (std::string_view name : kAllowed) allowed += (allowed.empty() ? "" : ", ") + std::string(name);
        return make_problem(Problem::UnknownParameter,
                            "unknown query parameter" + std::string(unknown.size() > 1 ? "s " : " ") + names +
                                " (allowed: " + allowed + ")",
                            *unknown.begin());
    }
    for (std::string_view name : kAllowed)
        if (query.count(std::string(name)) > 1)
            return make_problem(Problem::InvalidField,
                                "query parameter " + std::string(name) + " is given more than once", std::string(name));

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
        } else if (name == "format") {
            auto v = parse_enum_parameter(name, text, kOutputFormatNames);
            if (!v) return std::move(v.error());
            params.output.format = v.value();
        } else if (name == "compression") {
            auto v = parse_enum_parameter(name, text, kCompressionNames);
            if (!v) return std::move(v.error());
            params.output.draco = v.value();
        } else if (name == "quantize_position") {
            auto v = parse_integer_parameter(name, text);
            if (!v) return std::move(v.error());
            params.output.quantize_position = v.value();
        } else if (name == "normals") {
            auto v = parse_bool_parameter(name, text);
            if (!v) return std::move(v.error());
            params.output.normals = v.value();
        }
    }
    return params;
}

//! Range checks shared by both request forms. Field names: the JSON path (query parameters use the leaf name).
std::optional<ApiError> check_params(const SubdivideParams& params, const Limits& limits, Source source) {
    const auto output_field = [&](std::string_view leaf) {
        return (source == Source::Json ? "output." : "") + std::string(leaf);
    };
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
    const OutputOptions& out = params.output;
    const bool glb = out.format == OutputFormat::Glb || out.format == OutputFormat::Gltf;  // glTF, binary or text
    const std::string format(enum_name(kOutputFormatNames, out.format));
    if (out.draco && !glb)
        return make_problem(Problem::InvalidField, "compression applies only to formats \"glb\" and \"gltf\", not \"" + format + "\"",
                            output_field("compression"));
    if (out.quantize_position) {
        if (!glb || !out.draco.value_or(true))
            return make_problem(Problem::InvalidField,
                                "quantize_position applies only to formats \"glb\" and \"gltf\" with compression \"draco\"",
                                output_field("quantize_position"));
        if (*out.quantize_position < 1 || *out.quantize_position > 24)
            return make_problem(Problem::InvalidField,
                                "quantize_position must be between 1 and 24 bits, got " +
                                    std::to_string(*out.quantize_position),
                                output_field("quantize_position"));
    }
    if (out.normals.value_or(false) && out.format == OutputFormat::Json)
        return make_problem(Problem::InvalidField, "normals are not available in format \"json\"", output_field("normals"));
    return std::nullopt;
}

ApiResponse run(const ApiRequest& request, const ApiContext& context) {
    const Limits& limits = context.limits;
    const auto t_start = Clock::now();

    // 1. size and media type: nothing is parsed for a request we would refuse anyway.
    if (request.body.size() > limits.max_body_bytes)
        return error_response(make_problem(Problem::PayloadTooLarge,
                                           "request body is " + std::to_string(request.body.size()) +
                                               " bytes; the limit is " + std::to_string(limits.max_body_bytes) +
                                               " bytes"));
    const std::string media_type = media_type_of(request.content_type);
    if (media_type.empty())
        return error_response(make_problem(Problem::UnsupportedMediaType,
                                           "a Content-Type is required; accepted: " + accepted_mesh_media_types()));

    // 2. decode options and mesh
    Source source = Source::File;
    SubdivideParams params;
    PolygonMesh mesh;
    if (media_type == "application/json") {
        source = Source::Json;
        if (!request.query.empty())
            return error_response(make_problem(
                Problem::UnknownParameter,
                "query parameters are not accepted with a JSON body (options go in the body), got \"" +
                    request.query.begin()->first + "\"",
                request.query.begin()->first));
        auto decoded = decode_subdivide_request(request.body, limits);
        if (!decoded) return error_response(std::move(decoded.error()));
        params = std::move(decoded->params);
        if (auto error = check_params(params, limits, source)) return error_response(std::move(*error));
        mesh = std::move(decoded->mesh);
    } else {
        const auto format = mesh_format_for(media_type, request.body);
        if (!format) {
            const std::string detail =
                media_type == "application/octet-stream"
                    ? "could not recognise the mesh format from the content; send a specific Content-Type (" +
                          accepted_mesh_media_types() + ")"
                    : "Content-Type \"" + media_type + "\" is not accepted; accepted: " + accepted_mesh_media_types();
            return error_response(make_problem(Problem::UnsupportedMediaType, detail));
        }
        auto query_params = params_from_query(request.query);
        if (!query_params) return error_response(std::move(query_params.error()));
        params = std::move(query_params.value());
        if (auto error = check_params(params, limits, source)) return error_response(std::move(*error));
        ReadOptions read_options;
        read_options.max_vertices = static_cast<std::size_t>(limits.max_input_vertices);
        read_options.max_faces = static_cast<std::size_t>(limits.max_input_faces);
        auto read = read_mesh(request.body, *format, read_options);
        if (!read) return error_response(geometry_error(read.error(), source));
        mesh = std::move(read.value());
    }
    const auto t_decoded = Clock::now();

    // 3. input budget and validity (readers enforce their own limits; this covers every source the same way)
    if (mesh.face_count() > limits.max_input_faces || mesh.vertex_count() > limits.max_input_vertices)
        return error_response(make_problem(Problem::BudgetExceeded,
                                           "the mesh has " + std::to_string(mesh.vertex_count()) + " vertices and " +
                                               std::to_string(mesh.face_count()) + " faces; the limits are " +
                                               std::to_string(limits.max_input_vertices) + " and " +
                                               std::to_string(limits.max_input_faces)));
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
    const OutputOptions& out = params.output;
    const bool normals = out.normals.value_or(false);
    ApiResponse response;
    response.content_type = std::string(output_media_type(out.format));
    switch (out.format) {
        case OutputFormat::Glb:
        case OutputFormat::Gltf: {
            GltfOptions gltf;
            gltf.draco = out.draco.value_or(true);
            if (out.quantize_position) gltf.quantize_position = static_cast<int>(*out.quantize_position);
            gltf.normals = normals;
            auto encoded = out.format == OutputFormat::Glb ? write_glb(result, gltf) : write_gltf(result, gltf);
            if (!encoded) return error_response(geometry_error(encoded.error(), source));
            response.body = std::move(encoded.value());
            break;
        }
        case OutputFormat::Obj: {
            ObjWriteOptions obj;
            obj.write_normals = normals;
            if (normals && !result.has_normals()) result.normals = compute_vertex_normals(result);
            response.body = write_obj(result, obj);
            break;
        }
        case OutputFormat::Ply:
            // write_ply writes normals exactly when the mesh has them.
            if (normals && !result.has_normals()) result.normals = compute_vertex_normals(result);
            if (!normals) result.normals.clear();
            response.body = write_ply(result);
            break;
        case OutputFormat::Json: response.body = encode_mesh_response(result, stats); break;
    }
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
