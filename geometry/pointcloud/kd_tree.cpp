#include "geometry/pointcloud/kd_tree.h"

#include <algorithm>
#include <numeric>

namespace surfaced {
namespace {

constexpr std::uint32_t kLeafSize = 12;

bool heap_less(const Neighbor& a, const Neighbor& b) { return a.distance2 < b.distance2; }

}  // namespace

KdTree::KdTree(std::span<const Vec3> points) : points_(points.begin(), points.end()), order_(points.size()) {
    std::iota(order_.begin(), order_.end(), Index{0});
    if (!points_.empty()) {
        nodes_.reserve(2 * (points_.size() / kLeafSize + 1));
        build(0, static_cast<std::uint32_t>(points_.size()), 0);
        // store the points in tree order so that leaves are contiguous in memory
        std::vector<Vec3> sorted(points_.size());
        for (std::size_t i = 0; i < order_.size(); ++i) sorted[i] = points[order_[i]];
        points_ = std::move(sorted);
    }
}

std::int32_t KdTree::build(std::uint32_t begin, std::uint32_t end, int depth) {
    const auto id = static_cast<std::int32_t>(nodes_.size());
    nodes_.push_back(Node{0, begin, end, -1, -1, 0});
    if (end - begin <= kLeafSize || depth > 64) return id;
    // split the widest axis of this node's points at the median
    Box3 box;
    for (std::uint32_t i = begin; i < end; ++i) box.add(points_[order_[i]]);
    const Vec3 extent = box.max - box.min;
    int axis = 0;
    if (extent.y > extent[axis]) axis = 1;
    if (extent.z > extent[axis]) axis = 2;
    if (extent[axis] <= 0) return id;  // all points equal: one leaf
    const std::uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                     [&](Index a, Index b) { return points_[a][axis] < points_[b][axis]; });
    nodes_[static_cast<std::size_t>(id)].axis = static_cast<std::uint8_t>(axis);
    nodes_[static_cast<std::size_t>(id)].split = points_[order_[mid]][axis];
    const std::int32_t left = build(begin, mid, depth + 1);
    const std::int32_t right = build(mid, end, depth + 1);
    nodes_[static_cast<std::size_t>(id)].left = left;
    nodes_[static_cast<std::size_t>(id)].right = right;
    return id;
}

void KdTree::search(std::int32_t node_id, const Vec3& q, std::size_t k, std::vector<Neighbor>& heap) const {
    const Node& node = nodes_[static_cast<std::size_t>(node_id)];
    if (node.left < 0) {
        for (std::uint32_t i = node.begin; i < node.end; ++i) {
            const Vec3 d = points_[i] - q;
            const double d2 = dot(d, d);
            if (heap.size() < k) {
                heap.push_back({order_[i], d2});
                std::push_heap(heap.begin(), heap.end(), heap_less);
            } else if (d2 < heap.front().distance2) {
                std::pop_heap(heap.begin(), heap.end(), heap_less);
                heap.back() = {order_[i], d2};
                std::push_heap(heap.begin(), heap.end(), heap_less);
            }
        }
        return;
    }
    // Points equal to the split value may sit on either side (nth_element), so the far side is visited whenever
    // the query's slab distance does not exceed the current k-th distance.
    const double diff = q[node.axis] - node.split;
    const std::int32_t near = diff < 0 ? node.left : node.right;
    const std::int32_t far = diff < 0 ? node.right : node.left;
    search(near, q, k, heap);
    if (heap.size() < k || diff * diff <= heap.front().distance2) search(far, q, k, heap);
}

void KdTree::knn(const Vec3& query, std::size_t k, std::vector<Neighbor>& out) const {
    out.clear();
    if (k == 0 || points_.empty()) return;
    k = std::min(k, points_.size());
    out.reserve(k);
    search(0, query, k, out);
    std::sort_heap(out.begin(), out.end(), heap_less);
}

}  // namespace surfaced
