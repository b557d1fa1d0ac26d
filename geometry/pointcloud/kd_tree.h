// A static kd-tree over 3D points for k-nearest-neighbour queries (Friedman, Bentley & Finkel 1977): median splits
// on the widest axis, small leaves, branch-and-bound search with a bounded max-heap. Built once in O(n log n);
// a query visits O(log n + k) nodes on well-spread data.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "geometry/core/types.h"

namespace surfaced {

struct Neighbor {
    Index index = 0;       //!< into the points the tree was built from
    double distance2 = 0;  //!< squared Euclidean distance to the query
};

class KdTree {
public:
    //! Copies `points` (finite coordinates; fewer than 2^32).
    explicit KdTree(std::span<const Vec3> points);

    std::size_t size() const { return points_.size(); }

    //! The min(k, size()) points nearest to `query`, nearest first (ties in index order not guaranteed). A query
    //! equal to a stored point finds that point itself first, at distance 0.
    void knn(const Vec3& query, std::size_t k, std::vector<Neighbor>& out) const;

private:
    struct Node {
        double split = 0;
        std::uint32_t begin = 0, end = 0;    //!< range in order_/points_ (leaves)
        std::int32_t left = -1, right = -1;  //!< children, -1 for a leaf
        std::uint8_t axis = 0;
    };
    std::int32_t build(std::uint32_t begin, std::uint32_t end, int depth);
    void search(std::int32_t node, const Vec3& q, std::size_t k, std::vector<Neighbor>& heap) const;

    std::vector<Vec3> points_;  //!< in tree order
    std::vector<Index> order_;  //!< tree position -> original index
    std::vector<Node> nodes_;
};

}  // namespace surfaced
