// POST /limit/evaluate: the exact Catmull-Clark limit surface of a mesh at parametric points (face, u, v), with
// derivatives, normals and the limit of the mesh's texture coordinates (geometry/subdivision/limit_evaluation.h,
// uv_limit.h).
//
// Request (application/json; "mesh" and "points" required):
//   {"mesh": {...},                          the JSON mesh every endpoint takes, "uvs"/"uv_faces" included
//    "creases": [...], "corners": [...], "holes": [...],       subdivision tags, as POST /subdivide takes them
//    "scheme", "boundary", "crease_method", "triangle_rule", "uv_interpolation":  /subdivide's options (the surface)
//    "points": [{"face": f, "uv": [u, v]}, ...],                or {"float32" | "float64": base64} of packed
//                                                               little-endian (face, u, v) triples
//    "derivatives": 1 | 2,                                      2 adds duu, duv, dvv
//    "encoding": "json" | "float32" | "float64"}                answers as numbers, or base64 packed arrays
// or multipart/form-data: the mesh file (OBJ with its `t` tags, OFF, PLY, STL, GLB, glTF, JSON) in the part "file"
// and the rest of the JSON body in the part "request", as POST /mesh/query (api/operations/query_forms.h).
// (face, u, v) is OpenSubdiv Bfr's parameterization: u, v in [0, 1] on a quad (corner 0 at (0, 0), corner 1 at
// (1, 0)); an N-gon is N quad sub-faces tiled in the plane (docs/subdivision.md).
// Response: {"points": [{"position": [x, y, z], "du": [..], "dv": [..], "normal": [..], "duu", "duv", "dvv" (with
// derivatives 2), "uv": [s, t] (when the mesh has UVs), "exact": bool}, ...]}, in the order of the request. With a
// packed encoding: {"encoding": ..., "points": {"position": base64, "du": ..., ..., "exact": base64 of uint8}}, one
// array per member, vectors flattened. `exact` is false within 2^-24 of an irregular vertex (the evaluator's limit
// there is a blend; see limit_evaluation.h) and for the UVs uv_limit.h approximates.
// Errors: problem+json with field paths. 400 for the shape (points[3].uv must be [u, v]); 422 budget_exceeded when
// there are more points than Limits::max_limit_points (checked before any is decoded) and for the mesh's size;
// 422 naming points[k].face for a face out of range, a hole or a face the evaluator cannot take, points[k].uv for a
// non-finite (u, v) or one outside the face's domain; 422 naming scheme for a scheme the evaluator does not support;
// 503 when the compute deadline passes (polled between batches of points).
#pragma once

#include "api/operation.h"

namespace surfaced::api::operations {

ApiResponse limit_evaluate(const ApiRequest& request, const ApiContext& context) noexcept;

}  // namespace surfaced::api::operations
