// POST /pointcloud: convert, estimate normals for, or sample a point cloud.
//
// Input, one of:
//   - an uploaded point file (PLY ascii/binary, OBJ `v`/`vn`, XYZ text) by Content-Type (application/ply,
//     model/obj, text/x-xyz, ...) or sniffed for application/octet-stream and text/plain; options as query parameters
//     (estimate_normals, k, format, compression, quantize_position, normals); errors name the file line or offset;
//   - JSON {"points": [[x,y,z],...], "normals": [...], "colors": [[r,g,b(,a)],...] (0..1)};
//   - JSON {"sample": {"mesh": <mesh as /subdivide takes>, "count": N, "seed": s}} (area-uniform, face normals) or
//     {"sample": {"scene": <implicit scene>, "bounds": [[..],[..]], "count": N, "seed": s}} (points projected onto
//     f = 0, gradient normals; may return fewer than N, see X-Output-Points).
// Options: "estimate_normals": true | {"k": 3..256} (PCA of k neighbours, consistently oriented, outward on closed
// shapes); "output": {"format": "glb" (Draco point cloud by default, "compression": "none" for plain floats) |
// "ply" (binary) | "json", "quantize_position", "normals": false to leave normals out}.
// Budgets, before any work: Limits::max_points for uploaded/JSON points and sample.count (422 budget_exceeded naming
// the field), max_body_bytes, the input mesh budgets for sample.mesh, the scene budgets for sample.scene; the
// request's Cancel (compute deadline) gives 503.
#pragma once

#include "api/operation.h"

namespace surfaced::api::operations {

ApiResponse pointcloud(const ApiRequest& request, const ApiContext& context) noexcept;

}  // namespace surfaced::api::operations
