// The repair step of the operations that need a manifold mesh (/simplify, /remesh) and of POST /repair: what the
// `repair` option does, the X-Repairs header and the "repairs" JSON object.
//
// repair "auto" (the default): a mesh that needs it (geometry/repair/repair.h: needs_repair) is repaired with the
// default RepairOptions before the operation runs, and the report comes back in X-Repairs (and in JSON output);
// repair "none": the mesh must be valid as it is (validate(): a face that repeats a vertex is 422 degenerate_face)
// and manifold (the operation's own 422 non_manifold naming the edge).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "api/dto.h"
#include "api/operations/request_forms.h"
#include "geometry/core/cancel.h"
#include "geometry/mesh/polygon_mesh.h"
#include "geometry/repair/repair.h"

namespace surfaced::api::operations {

//! The input made ready for a manifold-only operation. With RepairMode::Auto the report is set (all zero when
//! nothing needed repair) and `repaired` holds the repaired mesh when there was anything to repair; with None the
//! input is only validated (and `report` and `repaired` stay empty). The operation then runs on
//! `repaired ? *repaired : input`.
std::optional<ApiError> prepare_manifold_input(const PolygonMesh& input, RepairMode mode, Source source,
                                               const Cancel& cancel, std::optional<PolygonMesh>& repaired,
                                               std::optional<RepairReport>& report);

//! Vertex indices of `before` (a mesh's input numbering) in its repair `after`: the vertex of `after` at the same
//! position (welding and cutting keep positions; a vertex whose every face was dropped has none: kInvalidIndex).
std::vector<Index> vertices_by_position(const PolygonMesh& before, const PolygonMesh& after,
                                        const std::vector<std::int64_t>& vertices);

//! "welded=12; degenerate=3; duplicate=0; flipped=120; nonmanifold_split=4; ...": every count of repair_counts()
//! (api/json_codec.h), in its order. The JSON form is repairs_json().
std::string repairs_header(const RepairReport& report);

}  // namespace surfaced::api::operations
