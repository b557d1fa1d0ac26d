// glTF 2.0 output and input, binary (GLB) and JSON (.gltf, data embedded), with KHR_draco_mesh_compression.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <string_view>

#include "geometry/core/result.h"
#include "geometry/io/mesh_io.h"
#include "geometry/mesh/polygon_mesh.h"

namespace surfaced {

struct GltfOptions {
    bool draco = true;           //!< KHR_draco_mesh_compression (required extension, no fallback)
    int quantize_position = 14;  //!< Draco quantization bits, 1..24 (normals 2..22): time and memory double per bit
    int quantize_normal = 10;
    int quantize_texcoord = 12;
    int encode_speed = 5;  //!< Draco speed 0 (best compression) .. 10 (fastest)
    int decode_speed = 5;
    bool normals = false;   //!< write NORMAL: the mesh's normals, or area-weighted vertex normals if it has none
    bool texcoords = true;  //!< write TEXCOORD_0 when the mesh has uvs (vertices split at uv seams)
    //! COLOR_0, one per mesh vertex when given (channels clamped to 0..1): float VEC3 (VEC4 with vertex_alpha), or
    //! with Draco normalised unsigned bytes. Not the mesh's: the caller's span must outlive the call.
    std::span<const Color> vertex_colors{};
    bool vertex_alpha = false;
};

//! Writes one mesh as one glTF node/primitive (TRIANGLES; polygons fan-triangulated). Output passes the Khronos
//! validator with no errors or warnings. Errors: InvalidArgument (options out of range, vertex_colors not one per
//! vertex), BudgetExceeded (> 2^32 indices), Internal (encoder failure).
Result<std::string> write_glb(const PolygonMesh& mesh, const GltfOptions& options = {});

//! The same scene as glTF JSON (.gltf): one self-contained text file, the binary data embedded as a base64 data URI.
Result<std::string> write_gltf(const PolygonMesh& mesh, const GltfOptions& options = {});
//! A GLB written by this library (write_glb, write_points_glb, ...) as that self-contained glTF JSON, numbers printed
//! as number_text.h prints them. Internal error when the bytes are not such a GLB.
Result<std::string> gltf_from_glb(std::string_view glb);

//! What a glTF read passed over, for the caller to report.
struct GltfReadReport {
    std::size_t skipped_primitives = 0;  //!< POINTS and LINES primitives: no surface, not read
};

//! Reads every triangle primitive (TRIANGLES, strips, fans) of every mesh instance of a GLB's default scene (node
//! transforms applied; Draco-compressed primitives decoded), POSITION and TEXCOORD_0 when present, welding vertices
//! split only by attributes. Point and line primitives are skipped and counted in `report`. Errors name what is
//! wrong (ParseError with byte offset where known, Unsupported for external buffers / only points or lines).
Result<PolygonMesh> read_glb(std::string_view bytes, const ReadOptions& options = {}, GltfReadReport* report = nullptr);

//! The same for glTF JSON (.gltf, model/gltf+json) whose buffers are embedded as base64 data: URIs (media type
//! application/octet-stream or application/gltf-buffer). A buffer or image named by a file path or URL is
//! Unsupported, naming it: nothing is ever opened or fetched. Bad base64 is a ParseError naming the buffer.
Result<PolygonMesh> read_gltf(std::string_view text, const ReadOptions& options = {}, GltfReadReport* report = nullptr);

}  // namespace surfaced
