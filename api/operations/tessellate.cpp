#include "api/operations/tessellate.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <exception>
#include <new>
#include <set>

#include "api/dto.h"
#include "api/json_codec.h"
#include "api/operations/request_forms.h"
#include "api/options/option_reader.h"
#include "api/patch_codec.h"
#include "api/trim_codec.h"
#include "geometry/io/bez.h"
#include "geometry/io/gltf.h"
#include "geometry/io/mesh_io.h"
#include "geometry/io/obj_patches.h"
#include "geometry/surfaces/bezier_patch.h"
#include "geometry/surfaces/bspline_surface.h"
#include "geometry/surfaces/trim_loops.h"
#include "geometry/surfaces/trimmed_surface.h"

namespace surfaced::api::operations {
namespace {

constexpr std::int64_t kDefaultSegments = 8;
constexpr std::string_view kBezMediaTypes[] = {"application/x-geomview-bez", "text/plain", "application/octet-stream"};
constexpr std::string_view kObjMediaType = "model/obj";  // free-form cstype [rat] bezier / bspline surfaces
//! GET /patches/{name}?format=patches: the sample's control points rather than a mesh (catalog.cpp lists it).
constexpr std::string_view kPatchesFormat = "patches";

std::string accepted_media_types() {
    std::string out = "application/json";
    for (std::string_view type : kBezMediaTypes) out += ", " + std::string(type);
    return out + ", " + std::string(kObjMediaType) + std::string(multipart_media_type_note());
}

//! The file types a POST /tessellate reads (for the file part of a form).
bool reads_patch_media_type(std::string_view media_type) {
    return media_type == "application/json" || media_type == kObjMediaType ||
           std::find(std::begin(kBezMediaTypes), std::end(kBezMediaTypes), media_type) != std::end(kBezMediaTypes);
}

ApiError invalid_parameter(const std::string& name, const std::string& detail) {
    return make_problem(Problem::InvalidField, "query parameter " + name + " " + detail, name);
}

//! Options from query parameters by the table of `operation`: "tessellate" (a raw BEZ or OBJ upload) or "patches"
//! (GET /patches/{name}); the same names as the JSON form.
ApiResult<TessellateParams> params_from_query(std::string_view operation,
                                              const std::multimap<std::string, std::string>& query) {
    auto values = options::read_query(*options::operation_options(operation), query);
    if (!values) return std::move(values.error());
    return tessellate_params(values.value());
}

//! What the option tables cannot say, for every request form, before any work: tolerance or segments, segments
//! against this server's limit, output options that do not fit the format. Field names: the JSON path or the
//! parameter name.
std::optional<ApiError> check_params(const TessellateParams& params, const Limits& limits, Source source) {
    if (params.tolerance && params.segments)
        return make_problem(Problem::InvalidField, "give either tolerance or segments, not both", "segments");
    if (params.segments && *params.segments > limits.max_patch_segments)
        return make_problem(Problem::BudgetExceeded,
                            "segments is " + std::to_string(*params.segments) + "; this server allows at most " +
                                std::to_string(limits.max_patch_segments) + " per patch direction",
                            "segments");
    return check_output_options(params.output, source);
}

TessellationOptions tessellation_options(const TessellateParams& params, const Limits& limits) {
    TessellationOptions options;
    options.tolerance = params.tolerance;
    options.segments = static_cast<int>(params.segments.value_or(kDefaultSegments));
    options.max_segments = limits.max_patch_segments;
    return options;
}

//! Where the patches of a JSON request came from: the first `direct` are "patches", then surface k's Bézier patches
//! start at surface_start[k].
struct PatchOrigins {
    std::size_t direct = 0;
    std::vector<std::size_t> surface_start;

    std::string field(std::size_t patch) const {
        if (patch < direct || surface_start.empty()) return "patches[" + std::to_string(patch) + "]";
        const auto next = std::upper_bound(surface_start.begin(), surface_start.end(), patch);
        return "surfaces[" + std::to_string(next - surface_start.begin() - 1) + "]";
    }
};

//! A GeoError from patch validation or planning, with the field it is about.
ApiError patch_error(const GeoError& error, const TessellateParams& params, Source source,
                     const PatchOrigins& origins) {
    ApiError out = from_geo_error(error);
    if (error.code == ErrorCode::BudgetExceeded) {
        out.field = params.tolerance ? "tolerance" : "segments";
    } else if (error.element >= 0 && source == Source::Json) {
        out.field = origins.field(static_cast<std::size_t>(error.element));
    }
    return out;
}

//! A trimmed surface to tessellate, with where it came from: the JSON field ("surfaces[2]") or the OBJ surf line.
struct TrimmedInput {
    TrimmedSurface trimmed;
    std::string field;
    std::int64_t line = 0;
};

//! An error about a trimmed surface, placed at its field (JSON) or line (OBJ); a budget at "tolerance".
ApiError trimmed_error(const GeoError& error, const TrimmedInput& input) {
    if (input.line > 0) {
        GeoError placed = error;
        placed.line = input.line;
        placed.message = "line " + std::to_string(input.line) + ": surf: " + error.message;
        return from_geo_error(placed);
    }
    ApiError out = from_geo_error(error);
    out.field = error.code == ErrorCode::BudgetExceeded ? "tolerance" : input.field;
    if (error.code != ErrorCode::BudgetExceeded) out.detail = input.field + ": " + out.detail;
    return out;
}

//! A trimmed surface whose guaranteed bound stayed above the tolerance (trimmed_surface.h: refinement stopped at its
//! limits, or the trim loops' gaps are wide for the model's size): 422 at its field or line, never a mesh out of
//! tolerance answered as a success.
ApiError tolerance_not_reached(const TrimmedTessellation& result, double tolerance, const TrimmedInput& input) {
    const double gaps = result.derivative_bound * result.max_gap;
    const bool gap_bound = gaps > tolerance / 20;  // the share trimmed_surface.h leaves them
    const std::string where = input.line > 0 ? "the surf at line " + std::to_string(input.line) : input.field;
    ApiError error = make_problem(
        Problem::BudgetExceeded,
        where + ": the guaranteed bound reached is " + format_double(result.bound) + ", above the tolerance " +
            format_double(tolerance) +
            (gap_bound ? ": gaps between its trim curves (up to " + format_double(result.max_gap) +
                             " in (u, v)) are up to " + format_double(gaps) + " on the surface"
                       : ": refinement stopped at its limits (" + std::to_string(result.refinement_points) +
                             " points inserted), as near a pole or another point where the surface's bound is weak"),
        input.line > 0 ? std::nullopt : std::optional<std::string>(input.field));
    if (input.line > 0) error.line = input.line;
    error.hint = gap_bound ? "close the trim loops more tightly (their curves' ends closer), or give a larger tolerance"
                           : "give a larger tolerance, or keep trims away from the surface's poles";
    return error;
}

//! What trimmed surfaces need from the options: a tolerance (the trimmed tessellator has no fixed segment count) and
//! a mesh format (format=patches lists Bézier patches, which carry no trim loops). `where` names the first trimmed
//! surface ("surfaces[1]", "the surf at line 12").
std::optional<ApiError> check_trimmed_params(const TessellateParams& params, const std::string& where) {
    if (params.patches_format) {
        ApiError error = from_geo_error(
            make_error(ErrorCode::Unsupported, "format=patches cannot carry trims: " + where +
                                                   " is trimmed, and Bézier patches have no trim loops (ask for a "
                                                   "mesh format, or send the surface without its trim)"));
        error.field = "format";
        return error;
    }
    if (params.segments)
        return make_problem(Problem::InvalidField,
                            where +
                                " is trimmed: trimmed surfaces are tessellated to a tolerance, not a number of "
                                "segments (give tolerance instead)",
                            "segments");
    if (!params.tolerance)
        return make_problem(Problem::InvalidField,
                            where + " is trimmed: trimmed surfaces need a tolerance (model units)", "tolerance");
    return std::nullopt;
}

//! The surfaces' Bézier patches appended to `set`, after checking what they will cost: the predicted patch count
//! against max_patches and their control points against max_input_vertices (O(knots) per surface, no allocation).
//! Trimmed surfaces (trims[k] set) count against the budgets but are left to the trimmed tessellator.
std::optional<ApiError> decompose_surfaces(const std::vector<BSplineSurface>& surfaces,
                                           const std::vector<std::optional<SurfaceTrim>>& trims, const Limits& limits,
                                           const Cancel& cancel, PatchSet& set, PatchOrigins& origins) {
    origins.direct = set.patches.size();
    std::uint64_t patches = set.patches.size(), points = 0;
    for (std::size_t k = 0; k < surfaces.size(); ++k) {
        const BSplineSurface& s = surfaces[k];
        const std::uint64_t count = bezier_patch_count(s);
        patches += count;
        points += count * static_cast<std::uint64_t>((s.degree_u + 1) * (s.degree_v + 1));
        const std::string field = "surfaces[" + std::to_string(k) + "]";
        if (patches > limits.max_patches)
            return make_problem(Problem::BudgetExceeded,
                                "the surfaces decompose into " + std::to_string(patches - set.patches.size()) +
                                    " Bézier patches or more (with " + std::to_string(set.patches.size()) +
                                    " given as patches); the limit is " + std::to_string(limits.max_patches),
                                field);
        if (points > limits.max_input_vertices)
            return make_problem(Problem::BudgetExceeded,
                                "the surfaces' Bézier patches would have " + std::to_string(points) +
                                    " control points or more; the limit is " +
                                    std::to_string(limits.max_input_vertices),
                                field);
    }
    set.patches.reserve(static_cast<std::size_t>(patches));
    for (std::size_t k = 0; k < surfaces.size(); ++k) {
        origins.surface_start.push_back(set.patches.size());  // a trimmed surface's range stays empty
        if (k < trims.size() && trims[k]) continue;
        auto decomposed = to_bezier(surfaces[k], cancel);
        if (!decomposed) {
            ApiError error = from_geo_error(decomposed.error());
            error.field = "surfaces[" + std::to_string(k) + "]";
            return error;
        }
        for (BezierPatch& patch : decomposed->patches) set.patches.push_back(std::move(patch));
    }
    return std::nullopt;
}

//! format=patches: the patches as the JSON POST /tessellate takes (a B-spline surface's Bézier decomposition).
ApiResponse patches_response(const PatchSet& set) {
    ApiResponse response;
    response.content_type = "application/json";
    response.body = patch_set_json(set);
    response.headers = {{"X-Patches", std::to_string(set.patches.size())}};
    return response;
}

//! Appends `part` to `mesh` (positions, normals, face-varying uvs, faces; both with normals and uvs or both without).
void append_mesh(PolygonMesh& mesh, const PolygonMesh& part) {
    const auto base = static_cast<Index>(mesh.positions.size());
    const auto uv_base = static_cast<Index>(mesh.uvs.size());
    const auto index_base = static_cast<Index>(mesh.face_indices.size());
    mesh.positions.insert(mesh.positions.end(), part.positions.begin(), part.positions.end());
    mesh.normals.insert(mesh.normals.end(), part.normals.begin(), part.normals.end());
    mesh.uvs.insert(mesh.uvs.end(), part.uvs.begin(), part.uvs.end());
    for (Index i : part.face_indices) mesh.face_indices.push_back(base + i);
    for (Index i : part.uv_indices) mesh.uv_indices.push_back(uv_base + i);
    for (std::size_t f = 1; f < part.face_offsets.size(); ++f)
        mesh.face_offsets.push_back(index_base + part.face_offsets[f]);
}

ApiError output_budget(std::uint64_t triangles, std::size_t patches, const TessellateParams& params,
                       const Limits& limits) {
    return make_problem(Problem::BudgetExceeded,
                        "tessellating " + std::to_string(patches) + " patches would produce up to " +
                            std::to_string(triangles) + " triangles; the limit is " +
                            std::to_string(limits.max_output_faces) +
                            (params.tolerance ? " (use a larger tolerance)" : " (use fewer segments)"),
                        params.tolerance ? "tolerance" : "segments");
}

//! Plan (budgets) -> tessellate -> encode. `start` is when the request started, for the timing headers. Trimmed
//! surfaces (their loops already validated) go to the trimmed tessellator with the request's tolerance; their meshes
//! follow the patches' in the output (not welded to them).
ApiResponse tessellate_and_encode(const PatchSet& set, const TessellateParams& params, const Limits& limits,
                                  Source source, Clock::time_point start, const Cancel& cancel,
                                  const PatchOrigins& origins = {}, const std::vector<TrimmedInput>& trimmed = {}) {
    TessellationOptions options = tessellation_options(params, limits);
    options.cancel = cancel;  // polled between patches
    std::uint64_t triangles = 0;
    std::size_t patch_count = set.patches.size();
    if (!set.patches.empty()) {
        auto plan = plan_tessellation(set.patches, options);
        if (!plan) return error_response(patch_error(plan.error(), params, source, origins));
        triangles = plan->triangles;
        if (triangles > limits.max_output_faces)
            return error_response(output_budget(triangles, patch_count, params, limits));
    }
    // a trimmed surface's own grid (before the trims remove and refine triangles) is its estimate
    for (const TrimmedInput& input : trimmed) {
        auto patches = to_bezier(input.trimmed.surface, cancel);
        if (!patches) return error_response(trimmed_error(patches.error(), input));
        auto plan = plan_tessellation(patches->patches, options);
        if (!plan) return error_response(trimmed_error(plan.error(), input));
        triangles += plan->triangles;
        patch_count += patches->patches.size();
        if (triangles > limits.max_output_faces)
            return error_response(output_budget(triangles, patch_count, params, limits));
    }
    const auto t_planned = Clock::now();

    PolygonMesh mesh;
    double error_bound = 0;
    if (!set.patches.empty()) {
        auto tessellated = tessellate_patches(set.patches, options);
        if (!tessellated) return error_response(patch_error(tessellated.error(), params, source, origins));
        mesh = std::move(tessellated->mesh);
        error_bound = tessellated->plan.error_bound;
    }
    for (const TrimmedInput& input : trimmed) {
        TrimmedTessellationOptions trim_options;
        trim_options.tolerance = *params.tolerance;
        trim_options.max_segments = limits.max_patch_segments;
        trim_options.max_trim_segments = kMaxTrimSegments;
        trim_options.max_triangles = static_cast<std::size_t>(limits.max_output_faces - mesh.face_count());
        trim_options.cancel = cancel;
        auto tessellated = surfaced::tessellate(input.trimmed, trim_options);
        if (!tessellated) return error_response(trimmed_error(tessellated.error(), input));
        if (tessellated->bound > *params.tolerance)
            return error_response(tolerance_not_reached(*tessellated, *params.tolerance, input));
        append_mesh(mesh, tessellated->mesh);
        error_bound = std::max(error_bound, tessellated->bound);
    }
    const auto t_tessellated = Clock::now();

    Headers headers = {
        {"X-Patches", std::to_string(patch_count)},
        {"X-Output-Vertices", std::to_string(mesh.vertex_count())},
        {"X-Output-Faces", std::to_string(mesh.face_count())},
        {"X-Error-Bound", format_double(error_bound)},
    };
    const double elapsed_ms = ms_between(start, t_tessellated);
    const auto encode_json = [&](const PolygonMesh& m) -> ApiResult<std::string> {
        const std::string stats =
            "{\"patches\":" + std::to_string(patch_count) + ",\"output_vertices\":" + std::to_string(m.vertex_count()) +
            ",\"output_faces\":" + std::to_string(m.face_count()) + ",\"error_bound\":" + format_double(error_bound) +
            ",\"elapsed_ms\":" + format_double(elapsed_ms) + "}";
        return encode_mesh_with_stats(m, stats);
    };
    // the tessellated mesh carries the patches' exact normals and (u, v): written unless normals is false
    return mesh_response(mesh, params.output, source, encode_json, std::move(headers),
                         Timing{start, {{"decode", t_planned}, {"tessellate", t_tessellated}}});
}

ApiResponse run_tessellate(const ApiRequest& sent, const ApiContext& context) {
    const Limits& limits = context.limits;
    const auto start = Clock::now();
    Upload upload;
    if (auto error = check_upload(sent, limits, accepted_media_types(), reads_patch_media_type, upload))
        return error_response(std::move(*error));
    const ApiRequest& request = *upload.request;
    const std::string& media_type = upload.media_type;
    if (media_type == "application/json") {
        if (!request.query.empty())
            return error_response(
                make_problem(Problem::UnknownParameter,
                             "query parameters are not accepted with a JSON body (options go in the body), got \"" +
                                 request.query.begin()->first + "\"",
                             request.query.begin()->first));
        auto decoded = decode_tessellate_request(request.body, limits);
        if (!decoded) return error_response(std::move(decoded.error()));
        if (auto error = negotiate_output_format(request, decoded->params.output))
            return error_response(std::move(*error));
        if (auto error = check_params(decoded->params, limits, Source::Json)) return error_response(std::move(*error));
        std::vector<TrimmedInput> trimmed;
        const auto first_trimmed = std::find_if(decoded->trims.begin(), decoded->trims.end(),
                                                [](const std::optional<SurfaceTrim>& t) { return t.has_value(); });
        if (first_trimmed != decoded->trims.end())
            if (auto error = check_trimmed_params(
                    decoded->params, "surfaces[" + std::to_string(first_trimmed - decoded->trims.begin()) + "]"))
                return error_response(std::move(*error));
        PatchOrigins origins;
        if (auto error = decompose_surfaces(decoded->surfaces, decoded->trims, limits, context.cancel, decoded->patches,
                                            origins))
            return error_response(std::move(*error));
        // every trim validated (validate_trims) before any tessellation: a broken rule is a 422 naming loop and curve
        std::size_t trim_segments = 0;
        for (std::size_t k = 0; k < decoded->trims.size(); ++k) {
            if (!decoded->trims[k]) continue;
            TrimmedInput input;
            input.field = "surfaces[" + std::to_string(k) + "]";
            input.trimmed.surface = std::move(decoded->surfaces[k]);
            input.trimmed.outer = std::move(decoded->trims[k]->outer);
            input.trimmed.holes = std::move(decoded->trims[k]->holes);
            TrimValidationOptions validation;
            validation.max_segments = kMaxTrimSegments - trim_segments;
            const TrimValidation valid = validate_trims(input.trimmed, validation);
            if (!valid.ok()) return error_response(trim_error(*valid.error, input.field + ".trim"));
            for (const TrimPolygon& loop : valid.trims.loops) trim_segments += loop.points.size();
            trimmed.push_back(std::move(input));
        }
        if (decoded->params.patches_format) {
            if (auto valid = validate(decoded->patches.patches); !valid)
                return error_response(patch_error(valid.error(), decoded->params, Source::Json, origins));
            return patches_response(decoded->patches);
        }
        return tessellate_and_encode(decoded->patches, decoded->params, limits, Source::Json, start, context.cancel,
                                     origins, trimmed);
    }
    const bool obj = media_type == kObjMediaType;
    if (!obj && std::find(std::begin(kBezMediaTypes), std::end(kBezMediaTypes), media_type) == std::end(kBezMediaTypes))
        return error_response(
            make_problem(Problem::UnsupportedMediaType,
                         "Content-Type \"" + media_type + "\" is not accepted; accepted: " + accepted_media_types()));
    // options first: a file is not parsed for a request we would refuse anyway
    auto params = params_from_query("tessellate", request.query);
    if (!params) return error_response(worded_for_form(request, std::move(params.error())));
    if (auto error = negotiate_output_format(request, params->output)) return error_response(std::move(*error));
    if (auto error = check_params(params.value(), limits, Source::File))
        return error_response(worded_for_form(request, std::move(*error)));
    Result<PatchSet> set = make_error(ErrorCode::Internal, "unread");
    std::vector<TrimmedInput> trimmed;
    if (obj) {
        ObjPatchReadOptions read_options;
        read_options.max_patches = static_cast<std::size_t>(limits.max_patches);
        read_options.max_vertices = static_cast<std::size_t>(limits.max_input_vertices);
        read_options.max_trim_loops = kMaxTrimLoops;
        read_options.max_trim_segments = kMaxTrimSegments;
        // the reader validates the trims (validate_trims), reporting a broken rule at its trim/hole line
        auto surfaces = read_obj_surfaces(request.body, read_options);
        if (!surfaces) return error_response(from_geo_error(surfaces.error()));
        for (ObjTrimmedSurface& t : surfaces->trimmed) trimmed.push_back({std::move(t.trimmed), std::string(), t.line});
        if (!trimmed.empty())
            if (auto error =
                    check_trimmed_params(params.value(), "the surf at line " + std::to_string(trimmed.front().line)))
                return error_response(worded_for_form(request, std::move(*error)));
        set = std::move(surfaces->patches);
    } else {
        BezReadOptions read_options;
        read_options.max_patches = static_cast<std::size_t>(limits.max_patches);
        set = read_bez(request.body, read_options);
    }
    if (!set) return error_response(from_geo_error(set.error()));
    if (params->patches_format) return patches_response(set.value());
    return tessellate_and_encode(set.value(), params.value(), limits, Source::File, start, context.cancel, {}, trimmed);
}

//! FNV-1a, 64 bit: a stable content hash for ETags (not security relevant).
std::uint64_t fnv1a(std::string_view bytes, std::uint64_t hash = 1469598103934665603ull) {
    for (unsigned char c : bytes) hash = (hash ^ c) * 1099511628211ull;
    return hash;
}

//! Whether an If-None-Match value ("*", or a comma-separated list of entity tags, weak or strong) matches `etag`
//! (RFC 9110 13.1.2 uses the weak comparison).
bool etag_matches(std::string_view if_none_match, std::string_view etag) {
    while (!if_none_match.empty()) {
        const std::size_t comma = if_none_match.find(',');
        std::string_view item = if_none_match.substr(0, comma);
        if_none_match.remove_prefix(comma == std::string_view::npos ? if_none_match.size() : comma + 1);
        while (!item.empty() && std::isspace(static_cast<unsigned char>(item.front()))) item.remove_prefix(1);
        while (!item.empty() && std::isspace(static_cast<unsigned char>(item.back()))) item.remove_suffix(1);
        if (item == "*") return true;
        if (item.starts_with("W/")) item.remove_prefix(2);
        if (item == etag) return true;
    }
    return false;
}

ApiResponse run_patch_sample(const ApiRequest& request, const ApiContext& context) {
    const auto start = Clock::now();
    const auto name_it = request.path_params.find("name");
    const std::string name = name_it == request.path_params.end() ? std::string() : name_it->second;
    const std::string_view text = patch_sample_text(name);
    if (text.empty()) {
        std::string available;
        for (std::string_view sample : patch_sample_names())
            available += (available.empty() ? "" : ", ") + std::string(sample);
        return error_response(make_problem(Problem::NotFound,
                                           "no built-in patch sample \"" + name + "\" (available: " + available + ")"));
    }
    auto params = params_from_query("patches", request.query);
    if (!params) return error_response(std::move(params.error()));
    if (auto error = negotiate_output_format(request, params->output)) return error_response(std::move(*error));
    // format=patches: the sample's control points (the body POST /tessellate accepts), for editors that show the
    // net. (read_query checked that format is given at most once and is one of the table's names.)
    const auto format_it = request.query.find("format");
    const bool control_points = format_it != request.query.end() && format_it->second == kPatchesFormat;
    if (control_points) {
        for (const auto& [option, value] : request.query)
            if (option != "format")
                return error_response(
                    invalid_parameter(option, "does not apply to format=patches (the control points, not a mesh)"));
    } else if (auto error = check_params(params.value(), context.limits, Source::File)) {
        return error_response(std::move(*error));
    }

    // The ETag covers everything the bytes depend on: sample data, normalised options, tessellator revision.
    const TessellateParams& p = params.value();
    std::string key = std::string(kPatchSampleRevision) + "|" + name;
    key += "|tolerance=" + (p.tolerance ? format_double(*p.tolerance) : std::string("-"));
    key += "|segments=" + std::to_string(p.segments.value_or(p.tolerance ? 0 : kDefaultSegments));
    key += "|format=" +
           (control_points ? std::string(kPatchesFormat) : std::string(enum_name(kOutputFormatNames, p.output.format)));
    key += "|draco=" + std::to_string(p.output.draco.value_or(true));
    key += "|quantize=" + std::to_string(p.output.quantize_position.value_or(0));
    key += "|normals=" + std::to_string(output_normals(p.output));
    char etag[24];
    std::snprintf(etag, sizeof etag, "\"%016llx\"", static_cast<unsigned long long>(fnv1a(text, fnv1a(key))));
    std::vector<std::pair<std::string, std::string>> cache_headers = {{"ETag", etag},
                                                                      {"Cache-Control", "public, max-age=3600"}};
    if (!p.output.format_given) cache_headers.emplace_back("Vary", "Accept");  // the format came from Accept

    if (etag_matches(request.header("if-none-match"), etag)) {
        ApiResponse not_modified;
        not_modified.status = 304;
        not_modified.content_type =
            control_points ? std::string("application/json") : std::string(output_media_type(p.output.format));
        not_modified.headers = cache_headers;
        return not_modified;
    }
    auto set = read_bez(text);
    if (!set) return error_response(make_problem(Problem::Internal, "built-in sample: " + set.error().message));
    if (control_points) {
        ApiResponse response;
        response.content_type = "application/json";
        response.body = patch_set_json(set.value());
        response.headers = cache_headers;
        return response;
    }
    ApiResponse response = tessellate_and_encode(set.value(), p, context.limits, Source::File, start, context.cancel);
    if (response.status == 200)
        response.headers.insert(response.headers.end(), cache_headers.begin(), cache_headers.end());
    return response;
}

}  // namespace

ApiResponse tessellate(const ApiRequest& request, const ApiContext& context) noexcept {
    return guarded([&] { return run_tessellate(request, context); });
}

ApiResponse patch_sample(const ApiRequest& request, const ApiContext& context) noexcept {
    return guarded([&] { return run_patch_sample(request, context); });
}

}  // namespace surfaced::api::operations
