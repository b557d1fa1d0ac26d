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
    static constexpr std::string_view kAllowed[] = {"target_faces", "ratio",       "max_error",         "lock_border",
                                                    "report_error", "format",      "compression",       "quantize_position",
                                                    "normals"};
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
    const auto output_field = [&](std::string_view leaf) {
        return (source == Source::Json ? "output." : "") + std::string(leaf);
    };
    const OutputOptions& out = params.output;
    const bool glb = out.format == OutputFormat::Glb || out.format == OutputFormat::Gltf;  // glTF, binary or text
    const std::string format(enum_name(kOutputFormatNames, out.format));
    if (out.draco && !glb)
        return make_problem(Problem::InvalidField,
                            "compression applies only to formats \"glb\" and \"gltf\", not \"" + format + "\"",
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

    // 1. size and media type
    if (request.body.size() > limits.max_body_bytes)
        return error_response(make_problem(Problem::PayloadTooLarge,
                                           "request body is " + std::to_string(request.body.size()) +
                                               " bytes; the limit is " + std::to_string(limits.max_body_bytes) +
                                               " bytes"));
    const std::string media_type = media_type_of(request.content_type);
    if (media_type.empty())
        return error_response(make_problem(Problem::UnsupportedMediaType,
                                           "a Content-Type is required; accepted: " + accepted_mesh_media_types()));

    // 2. options and mesh (for uploads the options are checked before the file is parsed)
    Source source = Source::File;
    SimplifyParams params;
    PolygonMesh mesh;
    if (media_type == "application/json") {
        source = Source::Json;
        if (!request.query.empty())
            return error_response(make_problem(
                Problem::UnknownParameter,
                "query parameters are not accepted with a JSON body (options go in the body), got \"" +
                    request.query.begin()->first + "\"",
                request.query.begin()->first));
        auto decoded = decode_simplify_request(request.body, limits);
        if (!decoded) return error_response(std::move(decoded.error()));
        params = std::move(decoded->params);
        if (auto error = check_params(params, source)) return error_response(std::move(*error));
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
        if (auto error = check_params(params, source)) return error_response(std::move(*error));
        ReadOptions read_options;
        read_options.max_vertices = static_cast<std::size_t>(limits.max_input_vertices);
        read_options.max_faces = static_cast<std::size_t>(limits.max_input_faces);
        auto read = read_mesh(request.body, *format, read_options);
        if (!read) return error_response(geometry_error(read.error(), source));
        mesh = std::move(read.value());
    }
    const auto t_decoded = Clock::now();

    // 3. budgets and validity, before any work
    if (mesh.face_count() > limits.max_input_faces || mesh.vertex_count() > limits.max_input_vertices)
        return error_response(make_problem(Problem::BudgetExceeded,
                                           "the mesh has " + std::to_string(mesh.vertex_count()) + " vertices and " +
                                               std::to_string(mesh.face_count()) + " faces; the limits are " +
                                               std::to_string(limits.max_input_vertices) + " and " +
                                               std::to_string(limits.max_input_faces)));
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
    PolygonMesh& out_mesh = result.mesh;
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
            auto encoded = out.format == OutputFormat::Glb ? write_glb(out_mesh, gltf) : write_gltf(out_mesh, gltf);
            if (!encoded) return error_response(geometry_error(encoded.error(), source));
            response.body = std::move(encoded.value());
            break;
        }
        case OutputFormat::Obj: {
            ObjWriteOptions obj;
            obj.write_normals = normals;
            if (normals && !out_mesh.has_normals()) out_mesh.normals = compute_vertex_normals(out_mesh);
            response.body = write_obj(out_mesh, obj);
            break;
        }
        case OutputFormat::Ply:
            if (normals && !out_mesh.has_normals()) out_mesh.normals = compute_vertex_normals(out_mesh);
            if (!normals) out_mesh.normals.clear();
            response.body = write_ply(out_mesh);
            break;
        case OutputFormat::Json: response.body = encode_simplify_response(out_mesh, stats); break;
    }
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
