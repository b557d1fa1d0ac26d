// Signed distance to a triangle mesh: the distance to the closest surface point, negative inside. Inside is decided
// by the generalized winding number (w >= 1/2), not by the normal at the closest point or by ray parity, so it stays
// right on meshes with holes, self-intersections, overlapping parts and non-manifold edges.
#pragma once

#include "geometry/core/result.h"
#include "geometry/spatial/closest_point.h"
#include "geometry/spatial/winding_number.h"

namespace surfaced {

struct SignedDistanceOptions {
    WindingNumberOptions winding;  //!< how the sign's winding number is computed (hierarchical by default)
};

struct SignedDistance {
    double distance = 0;  //!< |distance| = closest.distance; < 0 inside (winding >= 1/2)
    SurfacePoint closest;
    WindingNumber winding;
};

//! The signed distance at `query`. `tree` must come from build_winding_tree(bvh). InvalidArgument for an empty
//! hierarchy (no surface to be near), a non-finite query or winding options out of range.
Result<SignedDistance> signed_distance(const TriangleBvh& bvh, const WindingTree& tree, const Vec3& query,
                                       const SignedDistanceOptions& options = {});

}  // namespace surfaced
