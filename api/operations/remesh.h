// POST /remesh: isotropic remeshing of an uploaded mesh towards one edge length (geometry/remesh/remesh.h).
//
// Same two request forms as POST /subdivide and /simplify:
//  * Content-Type application/json:
//      {"mesh": {"positions": [[x,y,z],...], "faces": [[i,j,k,...],...]},
//       "edge_length": L, "iterations": 10, "feature_angle": 60, "lock_border": true,
//       "smoothing": "tangential"|"laplacian"|"none", "repair": "auto"|"none",
//       "output": {"format": "glb"|"gltf"|"obj"|"ply"|"json", "compression": "draco"|"none", "quantize_position": 14,
//                  "normals": false}}
//    Only "mesh" is required; without edge_length the input's mean edge length is used (same density, better
//    triangles). Query parameters are rejected.
//  * A mesh file as the body (model/obj, model/off, application/ply, model/stl, model/gltf-binary, model/gltf+json,
//    application/octet-stream): the same options as query parameters, output options unnested:
//    ?edge_length=0.01&iterations=5&feature_angle=45&lock_border=false&smoothing=laplacian&format=obj
// lock_border (default true: moving an open mesh's border shrinks it) keeps boundary vertices on the input's border;
// its deprecated name keep_boundary is accepted too (query and JSON), both names at once is 400 invalid_field.
// Polygons are triangulated first (X-Triangulated: true). UVs and normals of the input are not carried over.
// "repair": "auto" (default; query repair=auto) repairs a mesh that needs it first (api/operations/mesh_repair.h: weld,
// degenerate and duplicate faces, orientation, non-manifold edges and vertices cut apart), reported in X-Repairs and
// in the JSON stats' "repairs"; "none" refuses such input as before: 422 non_manifold naming the edge or vertex, 422
// degenerate_face for a face that repeats a vertex.
//
// Order of checks, all before remeshing: body size (413), media type (415), options (400: unknown, malformed, out of
// range: edge_length finite > 0, iterations 0..100, feature_angle 0..180), decode (400 with line/offset or field path),
// input size against Limits::max_input_* (422), validate() (422), the triangle count after triangulation against
// Limits::max_input_faces, and the predicted output, surface area / (0.433 L^2) faces (equilateral triangles of side
// L), against Limits::max_output_faces (422 budget_exceeded, field edge_length). Limits::compute_deadline_ms: 503.
//
// Response: the mesh as GLB (default), glTF, OBJ, PLY or JSON ({"mesh": ..., "stats": {..., "before": quality,
// "after": quality}}), with headers X-Input-Vertices, X-Input-Faces, X-Output-Vertices, X-Output-Faces,
// X-Triangulated, X-Edge-Length (the target used), X-Feature-Edges, X-Hausdorff (between input and output),
// X-Min-Angle-Before/-After (degrees), X-Below-30-Before/-After (share of triangles), X-Radius-Ratio-Before/-After
// (mean, Verdict R/2r), X-Mean-Edge-Length-After, X-Repairs (repair "auto"), X-Elapsed-Ms and Server-Timing
// (decode, remesh, encode, total).
#pragma once

#include "api/operation.h"

namespace surfaced::api::operations {

ApiResponse remesh(const ApiRequest& request, const ApiContext& context) noexcept;

}  // namespace surfaced::api::operations
