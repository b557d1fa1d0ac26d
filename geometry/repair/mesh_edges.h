// Corners and edges of a face list, for the repair steps: the face and neighbours of each corner, and the half-edges
// (corner c -> the next corner of its face) grouped by undirected edge. Faces must not repeat a vertex.
#pragma once

#include <span>
#include <vector>

#include "geometry/core/types.h"

namespace surfaced::repair_detail {

struct CornerTable {
    std::span<const Index> offsets;   //!< face f: corners offsets[f] .. offsets[f+1]
    std::span<const Index> indices;   //!< vertex of each corner
    std::vector<Index> corner_faces;  //!< face of each corner; empty when every face is a triangle
    bool triangles = false;           //!< every face is a triangle: corner c is corner c % 3 of face c / 3

    std::size_t corner_count() const { return indices.size(); }
    Index face(Index c) const { return triangles ? c / 3 : corner_faces[c]; }
    Index next(Index c) const {
        if (triangles) return c % 3 == 2 ? c - 2 : c + 1;
        return c + 1 == offsets[corner_faces[c] + 1] ? offsets[corner_faces[c]] : c + 1;
    }
    Index prev(Index c) const {
        if (triangles) return c % 3 == 0 ? c + 2 : c - 1;
        return c == offsets[corner_faces[c]] ? offsets[corner_faces[c] + 1] - 1 : c - 1;
    }
    //! The corner of c's face at vertex v (which the face must use).
    Index corner_at(Index c, Index v) const {
        Index k = offsets[face(c)];
        while (indices[k] != v) ++k;
        return k;
    }
};
CornerTable make_corner_table(std::span<const Index> offsets, std::span<const Index> indices);

//! Half-edges grouped by undirected edge. Edge e is used by the half-edges of corners[begin[e] .. begin[e+1]), in
//! increasing corner order; edges are ordered by (lower vertex, higher vertex).
struct EdgeGroups {
    std::vector<Index> corners;
    std::vector<Index> begin;        //!< size edge_count() + 1
    std::vector<Index> vertex_edge;  //!< edges whose lower vertex is v: vertex_edge[v] .. vertex_edge[v+1]

    std::size_t edge_count() const { return begin.size() - 1; }
    std::size_t size(std::size_t e) const { return begin[e + 1] - begin[e]; }
    std::span<const Index> of(std::size_t e) const { return {corners.data() + begin[e], size(e)}; }
    //! The edge between a and b, or kInvalidIndex when no face uses it.
    Index find(const CornerTable& table, Index a, Index b) const;
};
EdgeGroups group_edges(const CornerTable& table, std::size_t vertex_count);

}  // namespace surfaced::repair_detail
