#include "api/operations/simplify.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "api/dto.h"
#include "api/json_codec.h"
#include "api/operations/mesh_repair.h"
#include "api/operations/request_forms.h"
#include "api/options/mesh_params.h"
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
    auto values = options::read_query(*options::operation_options("simplify"), query);
    if (!values) return std::move(values.error());
    return options::simplify_params(values.value());
}

//! What the option table cannot say: that one stop criterion is needed, and output options that do not fit the
//! format (ranges were checked as the options were read).
std::optional<ApiError> check_params(const SimplifyParams& params, Source source) {
    if (!params.target_faces && !params.ratio && !params.max_error)
        return make_problem(Problem::InvalidField,
                            "one of target_faces, ratio or max_error is required (simplification stops at whichever "
                            "is reached first)",
                            "target_faces");
    return check_output_options(params.output, source);
}

//! The face count simplification works toward (as simplify_qem computes it, but not capped at the input: a target
//! above the triangles there are cannot be met): target_faces, floor(ratio x triangles), the smaller of the two when
//! both are given; none with max_error alone.
std::optional<std::size_t> face_target(const SimplifyParams& params, std::size_t triangles) {
    std::optional<std::size_t> target;
    if (params.target_faces) target = static_cast<std::size_t>(*params.target_faces);
    if (params.ratio) {
        const auto by_ratio = static_cast<std::size_t>(std::floor(*params.ratio * static_cast<double>(triangles)));
        target = target ? std::min(*target, by_ratio) : by_ratio;
    }
    return target;
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
    std::size_t simplified_triangles = 0;  // of the mesh simplified (the input or its repair), once triangulated
    auto simplified = run_with_repair(
        input, params.repair, source, read_report, context.cancel, repaired, repairs, [&](const PolygonMesh& mesh) {
            simplified_triangles = mesh.face_indices.size() - 2 * mesh.face_count();
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
    stats.target_faces = face_target(params, simplified_triangles);
    stats.achieved_faces = result.faces;
    stats.target_met =
        !stats.target_faces || (result.faces <= *stats.target_faces && *stats.target_faces <= simplified_triangles);
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
    if (stats.target_faces) headers.emplace_back("X-Target-Faces", std::to_string(*stats.target_faces));
    headers.emplace_back("X-Achieved-Faces", std::to_string(stats.achieved_faces));
    headers.emplace_back("X-Target-Met", stats.target_met ? "true" : "false");
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
