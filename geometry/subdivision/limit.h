// Limit positions and normals at the vertices of a refined level (internal to geometry/subdivision).
#pragma once

#include <vector>

#include "geometry/core/types.h"
#include "geometry/subdivision/topology.h"

namespace surfaced::subdivision {

//! Evaluates the limit position and unit normal of vertices [0, count) of `level` from the level's points, with
//! OpenSubdiv's limit masks (smooth, crease, corner; Catmull-Clark needs an all-quad level). Sharpness must be
//! 0 or infinite here (semi-sharp features give a limit only after they decay: the caller refines past them).
//! `warren`: Loop with Warren's weights (the limit position mask follows the scheme's vertex weight).
//! Vertices whose faces do not form one fan (non-manifold) keep their position and get the area-weighted normal.
void evaluate_limit(const Level& level, const std::vector<float>& edge_sharpness,
                    const std::vector<float>& vertex_sharpness, bool loop, bool warren, const Vec3* points, Index count,
                    Vec3* limit_positions, Vec3* limit_normals);

}  // namespace surfaced::subdivision
