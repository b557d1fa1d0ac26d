// CGAL's AABB_tree as the closest-point peer of bench_spatial_peers. CGAL's and Boost's headers compile here only.
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/version.h>

#include "bench/spatial_peers.h"

namespace surfaced::bench {

namespace {
using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;
using Iterator = std::vector<Triangle>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, Iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
}  // namespace

struct CgalTree::Impl {
    std::vector<Triangle> triangles;
    Tree tree;
};

CgalTree::CgalTree(const std::vector<double>& positions, const std::vector<unsigned>& triangles)
    : impl_(std::make_unique<Impl>()) {
    auto point = [&](unsigned v) { return Point(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]); };
    impl_->triangles.reserve(triangles.size() / 3);
    for (std::size_t t = 0; t + 2 < triangles.size(); t += 3)
        impl_->triangles.emplace_back(point(triangles[t]), point(triangles[t + 1]), point(triangles[t + 2]));
    impl_->tree.insert(impl_->triangles.cbegin(), impl_->triangles.cend());
    impl_->tree.build();
    impl_->tree.accelerate_distance_queries();
    // both structures are built lazily in some CGAL versions: one query forces them
    (void)impl_->tree.closest_point(point(0));
}

CgalTree::~CgalTree() = default;

void CgalTree::closest_points(const std::vector<double>& queries, std::vector<double>& out) const {
    out.resize(queries.size());
    for (std::size_t i = 0; i + 2 < queries.size(); i += 3) {
        const Point p = impl_->tree.closest_point(Point(queries[i], queries[i + 1], queries[i + 2]));
        out[i] = p.x();
        out[i + 1] = p.y();
        out[i + 2] = p.z();
    }
}

std::string cgal_version() { return CGAL_VERSION_STR; }

}  // namespace surfaced::bench
