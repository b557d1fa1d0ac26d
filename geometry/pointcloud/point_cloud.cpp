#include "geometry/pointcloud/point_cloud.h"

#include <cmath>
#include <string>

namespace surfaced {

Status validate(const PointCloud& cloud) {
    const std::size_t n = cloud.size();
    if (!cloud.normals.empty() && cloud.normals.size() != n)
        return make_error(ErrorCode::InvalidArgument,
                          std::to_string(cloud.normals.size()) + " normals for " + std::to_string(n) + " points");
    if (!cloud.colors.empty() && cloud.colors.size() != n)
        return make_error(ErrorCode::InvalidArgument,
                          std::to_string(cloud.colors.size()) + " colors for " + std::to_string(n) + " points");
    if (!cloud.confidence.empty() && cloud.confidence.size() != n)
        return make_error(ErrorCode::InvalidArgument, std::to_string(cloud.confidence.size()) +
                                                          " confidence values for " + std::to_string(n) + " points");
    for (std::size_t i = 0; i < n; ++i) {
        const auto id = static_cast<std::int64_t>(i);
        if (!is_finite(cloud.positions[i]))
            return element_error(ErrorCode::NonFinite, "point " + std::to_string(i) + " has a non-finite coordinate",
                                 ElementKind::Vertex, id);
        if (cloud.has_normals() && !is_finite(cloud.normals[i]))
            return element_error(ErrorCode::NonFinite, "normal of point " + std::to_string(i) + " is not finite",
                                 ElementKind::Vertex, id);
        if (cloud.has_colors()) {
            const Color& c = cloud.colors[i];
            for (float v : {c.r, c.g, c.b, c.a})
                if (!(v >= 0.0f && v <= 1.0f))
                    return element_error(ErrorCode::InvalidArgument,
                                         "color of point " + std::to_string(i) + " has a channel outside [0, 1]",
                                         ElementKind::Vertex, id);
        }
        if (cloud.has_confidence() && !(std::isfinite(cloud.confidence[i]) && cloud.confidence[i] >= 0.0f))
            return element_error(ErrorCode::InvalidArgument,
                                 "confidence of point " + std::to_string(i) + " is negative or not finite",
                                 ElementKind::Vertex, id);
    }
    return Ok{};
}

}  // namespace surfaced
