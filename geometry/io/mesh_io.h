// Reading and writing polygon mesh files. Every reader returns a ParseError naming the 1-based line (text formats)
// or byte offset (binary formats) and what is wrong; none allocates more than the input can justify (a header
// count is checked against the bytes that remain before anything is reserved). Text formats (OBJ, OFF, ascii PLY and
// STL) are read from UTF-8/ASCII or from UTF-16 with a byte order mark (converted first; line numbers unchanged).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "geometry/core/result.h"
#include "geometry/mesh/polygon_mesh.h"
#include "geometry/pointcloud/point_cloud.h"

namespace surfaced {

enum class MeshFormat { Obj, Off, Ply, Stl, Glb, Gltf };

//! Limits applied while reading, before allocation.
struct ReadOptions {
    std::size_t max_vertices = 20'000'000;
    std::size_t max_faces = 20'000'000;
    std::size_t max_face_size = 65'536;  //!< vertices in one polygon
    //! Keep faces that use a vertex more than once (`f 4 3 5 5`) instead of failing with DegenerateFace.
    //! OpenSubdiv's non-manifold regression shapes contain such faces; validate() still rejects them.
    bool allow_repeated_vertices = false;
};

//! What a read passed over, for the caller to report (glTF: point and line primitives, which have no surface), and
//! where each face came from, so that an error found after reading (a face Loop subdivision cannot take, a
//! non-manifold edge) can name the face's line in the file.
struct ReadReport {
    std::size_t skipped_primitives = 0;
    //! Text formats (OBJ, OFF, ascii PLY): the 1-based line each face starts on, one per face in order (4 bytes a
    //! face). Empty for binary formats, whose errors name the face's index, and for STL (its reader welds and drops
    //! triangles). Lines past 2^32 - 1 are not recorded: the vector then stops short of the faces.
    std::vector<std::uint32_t> face_lines;
};

//! Wavefront OBJ: `v`, `vt`, `vn`, `f` (v, v/vt, v//vn, v/vt/vn, negative indices, any polygon size), comments,
//! blank lines, CRLF, line continuations; OpenSubdiv's `t` tags (crease, corner, hole, interpolateboundary) into
//! mesh.tags. Other statements (g, o, s, usemtl, mtllib, l, p) are ignored. Face-varying `vt` go to uvs/uv_indices
//! when every face has them. Vertex normals `vn` are ignored (recomputed on output when asked).
//! Details: when only some faces have `vt` the uvs are dropped (not an error); one face mixing corners with and
//! without `vt` is a ParseError. Positive indices must refer to vertices already read. Tag indices are 0-based and
//! checked against the final counts; a negative sharpness is clamped to 0 as OpenSubdiv does; unknown tags are
//! skipped by their declared counts. A file without faces is a ParseError ("no faces").
Result<PolygonMesh> read_obj(std::string_view text, const ReadOptions& options = {});
//! The same, appending each face's line to `report->face_lines` (report may be null).
Result<PolygonMesh> read_obj(std::string_view text, const ReadOptions& options, ReadReport* report);
//! OFF / COFF / NOFF (ascii), with `#` comments.
Result<PolygonMesh> read_off(std::string_view text, const ReadOptions& options = {});
//! The same, appending each face's line to `report->face_lines` (report may be null).
Result<PolygonMesh> read_off(std::string_view text, const ReadOptions& options, ReadReport* report);
//! PLY ascii, binary_little_endian and binary_big_endian 1.0; vertex x/y/z (float or double, any other properties
//! skipped), face vertex_indices / vertex_index list of any integer types; other elements skipped.
//! nx/ny/nz, when all three are present and finite, are read into normals (so write_ply round-trips). Header lines
//! whose first word is not a PLY keyword ("Created by Blender 2.49") are ignored.
Result<PolygonMesh> read_ply(std::string_view bytes, const ReadOptions& options = {});
//! The same, appending each face's line to `report->face_lines` (report may be null).
Result<PolygonMesh> read_ply(std::string_view bytes, const ReadOptions& options, ReadReport* report);
//! STL ascii or binary (detected by content, not by the word "solid"); coincident corners welded exactly.
//! Binary when the size is 84 + 50 * count; bytes after the last triangle of a non-"solid" file are ignored.
//! Triangles with two exactly equal corners (degenerate by index after welding) are dropped, not reported;
//! DegenerateFace only when nothing is left.
Result<PolygonMesh> read_stl(std::string_view bytes, const ReadOptions& options = {});

//! Dispatch on format (Glb and Gltf go to read_glb and read_gltf in gltf.h); `report`, when given, is reset first.
Result<PolygonMesh> read_mesh(std::string_view bytes, MeshFormat format, const ReadOptions& options = {},
                              ReadReport* report = nullptr);

//! Format from a file name's extension (.obj .off .ply .stl .glb .gltf, case-insensitive).
std::optional<MeshFormat> format_from_extension(std::string_view path);
//! Format from a media type (model/obj, model/stl, application/sla, model/gltf-binary, model/gltf+json,
//! application/ply, ...).
std::optional<MeshFormat> format_from_media_type(std::string_view media_type);
//! Best guess from the first bytes (glTF magic, a JSON object with "asset", "ply", "OFF", binary STL size rule, OBJ
//! statements).
std::optional<MeshFormat> sniff_format(std::string_view bytes);

struct ObjWriteOptions {
    bool write_tags = true;     //!< emit OpenSubdiv `t` lines for mesh.tags
    bool write_uvs = true;      //!< emit `vt` and v/vt faces when the mesh has uvs
    bool write_normals = true;  //!< emit `vn` when the mesh has normals
    int precision = 17;         //!< significant digits; 17 (or more) writes the shortest text that round-trips exactly
    //! One colour per vertex, written after each `v` as `r g b` in 0..1 (the common extension MeshLab and Open3D
    //! read); empty: none. Precondition: empty or one per vertex.
    std::span<const Color> vertex_colors{};
};
std::string write_obj(const PolygonMesh& mesh, const ObjWriteOptions& options = {});

enum class PlyEncoding { Ascii, BinaryLittleEndian };
//! PLY with double x/y/z, and nx/ny/nz when the mesh has normals; faces as `list uchar uint vertex_indices`
//! (`list uint uint` when a face has more than 255 vertices). UVs and subdivision tags are not written.
//! `vertex_colors`, one per vertex when given, are written as uchar red green blue (alpha too with `alpha`).
std::string write_ply(const PolygonMesh& mesh, PlyEncoding encoding = PlyEncoding::BinaryLittleEndian,
                      std::span<const Color> vertex_colors = {}, bool alpha = false);

//! Binary STL: float32 corners, each triangle with its unit facet normal (zero for a degenerate triangle), polygons
//! split by triangulate() as the glTF writer splits them (a fan from the first corner when convex, ear clipping
//! otherwise). Vertex normals, UVs and tags have no place in STL. Coordinates beyond the float32 range become
//! infinities: callers check the range first.
std::string write_stl(const PolygonMesh& mesh);
//! ascii OFF: "OFF", the counts (edges 0), one vertex per line, one polygon per line (kept as polygons). Numbers in
//! number_text.h's shortest round-trip form, so read_off gives back the same doubles. Normals, UVs and tags are not
//! written.
std::string write_off(const PolygonMesh& mesh);

}  // namespace surfaced
