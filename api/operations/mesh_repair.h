// The repair step of the operations that need a manifold mesh (/simplify, /remesh) and of POST /repair: what the
// `repair` option does, the X-Repairs header and the "repairs" JSON object.
//
// repair "auto" (the default): a mesh that needs it is repaired with the default RepairOptions before the operation
// runs, and the report comes back in X-Repairs (and in JSON output);
// repair "none": the mesh must be valid as it is (validate(): a face that repeats a vertex is 422 degenerate_face)
// and manifold (check_manifold(): 422 non_manifold naming the edge or vertex, located at one of its faces), the same
// rules for every operation.
#pragma once

#include <optional>
#include <type_traits>
#include <string>
#include <vector>

#include "api/dto.h"
#include "api/operations/request_forms.h"
#include "geometry/core/cancel.h"
#include "geometry/mesh/polygon_mesh.h"
#include "geometry/repair/open_seams.h"
#include "geometry/repair/repair.h"

namespace surfaced::api::operations {

//! The manifold rules every operation that needs a manifold mesh applies (/simplify, /remesh): the mesh is valid
//! (validate(): a face that repeats a vertex is 422 degenerate_face) and manifold (check_manifold(): every edge of one
//! face or of two in opposite directions, one fan of faces around every vertex; else 422 non_manifold naming the edge
//! or vertex). The error is located: the JSON field of a face at the defect (mesh.faces[i]), or for an uploaded text
//! file that face's line, with the hint that repair "auto" repairs it. nullopt when the mesh passes.
std::optional<ApiError> check_manifold_input(const PolygonMesh& mesh, Source source, const ReadReport& read);

//! An error the operation itself found in its input, located as check_manifold_input() locates its own (a
//! non-manifold or degenerate face gets the repair hint).
ApiError input_error(const GeoError& error, Source source, const ReadReport& read);

//! Runs a manifold-only operation, `run(mesh)` -> Result<T>, under the repair mode:
//! * None: the input must pass check_manifold_input() (the same meshes are refused by every such operation, with the
//!   same error), and the operation's own refusal stands.
//! * Auto: the input is repaired first when it fails check_manifold_input() or has open seams (boundary vertices that
//!   welding would merge: a triangle soup, a flat-shaded export; count_open_seam_vertices, which costs one sort of the
//!   positions when there are coincident vertices and one hash pass otherwise); otherwise it is run as it is (the
//!   checks are linear: a clean mesh costs little extra), and repaired when the operation refuses it as non-manifold
//!   or degenerate all the same. The operation runs on the repair (bow-tie vertices split, fins cut off); a repair
//!   left with no face is 422 degenerate_face. `report` is set (all zero when nothing needed repair) and `repaired`
//!   holds the repaired mesh when there was one.
//! `read` is what the file reader kept (face lines), for locating errors in an upload.
template <class Run>
auto run_with_repair(const PolygonMesh& input, RepairMode mode, Source source, const ReadReport& read,
                     const Cancel& cancel, std::optional<PolygonMesh>& repaired, std::optional<RepairReport>& report,
                     Run&& run) -> ApiResult<typename std::invoke_result_t<Run&, const PolygonMesh&>::value_type> {
    repaired.reset();
    report.reset();
    if (mode == RepairMode::None) {
        if (auto error = check_manifold_input(input, source, read)) return std::move(*error);
        auto result = run(input);
        if (!result) return input_error(result.error(), source, read);
        return std::move(result.value());
    }
    report = RepairReport{};
    if (validate(input) && check_manifold(input) && count_open_seam_vertices(input) == 0) {
        auto result = run(input);
        if (result) return std::move(result.value());
        const ErrorCode code = result.error().code;
        if (code != ErrorCode::NonManifold && code != ErrorCode::DegenerateFace)
            return input_error(result.error(), source, read);
    }
    RepairOptions options;
    options.cancel = cancel;
    auto fixed = repair_mesh(input, options);
    if (!fixed) return geometry_error(fixed.error(), source, read);
    report = fixed->report;
    repaired = std::move(fixed->mesh);
    if (repaired->face_count() == 0)
        return geometry_error(make_error(ErrorCode::DegenerateFace,
                                         "no face is left after repair: every face was degenerate (a repeated "
                                         "vertex or zero area) or a duplicate"),
                              source);
    auto result = run(*repaired);
    // (the repaired mesh's faces are not the input's: no line or field to name)
    if (!result) return from_geo_error(result.error());
    return std::move(result.value());
}

//! Vertex indices of `before` (a mesh's input numbering) in its repair `after`: the vertex of `after` at the same
//! position (welding and cutting keep positions; a vertex whose every face was dropped has none: kInvalidIndex).
std::vector<Index> vertices_by_position(const PolygonMesh& before, const PolygonMesh& after,
                                        const std::vector<std::int64_t>& vertices);

//! "welded=12; degenerate=3; duplicate=0; flipped=120; nonmanifold_split=4; ...": every count of repair_counts()
//! (api/json_codec.h), in its order. The JSON form is repairs_json().
std::string repairs_header(const RepairReport& report);

}  // namespace surfaced::api::operations
