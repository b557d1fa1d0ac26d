// POST /simplify: quadric-error edge-collapse simplification of an uploaded mesh (geometry/simplify/qem.h).
//
// Same two request forms as POST /subdivide:
//  * Content-Type application/json:
//      {"mesh": {"positions": [[x,y,z],...], "faces": [[i,j,k,...],...]},
//       "target_faces": N, "ratio": r, "max_error": e, "lock_border": false, "restore_volume": 0, "threads": 1,
//       "report_error": false, "locked_vertices": [i, ...], "repair": "auto"|"none",
//       "output": {"format": "glb"|"gltf"|"obj"|"ply"|"json", "compression": "draco"|"none", "quantize_position": 14,
//                  "normals": false}}
//    "mesh" and at least one of target_faces (>= 0), ratio (in (0, 1]) and max_error (absolute distance, >= 0) are
//    required; simplification stops at whichever is reached first. Query parameters are rejected.
//  * A mesh file as the body (model/obj, model/off, application/ply, model/stl, model/gltf-binary, model/gltf+json,
//    application/octet-stream): the same options as query parameters, output options unnested:
//    ?target_faces=1000&ratio=0.1&max_error=0.01&lock_border=true&report_error=true&format=obj&compression=none
//    &locked_vertices=0,5,100&restore_volume=0.5&threads=2&repair=none
//    restore_volume in [0, 1] (default 0): volume restoration, see SimplifyOptions::restore_volume; threads 1 or 2
//    (default 1), see SimplifyOptions::threads; outside: 400 naming the field.
//    Locked vertices keep their positions bit for bit and are never removed (indices into the input's vertices, which
//    triangulation keeps); an index that is not a vertex is 422 index_out_of_range naming locked_vertices[k], one
//    that is not a non-negative integer 400 naming the same.
//    UVs of OBJ/GLB uploads are kept (seams preserved, uvs interpolated) and written to OBJ/GLB outputs.
// Polygons are triangulated first (X-Triangulated: true). "repair": "auto" (default; query repair=auto) repairs a mesh
// that needs it first (api/operations/mesh_repair.h), reported in X-Repairs and the JSON stats' "repairs"; locked
// vertices follow their positions into the repaired mesh. "none": non-manifold input (an edge shared by more than two
// faces, inconsistently oriented faces, a vertex where several fans meet) is refused with 422 non_manifold naming the
// edge or vertex, a face that repeats a vertex with 422 degenerate_face: the rules /remesh applies
// (check_manifold_input() in mesh_repair.h), located at a face (field or file line) with a hint.
//
// Order of checks, all before simplifying: body size (413), media type (415), options (400: unknown, malformed, out
// of range, no stop criterion), decode (400 with line/offset or field path), input size against Limits::max_input_*
// (422), validate() (422), the triangle count after triangulation against Limits::max_input_faces (422).
//
// Response: the mesh as GLB (default), glTF, OBJ, PLY or JSON ({"mesh": ..., "stats": ...}), with headers
// X-Input-Vertices, X-Input-Faces, X-Output-Vertices, X-Output-Faces, X-Triangulated (true|false),
// X-Target-Faces (the face count worked toward: target_faces, floor(ratio x the triangles simplified), the smaller
// of the two; absent with max_error alone), X-Achieved-Faces, X-Target-Met (false when the output has more faces than
// the target or the target is above the triangles there were: still 200; true with max_error alone), the same as
// "target_faces", "achieved_faces", "target_met" in the JSON stats, X-Achieved-Error, X-Relative-Error (SimplifyResult's, relative to the input's bounding-box diagonal),
// X-Hausdorff and X-RMS (report_error: measured between input and output by mesh_distance()), X-Repairs (repair
// "auto": "welded=0; degenerate=0; ..."), X-Elapsed-Ms and
// Server-Timing (decode, simplify, measure, encode, total).
#pragma once

#include "api/operation.h"

namespace surfaced::api::operations {

ApiResponse simplify(const ApiRequest& request, const ApiContext& context) noexcept;

}  // namespace surfaced::api::operations
