#include "api/operations/simplify.h"

#include <algorithm>
#include <charconv>
#include <cstddef>
#include <cstdint>
#include <string>
#include <system_error>
#include <vector>

#include "api/dto.h"
#include "api/json_codec.h"
#include "api/operations/mesh_repair.h"
#include "api/operations/request_forms.h"
#include "geometry/core/block_pool.h"
#include "geometry/simplify/mesh_distance.h"
#include "geometry/simplify/qem.h"

namespace surfaced::api::operations {
namespace {

//! The most memory the simplification pool keeps between requests; beyond it the oldest blocks returned are freed.
constexpr std::size_t kSimplifyPoolBytes = std::size_t{64} << 20;

//! The process's pool for simplify_qem's large arrays (SimplifyOptions::block_pool): the service simplifies one
//! request after another, so each one reuses the blocks of the last ones, whose pages are already faulted in, shared
//! by all worker threads so that what is kept does not grow with their number. Never destroyed: a block may still be
//! returned by a thread that outlives static destruction.
BlockPool& simplify_block_pool() {
    static BlockPool& pool = *new BlockPool(kSimplifyPoolBytes);
    return pool;
}

//! "0,5,100": vertex indices, comma-separated (empty: none). Each must be a non-negative integer; whether it names a
//! vertex is checked once the mesh is read (check_locked_vertices).
std::optional<ApiError> read_locked_vertices(const std::string& text, std::vector<std::int64_t>& out) {
    out.clear();
    if (text.empty()) return std::nullopt;
    for (std::size_t start = 0, k = 0;; ++k) {
        const std::size_t comma = std::min(text.find(',', start), text.size());
        const std::string item = text.substr(start, comma - start);
        const std::string field = "locked_vertices[" + std::to_string(k) + "]";
        std::int64_t value = -1;
        const auto parsed = std::from_chars(item.data(), item.data() + item.size(), value);
        if (item.empty() || parsed.ec != std::errc() || parsed.ptr != item.data() + item.size() || value < 0)
            return make_problem(Problem::InvalidField,
                                "query parameter locked_vertices: item " + std::to_string(k) + " (\"" + item +
                                    "\") must be a non-negative integer vertex index (locked_vertices=0,5,100)",
                                field);
        out.push_back(value);
        if (comma == text.size()) return std::nullopt;
        start = comma + 1;
    }
}

//! Every locked vertex must be a vertex of the mesh (422 naming locked_vertices[k]). Triangulation keeps the vertices
//! and their order, so the indices mean the same after it.
std::optional<ApiError> check_locked_vertices(const std::vector<std::int64_t>& locked, const PolygonMesh& mesh) {
    const std::size_t nv = mesh.vertex_count();
    for (std::size_t k = 0; k < locked.size(); ++k)
        if (locked[k] < 0 || static_cast<std::uint64_t>(locked[k]) >= nv) {
            const std::string field = "locked_vertices[" + std::to_string(k) + "]";
            ApiError error = from_geo_error(make_error(
                ErrorCode::IndexOutOfRange, field + ": vertex " + std::to_string(locked[k]) + " out of range (" +
                                                std::to_string(nv) + (nv == 1 ? " vertex)" : " vertices)")));
            error.field = field;
            return error;
        }
    return std::nullopt;
}

ApiResult<SimplifyParams> params_from_query(const std::multimap<std::string, std::string>& query) {
    if (auto error = check_query_names(
            query, {"target_faces", "ratio", "max_error", "lock_border", "restore_volume", "threads", "report_error",
                    "locked_vertices", "repair", "format", "compression", "quantize_position", "normals"}))
        return std::move(*error);

    SimplifyParams params;
    for (const auto& [name, text] : query) {
        std::optional<ApiError> error;
        if (name == "target_faces")
            error = read_parameter(name, text, params.target_faces);
        else if (name == "ratio")
            error = read_parameter(name, text, params.ratio);
        else if (name == "max_error")
            error = read_parameter(name, text, params.max_error);
        else if (name == "lock_border")
            error = read_parameter(name, text, params.lock_border);
        else if (name == "restore_volume")
            error = read_parameter(name, text, params.restore_volume);
        else if (name == "threads")
            error = read_parameter(name, text, params.threads);
        else if (name == "report_error")
            error = read_parameter(name, text, params.report_error);
        else if (name == "repair")
            error = read_parameter(name, text, kRepairModeNames, params.repair);
        else if (name == "locked_vertices")
            error = read_locked_vertices(text, params.locked_vertices);
        else if (auto output = parse_output_parameter(name, text, params.output); !output)
            error = std::move(output.error());
        if (error) return std::move(*error);
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
    if (!(params.restore_volume >= 0 && params.restore_volume <= 1))
        return make_problem(Problem::InvalidField,
                            "restore_volume must be in [0, 1], got " + format_double(params.restore_volume),
                            "restore_volume");
    if (params.threads != 1 && params.threads != 2)
        return make_problem(Problem::InvalidField, "threads must be 1 or 2, got " + std::to_string(params.threads),
                            "threads");
    return check_output_options(params.output, source);
}

//! The options for simplifying `mesh`: `input` itself, or its repair, into which the locked vertices follow their
//! positions (one whose every face repair dropped has nothing left to keep).
SimplifyOptions simplify_options(const SimplifyParams& params, const PolygonMesh& input, const PolygonMesh& mesh,
                                 const Cancel& cancel) {
    SimplifyOptions options;
    if (params.target_faces) options.target_faces = static_cast<std::size_t>(*params.target_faces);
    options.ratio = params.ratio;
    options.max_error = params.max_error;
    options.lock_border = params.lock_border;
    options.restore_volume = params.restore_volume;
    options.threads = static_cast<int>(params.threads);
    const std::vector<Index> locked =
        &mesh == &input ? std::vector<Index>(params.locked_vertices.begin(), params.locked_vertices.end())
                        : vertices_by_position(input, mesh, params.locked_vertices);  // indices checked against input
    for (Index v : locked)
        if (v != kInvalidIndex) options.locked_vertices.push_back(v);
    options.cancel = cancel;
    options.block_pool = &simplify_block_pool();
    return options;
}

ApiResponse run(const ApiRequest& request, const ApiContext& context) {
    const Limits& limits = context.limits;
    const auto t_start = Clock::now();

    // 1-3. size and media type, options and mesh (for uploads the options are checked before the file is parsed),
    // budgets and validity, before any work
    // (read as leniently as /subdivide reads: what repair "none" refuses is refused by run_with_repair)
    auto decoded = decode_mesh_request<SimplifyParams>(request, limits, decode_simplify_request, params_from_query,
                                                       check_params, MeshRules::Subdivision);
    if (!decoded) return error_response(std::move(decoded.error()));
    auto& [source, params, input, t_decoded, read_report] = decoded.value();
    if (auto error = check_triangulated_budget(input, limits)) return error_response(std::move(*error));
    if (auto error = check_locked_vertices(params.locked_vertices, input)) return error_response(std::move(*error));

    // 4. simplify, repaired first when it must be (repair "auto")
    std::optional<PolygonMesh> repaired;
    std::optional<RepairReport> repairs;
    // named references: clang 14 does not let a lambda capture structured bindings
    const SimplifyParams& wanted = params;
    const PolygonMesh& sent = input;
    auto simplified =
        run_with_repair(input, params.repair, source, context.cancel, repaired, repairs, [&](const PolygonMesh& mesh) {
            return simplify_qem(mesh, simplify_options(wanted, sent, mesh, context.cancel));
        });
    if (!simplified) return error_response(std::move(simplified.error()));
    if (auto error = check_deadline_before_encoding(context.cancel)) return error_response(std::move(*error));
    SimplifyResult& result = simplified.value();
    const auto t_simplified = Clock::now();

    SimplifyStats stats;
    stats.input_vertices = input.vertex_count();
    stats.input_faces = input.face_count();
    stats.repairs = repairs;
    stats.output_vertices = result.mesh.vertex_count();
    stats.output_faces = result.faces;
    stats.triangulated = result.triangulated;
    stats.achieved_error = result.achieved_error;
    stats.relative_error = result.relative_error;
    if (params.report_error) {
        const MeshDistance distance = mesh_distance(input, result.mesh);
        stats.hausdorff = distance.hausdorff;
        stats.rms = distance.rms;
    }
    const auto t_measured = Clock::now();
    stats.elapsed_ms = ms_between(t_start, t_measured);

    // 5. encode
    Headers headers =
        mesh_count_headers(stats.input_vertices, stats.input_faces, stats.output_vertices, stats.output_faces);
    append_read_headers(headers, read_report);
    headers.emplace_back("X-Triangulated", stats.triangulated ? "true" : "false");
    headers.emplace_back("X-Achieved-Error", format_double(stats.achieved_error));
    headers.emplace_back("X-Relative-Error", format_double(stats.relative_error));
    if (stats.hausdorff) headers.emplace_back("X-Hausdorff", format_double(*stats.hausdorff));
    if (stats.rms) headers.emplace_back("X-RMS", format_double(*stats.rms));
    if (stats.repairs) headers.emplace_back("X-Repairs", repairs_header(*stats.repairs));
    return mesh_response(
        result.mesh, params.output, source, [&](const PolygonMesh& m) { return encode_simplify_response(m, stats); },
        std::move(headers),
        Timing{t_start, {{"decode", t_decoded}, {"simplify", t_simplified}, {"measure", t_measured}}});
}

}  // namespace

ApiResponse simplify(const ApiRequest& request, const ApiContext& context) noexcept {
    return guarded([&] { return run(request, context); });
}

}  // namespace surfaced::api::operations
