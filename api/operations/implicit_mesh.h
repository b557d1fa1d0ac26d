// POST /implicit/mesh: the zero level set of an implicit scene, inside given bounds, as a closed triangle mesh
// (dual marching cubes with QEF vertices: geometry/implicit/mesh_field.h).
//
// Body (application/json only; query parameters are refused):
//   {"scene": {...} (api/scene_codec.h), "bounds": [[xmin,ymin,zmin],[xmax,ymax,zmax]],
//    "resolution": N (cells along the longest side, 2..; default 64) | "cell_size": h,
//    "mode": "uniform" (default) | "adaptive", "simplify_tolerance": t (adaptive only; QEM to this Hausdorff
//    distance; default 0: none), "output": {"format", "compression", "quantize_position", "normals"}}
// Where the surface meets the bounds it is closed by flat caps on the bounds (the field counts as outside on and
// beyond them), so the result is always watertight.
// Order of checks, all before the field is evaluated: body size (413), media type (415), JSON and members (400),
// resolution / cell_size / mode / output options (400), the grid's cell count against Limits::max_grid_cells (422
// budget_exceeded, field "resolution" or "cell_size"), the scene and its own budgets (400/422 with the field path).
// After meshing, a result above Limits::max_output_faces is 422 budget_exceeded (field "resolution"); a fired
// compute deadline is 503.
// Response headers: X-Grid (nx x ny x nz), X-Grid-Cells, X-Surface-Cells, X-Field-Evaluations, X-Output-Vertices,
// X-Output-Faces, X-Elapsed-Ms, Server-Timing.
#pragma once

#include <string>

#include "api/dto.h"
#include "api/operation.h"
#include "geometry/implicit/mesh_field.h"

namespace surfaced::api::operations {

//! "mode": the meshing grid, uniform or adaptive (octree with dual contouring).
inline constexpr EnumName<implicit::MeshFieldMode> kImplicitMeshModeNames[] = {
    {"uniform", implicit::MeshFieldMode::Uniform},
    {"adaptive", implicit::MeshFieldMode::Adaptive},
};

ApiResponse implicit_mesh(const ApiRequest& request, const ApiContext& context) noexcept;

}  // namespace surfaced::api::operations
