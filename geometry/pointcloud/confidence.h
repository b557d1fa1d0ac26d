// Per-point confidence as reconstruction weights.
//
// reconstruct_poisson with PoissonOptions::use_confidence weighs each sample by the length of its normal (as
// PoissonRecon's --confidence does). A scanner's per-point confidence (PLY `confidence` or `quality`) becomes that
// weight by scaling each unit normal by it; a point of confidence 0 is then ignored by the reconstruction.
#pragma once

#include "geometry/pointcloud/point_cloud.h"

namespace surfaced {

//! Replaces each normal n_i by n_i / |n_i| * confidence_i, so that reconstruct_poisson with use_confidence = true
//! weighs point i by its confidence. Normals of zero length stay zero.
//! Errors: InvalidArgument (no normals or no confidence), whatever validate(cloud) reports (non-finite or negative
//! confidence, naming the point).
Status weight_normals_by_confidence(PointCloud& cloud);

}  // namespace surfaced
