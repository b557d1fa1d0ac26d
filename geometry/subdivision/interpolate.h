// One level of point interpolation: the child points of a Catmull-Clark or Loop step from the parent level's points,
// with the smooth weights of rules.h and, where sharpness governs, the crease rules of creases.h. Used for positions
// and for face-varying values alike. Internal to geometry/subdivision.
#pragma once

#include "geometry/core/types.h"
#include "geometry/subdivision/creases.h"
#include "geometry/subdivision/subdivide.h"
#include "geometry/subdivision/topology.h"

namespace surfaced::subdivision {

//! The parent level and the options that shape its child points.
struct LevelInput {
    const Level& topology;
    const Sharpness& sharp;
    CreaseMethod method;
    TriangleRule triangle_rule;
    LoopWeights loop_weights;
    bool threaded;
};

//! One Catmull-Clark level: `src` has a point per vertex of in.topology, `dst` gets one per child vertex (children of
//! vertices, faces, edges) and must be all zero on entry. `n`: the parent level's neighbourhood.
void interpolate_catmark(const LevelInput& in, const Neighbourhood& n, const Vec3* src, Vec3* dst);

//! One Loop level: as interpolate_catmark, with children of vertices, then of edges.
void interpolate_loop(const LevelInput& in, const Neighbourhood& n, const Vec3* src, Vec3* dst);

}  // namespace surfaced::subdivision
