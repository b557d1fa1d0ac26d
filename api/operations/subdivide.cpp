#include "api/operations/subdivide.h"

#include <algorithm>
#include <cstdint>
#include <string>

#include "api/dto.h"
#include "api/json_codec.h"
#include "api/operations/request_forms.h"
#include "api/options/mesh_params.h"
#include "api/patch_codec.h"
#include "geometry/subdivision/limit_patches.h"
#include "geometry/subdivision/adaptive_tessellation.h"
#include "geometry/subdivision/limit_evaluation.h"
#include "geometry/subdivision/subdivide.h"

namespace surfaced::api::operations {
namespace {

//! format "patches" without levels: the approximated patches' bounded error allowed, relative to the bounding-box
//! diagonal.
constexpr double kPatchTolerance = 1e-3;

//! Options of the raw-file form: the same names and values as the JSON form (output options unnested).
ApiResult<SubdivideParams> params_from_query(const std::multimap<std::string, std::string>& query) {
    auto values = options::read_query(*options::operation_options("subdivide"), query);
    if (!values) return std::move(values.error());
    return options::subdivide_params(values.value());
}

//! What the option table cannot say: levels against this server's limit, and output options that do not fit the
//! format. Field names: the JSON path (query parameters use the leaf name).
std::optional<ApiError> check_params(const SubdivideParams& params, const Limits& limits, Source source) {
    if (params.tolerance) {
        if (params.levels_given)
            return make_problem(Problem::InvalidField, "give either tolerance or levels, not both", "tolerance");
        if (params.target_faces)
            return make_problem(Problem::InvalidField, "give either tolerance or target_faces, not both", "tolerance");
        if (params.scheme != SubdivisionScheme::CatmullClark)
            return make_problem(Problem::InvalidField,
                                "tolerance tessellates the Catmull-Clark limit surface; scheme must be catmull-clark",
                                "tolerance");
    }
    if (params.straddle && !params.tolerance)
        return make_problem(Problem::InvalidField, "straddle applies to tolerance tessellation; give tolerance with it",
                            "straddle");
    if (params.levels > limits.max_levels)
        return make_problem(Problem::BudgetExceeded,
                            "levels is " + std::to_string(params.levels) + "; this server allows at most " +
                                std::to_string(limits.max_levels),
                            "levels");
    if (params.patches) {
        // patches are control points, not a mesh: the mesh encoders' options and the mesh-size target do not apply
        const auto refuse = [&](bool given, std::string_view name, bool output) -> std::optional<ApiError> {
            if (!given) return std::nullopt;
            const std::string field = (output && source == Source::Json ? "output." : "") + std::string(name);
            return make_problem(Problem::InvalidField,
                                field + " does not apply to format \"patches\" (control points, not a mesh)", field);
        };
        if (auto error = refuse(params.output.draco.has_value(), "compression", true)) return error;
        if (auto error = refuse(params.output.quantize_position.has_value(), "quantize_position", true)) return error;
        if (auto error = refuse(params.output.normals.has_value(), "normals", true)) return error;
        if (auto error = refuse(params.target_faces.has_value(), "target_faces", false)) return error;
        if (auto error = refuse(params.limit_surface, "limit_surface", false)) return error;
        if (params.scheme != SubdivisionScheme::CatmullClark)
            return make_problem(Problem::InvalidField,
                                "format \"patches\" gives bicubic patches: scheme catmull-clark only", "scheme");
        return std::nullopt;
    }
    return check_output_options(params.output, source);
}

//! The bounding-box diagonal of the mesh's positions.
double diagonal(const PolygonMesh& mesh) {
    Box3 box;
    for (const Vec3& p : mesh.positions) box.add(p);
    return box.diagonal();
}

//! format "patches": the limit surface as bicubic Bézier patches (limit_patches.h), at isolation level `levels` when
//! given, else at the smallest level whose approximated patches are within `tolerance` (default: kPatchTolerance of
//! the bounding diagonal).
ApiResponse patches_response(const PolygonMesh& mesh, const SubdivideParams& params, const SubdivisionOptions& options,
                             const Limits& limits, const Cancel& cancel, Source source, const ReadReport& read_report,
                             Clock::time_point t_start, Clock::time_point t_decoded) {
    auto evaluator = LimitSurfaceEvaluator::create(mesh, options);
    if (!evaluator) return error_response(geometry_error(evaluator.error(), source, read_report));
    LimitPatchOptions patch_options;
    if (params.levels_given) patch_options.levels = static_cast<int>(params.levels);
    // `tolerance`, when given, caps the bound on the approximated patches' error
    patch_options.tolerance = params.tolerance ? *params.tolerance : kPatchTolerance * diagonal(mesh);
    if (!(patch_options.tolerance > 0)) patch_options.tolerance = kPatchTolerance;
    patch_options.max_levels = std::min(limits.max_levels, 10);
    patch_options.max_patches = limits.max_patches;
    patch_options.cancel = cancel;
    if (patch_options.levels && *patch_options.levels < min_limit_patch_level(mesh))
        return error_response(make_problem(Problem::InvalidField,
                                           "format \"patches\" needs levels >= 1 for a mesh with faces that are not "
                                           "quads (their patches lie in the quad sub-faces)",
                                           "levels"));
    if (patch_options.levels && limit_patch_count(mesh, *patch_options.levels) > limits.max_patches)
        return error_response(make_problem(Problem::BudgetExceeded,
                                           "isolation level " + std::to_string(*patch_options.levels) + " makes " +
                                               std::to_string(limit_patch_count(mesh, *patch_options.levels)) +
                                               " patches; the limit is " + std::to_string(limits.max_patches) +
                                               " (use fewer levels or a smaller mesh)",
                                           "levels"));
    auto set = limit_patches(evaluator.value(), mesh, patch_options);
    if (!set) {
        ApiError error = geometry_error(set.error(), source, read_report);
        if (set.error().code == ErrorCode::BudgetExceeded) error.field = "levels";
        return error_response(std::move(error));
    }
    if (auto error = check_deadline_before_encoding(cancel)) return error_response(std::move(*error));
    const auto t_done = Clock::now();
    ApiResponse response;
    response.content_type = "application/json";
    PatchSet patches;
    patches.patches = std::move(set->patches);
    response.body = patch_set_json(patches);
    response.headers = {{"X-Input-Vertices", std::to_string(mesh.vertex_count())},
                        {"X-Input-Faces", std::to_string(mesh.face_count())},
                        {"X-Patches", std::to_string(patches.patches.size())},
                        {"X-Isolation-Level", std::to_string(set->levels)},
                        {"X-Approximate-Patches", std::to_string(set->approximate_count)},
                        {"X-Max-Error", format_double(set->max_error)}};
    append_timing_headers(response.headers, Timing{t_start, {{"decode", t_decoded}, {"patches", t_done}}});
    return response;
}

//! `tolerance`: the limit surface tessellated adaptively (adaptive_tessellation.h). The plan's exact triangle count is
//! checked against the output budget before any output vertex is evaluated.
ApiResponse tessellate_limit_surface(const SubdivideParams& params, const PolygonMesh& mesh,
                                     const SubdivisionOptions& options, Source source, const ReadReport& read_report,
                                     const ApiContext& context, Timing timing) {
    const Limits& limits = context.limits;
    auto evaluator = LimitSurfaceEvaluator::create(mesh, options);
    if (!evaluator) return error_response(geometry_error(evaluator.error(), source, read_report));
    LimitTessellationOptions tess;
    tess.tolerance = *params.tolerance;
    tess.max_segments = limits.max_patch_segments;
    tess.max_triangles = limits.max_output_faces;
    tess.threads = options.threads;
    if (params.straddle) tess.straddle = *params.straddle;
    tess.cancel = context.cancel;
    auto tessellated = tessellate_limit(*evaluator, mesh, tess);
    if (!tessellated) {
        if (tessellated.error().code == ErrorCode::BudgetExceeded) {
            ApiError error = from_geo_error(tessellated.error());
            error.field = "tolerance";
            error.hint = "use a larger tolerance";
            return error_response(std::move(error));
        }
        return error_response(geometry_error(tessellated.error(), source, read_report));
    }
    if (auto error = check_deadline_before_encoding(context.cancel)) return error_response(std::move(*error));
    PolygonMesh& result = tessellated->mesh;
    const auto t_done = Clock::now();

    SubdivideStats stats;
    stats.input_vertices = mesh.vertex_count();
    stats.input_faces = mesh.face_count();
    stats.output_vertices = result.vertex_count();
    stats.output_faces = result.face_count();
    stats.scheme = params.scheme;
    stats.levels = 0;
    stats.elapsed_ms = ms_between(timing.start, t_done);

    Headers headers =
        mesh_count_headers(stats.input_vertices, stats.input_faces, stats.output_vertices, stats.output_faces);
    append_read_headers(headers, read_report);
    headers.emplace_back("X-Tolerance", format_double(*params.tolerance));
    headers.emplace_back("X-Achieved-Tolerance", format_double(tessellated->achieved_error));
    timing.stages.emplace_back("tessellate", t_done);
    return mesh_response(
        result, params.output, source, [&](const PolygonMesh& m) { return encode_mesh_response(m, stats); },
        std::move(headers), std::move(timing));
}

ApiResponse run(const ApiRequest& request, const ApiContext& context) {
    const Limits& limits = context.limits;
    const auto t_start = Clock::now();

    // 1-3. size and media type, options and mesh (for uploads the options are checked before the file is parsed), input
    // budget and validity
    auto decoded = decode_mesh_request<SubdivideParams>(
        request, limits, decode_subdivide_request, params_from_query,
        [&](const SubdivideParams& params, Source source) { return check_params(params, limits, source); },
        MeshRules::Subdivision);
    if (!decoded) return error_response(std::move(decoded.error()));
    auto& [source, params, mesh, t_decoded, read_report] = decoded.value();

    // 4. options, and the predicted output against the budget, before refining anything
    SubdivisionOptions options;
    options.scheme = params.scheme;
    options.crease_method = params.crease_method;
    options.triangle_rule = params.triangle_rule;
    options.limit_surface = params.limit_surface;
    options.uv_interpolation = params.uv_interpolation;
    options.loop_weights = params.loop_weights;
    options.threads = static_cast<int>(params.threads);
    if (params.boundary) {
        options.boundary = *params.boundary;
        options.use_mesh_boundary_tag = false;  // an explicit request wins over the file's tag
    }
    if (params.patches)
        return patches_response(mesh, params, options, limits, context.cancel, source, read_report, t_start, t_decoded);
    if (params.tolerance)
        return tessellate_limit_surface(params, mesh, options, source, read_report, context,
                                        Timing{t_start, {{"decode", t_decoded}}});

    // The work is that of refining to levels + limit_extra_levels (exact limits refine past semi-sharp creases);
    // the output is that of `levels`.
    // (init-captures: clang 14, which builds the fuzzers, cannot capture structured bindings)
    const auto work_faces = [&options, &input = mesh, scheme = params.scheme](int levels) {
        options.levels = levels;
        return predicted_face_count(input, scheme, levels + limit_extra_levels(input, options));
    };
    int levels = static_cast<int>(params.levels);  // range-checked above
    bool target_met = true;
    if (params.target_faces) {
        // the largest level whose output fits target_faces (and whose work fits the server's budget); an input that
        // already has more faces is answered as it is (level 0), reported as a target not met, as /simplify does
        const int upper = params.levels_given ? levels : limits.max_levels;
        const auto cap = static_cast<std::uint64_t>(*params.target_faces);
        int chosen = 0;
        for (int l = 1; l <= upper; ++l) {
            if (predicted_face_count(mesh, params.scheme, l) > cap || work_faces(l) > limits.max_output_faces) break;
            chosen = l;
        }
        target_met = predicted_face_count(mesh, params.scheme, chosen) <= cap;
        levels = chosen;
    }
    const std::uint64_t predicted = work_faces(levels);
    if (predicted > limits.max_output_faces)
        return error_response(
            make_problem(Problem::BudgetExceeded,
                         "subdividing " + std::to_string(mesh.face_count()) + " faces " + std::to_string(levels) +
                             (levels == 1 ? " time" : " times") +
                             (options.limit_surface && limit_extra_levels(mesh, options) > 0
                                  ? " (plus " + std::to_string(limit_extra_levels(mesh, options)) +
                                        " internal levels to evaluate the limit past semi-sharp creases)"
                                  : std::string()) +
                             " would produce " + std::to_string(predicted) + " faces; the limit is " +
                             std::to_string(limits.max_output_faces) + " (use fewer levels or a smaller mesh)",
                         "levels"));

    // 5. refine (polling the request's deadline between levels; also before encoding, which cannot be stopped)
    options.levels = levels;
    options.cancel = context.cancel;
    auto refined = surfaced::subdivide(mesh, options);
    if (!refined) {
        // located at the face the error names: its line in an uploaded text file, its field in a JSON body
        ApiError error = geometry_error(refined.error(), source, read_report);
        if (refined.error().code == ErrorCode::NotTriangleMesh) error.hint = "scheme catmull-clark takes any polygons";
        return error_response(std::move(error));
    }
    if (auto error = check_deadline_before_encoding(context.cancel)) return error_response(std::move(*error));
    PolygonMesh& result = refined.value();
    const auto t_refined = Clock::now();

    SubdivideStats stats;
    stats.input_vertices = mesh.vertex_count();
    stats.input_faces = mesh.face_count();
    stats.output_vertices = result.vertex_count();
    stats.output_faces = result.face_count();
    stats.scheme = params.scheme;
    stats.levels = levels;
    stats.target_faces = params.target_faces;
    stats.target_met = target_met;
    stats.elapsed_ms = ms_between(t_start, t_refined);

    // 6. encode
    Headers headers =
        mesh_count_headers(stats.input_vertices, stats.input_faces, stats.output_vertices, stats.output_faces);
    append_read_headers(headers, read_report);
    if (stats.target_faces) {
        headers.emplace_back("X-Target-Faces", std::to_string(*stats.target_faces));
        headers.emplace_back("X-Achieved-Faces", std::to_string(stats.output_faces));
        headers.emplace_back("X-Target-Met", stats.target_met ? "true" : "false");
    }
    return mesh_response(
        result, params.output, source, [&](const PolygonMesh& m) { return encode_mesh_response(m, stats); },
        std::move(headers), Timing{t_start, {{"decode", t_decoded}, {"subdivide", t_refined}}});
}

}  // namespace

ApiResponse subdivide(const ApiRequest& request, const ApiContext& context) noexcept {
    return guarded([&] { return run(request, context); });
}

}  // namespace surfaced::api::operations
