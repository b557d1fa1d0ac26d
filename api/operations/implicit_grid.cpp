// POST /implicit/grid (see implicit_grid.h): decode, check the node budget, sample, write the level_set node.
#include "api/operations/implicit_grid.h"

#include <memory>
#include <optional>
#include <string>

#include "api/json_codec.h"
#include "api/json_util.h"
#include "api/operations/request_forms.h"
#include "api/options/option_reader.h"
#include "api/scene_codec.h"
#include "geometry/implicit/distance_grid.h"
#include "geometry/io/number_text.h"

namespace surfaced::api::operations {
namespace {

using json::Json;

struct GridRequest {
    std::shared_ptr<const implicit::Field> field;  //!< the scene, or
    std::optional<PolygonMesh> mesh;               //!< the mesh
    implicit::DistanceGridOptions options;
};

ApiError node_budget(const GeoError& error) {
    ApiError out = from_geo_error(error);
    out.field = "voxel_size";
    if (error.code == ErrorCode::BudgetExceeded) out.detail += " (use a larger voxel_size or smaller bounds)";
    return out;
}

ApiResult<GridRequest> decode(const ApiRequest& request, const Limits& limits, const Cancel& cancel) {
    Json root;
    if (auto error = json::parse(request.body, root)) return std::move(*error);
    if (!root.is_object()) return json::invalid("", "the body must be a JSON object");
    const auto& spec = *options::operation_options("implicit_grid");
    if (auto error = json::check_members(root, "", options::json_members(spec))) return std::move(*error);
    auto values = options::read_json(spec, root);
    if (!values) return std::move(values.error());
    GridRequest out;
    const bool has_mesh = root.contains("mesh"), has_scene = root.contains("scene");
    if (!has_mesh && !has_scene) return json::invalid("mesh", "give a mesh or a scene");
    if (has_mesh && has_scene) return json::invalid("scene", "give either mesh or scene, not both");
    if (!values->has("voxel_size")) return json::invalid("voxel_size", "voxel_size is required");
    values->get("voxel_size", out.options.voxel_size);
    std::int64_t band = out.options.band;
    values->get("band", band);
    out.options.band = static_cast<int>(band);
    out.options.max_nodes = limits.max_level_set_samples;
    if (root.contains("bounds")) {
        auto bounds = parse_bounds(root["bounds"], "bounds");
        if (!bounds) return std::move(bounds.error());
        out.options.bounds = bounds.value();
    } else if (has_scene) {
        return json::invalid("bounds", "bounds is required with a scene");
    }
    // the node count before the input is decoded, when the bounds say it
    if (out.options.bounds) {
        auto layout =
            implicit::distance_grid_layout(*out.options.bounds, out.options.voxel_size, out.options.max_nodes);
        if (!layout) return node_budget(layout.error());
    }

    if (has_scene) {
        auto field = parse_scene(root["scene"], limits, "scene", cancel);
        if (!field) return std::move(field.error());
        out.field = std::move(field.value());
        return out;
    }
    auto mesh = decode_mesh(root["mesh"].dump(), limits, "mesh");
    if (!mesh) return std::move(mesh.error());
    if (auto error = check_mesh_input(mesh.value(), limits, Source::Json)) return std::move(*error);
    if (auto error = check_triangulated_budget(mesh.value(), limits)) return std::move(*error);
    if (mesh->face_count() == 0)
        return json::geometry_error(ErrorCode::InvalidArgument, "mesh.faces",
                                    "mesh.faces is empty: a mesh without faces has no surface to measure distances to");
    if (!out.options.bounds) {
        const Box3 bounds =
            implicit::default_distance_grid_bounds(mesh->bounds(), out.options.voxel_size, out.options.band);
        auto layout = implicit::distance_grid_layout(bounds, out.options.voxel_size, out.options.max_nodes);
        if (!layout) return node_budget(layout.error());
    }
    out.mesh = std::move(mesh.value());
    return out;
}

//! The level_set scene node of the grid: {"op", "dims", "origin", "spacing", "values"}.
std::string encode(const implicit::LevelSetGrid& grid) {
    std::string out;
    out.reserve(64 + grid.values.size() * 12);
    out += R"({"op":"level_set","dims":[)";
    for (std::size_t a = 0; a < 3; ++a) {
        if (a) out += ',';
        out += std::to_string(grid.dims[a]);
    }
    out += R"(],"origin":[)";
    for (int a = 0; a < 3; ++a) {
        if (a) out += ',';
        append_number_text(out, grid.origin[a]);
    }
    out += R"(],"spacing":)";
    append_number_text(out, grid.spacing.x);
    out += R"(,"values":[)";
    for (std::size_t i = 0; i < grid.values.size(); ++i) {
        if (i) out += ',';
        append_number_text(out, grid.values[i]);
    }
    out += "]}";
    return out;
}

ApiResponse run(const ApiRequest& request, const ApiContext& context) {
    const Limits& limits = context.limits;
    const auto t_start = Clock::now();
    if (auto error = check_json_only_body(request, limits, "POST /implicit/grid"))
        return error_response(std::move(*error));
    auto decoded = decode(request, limits, context.cancel);
    if (!decoded) return error_response(std::move(decoded.error()));
    GridRequest& req = decoded.value();
    req.options.cancel = context.cancel;
    const auto t_decoded = Clock::now();

    implicit::DistanceGridStats stats;
    auto grid = req.mesh ? implicit::mesh_distance_grid(*req.mesh, req.options, &stats)
                         : implicit::field_distance_grid(*req.field, req.options, &stats);
    if (!grid) {
        const GeoError& error = grid.error();
        if (error.code == ErrorCode::BudgetExceeded) return error_response(node_budget(error));
        if (req.mesh) return error_response(geometry_error(error, Source::Json));
        ApiError out = from_geo_error(error);
        if (error.code == ErrorCode::NonFinite) out.field = "scene";
        return error_response(std::move(out));
    }
    const auto t_sampled = Clock::now();
    if (auto error = check_deadline_before_encoding(context.cancel)) return error_response(std::move(*error));

    ApiResponse response;
    response.content_type = "application/json";
    response.body = encode(grid.value());
    const auto t_encoded = Clock::now();
    const auto& dims = stats.layout.dims;
    response.headers = {
        {"X-Grid", std::to_string(dims[0]) + "x" + std::to_string(dims[1]) + "x" + std::to_string(dims[2])},
        {"X-Grid-Nodes", std::to_string(stats.layout.nodes)},
        {"X-Band-Nodes", std::to_string(stats.band_nodes)},
    };
    response.headers.emplace_back("X-Winding-Queries", std::to_string(stats.winding_queries));
    response.headers.emplace_back("X-Field-Evaluations", std::to_string(stats.field_evaluations));
    response.headers.emplace_back("X-Elapsed-Ms", format_ms(ms_between(t_start, t_encoded)));
    response.headers.emplace_back("Server-Timing", "decode;dur=" + format_ms(ms_between(t_start, t_decoded)) +
                                                       ", grid;dur=" + format_ms(ms_between(t_decoded, t_sampled)) +
                                                       ", encode;dur=" + format_ms(ms_between(t_sampled, t_encoded)) +
                                                       ", total;dur=" + format_ms(ms_between(t_start, t_encoded)));
    return response;
}

}  // namespace

ApiResponse implicit_grid(const ApiRequest& request, const ApiContext& context) noexcept {
    return guarded([&] { return run(request, context); });
}

}  // namespace surfaced::api::operations
