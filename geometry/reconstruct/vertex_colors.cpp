#include "geometry/reconstruct/vertex_colors.h"

#include <algorithm>
#include <limits>

#include "geometry/pointcloud/kd_tree.h"

namespace surfaced {

Result<std::vector<Color>> transfer_colors(const PolygonMesh& mesh, const PointCloud& cloud,
                                           const ColorTransferOptions& options, const Cancel& cancel) {
    if (cloud.empty()) return make_error(ErrorCode::InvalidArgument, "colors: the point cloud is empty");
    if (!cloud.has_colors()) return make_error(ErrorCode::InvalidArgument, "colors: the point cloud has no colours");
    if (options.neighbors < 1 || options.neighbors > 64)
        return make_error(ErrorCode::InvalidArgument, "colors: neighbors must be in 1..64");
    if (auto valid = validate(cloud); !valid) return valid.error();

    const KdTree tree(cloud.positions);
    const std::size_t k = std::min(options.neighbors, cloud.size());
    const Box3 box = cloud.bounds();
    const Vec3 diagonal = box.max - box.min;
    // the regulariser keeps the weight of a sample at distance 0 finite; relative to the cloud's size so that it
    // does not depend on units
    const double eps = std::max(1e-12 * dot(diagonal, diagonal), std::numeric_limits<double>::min());
    std::vector<Color> colors(mesh.vertex_count());
    std::vector<Neighbor> near;
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
        if (v % 4096 == 0 && cancel.requested()) return make_error(ErrorCode::Cancelled, "colors: cancelled");
        tree.knn(mesh.positions[v], k, near);
        double r = 0, g = 0, b = 0, a = 0, sum = 0;
        for (const Neighbor& n : near) {
            const double w = 1.0 / (n.distance2 + eps);
            const Color& c = cloud.colors[n.index];
            r += w * c.r;
            g += w * c.g;
            b += w * c.b;
            a += w * c.a;
            sum += w;
        }
        auto channel = [sum](double x) { return static_cast<float>(std::clamp(x / sum, 0.0, 1.0)); };
        colors[v] = {channel(r), channel(g), channel(b), channel(a)};
    }
    return colors;
}

}  // namespace surfaced
