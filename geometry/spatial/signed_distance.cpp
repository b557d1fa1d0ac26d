#include "geometry/spatial/signed_distance.h"

namespace surfaced {

Result<SignedDistance> signed_distance(const TriangleBvh& bvh, const WindingTree& tree, const Vec3& query,
                                       const SignedDistanceOptions& options) {
    if (bvh.empty()) return make_error(ErrorCode::InvalidArgument, "signed distance to a mesh without faces");
    auto winding = winding_number(bvh, tree, query, options.winding);
    if (!winding) return winding.error();
    auto closest = closest_point(bvh, query);
    if (!closest) return make_error(ErrorCode::Internal, "no closest point on a non-empty hierarchy");
    SignedDistance out;
    out.closest = *closest;
    out.winding = *winding;
    out.distance = winding->value >= 0.5 ? -closest->distance : closest->distance;
    return out;
}

}  // namespace surfaced
