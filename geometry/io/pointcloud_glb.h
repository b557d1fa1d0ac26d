// Point clouds as glTF 2.0 binary: one node, one mesh, one POINTS primitive (mode 0) with POSITION and, when the
// cloud has them, NORMAL and COLOR_0; optionally Draco-compressed (KHR_draco_mesh_compression on the points
// primitive, no uncompressed fallback).
#pragma once

#include <string>

#include "geometry/core/result.h"
#include "geometry/pointcloud/point_cloud.h"

namespace surfaced {

struct PointGlbOptions {
    bool draco = true;
    int quantize_position = 14;  //!< 1..24 bits (Draco)
    int quantize_normal = 10;    //!< 2..22 bits (Draco)
    int encode_speed = 5;        //!< 0..10
    int decode_speed = 5;        //!< 0..10
    bool normals = true;         //!< write NORMAL when the cloud has normals
    bool colors = true;          //!< write COLOR_0 when the cloud has colours
};

//! Uncompressed: float POSITION/NORMAL, float COLOR_0 (VEC3, or VEC4 when has_alpha). Draco: the same attributes in
//! a Draco point cloud (colours as normalised unsigned bytes); accessors describe the decoded data. Passes the
//! Khronos validator. Errors: InvalidArgument (empty cloud, options out of range, invalid cloud), BudgetExceeded
//! (more than 2^32 - 2 points or 4 GiB), Internal.
Result<std::string> write_points_glb(const PointCloud& cloud, const PointGlbOptions& options = {});

}  // namespace surfaced
