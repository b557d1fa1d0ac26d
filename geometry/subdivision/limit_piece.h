// Local refinement for limit evaluation (limit_evaluation.h): a piece of one refinement level cut around one face,
// one subdivision step of such a piece with subdivide()'s rules (Catmull-Clark or Loop), and the adjacency queries
// that the regular-patch tests share. Internal to geometry/subdivision.
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/core/types.h"
#include "geometry/subdivision/creases.h"
#include "geometry/subdivision/subdivide.h"
#include "geometry/subdivision/topology.h"

namespace surfaced::subdivision {

//! A piece of one refinement level: topology, sharpness and points, cut around one face.
struct Piece {
    Level level;
    Sharpness sharp;
    std::vector<Vec3> points;
    Index target = 0;  //!< the face the piece was cut around
};

//! Vertex -> faces lists of a level.
void vertex_faces(const Level& level, std::vector<Index>& offsets, std::vector<Index>& faces);

//! The faces of `src` within two vertex rings of `face` (its corners first among the vertices): enough for one
//! Catmull-Clark or Loop step to give exact points, sharpness and topology on the child faces' 2-rings. Sharpness is
//! copied, not recomputed, so that the piece's cut edges keep their true (usually smooth) rule.
Piece extract(const Piece& src, const std::vector<Index>& vf_offsets, const std::vector<Index>& vf_faces, Index face);

//! One step of options.scheme over a whole piece, with subdivide()'s rules (`first_level`: the base mesh's step,
//! where the Catmull-Clark triangle rule applies).
Piece refine(const Piece& p, const SubdivisionOptions& options, bool first_level);

//! The index, in the refined level, of child `j` of face `f` (quads: one per corner; triangles: three corners, then
//! the middle one).
inline Index child_face(const Level& parent, Index f, int j, bool loop) {
    return (loop ? 4 * f : parent.face_offsets[f]) + static_cast<Index>(j);
}

//! Edge -> faces (up to two recorded, and the count) and vertex -> faces of a small level.
struct Adjacency {
    std::vector<Index> edge_face0, edge_face1;
    std::vector<std::uint32_t> edge_uses;
    std::vector<Index> vf_offsets, vf_faces;
    explicit Adjacency(const Level& L);
    Index across(Index e, Index f) const { return edge_face0[e] == f ? edge_face1[e] : edge_face0[e]; }
};

//! The slot of vertex v in face f (its first), or kInvalidIndex.
Index slot_of(const Level& L, Index f, Index v);

//! Corner k (taken modulo the face's size) of face f.
inline Index face_vert(const Level& L, Index f, Index k) {
    const Index n = L.face_offsets[f + 1] - L.face_offsets[f];
    return L.face_verts[L.face_offsets[f] + k % n];
}

}  // namespace surfaced::subdivision
