// Colours for a reconstructed surface from the coloured samples it was built from.
//
// Each mesh vertex takes an inverse-distance-weighted blend of the colours of its k nearest samples
// (weights 1 / (d^2 + eps), eps = 1e-12 times the squared bounding diagonal, so a vertex on a sample takes that
// sample's colour). Blending k > 1 samples smooths scanner colour noise and the seams a nearest-sample lookup
// shows between neighbouring samples; k = 1 is the nearest sample's colour exactly.
#pragma once

#include <cstddef>
#include <vector>

#include "geometry/core/cancel.h"
#include "geometry/core/result.h"
#include "geometry/mesh/polygon_mesh.h"
#include "geometry/pointcloud/point_cloud.h"

namespace surfaced {

struct ColorTransferOptions {
    std::size_t neighbors = 4;  //!< k nearest samples blended; 1..64
};

//! One colour per vertex of `mesh` (PolygonMesh has no colour attribute: the caller carries them beside it, e.g.
//! into PLY red/green/blue or glTF COLOR_0). Call it after trim_reconstruction, which renumbers vertices. Alpha is
//! blended like the other channels (1 when the cloud has no alpha).
//! Errors: InvalidArgument (the cloud has no colours or no points, neighbors out of range), Cancelled.
Result<std::vector<Color>> transfer_colors(const PolygonMesh& mesh, const PointCloud& cloud,
                                           const ColorTransferOptions& options = {}, const Cancel& cancel = {});

}  // namespace surfaced
