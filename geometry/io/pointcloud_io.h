// Reading and writing point clouds: PLY (ascii and binary), OBJ `v` lines, XYZ text; glTF (GLB and .gltf POINTS,
// or a mesh's vertices) in gltf_points.h, which read_points dispatches to. As for meshes (mesh_io.h),
// every reader reports a ParseError with the 1-based line (text) or byte offset (binary) and never allocates more
// than the input justifies: a header count is checked against the bytes present and the point limit first.
// GLB output is in pointcloud_glb.h (target geo_gltf).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

#include "geometry/core/result.h"
#include "geometry/io/mesh_io.h"
#include "geometry/pointcloud/point_cloud.h"

namespace surfaced {

enum class PointFormat { Ply, Obj, Xyz, Glb, Gltf };

struct PointReadOptions {
    std::size_t max_points = 20'000'000;  //!< more: BudgetExceeded (a PLY header saying so fails before reading)
};

//! PLY 1.0 ascii / binary_little_endian / binary_big_endian: the `vertex` element's x y z (any numeric type),
//! nx ny nz when all three are present (dropped, not an error, when any is non-finite), red green blue [alpha]
//! (integer types scaled by their maximum, uchar 255 -> 1.0; float types taken as 0..1), `confidence` (or, when
//! absent, `quality`) as PointCloud::confidence, taken as is and finite and >= 0. Other elements (faces, edges)
//! are skipped. Errors: ParseError/NonFinite with line or offset, BudgetExceeded.
Result<PointCloud> read_ply_points(std::string_view bytes, const PointReadOptions& options = {});
//! Wavefront OBJ: `v x y z` with optional `r g b` (0..1, or 0..255 when any value exceeds 1), `vn` taken as the
//! normals when there are exactly as many as `v`. Faces and other statements are ignored; no faces is fine.
//! Colours are kept only when every `v` line has them.
Result<PointCloud> read_obj_points(std::string_view text, const PointReadOptions& options = {});
//! XYZ text: one point per line, `x y z`, `x y z nx ny nz` or `x y z nx ny nz r g b` (colours 0..1, or 0..255
//! when any exceeds 1); whitespace or commas between values; `#` starts a comment; every point line must have the
//! same number of values as the first.
Result<PointCloud> read_xyz_points(std::string_view text, const PointReadOptions& options = {});
//! Dispatch on format (Glb and Gltf go to read_glb_points and read_gltf_points in gltf_points.h; defined in geo_io).
Result<PointCloud> read_points(std::string_view bytes, PointFormat format, const PointReadOptions& options = {});

//! .ply .obj .xyz (also .txt, .pts as XYZ), .glb, .gltf, case-insensitive.
std::optional<PointFormat> point_format_from_extension(std::string_view path);
//! application/ply (and the PLY aliases mesh_io accepts), model/obj (and aliases), text/x-xyz, chemical/x-xyz,
//! application/x-xyz, model/gltf-binary, model/gltf+json. Parameters are ignored.
std::optional<PointFormat> point_format_from_media_type(std::string_view media_type);
//! The media type a point endpoint reads `format` as: application/ply, model/obj, text/x-xyz, model/gltf-binary,
//! model/gltf+json.
std::string_view point_media_type(PointFormat format);
//! "glTF" magic, a JSON object with "asset" (glTF JSON), "ply" magic, OBJ statements, or lines of 3/6/9 numbers.
std::optional<PointFormat> sniff_point_format(std::string_view bytes);

//! PLY with double x y z, double nx ny nz when the cloud has normals, uchar red green blue (and alpha when
//! has_alpha) when it has colours, float confidence when it has confidence; no faces. Precondition:
//! validate(cloud) passes.
std::string write_ply_points(const PointCloud& cloud, PlyEncoding encoding = PlyEncoding::BinaryLittleEndian);

}  // namespace surfaced
