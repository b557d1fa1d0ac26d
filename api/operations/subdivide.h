// POST /subdivide: uniform Catmull-Clark or Loop subdivision of an uploaded mesh.
//
// Two request forms:
//  * Content-Type application/json:
//      {"mesh": {"positions": [[x,y,z],...], "faces": [[i,j,k,...],...]},
//       "scheme": "catmull-clark"|"loop", "levels": N, "boundary": "edge-only"|"edge-and-corner"|"none",
//       "output": {"format": "glb"|"obj"|"ply"|"json", "compression": "draco"|"none", "quantize_position": 14,
//                  "normals": false}}
//    Only "mesh" is required; query parameters are rejected (options belong in the body).
//  * A mesh file as the body: model/obj, model/off, application/ply | model/ply, model/stl | application/sla,
//    model/gltf-binary, model/gltf+json, or application/octet-stream (format sniffed from the bytes). Options come as
//    query parameters with the same names: ?scheme=loop&levels=2&boundary=none&format=obj&compression=none
//    &quantize_position=12&normals=true. Unknown parameters are rejected, naming them.
// Defaults: catmull-clark, 1 level, the mesh's boundary tag or edge-only, GLB with Draco (quantize_position 14).
//
// Order of checks, all before any refinement: body size (413), media type (415), options (400) and levels against
// Limits::max_levels (422) -- for a file upload before the file is parsed; for JSON right after decoding, since the
// options are in the body --, decode (400 with line/offset or field path), input size, validate() (422),
// predicted_face_count against Limits::max_output_faces (422). Then subdivide, then encode. Scheme loop on a mesh with
// a face that is not a triangle is 422 not_triangle_mesh naming the first such face: its line in an uploaded text
// file (OBJ, OFF, ascii PLY; its index in a binary one), its field (mesh.faces[i]) in a JSON body, with the hint that
// scheme catmull-clark takes any polygons.
//
// Response: the mesh as model/gltf-binary (default), model/obj, application/ply or application/json
// ({"mesh": ..., "stats": ...}), with headers X-Input-Vertices, X-Input-Faces, X-Output-Vertices, X-Output-Faces,
// X-Elapsed-Ms and Server-Timing (decode, subdivide, encode, total). Errors: problem+json, see api/errors.h.
#pragma once

#include "api/operation.h"

namespace surfaced::api::operations {

ApiResponse subdivide(const ApiRequest& request, const ApiContext& context) noexcept;

}  // namespace surfaced::api::operations
