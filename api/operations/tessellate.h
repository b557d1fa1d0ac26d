// POST /tessellate and GET /patches/{name}: Bézier patch sets tessellated crack-free, by chord tolerance or by a
// fixed number of segments, to a mesh with normals and UVs.
//
// POST /tessellate, two request forms:
//  * application/json: see api/patch_codec.h ({"patches": [...], "tolerance": t | "segments": n, "output": {...}}).
//    Query parameters are rejected (options belong in the body).
//  * a geomview BEZ/BBP file as the body (Content-Type application/x-geomview-bez, text/plain, or
//    application/octet-stream), or a Wavefront OBJ file with free-form `cstype [rat] bezier` surfaces
//    (Content-Type model/obj; geometry/io/obj_patches.h), options as query parameters: ?tolerance=0.01 |
//    ?segments=8, format, compression, quantize_position, normals. BEZ _ST corner texture coordinates become the
//    output UVs; BEZ Nd = 4, OBJ `rat` and JSON "weights" give rational patches (X-Error-Bound still a guarantee).
// Trimmed surfaces: a JSON surface with "trim": {"outer"?: [curve, ...], "holes"?: [[curve, ...], ...]}
// (api/trim_codec.h), or an OBJ surf with trim/hole statements over curv2 curves (geometry/io/obj_patches.h). Their
// loops are validated (validate_trims) before any work: a broken rule is a 422 whose field names the loop and curve
// ("surfaces[2].trim.holes[0][1]") or, for OBJ, the line of the trim/hole (or curv2) statement. They need a tolerance
// (400 with segments, or with neither) and a mesh format (format=patches: 422 unsupported, Bézier patches carry no
// trims), and are tessellated by trimmed_surface.h within the tolerance (a surface whose guaranteed bound stays above
// it -- refinement stopped at its limits, or wide loop gaps on a large model -- is 422 budget_exceeded with field
// "surfaces[i]" or its surf's line, never a 200 with X-Error-Bound above the tolerance); their meshes follow the
// untrimmed patches' in the output, not welded to them. Budgets: trim loops, curves and control points (kMaxTrim*,
// api/trim_codec.h) from the array sizes before decoding; the chords of the validated loops; each surface's grid
// triangles against max_output_faces before tessellating, and the trimmed tessellator's count as it works.
// GET /patches/{name} (name: a built-in sample, `teapot`): the same query parameters. The response carries a strong
// ETag (a hash of the name, the sample's data, the options and kPatchSampleRevision) and Cache-Control; a request
// whose If-None-Match lists that ETag (or is "*") gets 304 Not Modified without any tessellation.
//
// Options: tolerance (> 0, model units) and segments (1..Limits::max_patch_segments) exclude each other; with
// neither, segments = 8. Output: format glb (default) | obj | ply; compression draco (default) | none (glb);
// quantize_position 1..30 (glb + draco); normals default true (NORMAL and TEXCOORD_0 in the GLB).
// Order of checks, all before tessellating: body size (413), media type (415), options (400/422), decode (400 with
// line or field path), patch validity (422, field "patches[i]"), trim validity (422), the plan's segment counts against
// Limits::max_patch_segments and its triangle count against Limits::max_output_faces (422 budget_exceeded, field
// "tolerance" or "segments").
// Response headers: X-Patches, X-Output-Vertices, X-Output-Faces, X-Error-Bound (the guaranteed maximum distance
// between triangles and surface), X-Elapsed-Ms, Server-Timing.
#pragma once

#include "api/operation.h"

namespace surfaced::api::operations {

//! Bump when the tessellation output changes for the same input (it is part of every sample's ETag).
inline constexpr std::string_view kPatchSampleRevision = "bezier-patch-1";

ApiResponse tessellate(const ApiRequest& request, const ApiContext& context) noexcept;
ApiResponse patch_sample(const ApiRequest& request, const ApiContext& context) noexcept;

}  // namespace surfaced::api::operations
