// POST /reconstruct (see reconstruct.h): decode the cloud as POST /pointcloud does, check the budgets, estimate
// normals when needed, reconstruct, encode the mesh as the other mesh endpoints do.
#include "api/operations/reconstruct.h"

#include <cstdint>
#include <optional>
#include <string>

#include "api/json_codec.h"
#include "api/json_util.h"
#include "api/operations/point_input.h"
#include "api/operations/request_forms.h"
#include "api/options/option_reader.h"
#include "geometry/pointcloud/confidence.h"
#include "geometry/pointcloud/point_cloud.h"
#include "geometry/reconstruct/trim.h"
#include "geometry/reconstruct/vertex_colors.h"

namespace surfaced::api::operations {
namespace {

using json::Json;

struct Params {
    PoissonOptions poisson;
    NormalEstimation estimate = NormalEstimation::Auto;
    std::int64_t k = 16;
    bool k_given = false;
    TrimOptions trim;                   //!< trim 0: not trimmed
    std::optional<bool> vertex_colors;  //!< unset: when the cloud has colours and the format holds them
    OutputOptions output;
};

const options::OperationOptions& reconstruct_options() { return *options::operation_options("reconstruct"); }

//! The formats that carry vertex colours: glTF (COLOR_0), PLY (uchar red green blue), OBJ (`v x y z r g b`) and the
//! JSON answer.
bool colors_format(OutputFormat format) {
    return format == OutputFormat::Glb || format == OutputFormat::Gltf || format == OutputFormat::Ply ||
           format == OutputFormat::Obj || format == OutputFormat::Json;
}

Params params_from(const options::OptionValues& values) {
    Params params;
    std::int64_t depth = params.poisson.depth;
    values.get("depth", depth);
    params.poisson.depth = static_cast<int>(depth);
    values.get("point_weight", params.poisson.point_weight);
    values.get("samples_per_node", params.poisson.samples_per_node);
    values.get("boundary", kPoissonBoundaryNames, params.poisson.boundary);
    values.get("scale", params.poisson.scale);
    values.get("fit_to_samples", params.poisson.fit_to_samples);
    values.get("confidence", params.poisson.use_confidence);
    values.get("estimate_normals", kNormalEstimationNames, params.estimate);
    values.get("k", params.k);
    params.k_given = values.has("k");
    values.get("trim", params.trim.trim);
    values.get("island_area", params.trim.island_area);
    params.trim.samples_per_node = params.poisson.samples_per_node;
    values.get("vertex_colors", params.vertex_colors);
    std::int64_t threads = params.poisson.threads;
    values.get("threads", threads);
    params.poisson.threads = static_cast<int>(threads);
    values.get_output(params.output);
    return params;
}

//! What the table cannot say: k goes with estimation, output options that do not fit the format.
std::optional<ApiError> check_params(const Params& params, Source source) {
    if (params.k_given && params.estimate == NormalEstimation::Never)
        return make_problem(Problem::InvalidField,
                            "k applies only when normals are estimated (estimate_normals auto "
                            "or always)",
                            "k");
    if (params.vertex_colors.value_or(false) && !colors_format(params.output.format))
        return make_problem(Problem::InvalidField,
                            "vertex colours are written in glb, gltf, ply, obj and json output, not in " +
                                std::string(enum_name(kOutputFormatNames, params.output.format)),
                            "vertex_colors");
    return check_output_options(params.output, source);
}

//! A decoded request: where it came from, the options and the cloud.
struct Decoded {
    Source source = Source::File;
    Params params;
    PointCloud cloud;
};

std::optional<ApiError> decode_json_request(const ApiRequest& request, const ApiContext& context, Decoded& d) {
    d.source = Source::Json;
    if (auto error = reject_query_with_json(request)) return error;
    Json root;
    if (auto error = json::parse(request.body, root)) return error;
    if (!root.is_object())
        return json::invalid("", R"(the body must be a JSON object {"points": [[x,y,z],...], "depth": 8, ...})");
    if (auto error = json::check_members(root, "", options::json_members(reconstruct_options()))) return error;
    auto values = options::read_json(reconstruct_options(), root);
    if (!values) return std::move(values.error());
    d.params = params_from(values.value());
    if (auto error = negotiate_output_format(request, d.params.output)) return error;
    if (auto error = check_params(d.params, d.source)) return error;
    if (!root.contains("points"))
        return json::invalid("points", R"(points is required: [[x, y, z], ...], with "normals" and "colors" optional)");
    auto points = decode_json_points(root, context.limits, d.params.poisson.use_confidence);
    if (!points) return std::move(points.error());
    d.cloud = std::move(points.value());
    return std::nullopt;
}

//! A point file as the body, the options in the query (or the fields of a form): the format and the options are
//! checked before the file is read.
std::optional<ApiError> decode_file_request(const ApiRequest& request, const ApiContext& context,
                                            const std::string& media_type, Decoded& d) {
    auto format = uploaded_point_format(media_type, request.body);
    if (!format) return std::move(format.error());
    auto values = options::read_query(reconstruct_options(), request.query);
    if (!values) return worded_for_form(request, std::move(values.error()));
    d.params = params_from(values.value());
    if (auto error = negotiate_output_format(request, d.params.output)) return error;
    if (auto error = check_params(d.params, d.source)) return worded_for_form(request, std::move(*error));
    auto read = read_uploaded_points(request.body, format.value(), context.limits);
    if (!read) return std::move(read.error());
    d.cloud = std::move(read.value());
    return std::nullopt;
}

//! The budgets on depth alone (the configured limit and the mesher's grid), before the cloud is read.
std::optional<ApiError> check_depth_budget(const PoissonOptions& options, const Limits& limits) {
    if (options.depth > limits.max_reconstruct_depth)
        return make_problem(Problem::BudgetExceeded,
                            "depth " + std::to_string(options.depth) + " is over the limit of " +
                                std::to_string(limits.max_reconstruct_depth),
                            "depth");
    // The finest grid, (2^depth)^3 cells, is held to the grid-cell limit as the implicit mesher's grid is: the
    // extraction visits only the cells the surface crosses, but the work and memory still grow 4-8x per level.
    const std::uint64_t side = std::uint64_t{1} << options.depth;
    const std::uint64_t grid = side * side * side;
    if (grid > limits.max_grid_cells)
        return make_problem(Problem::BudgetExceeded,
                            "depth " + std::to_string(options.depth) + " has a finest grid of " + std::to_string(grid) +
                                " cells (2^depth per side); the grid-cell limit is " +
                                std::to_string(limits.max_grid_cells),
                            "depth");
    return std::nullopt;
}

//! The predicted peak memory for this many points (estimate_poisson), before any work.
std::optional<ApiError> check_memory_budget(std::size_t points, const PoissonOptions& options, const Limits& limits) {
    const PoissonEstimate estimate = estimate_poisson(points, options);
    if (estimate.bytes > limits.max_reconstruct_bytes)
        return make_problem(Problem::BudgetExceeded,
                            "depth " + std::to_string(options.depth) + " with " + std::to_string(points) +
                                " points predicts " + std::to_string(estimate.bytes) + " bytes (" +
                                std::to_string(estimate.octree_cells) + " octree cells); the limit is " +
                                std::to_string(limits.max_reconstruct_bytes) + " bytes",
                            "depth");
    return std::nullopt;
}

//! A reconstruction error: options and samples name their field, the rest as geometry says.
ApiError reconstruction_error(const GeoError& error, Source source) {
    ApiError out = point_error(error, source);
    if (error.code == ErrorCode::InvalidArgument && !out.field) out.field = "points";
    return out;
}

ApiResponse run(const ApiRequest& sent, const ApiContext& context) {
    const Limits& limits = context.limits;
    const auto t_start = Clock::now();
    Upload upload;
    if (auto error = check_upload(sent, limits, kPointMediaTypes, reads_point_media_type, upload))
        return error_response(std::move(*error));
    const ApiRequest& request = *upload.request;
    const std::string& media_type = upload.media_type;

    // 1. the options, the budgets on depth, then the cloud (within max_points) and the budget on its size
    Decoded d;
    auto decode_error = media_type == "application/json" ? decode_json_request(request, context, d)
                                                         : decode_file_request(request, context, media_type, d);
    if (decode_error) return error_response(std::move(*decode_error));
    const auto t_decoded = Clock::now();
    Params& params = d.params;
    if (auto error = check_depth_budget(params.poisson, limits)) return error_response(std::move(*error));
    if (auto error = check_memory_budget(d.cloud.size(), params.poisson, limits))
        return error_response(std::move(*error));
    if (Status s = validate(d.cloud); !s) return error_response(point_error(s.error(), d.source));

    // 2. normals: estimated and oriented when missing (auto) or always; refused when missing and never
    const std::size_t input_points = d.cloud.size();
    const bool estimate = params.estimate == NormalEstimation::Always ||
                          (params.estimate == NormalEstimation::Auto && !d.cloud.has_normals());
    if (!estimate && !d.cloud.has_normals()) {
        ApiError error = from_geo_error(
            make_error(ErrorCode::InvalidArgument, "the cloud has no normals and estimate_normals is never"));
        if (d.source == Source::Json) error.field = "normals";
        error.hint = "estimate_normals=auto estimates and orients them from the k nearest neighbours";
        return error_response(std::move(error));
    }
    if (estimate) {
        if (auto error =
                estimate_point_normals(d.cloud, params.k, limits, context.cancel, d.source, "k", std::string("points")))
            return error_response(std::move(*error));
    }
    // a PLY cloud's per-point confidence becomes the normals' lengths, which confidence weighs the points by
    const bool confidence_property = params.poisson.use_confidence && d.cloud.has_confidence();
    if (confidence_property)
        if (Status s = weight_normals_by_confidence(d.cloud); !s)
            return error_response(point_error(s.error(), d.source));
    const auto t_normals = Clock::now();

    // 3. reconstruct (polls the request's Cancel)
    auto reconstructed = reconstruct_poisson(d.cloud, params.poisson, context.cancel);
    if (!reconstructed) return error_response(reconstruction_error(reconstructed.error(), d.source));
    PoissonResult& result = reconstructed.value();
    const auto t_reconstructed = Clock::now();

    // 4. trim where the samples do not support the surface
    std::optional<TrimReport> trimmed;
    if (params.trim.trim > 0) {
        auto report = trim_reconstruction(result.mesh, d.cloud, result, params.trim, context.cancel);
        if (!report) {
            ApiError error = from_geo_error(report.error());
            if (report.error().code == ErrorCode::InvalidArgument) error.field = "trim";
            return error_response(std::move(error));
        }
        trimmed = report.value();
        if (result.mesh.face_count() == 0) {
            ApiError error =
                from_geo_error(make_error(ErrorCode::InvalidArgument,
                                          "trim " + format_double(params.trim.trim) +
                                              " removes the whole surface; the typical density on the scanned surface "
                                              "is " +
                                              format_double(trimmed->sample_density)));
            error.field = "trim";
            error.hint = "a trim 0.3 to 1 below the typical density cuts only where the samples end";
            return error_response(std::move(error));
        }
    }
    // 5. the samples' colours carried to the vertices (after trimming, which renumbers them)
    std::vector<Color> colors;
    if (params.vertex_colors.value_or(d.cloud.has_colors() && colors_format(params.output.format))) {
        if (!d.cloud.has_colors()) {
            ApiError error = from_geo_error(make_error(ErrorCode::InvalidArgument, "the cloud has no colours"));
            error.field = "vertex_colors";
            return error_response(std::move(error));
        }
        auto transferred = transfer_colors(result.mesh, d.cloud, {}, context.cancel);
        if (!transferred) return error_response(from_geo_error(transferred.error()));
        colors = std::move(transferred.value());
    }
    const auto t_trimmed = Clock::now();
    if (auto error = check_deadline_before_encoding(context.cancel)) return error_response(std::move(*error));

    // 5. encode
    std::size_t octree_cells = 0;
    for (std::size_t cells : result.stats.cells) octree_cells += cells;
    Json stats = {
        {"input_points", input_points},
        {"output_vertices", result.mesh.vertex_count()},
        {"output_faces", result.mesh.face_count()},
        {"normals_estimated", estimate},
        {"depth", params.poisson.depth},
        {"iso_value", result.iso_value},
        {"octree_cells", octree_cells},
        {"cells_per_level", result.stats.cells},
        {"iterations_per_level", result.stats.iterations},
        {"area_estimate", result.stats.area_estimate},
        {"cube",
         {{"origin", {result.cube_origin.x, result.cube_origin.y, result.cube_origin.z}}, {"size", result.cube_size}}},
        {"elapsed_ms", ms_between(t_start, t_trimmed)}};
    if (trimmed)
        stats["trim"] = {{"faces_removed", trimmed->faces_removed},
                         {"islands_removed", trimmed->islands_removed},
                         {"sample_density", trimmed->sample_density},
                         {"min_density", trimmed->min_density},
                         {"max_density", trimmed->max_density}};
    Headers headers = {
        {"X-Input-Points", std::to_string(input_points)},
        {"X-Output-Vertices", std::to_string(result.mesh.vertex_count())},
        {"X-Output-Faces", std::to_string(result.mesh.face_count())},
        {"X-Normals-Estimated", estimate ? "true" : "false"},
        {"X-Depth", std::to_string(params.poisson.depth)},
        {"X-Iso-Value", format_double(result.iso_value)},
        {"X-Octree-Cells", std::to_string(octree_cells)},
        {"X-Colors", colors.empty() ? "false" : "true"},
        {"X-Confidence", confidence_property             ? "property"
                         : params.poisson.use_confidence ? "normals"
                                                         : "none"},
    };
    if (trimmed)
        headers.insert(headers.end(), {{"X-Trimmed-Faces", std::to_string(trimmed->faces_removed)},
                                       {"X-Islands-Removed", std::to_string(trimmed->islands_removed)},
                                       {"X-Sample-Density", format_double(trimmed->sample_density)}});
    Timing timing{
        t_start,
        {{"decode", t_decoded}, {"normals", t_normals}, {"reconstruct", t_reconstructed}, {"trim", t_trimmed}}};
    const auto encode_json = [&](const PolygonMesh& m) {
        std::string out = encode_mesh_with_stats(m, json_text(stats));
        if (colors.empty()) return out;
        // {"mesh": ..., "colors": [[r, g, b(, a)], ...], "stats": ...}: the stats are the last member
        Json list = Json::array();
        for (const Color& c : colors) {
            Json rgb = Json::array({c.r, c.g, c.b});
            if (d.cloud.has_alpha) rgb.push_back(c.a);
            list.push_back(std::move(rgb));
        }
        const auto at = out.rfind(",\"stats\":");
        return out.substr(0, at) + ",\"colors\":" + json_text(list) + out.substr(at);
    };
    return mesh_response(result.mesh, params.output, d.source, encode_json, std::move(headers), std::move(timing),
                         {colors, d.cloud.has_alpha});
}

}  // namespace

ApiResponse reconstruct(const ApiRequest& request, const ApiContext& context) noexcept {
    return guarded([&] { return run(request, context); });
}

}  // namespace surfaced::api::operations
