// JSON <-> DTOs and PolygonMesh. The only api/ translation unit that includes nlohmann/json (build time).
//
// Mesh JSON form:  {"positions": [[x, y, z], ...], "faces": [[i, j, k, ...], ...], "normals": [[x, y, z], ...]}
//   positions: finite numbers; faces: >= 3 non-negative integer indices into positions; normals (optional, as the
//   JSON output writes them): one finite [x, y, z] per position. Also "uvs" and "uv_faces" (optional).
// Errors name the exact place with a field path and say what was expected:
//   400 invalid_json       the body is not JSON (offset = byte position where parsing stopped)
//   400 invalid_field      wrong type ("mesh.positions[3][1] must be a finite number"), unknown enum value (the
//                          allowed ones are listed), missing required member
//   400 unknown_field      members we do not know, all of them named ("unknown field(s) at top level: \"mesh2\"")
//   400 number_out_of_range a number overflows a double (1e999; refused while parsing, so with the line, column
//                          and offset, without a field path)
//   422 index_out_of_range "mesh.faces[12][3]: vertex 99 out of range (8 vertices)"
//   422 degenerate_face    a face with fewer than 3 vertices
//   422 budget_exceeded    more positions/faces than Limits allows (checked before they are decoded)
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "api/dto.h"
#include "api/errors.h"
#include "api/limits.h"
#include "geometry/mesh/polygon_mesh.h"

namespace surfaced::api {

struct SubdivideJsonRequest {
    PolygonMesh mesh;
    SubdivideParams params;
};

//! Decodes {"mesh": {...}, "scheme": ..., "levels": N, "boundary": ..., "crease_method": ..., "triangle_rule": ...,
//! "limit_surface": bool, "target_faces": N, "creases": [{"edge": [a, b], "sharpness": s}], "corners": [{"vertex": v,
//! "sharpness": s}], "holes": [f, ...], "output": {"format", "compression", "quantize_position", "normals"}}. Only "mesh" is required. Option *ranges* (levels vs. budget, quantization bits)
//! are checked by the operation, which also handles the same options coming from query parameters.
ApiResult<SubdivideJsonRequest> decode_subdivide_request(std::string_view body, const Limits& limits);

//! The subdivision tags of a request body into `mesh.tags`: "creases": [{"edge": [a, b], "sharpness": s}], "corners":
//! [{"vertex": v, "sharpness": s}], "holes": [f, ...] (as POST /subdivide reads them), checked against the mesh.
std::optional<ApiError> decode_subdivision_tags(const nlohmann::json& body, PolygonMesh& mesh);

//! Decodes a mesh object on its own (`path` prefixes field paths in errors, e.g. "mesh").
ApiResult<PolygonMesh> decode_mesh(std::string_view json_text, const Limits& limits, std::string_view path = "mesh");
//! The same, for a mesh object inside a document already parsed (a scene's mesh node), without printing it again.
ApiResult<PolygonMesh> decode_mesh_json(const nlohmann::json& value, const Limits& limits, std::string_view path);

//! {"mesh": {"positions": [...], "faces": [...], "normals": [...] (when the mesh has them)}, "stats": {...}}. Numbers
//! are written as geometry/io/number_text.h prints them (shortest round trip, no -0).
std::string encode_mesh_response(const PolygonMesh& mesh, const SubdivideStats& stats);

struct SimplifyJsonRequest {
    PolygonMesh mesh;
    SimplifyParams params;
};

//! Decodes {"mesh": {...}, "target_faces": N, "ratio": r, "max_error": e, "lock_border": bool, "restore_volume": r,
//! "threads": n, "report_error": bool, "output": {...}} for POST /simplify. Only "mesh" is required here; the operation
//! checks that a stop criterion is given and the ranges (the same checks apply to query parameters).
ApiResult<SimplifyJsonRequest> decode_simplify_request(std::string_view body, const Limits& limits);

//! {"mesh": {...}, "stats": {"input_vertices", ..., "triangulated", "achieved_error", "relative_error",
//! "hausdorff", "rms" (when measured), "elapsed_ms"}}.
std::string encode_simplify_response(const PolygonMesh& mesh, const SimplifyStats& stats);

//! A repair report's counts by name ("welded", "degenerate", "duplicate", "flipped", "nonmanifold_split",
//! "small_components", "removed_faces", "holes_filled", "fill_faces", "unreferenced", "components"), in that order.
std::vector<std::pair<std::string_view, std::size_t>> repair_counts(const RepairReport& report);
//! {"welded":12,"degenerate":3,...}: repair_counts() as the text of a JSON object.
std::string encode_repairs(const RepairReport& report);
//! {"mesh": {...}, "stats": STATS}: the mesh as every endpoint writes it, with `stats_json` (a JSON object's text).
std::string encode_mesh_with_stats(const PolygonMesh& mesh, std::string_view stats_json);

}  // namespace surfaced::api
