// Level-set grids: a dense array of samples (x varying fastest) with an origin and a per-axis spacing, read by
// trilinear interpolation. Sample (i, j, k) sits at origin + (i hx, j hy, k hz) and is values[i + nx (j + ny k)].
//
// Inside the grid box the value is the trilinear interpolant and the gradient its exact derivative (one-sided at
// cell faces). Outside, the value is f(c) + |p - c| with c the closest point of the box (p clamped): continuous,
// equal to the grid on its boundary and growing outward, so a surface that is open at the grid boundary is closed
// within |f| of it and nothing appears far away. The gradient there is that of the same expression.
//
// FieldKind::DistanceBound with an exact Lipschitz constant: inside a cell the partial derivative along x is a
// bilinear blend of the cell's four x-differences / hx, so |∂f/∂x| <= Gx (the largest such difference over the grid)
// and likewise for y, z; L = sqrt(Gx² + Gy² + Gz²) + 1 (the + 1 for the outside extension), at least 1. Hence
// |f(p)| / L never exceeds the distance to the zero set, whatever the samples are (a true SDF gives L close to 2).
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "geometry/core/result.h"
#include "geometry/implicit/primitives.h"

namespace surfaced::implicit {

struct LevelSetGrid {
    std::array<std::size_t, 3> dims{0, 0, 0};  //!< samples per axis, each >= 2
    Vec3 origin;
    Vec3 spacing{1, 1, 1};       //!< > 0 per axis
    std::vector<double> values;  //!< dims[0] * dims[1] * dims[2] finite samples, x fastest
};

//! Validates the grid (InvalidArgument / NonFinite with the sample index in GeoError::element) and wraps it.
Result<FieldPtr> level_set(LevelSetGrid grid);

}  // namespace surfaced::implicit
