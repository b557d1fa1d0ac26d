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
// GET /patches/{name} (name: a built-in sample, `teapot`): the same query parameters. The response carries a strong
// ETag (a hash of the name, the sample's data, the options and kPatchSampleRevision) and Cache-Control; a request
// whose If-None-Match lists that ETag (or is "*") gets 304 Not Modified without any tessellation.
//
// Options: tolerance (> 0, model units) and segments (1..Limits::max_patch_segments) exclude each other; with
// neither, segments = 8. Output: format glb (default) | obj | ply; compression draco (default) | none (glb);
// quantize_position 1..30 (glb + draco); normals default true (NORMAL and TEXCOORD_0 in the GLB).
// Order of checks, all before tessellating: body size (413), media type (415), options (400/422), decode (400 with
// line or field path), patch validity (422, field "patches[i]"), the plan's segment counts against
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
