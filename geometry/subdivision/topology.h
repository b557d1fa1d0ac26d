// Refinement topology: OpenSubdiv Vtr-style relation tables (face-vertices, face-edges, edge-vertices), built once for
// the base mesh and then level by level, and the queries on them that the rules share. Internal to
// geometry/subdivision.
//
// Numbering follows OpenSubdiv Far with default options so that our output can be compared index for index:
//  * base level: edges in order of first appearance walking faces and their corners, oriented as first walked;
//  * child vertices: from parent vertices, then from faces (Catmull-Clark only), then from edges;
//  * child edges: from faces first (Catmull-Clark: (face point, edge point j); Loop: (edge point j, edge point j-1)),
//    then two per parent edge, (edge point, child of edge vertex 0) and (edge point, child of edge vertex 1);
//  * child faces: grouped by parent face, one per corner (Loop: three corners, then the middle triangle).
#pragma once

#include <cstdint>
#include <memory>
#include <new>
#include <utility>
#include <vector>

#include "geometry/core/result.h"
#include "geometry/core/types.h"
#include "geometry/mesh/polygon_mesh.h"

namespace surfaced::subdivision {

//! Allocator whose resize() leaves new elements uninitialised (default-initialised): for tables that refinement
//! writes completely anyway, so that sizing them costs no pass over memory (a serial one, before the parallel fill).
template <class T>
struct UninitializedAllocator : std::allocator<T> {
    template <class U>
    struct rebind {
        using other = UninitializedAllocator<U>;
    };
    UninitializedAllocator() = default;
    template <class U>
    UninitializedAllocator(const UninitializedAllocator<U>&) noexcept {}
    template <class U>
    void construct(U* p) noexcept {
        ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
};
using IndexTable = std::vector<Index, UninitializedAllocator<Index>>;

struct Level {
    Index vertex_count = 0;
    std::vector<Index> face_offsets{0};  //!< size face_count + 1
    std::vector<Index> face_verts;       //!< std::vector: it becomes the output's face_indices
    IndexTable face_edges;               //!< edge j of a face joins corners j and j+1; parallels face_verts
    IndexTable edge_verts;               //!< two per edge
    //! Base level only (empty when there are none, and on refined levels): edges OpenSubdiv tags non-manifold while
    //! building them, beyond what face counts show: degenerate edges (a face's corner followed by the same vertex)
    //! and every instance of an edge a face uses twice (Vtr::Level::completeTopologyFromFaceVertices).
    std::vector<std::uint8_t> non_manifold_edge;

    Index face_count() const { return static_cast<Index>(face_offsets.size() - 1); }
    Index edge_count() const { return static_cast<Index>(edge_verts.size() / 2); }
};

//! Builds the base level from a validated mesh (edges by first appearance, as OpenSubdiv does). Faces may repeat a
//! vertex, as in OpenSubdiv: a corner followed by the same vertex gets a degenerate edge of its own (both ends the
//! same vertex), and a face that uses an edge a second time gets a second instance of it; both are tagged in
//! `non_manifold_edge`. Lookups of an existing edge find its first instance.
Level build_base_level(const PolygonMesh& mesh);

//! Which of the two child edges of parent edge `e` (0: at edge_verts[2e], 1: at edge_verts[2e+1]) touches corner
//! vertex `v` of a face. `corner_ends_edge`: the face runs along e into v (e is the edge before the corner) rather than
//! out of it. Only a degenerate edge (both ends v) needs that: its first child then belongs to the corner the face
//! leaves it from, its second to the corner it arrives at, as in OpenSubdiv's quad and triangle refinement.
inline Index edge_child_at(const Level& p, Index e, Index v, bool corner_ends_edge) {
    const Index a = p.edge_verts[2 * e], b = p.edge_verts[2 * e + 1];
    if (a == b) return corner_ends_edge ? 1 : 0;
    return a == v ? 0 : 1;
}

//! The end of edge `e` that is not `v`.
inline Index other_end(const Level& level, Index e, Index v) {
    return level.edge_verts[2 * e] == v ? level.edge_verts[2 * e + 1] : level.edge_verts[2 * e];
}

//! Number of face fans at each vertex: faces around a vertex are in one fan when a chain of manifold edges at the
//! vertex joins them. `edge_faces`: faces per edge; `non_manifold_edge`: edges that join no fans (per edge).
std::vector<std::uint32_t> count_fans(const Level& level, const std::vector<std::uint32_t>& edge_faces,
                                      const std::vector<std::uint8_t>& non_manifold_edge);

//! Child topology of one uniform Catmull-Clark (quad split) or Loop (triangle split) step.
//! `with_edges` = false leaves face_edges/edge_verts empty (enough for the last level).
//! `threaded`: the face and edge loops may run on two threads (results do not depend on it).
Level refine_quads(const Level& parent, bool with_edges, bool threaded = false);
Level refine_triangles(const Level& parent, bool with_edges, bool threaded = false);

}  // namespace surfaced::subdivision
