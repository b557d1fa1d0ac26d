// Point clouds from glTF 2.0: GLB, and glTF JSON (.gltf) with its buffers embedded as data: URIs, on the same checked
// document as the mesh readers (gltf.h). What write_points_glb (pointcloud_glb.h) writes reads back.
#pragma once

#include <cstddef>
#include <string_view>

#include "geometry/core/result.h"
#include "geometry/io/pointcloud_io.h"
#include "geometry/pointcloud/point_cloud.h"

namespace surfaced {

//! Where the points of a glTF read came from.
struct GltfPointsReport {
    std::size_t point_primitives = 0;     //!< POINTS primitives read
    std::size_t triangle_primitives = 0;  //!< triangle primitives whose vertices were read (only when no POINTS)
    std::size_t skipped_primitives = 0;   //!< lines, and triangles when the scene has POINTS primitives
    bool normals_dropped = false;         //!< some NORMAL was zero or not finite, or only some primitives had NORMAL
    bool colors_dropped = false;          //!< only some primitives had COLOR_0
};

//! The points of a GLB's default scene (node transforms applied; KHR_draco_mesh_compression decoded):
//!  - the vertices of every POINTS primitive (mode 0; with indices, the indexed vertices in index order);
//!  - when the scene has no POINTS primitive, the vertices of its triangle primitives (TRIANGLES, strips, fans), as
//!    a mesh's samples: every vertex of the POSITION accessor, the duplicates at seams included;
//!  - line primitives are skipped.
//! Attributes: POSITION (float, normalised or KHR_mesh_quantization integers), NORMAL (normalised after the
//! transform, by its inverse transpose), COLOR_0 (VEC3 or VEC4; float, or normalised unsigned byte / short; 0..1).
//! Normals and colours are kept when every primitive read has them; normals are dropped (not an error) when one is
//! zero or not finite, as read_ply_points does. Errors: ParseError naming the accessor and what is wrong ("glTF
//! meshes[0].primitives[0]: COLOR_0 (accessors[2]) has 5 elements, POSITION (accessors[0]) has 6"), Unsupported
//! (external buffers, required extensions other than Draco and KHR_mesh_quantization, no point or triangle
//! primitive), NonFinite (a position), BudgetExceeded when the counts the accessors announce exceed
//! options.max_points, checked before anything is read or decoded.
Result<PointCloud> read_glb_points(std::string_view bytes, const PointReadOptions& options = {},
                                   GltfPointsReport* report = nullptr);
//! The same for glTF JSON whose buffers are embedded as base64 data: URIs (nothing named by a path or URL is read).
Result<PointCloud> read_gltf_points(std::string_view text, const PointReadOptions& options = {},
                                    GltfPointsReport* report = nullptr);

}  // namespace surfaced
