// POST /mesh/query: closest points, signed distances, winding numbers and ray hits on a mesh, answered in JSON.
//
// Request (application/json; "mesh" and at least one of "points" / "rays" required):
//   {"mesh": {...},                              the JSON mesh every endpoint takes (polygons are triangulated)
//    "points": [[x, y, z], ...],
//    "rays": [[ox, oy, oz, dx, dy, dz], ...],    direction non-zero; t is in units of its length
//    "want": ["inside", "winding_number", "distance", "closest"],   point answers wanted (default: all four)
//    "winding": {"exact": false, "accuracy": 2},                   how winding numbers are computed
//    "encoding": "json" | "float32" | "float64"}                   answers as numbers, or base64 packed arrays
// or multipart/form-data: the mesh file (OBJ, OFF, PLY, STL, GLB, glTF, JSON) in the part "file" and the rest of the
// JSON body in the part "request". points and rays may also be packed: {"float32" | "float64": base64} of
// little-endian numbers, 3 (6) per item, counted against the budget before they are decoded.
// Response: {"points": {"inside": [b..], "winding_number": [w..], "distance": [d..] (negative inside),
//                       "closest": [[x, y, z]..], "face": [f..]},       only the members `want` asks for
//            "rays": {"hit": [b..], "t": [..], "face": [..], "point": [[..]..], "normal": [[..]..]}}  null on a miss
// With a packed encoding each array is base64 of little-endian values instead: booleans uint8, faces int32 (-1 for
// none), the rest float32 / float64 (NaN for none), vectors flattened; and "encoding" names it.
// Inside is winding number >= 1/2 (robust on meshes with holes and self-intersections). Errors: problem+json with
// field paths ("points[3][1]", "rays[0]", "want[1]", "winding.accuracy", "mesh.faces[2][0]"); 422 budget_exceeded
// when points + rays exceed Limits::max_mesh_queries or exact winding numbers would take more than
// Limits::max_exact_winding_work point-triangle terms, both checked before the mesh is indexed; 422 for a mesh
// without faces; 503 when the compute deadline passes (polled between batches of queries).
#pragma once

#include "api/operation.h"

namespace surfaced::api::operations {

ApiResponse mesh_query(const ApiRequest& request, const ApiContext& context) noexcept;

}  // namespace surfaced::api::operations
