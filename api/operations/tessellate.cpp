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
#include "geometry/io/bez.h"
#include "geometry/io/gltf.h"
#include "geometry/io/mesh_io.h"
#include "geometry/io/obj_patches.h"
#include "geometry/surfaces/bezier_patch.h"
#include "geometry/surfaces/bspline_surface.h"

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

//! The surfaces' Bézier patches appended to `set`, after checking what they will cost: the predicted patch count
//! against max_patches and their control points against max_input_vertices (O(knots) per surface, no allocation).
std::optional<ApiError> decompose_surfaces(const std::vector<BSplineSurface>& surfaces, const Limits& limits,
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
        origins.surface_start.push_back(set.patches.size());
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

//! Plan (budgets) -> tessellate -> encode. `start` is when the request started, for the timing headers.
ApiResponse tessellate_and_encode(const PatchSet& set, const TessellateParams& params, const Limits& limits,
                                  Source source, Clock::time_point start, const Cancel& cancel,
                                  const PatchOrigins& origins = {}) {
    TessellationOptions options = tessellation_options(params, limits);
    options.cancel = cancel;  // polled between patches
    auto plan = plan_tessellation(set.patches, options);
    if (!plan) return error_response(patch_error(plan.error(), params, source, origins));
    if (plan->triangles > limits.max_output_faces)
        return error_response(
            make_problem(Problem::BudgetExceeded,
                         "tessellating " + std::to_string(set.patches.size()) + " patches would produce up to " +
                             std::to_string(plan->triangles) + " triangles; the limit is " +
                             std::to_string(limits.max_output_faces) +
                             (params.tolerance ? " (use a larger tolerance)" : " (use fewer segments)"),
                         params.tolerance ? "tolerance" : "segments"));
    const auto t_planned = Clock::now();

    auto tessellated = tessellate_patches(set.patches, options);
    if (!tessellated) return error_response(patch_error(tessellated.error(), params, source, origins));
    PolygonMesh& mesh = tessellated->mesh;
    const auto t_tessellated = Clock::now();

    Headers headers = {
        {"X-Patches", std::to_string(set.patches.size())},
        {"X-Output-Vertices", std::to_string(mesh.vertex_count())},
        {"X-Output-Faces", std::to_string(mesh.face_count())},
        {"X-Error-Bound", format_double(tessellated->plan.error_bound)},
    };
    const double error_bound = tessellated->plan.error_bound;
    const double elapsed_ms = ms_between(start, t_tessellated);
    const auto encode_json = [&](const PolygonMesh& m) -> ApiResult<std::string> {
        const std::string stats = "{\"patches\":" + std::to_string(set.patches.size()) +
                                  ",\"output_vertices\":" + std::to_string(m.vertex_count()) +
                                  ",\"output_faces\":" + std::to_string(m.face_count()) +
                                  ",\"error_bound\":" + format_double(error_bound) +
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
        PatchOrigins origins;
        if (auto error = decompose_surfaces(decoded->surfaces, limits, context.cancel, decoded->patches, origins))
            return error_response(std::move(*error));
        if (decoded->params.patches_format) {
            if (auto valid = validate(decoded->patches.patches); !valid)
                return error_response(patch_error(valid.error(), decoded->params, Source::Json, origins));
            return patches_response(decoded->patches);
        }
        return tessellate_and_encode(decoded->patches, decoded->params, limits, Source::Json, start, context.cancel,
                                     origins);
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
    if (obj) {
        ObjPatchReadOptions read_options;
        read_options.max_patches = static_cast<std::size_t>(limits.max_patches);
        read_options.max_vertices = static_cast<std::size_t>(limits.max_input_vertices);
        set = read_obj_patches(request.body, read_options);
    } else {
        BezReadOptions read_options;
        read_options.max_patches = static_cast<std::size_t>(limits.max_patches);
        set = read_bez(request.body, read_options);
    }
    if (!set) return error_response(from_geo_error(set.error()));
    if (params->patches_format) return patches_response(set.value());
    return tessellate_and_encode(set.value(), params.value(), limits, Source::File, start, context.cancel);
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
