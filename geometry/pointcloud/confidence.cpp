#include "geometry/pointcloud/confidence.h"

namespace surfaced {

Status weight_normals_by_confidence(PointCloud& cloud) {
    if (!cloud.has_normals())
        return make_error(ErrorCode::InvalidArgument, "the cloud has no normals to weight by confidence");
    if (!cloud.has_confidence()) return make_error(ErrorCode::InvalidArgument, "the cloud has no confidence values");
    if (auto valid = validate(cloud); !valid) return valid.error();
    for (std::size_t i = 0; i < cloud.size(); ++i) {
        Vec3& n = cloud.normals[i];
        const double length = norm(n);
        if (length > 0) n *= static_cast<double>(cloud.confidence[i]) / length;
    }
    return Ok{};
}

}  // namespace surfaced
