// Bounding volume hierarchy over the triangles of a mesh: the one acceleration structure that closest-point, ray,
// winding-number and signed-distance queries share. Built once (binned surface area heuristic), immutable afterwards,
// so any number of threads may query it at once. Rays walk a second layout of the same tree, built with it
// (BvhOptions::ray_nodes): the binary nodes collapsed into 8-wide nodes with float boxes rounded outward, and each
// ray leaf's triangles in float blocks of four, which a ray tests together before the exact double-precision test
// reads the copies of the same triangles stored beside them. On the Stanford bunny (69,666 triangles) the binary
// nodes and triangles take 9.9 MiB, the ray layout 9.1 MiB more.
//
// References: I. Wald, "On fast Construction of SAH-based Bounding Volume Hierarchies", IEEE RT 2007 (binned SAH).
//             T. Ize, "Robust BVH Ray Traversal", JCGT 2(2), 2013 (the conservative slab test, ray_cast.cpp).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "geometry/core/cancel.h"
#include "geometry/core/result.h"
#include "geometry/core/types.h"
#include "geometry/mesh/polygon_mesh.h"

namespace surfaced {

struct BvhOptions {
    //! A node with at most this many triangles becomes a leaf when the SAH says splitting does not pay; nodes with
    //! more are always split. 1..64.
    int max_leaf_size = 4;
    //! Centroid bins per axis for the SAH sweep. 2..256.
    int bins = 16;
    //! Polygons with more than three vertices are triangulated (geometry/mesh/triangulate.h); false refuses them
    //! with NotTriangleMesh.
    bool triangulate = true;
    //! Also build the 8-wide float layout that ray casting traverses (TriangleBvh::ray_nodes, ray_triangles), about
    //! twice the memory of the binary nodes and triangles. Without it rays walk the binary double-precision nodes, with the same answers but fewer
    //! rays per second (see docs/benchmarks.md); closest points and winding numbers never use it.
    bool ray_nodes = true;
    Cancel cancel;
};

//! One node of the flat, depth-first node array. An inner node's left child is the next node in the array and its
//! right child is `index`; a leaf's triangles are `index .. index + count` of TriangleBvh::triangles.
struct BvhNode {
    Box3 bounds;
    Index index = 0;
    Index count = 0;  //!< 0 for an inner node
    bool is_leaf() const { return count != 0; }
};

//! A triangle in leaf order: its corners' positions (copied, so that a leaf is read from one place), the vertex
//! indices of the mesh they come from, and the mesh face it is part of (a polygon's triangles share its face).
struct BvhTriangle {
    std::array<Vec3, 3> p;
    std::array<Index, 3> vertices;
    Index face = 0;
};

//! One node of the ray layout: up to eight children whose boxes are tested at once (SIMD), in float, each box the
//! double box of a node of the binary hierarchy rounded outward, so that it still contains every triangle below it.
//! A child is an inner node (count 0, `child` its index in TriangleBvh::ray_nodes), a leaf (count > 0: triangles
//! `child .. child + count` of TriangleBvh::triangles, in float and copied in TriangleBvh::ray_triangles), or an
//! unused slot (count 0 and an empty box, min > max, that no ray enters). Boxes are stored by plane then child:
//! box[0..2] the min x, y, z planes, box[3..5] the max planes.
inline constexpr int kRayNodeWidth = 8;
struct alignas(64) RayNode {
    float box[6][kRayNodeWidth];
    std::uint32_t child[kRayNodeWidth];
    std::uint8_t count[kRayNodeWidth];
};

//! Four consecutive triangles of TriangleBvh::triangles (block b holds 4b .. 4b + 3), in the two forms a ray reads:
//! in float, relative to TriangleBvh::ray_centre, by coordinate then triangle (p[3 * corner + axis][lane]), which a
//! ray tests four at once to discard those it surely misses; and copies of the four BvhTriangles, which the exact
//! double-precision test and the hit read. Side by side, a leaf is one stream of memory rather than two (512 bytes,
//! eight cache lines, a block). The last block's unused lanes hold zeros.
struct alignas(64) RayTriangles {
    float p[9][4] = {};
    BvhTriangle triangle[4] = {};
};

struct TriangleBvh {
    std::vector<BvhNode> nodes;  //!< nodes[0] is the root; empty for a mesh without faces
    std::vector<BvhTriangle> triangles;
    //! The same hierarchy for rays (BvhOptions::ray_nodes): the binary tree collapsed into 8-wide nodes, subtrees of
    //! at most sixteen triangles (or a larger binary leaf) made leaves; ray_nodes[0] is the root. Empty when not built:
    //! rays then walk `nodes`.
    std::vector<RayNode> ray_nodes;
    std::vector<RayTriangles> ray_triangles;  //!< `triangles` in float and copied, four a block
    Vec3 ray_centre;                          //!< the root box's centre, which ray_triangles are relative to
    double ray_extent = 0;                    //!< largest |coordinate - ray_centre| of any triangle corner
    std::size_t face_count = 0;               //!< faces of the input mesh
    bool triangulated = false;                //!< the input had polygons that were split into triangles
    std::size_t depth = 0;                    //!< levels from the root to the deepest leaf (1 for a single leaf)

    bool empty() const { return nodes.empty(); }
    const Box3& bounds() const { return nodes.front().bounds; }
    //! Bytes held by the node and triangle arrays.
    std::size_t memory_bytes() const {
        return nodes.capacity() * sizeof(BvhNode) + triangles.capacity() * sizeof(BvhTriangle) +
               ray_nodes.capacity() * sizeof(RayNode) + ray_triangles.capacity() * sizeof(RayTriangles);
    }
};

//! Builds the hierarchy over the mesh's triangles. The mesh must pass validate() (finite coordinates, indices in
//! range); polygons are triangulated unless options.triangulate is false (NotTriangleMesh then). A mesh without
//! faces gives an empty hierarchy, which every query treats as "nothing there". O(F log F) time, O(F) memory
//! (nodes <= 2F - 1). InvalidArgument for options out of range; Cancelled when options.cancel fires.
Result<TriangleBvh> build_bvh(const PolygonMesh& mesh, const BvhOptions& options = {});

//! Squared distance from p to the box (0 inside).
inline double squared_distance(const Box3& box, const Vec3& p) {
    double d2 = 0;
    for (int i = 0; i < 3; ++i) {
        const double below = box.min[i] - p[i], above = p[i] - box.max[i];
        const double d = below > 0 ? below : (above > 0 ? above : 0.0);
        d2 += d * d;
    }
    return d2;
}

}  // namespace surfaced
