// The triangle hierarchy: every triangle in exactly one leaf, boxes nested and tight around what they hold, leaf sizes
// within the option, polygons triangulated or refused, degenerate inputs (coincident centroids) still split.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <algorithm>
#include <array>
#include <map>

#include "geometry/mesh/shapes.h"
#include "geometry/spatial/bvh.h"
#include "tests/support/spatial_meshes.h"

namespace surfaced {
namespace {

bool contains(const Box3& outer, const Box3& inner) {
    return outer.min.x <= inner.min.x && outer.min.y <= inner.min.y && outer.min.z <= inner.min.z &&
           outer.max.x >= inner.max.x && outer.max.y >= inner.max.y && outer.max.z >= inner.max.z;
}

//! Walks the tree from the root and checks its invariants; returns how often each triangle slot is reached.
std::vector<int> check_tree(const TriangleBvh& bvh, int max_leaf) {
    std::vector<int> seen(bvh.triangles.size(), 0);
    std::vector<int> visits(bvh.nodes.size(), 0);
    std::vector<std::pair<Index, std::size_t>> stack{{0, 1}};
    std::size_t deepest = 0;
    while (!stack.empty()) {
        const auto [k, depth] = stack.back();
        stack.pop_back();
        deepest = std::max(deepest, depth);
        EXPECT_LT(k, bvh.nodes.size());
        if (k >= bvh.nodes.size()) return seen;
        ++visits[k];
        const BvhNode& node = bvh.nodes[k];
        if (node.is_leaf()) {
            EXPECT_LE(node.count, static_cast<Index>(max_leaf));
            Box3 tight;
            for (Index i = node.index; i < node.index + node.count; ++i) {
                ++seen[i];
                for (const Vec3& p : bvh.triangles[i].p) tight.add(p);
            }
            EXPECT_TRUE(contains(node.bounds, tight) && contains(tight, node.bounds)) << "leaf " << k << " not tight";
            continue;
        }
        const BvhNode& l = bvh.nodes[k + 1];
        const BvhNode& r = bvh.nodes[node.index];
        EXPECT_GT(node.index, k + 1);
        EXPECT_TRUE(contains(node.bounds, l.bounds) && contains(node.bounds, r.bounds)) << "node " << k;
        stack.push_back({k + 1, depth + 1});
        stack.push_back({node.index, depth + 1});
    }
    for (std::size_t k = 0; k < visits.size(); ++k) EXPECT_EQ(visits[k], 1) << "node " << k;
    EXPECT_EQ(deepest, bvh.depth);
    return seen;
}

//! The mesh's triangles as sorted (face, vertices) keys, with multiplicity.
std::map<std::array<Index, 4>, int> triangle_keys(const PolygonMesh& mesh) {
    std::map<std::array<Index, 4>, int> keys;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const auto face = mesh.face(f);
        keys[{static_cast<Index>(f), face[0], face[1], face[2]}]++;
    }
    return keys;
}

TEST(Bvh, EveryTriangleInOneLeafAndBoxesNested) {
    for (int max_leaf : {1, 4, 8}) {
        const PolygonMesh mesh = testing::icosphere(4);
        BvhOptions options;
        options.max_leaf_size = max_leaf;
        auto bvh = build_bvh(mesh, options);
        ASSERT_TRUE(bvh.ok()) << bvh.error().message;
        ASSERT_EQ(bvh->triangles.size(), mesh.face_count());
        EXPECT_LE(bvh->nodes.size(), 2 * mesh.face_count() - 1);
        EXPECT_FALSE(bvh->triangulated);
        const auto seen = check_tree(*bvh, max_leaf);
        for (std::size_t i = 0; i < seen.size(); ++i) EXPECT_EQ(seen[i], 1) << "slot " << i;
        // the slots hold each input triangle once, with its positions
        std::map<std::array<Index, 4>, int> keys;
        for (const BvhTriangle& t : bvh->triangles) {
            keys[{t.face, t.vertices[0], t.vertices[1], t.vertices[2]}]++;
            for (int c = 0; c < 3; ++c) EXPECT_EQ(t.p[c], mesh.positions[t.vertices[c]]);
        }
        EXPECT_EQ(keys, triangle_keys(mesh));
        // a balanced-enough tree: SAH on a sphere stays far from the worst case
        EXPECT_LE(bvh->depth, 40u);
    }
}

TEST(Bvh, PolygonsAreTriangulatedOrRefused) {
    const PolygonMesh cube = shapes::cube();
    auto bvh = build_bvh(cube);
    ASSERT_TRUE(bvh.ok());
    EXPECT_TRUE(bvh->triangulated);
    EXPECT_EQ(bvh->face_count, 6u);
    ASSERT_EQ(bvh->triangles.size(), 12u);
    std::vector<int> per_face(6, 0);
    for (const BvhTriangle& t : bvh->triangles) {
        ASSERT_LT(t.face, 6u);
        ++per_face[t.face];
        // each triangle's corners are corners of its quad
        const auto quad = cube.face(t.face);
        for (Index v : t.vertices) EXPECT_NE(std::find(quad.begin(), quad.end(), v), quad.end());
    }
    for (int n : per_face) EXPECT_EQ(n, 2);

    BvhOptions refuse;
    refuse.triangulate = false;
    auto refused = build_bvh(cube, refuse);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().code, ErrorCode::NotTriangleMesh);
    EXPECT_EQ(refused.error().element_kind, ElementKind::Face);
    EXPECT_EQ(refused.error().element, 0);
}

TEST(Bvh, InvalidInputAndOptions) {
    PolygonMesh bad = shapes::tetrahedron();
    bad.face_indices[4] = 99;
    auto r = build_bvh(bad);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, ErrorCode::IndexOutOfRange);

    for (int leaf : {0, 65}) {
        BvhOptions options;
        options.max_leaf_size = leaf;
        auto out = build_bvh(shapes::tetrahedron(), options);
        ASSERT_FALSE(out.ok());
        EXPECT_EQ(out.error().code, ErrorCode::InvalidArgument);
    }
    BvhOptions one_bin;
    one_bin.bins = 1;
    EXPECT_FALSE(build_bvh(shapes::tetrahedron(), one_bin).ok());

    auto empty = build_bvh(PolygonMesh{});
    ASSERT_TRUE(empty.ok());
    EXPECT_TRUE(empty->empty());
}

TEST(Bvh, CoincidentTrianglesStillSplitToLeafSize) {
    // 1000 copies of one triangle: every centroid is the same point, no SAH split separates them
    PolygonMesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    for (int i = 0; i < 1000; ++i) mesh.add_face({0, 1, 2});
    auto bvh = build_bvh(mesh);
    ASSERT_TRUE(bvh.ok());
    const auto seen = check_tree(*bvh, 4);
    for (int s : seen) EXPECT_EQ(s, 1);
    EXPECT_LE(bvh->depth, 12u);  // halving 1000 down to <= 4
}

TEST(Bvh, CancelledBuildReportsCancelled) {
    BvhOptions options;
    options.cancel.deadline = Cancel::Clock::now() - std::chrono::seconds(1);
    auto out = build_bvh(testing::icosphere(5), options);  // 20480 triangles, more nodes than the polling interval
    ASSERT_FALSE(out.ok());
    EXPECT_EQ(out.error().code, ErrorCode::Cancelled);
}

//! Walks the ray layout from its root: every slot used is a node reached once or a leaf of triangles whose copies
//! (float and double) are in the blocks; every box (float) contains what is below it in double; unused slots have empty boxes.
//! Returns how often each triangle is reached.
std::vector<int> check_ray_nodes(const TriangleBvh& bvh) {
    std::vector<int> seen(bvh.triangles.size(), 0);
    std::vector<int> visits(bvh.ray_nodes.size(), 0);
    const Vec3 c = bvh.ray_centre;
    // the double box of what is below a slot
    std::function<Box3(Index, Index)> below = [&](Index child, Index count) {
        Box3 box;
        if (count > 0) {
            for (Index t = child; t < child + count; ++t) {
                EXPECT_LT(t, bvh.triangles.size());
                if (t >= bvh.triangles.size()) return box;
                ++seen[t];
                const RayTriangles& block = bvh.ray_triangles[t / 4];
                // the copy the exact test and the hit read is the triangle itself
                const BvhTriangle& copy = block.triangle[t % 4];
                EXPECT_EQ(copy.face, bvh.triangles[t].face);
                EXPECT_EQ(copy.vertices, bvh.triangles[t].vertices);
                for (int k = 0; k < 3; ++k)
                    for (int a = 0; a < 3; ++a) EXPECT_EQ(copy.p[k][a], bvh.triangles[t].p[k][a]);
                for (int k = 0; k < 3; ++k) {
                    const Vec3& p = bvh.triangles[t].p[k];
                    box.add(p);
                    for (int a = 0; a < 3; ++a) {
                        EXPECT_EQ(block.p[3 * k + a][t % 4], static_cast<float>(p[a] - c[a]));
                        EXPECT_LE(std::fabs(p[a] - c[a]), bvh.ray_extent * (1 + 1e-15));
                    }
                }
            }
            return box;
        }
        EXPECT_LT(child, bvh.ray_nodes.size());
        if (child >= bvh.ray_nodes.size()) return box;
        ++visits[child];
        const RayNode& node = bvh.ray_nodes[child];
        for (int k = 0; k < kRayNodeWidth; ++k) {
            const bool unused = node.count[k] == 0 && node.box[0][k] > node.box[3][k];
            if (unused) {
                for (int a = 0; a < 3; ++a) {
                    EXPECT_EQ(node.box[a][k], std::numeric_limits<float>::infinity());
                    EXPECT_EQ(node.box[3 + a][k], -std::numeric_limits<float>::infinity());
                }
                continue;
            }
            const Box3 inner = below(node.child[k], node.count[k]);
            for (int a = 0; a < 3; ++a) {
                EXPECT_LE(static_cast<double>(node.box[a][k]), inner.min[a]) << "node " << child << " slot " << k;
                EXPECT_GE(static_cast<double>(node.box[3 + a][k]), inner.max[a]) << "node " << child << " slot " << k;
                // rounded outward by at most one float step
                EXPECT_GE(static_cast<double>(std::nextafter(node.box[a][k], std::numeric_limits<float>::infinity())),
                          inner.min[a]);
            }
            box.add(inner.min);
            box.add(inner.max);
        }
        return box;
    };
    below(0, 0);
    for (std::size_t k = 0; k < visits.size(); ++k) EXPECT_EQ(visits[k], 1) << "ray node " << k;
    return seen;
}

TEST(Bvh, RayNodesContainTheirTrianglesOnce) {
    for (int max_leaf : {1, 4, 64}) {
        for (const PolygonMesh& mesh :
             {testing::icosphere(4), testing::translated(shapes::torus(40, 30), {1e6, -3e5, 2.5}), shapes::cube()}) {
            BvhOptions options;
            options.max_leaf_size = max_leaf;
            auto bvh = build_bvh(mesh, options);
            ASSERT_TRUE(bvh.ok());
            ASSERT_FALSE(bvh->ray_nodes.empty());
            const auto seen = check_ray_nodes(*bvh);
            for (std::size_t i = 0; i < seen.size(); ++i) EXPECT_EQ(seen[i], 1) << "triangle " << i;
            EXPECT_LE(bvh->ray_nodes.size(), bvh->nodes.size());
            EXPECT_EQ(bvh->ray_triangles.size(), (bvh->triangles.size() + 3) / 4);
            EXPECT_EQ(bvh->memory_bytes(), bvh->nodes.capacity() * sizeof(BvhNode) +
                                               bvh->triangles.capacity() * sizeof(BvhTriangle) +
                                               bvh->ray_nodes.capacity() * sizeof(RayNode) +
                                               bvh->ray_triangles.capacity() * sizeof(RayTriangles));
        }
    }
    // a single triangle: the root is one leaf in an otherwise unused node
    PolygonMesh one;
    one.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    one.add_face({0, 1, 2});
    auto bvh = build_bvh(one);
    ASSERT_TRUE(bvh.ok());
    ASSERT_EQ(bvh->ray_nodes.size(), 1u);
    EXPECT_EQ(bvh->ray_nodes[0].count[0], 1);
    EXPECT_EQ(check_ray_nodes(*bvh), std::vector<int>{1});
    // not asked for: none
    BvhOptions without;
    without.ray_nodes = false;
    auto plain = build_bvh(testing::icosphere(2), without);
    ASSERT_TRUE(plain.ok());
    EXPECT_TRUE(plain->ray_nodes.empty());
    EXPECT_TRUE(plain->ray_triangles.empty());
}

}  // namespace
}  // namespace surfaced
