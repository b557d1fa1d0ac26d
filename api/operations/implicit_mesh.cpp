#include "api/operations/implicit_mesh.h"

#include <cmath>
#include <string>

#include "api/json_codec.h"
#include "api/json_util.h"
#include "api/operations/request_forms.h"
#include "api/options/option_reader.h"
#include "api/scene_codec.h"
#include "geometry/implicit/mesh_field.h"

namespace surfaced::api::operations {
namespace {

using json::Json;

constexpr std::int64_t kDefaultResolution = 64;
//! Faces meeting at more than this many degrees get separate normals in GLB/glTF (split_normals_at_creases).
constexpr double kDefaultCreaseAngle = 40;

struct MeshRequest {
    std::shared_ptr<const implicit::Field> field;
    Box3 bounds;
    implicit::MeshFieldOptions options;
    bool cell_size_given = false;
    double crease_angle = kDefaultCreaseAngle;
    OutputOptions output;
};

std::string grid_text(const implicit::MeshFieldGrid& grid) {
    return std::to_string(grid.nx) + "x" + std::to_string(grid.ny) + "x" + std::to_string(grid.nz);
}

//! {"mesh": {"positions", "faces", "normals" (when the mesh has them)}, "stats": {...}}
std::string encode_json(const PolygonMesh& mesh, const implicit::MeshFieldStats& stats, double elapsed_ms) {
    Json stats_json = {
        {"grid", {stats.grid.nx, stats.grid.ny, stats.grid.nz}},
        {"grid_cells", stats.grid.cells},
        {"surface_cells", stats.surface_cells},
        {"field_evaluations", stats.field_evaluations},
        {"output_vertices", mesh.vertex_count()},
        {"output_faces", mesh.face_count()},
        {"elapsed_ms", elapsed_ms},
    };
    // the mesh as every endpoint writes it (json_codec), the stats with the same number printing
    return encode_mesh_with_stats(mesh, json_text(stats_json));
}

ApiResult<MeshRequest> decode(const ApiRequest& request, const Limits& limits, const Cancel& cancel) {
    Json root;
    if (auto error = json::parse(request.body, root)) return std::move(*error);
    if (!root.is_object()) return json::invalid("", "the body must be a JSON object");
    const auto& spec = *options::operation_options("implicit_mesh");
    if (auto error = json::check_members(root, "", options::json_members(spec))) return std::move(*error);
    auto values = options::read_json(spec, root);
    if (!values) return std::move(values.error());
    MeshRequest out;
    if (!root.contains("scene")) return json::invalid("scene", "scene is required");
    if (!root.contains("bounds")) return json::invalid("bounds", "bounds is required");
    auto bounds = parse_bounds(root["bounds"], "bounds");
    if (!bounds) return std::move(bounds.error());
    out.bounds = bounds.value();

    // grid size
    if (root.contains("resolution") && root.contains("cell_size"))
        return json::invalid("cell_size", "give either resolution or cell_size, not both");
    std::int64_t resolution = kDefaultResolution;
    values->get("resolution", resolution);
    out.options.resolution = static_cast<int>(resolution);
    out.cell_size_given = values->has("cell_size");
    if (out.cell_size_given) values->get("cell_size", out.options.cell_size);
    values->get("mode", kImplicitMeshModeNames, out.options.mode);
    values->get("simplify_tolerance", out.options.simplify_tolerance);
    if (out.options.simplify_tolerance > 0 && out.options.mode != implicit::MeshFieldMode::Adaptive)
        return json::invalid("simplify_tolerance", "simplify_tolerance applies only to mode \"adaptive\"");
    values->get("crease_angle", out.crease_angle);
    values->get_output(out.output);
    if (auto error = negotiate_output_format(request, out.output)) return std::move(*error);
    if (auto error = check_output_options(out.output, Source::Json)) return std::move(*error);

    // the grid against the budget, before the scene is even parsed
    const char* grid_field = out.cell_size_given ? "cell_size" : "resolution";
    out.options.max_cells = limits.max_grid_cells;
    auto grid = implicit::mesh_field_grid(out.bounds, out.options);
    if (!grid) {
        ApiError error = from_geo_error(grid.error());
        error.field = grid_field;
        if (grid.error().code == ErrorCode::BudgetExceeded)
            error.detail += out.cell_size_given ? " (use a larger cell_size or smaller bounds)"
                                                : " (use a lower resolution or smaller bounds)";
        return error;
    }

    auto field = parse_scene(root["scene"], limits, "scene", cancel);
    if (!field) return std::move(field.error());
    out.field = std::move(field.value());
    return out;
}

ApiResponse run(const ApiRequest& request, const ApiContext& context) {
    const Limits& limits = context.limits;
    const auto t_start = Clock::now();
    if (auto error = check_json_only_body(request, limits, "POST /implicit/mesh"))
        return error_response(std::move(*error));
    auto decoded = decode(request, limits, context.cancel);
    if (!decoded) return error_response(std::move(decoded.error()));
    MeshRequest& req = decoded.value();
    req.options.cancel = context.cancel;
    const auto t_decoded = Clock::now();

    implicit::MeshFieldStats stats;
    auto meshed = implicit::mesh_field(*req.field, req.bounds, req.options, &stats);
    if (!meshed) {
        ApiError error = from_geo_error(meshed.error());
        if (meshed.error().code == ErrorCode::BudgetExceeded || meshed.error().code == ErrorCode::InvalidArgument)
            error.field = req.cell_size_given ? "cell_size" : "resolution";
        return error_response(std::move(error));
    }
    PolygonMesh& mesh = meshed.value();
    if (mesh.face_count() > limits.max_output_faces)
        return error_response(make_problem(Problem::BudgetExceeded,
                                           "the mesh has " + std::to_string(mesh.face_count()) +
                                               " triangles; the limit is " + std::to_string(limits.max_output_faces) +
                                               " (use a lower resolution)",
                                           req.cell_size_given ? "cell_size" : "resolution"));
    // GLB/glTF with normals: vertices on sharp edges are split so each side is shaded with its own normal (the
    // positions stay identical, so the mesh welds back to the watertight one). OBJ and PLY write one normal per
    // vertex index, where a split would show as duplicate vertices: they keep the welded mesh and smooth normals.
    const bool gltf = req.output.format == OutputFormat::Glb || req.output.format == OutputFormat::Gltf;
    if (gltf && output_normals(req.output)) mesh = implicit::split_normals_at_creases(mesh, req.crease_angle);
    const auto t_meshed = Clock::now();

    ApiResponse response;
    response.content_type = std::string(output_media_type(req.output.format));
    const double mesh_ms = ms_between(t_start, t_meshed);
    auto encoded = encode_mesh_output(
        mesh, req.output, Source::Json,
        [&](const PolygonMesh& m) -> ApiResult<std::string> { return encode_json(m, stats, mesh_ms); });
    if (!encoded) return error_response(std::move(encoded.error()));
    response.body = std::move(encoded.value());
    const auto t_encoded = Clock::now();
    response.headers = {
        {"X-Grid", grid_text(stats.grid)},
        {"X-Grid-Cells", std::to_string(stats.grid.cells)},
        {"X-Surface-Cells", std::to_string(stats.surface_cells)},
        {"X-Field-Evaluations", std::to_string(stats.field_evaluations)},
        {"X-Output-Vertices", std::to_string(mesh.vertex_count())},
        {"X-Output-Faces", std::to_string(mesh.face_count())},
        {"X-Elapsed-Ms", format_ms(ms_between(t_start, t_encoded))},
        {"Server-Timing", "decode;dur=" + format_ms(ms_between(t_start, t_decoded)) +
                              ", mesh;dur=" + format_ms(ms_between(t_decoded, t_meshed)) +
                              ", encode;dur=" + format_ms(ms_between(t_meshed, t_encoded)) +
                              ", total;dur=" + format_ms(ms_between(t_start, t_encoded))},
    };
    return response;
}

}  // namespace

ApiResponse implicit_mesh(const ApiRequest& request, const ApiContext& context) noexcept {
    return guarded([&] { return run(request, context); });
}

}  // namespace surfaced::api::operations
