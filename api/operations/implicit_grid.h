// POST /implicit/grid: a mesh or an implicit scene as a narrow-band signed distance grid, answered as a level_set
// scene node (geometry/implicit/distance_grid.h), so the answer can be sent back as (part of) a scene.
//
// Body (application/json only; query parameters are refused):
//   {"mesh": {...} (the JSON mesh every endpoint takes; polygons are triangulated) | "scene": {...} (api/scene_codec.h),
//    exactly one of the two,
//    "voxel_size": h (> 0, required), "band": w (voxels, 1..64, default 3),
//    "bounds": [[xmin,ymin,zmin],[xmax,ymax,zmax]] (required for a scene; for a mesh the default is its box grown
//    by w + 1 voxels)}
// Mesh: exact distance to the nearest triangle at every node within w * h of the surface, the sign of the generalized
// winding number (robust on holes and self-intersections), +-w * h beyond. Scene: f at every node clamped to
// +-w * h.
// Order of checks: body size (413), media type (415), JSON and members, options (400), one of mesh / scene, bounds
// (400), the node count against Limits::max_level_set_samples when the bounds are given (422 budget_exceeded, field
// "voxel_size"), the scene or mesh (400/422 with field paths; the mesh's input budgets), for a mesh without bounds
// the node count of its default bounds (422, "voxel_size"), then the work; a fired compute deadline is 503.
// Response: application/json, {"op": "level_set", "dims": [nx, ny, nz], "origin": [x, y, z], "spacing": h,
// "values": [...]} (x fastest, numbers shortest round-trip). Headers: X-Grid (nx x ny x nz), X-Grid-Nodes,
// X-Band-Nodes, X-Winding-Queries (0 for a scene), X-Field-Evaluations (0 for a mesh), X-Elapsed-Ms, Server-Timing.
#pragma once

#include "api/operation.h"

namespace surfaced::api::operations {

ApiResponse implicit_grid(const ApiRequest& request, const ApiContext& context) noexcept;

}  // namespace surfaced::api::operations
