// glTF 2.0 binary (GLB) output and input, with KHR_draco_mesh_compression.
#pragma once

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
};

//! Writes one mesh as one glTF node/primitive (TRIANGLES; polygons fan-triangulated). Output passes the Khronos
//! validator with no errors or warnings. Errors: InvalidArgument (options out of range), BudgetExceeded (> 2^32
//! indices), Internal (encoder failure).
Result<std::string> write_glb(const PolygonMesh& mesh, const GltfOptions& options = {});

//! The same scene as glTF JSON (.gltf): one self-contained text file, the binary data embedded as a base64 data URI.
Result<std::string> write_gltf(const PolygonMesh& mesh, const GltfOptions& options = {});

//! Reads every TRIANGLES primitive of every mesh in a GLB (node transforms applied; Draco-compressed primitives
//! decoded), POSITION and TEXCOORD_0 when present, welding vertices split only by attributes. Errors name what is
//! wrong (ParseError with byte offset where known, Unsupported for external buffers / other primitive modes).
Result<PolygonMesh> read_glb(std::string_view bytes, const ReadOptions& options = {});

}  // namespace surfaced
