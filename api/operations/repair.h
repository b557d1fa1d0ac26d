// POST /repair: mesh repair alone (geometry/repair/repair.h), with its report.
//
// The two request forms of the mesh operations:
//  * Content-Type application/json:
//      {"mesh": {"positions": [[x,y,z],...], "faces": [[i,j,k,...],...], "uvs"?, "uv_faces"?},
//       "weld_tolerance": 0, "orient": true, "min_component_faces": 0, "max_hole_edges": 0,
//       "output": {"format": "glb"|"gltf"|"obj"|"ply"|"json", "compression": "draco"|"none", "quantize_position": 14,
//                  "normals": false}}
//    Only "mesh" is required. Query parameters are rejected.
//  * A mesh file as the body (model/obj, model/off, application/ply, model/stl, model/gltf-binary, model/gltf+json,
//    application/octet-stream): the same options as query parameters, output options unnested:
//    ?weld_tolerance=1e-6&orient=false&min_component_faces=10&max_hole_edges=32&format=obj
// Options: weld_tolerance, a distance >= 0 (0: only identical positions are welded); orient (faces oriented
// consistently per component, outward for closed ones); min_component_faces >= 0 (smaller components are dropped,
// and counted); max_hole_edges in 0..10000 (holes with at most this many edges are filled).
// Faces that repeat a vertex are accepted (and dropped as degenerate).
//
// Order of checks, all before repairing: body size (413), media type (415), options (400 naming the field), decode
// (400 with line/offset or field path), input size against Limits::max_input_* (422).
//
// Response: the repaired mesh as GLB (default), glTF, OBJ, PLY or JSON ({"mesh": ..., "stats": {"input_vertices",
// "input_faces", "output_vertices", "output_faces", "repairs": {"welded", "degenerate", "duplicate", "flipped",
// "nonmanifold_split", "small_components", "removed_faces", "holes_filled", "fill_faces", "unreferenced",
// "components"},
// "elapsed_ms"}}), with headers X-Input-Vertices, X-Input-Faces, X-Output-Vertices, X-Output-Faces, X-Repairs (the
// same counts: "welded=12; degenerate=3; ..."), X-Elapsed-Ms and Server-Timing (decode, repair, encode, total).
#pragma once

#include "api/operation.h"

namespace surfaced::api::operations {

ApiResponse repair(const ApiRequest& request, const ApiContext& context) noexcept;

}  // namespace surfaced::api::operations
