// Splitting non-manifold vertices: the corners at each vertex grouped into fans, one output vertex per fan.
#pragma once

#include <vector>

#include "geometry/repair/disjoint_sets.h"
#include "geometry/repair/mesh_edges.h"

namespace surfaced::repair_detail {

//! The fan of every corner, named by its lowest corner: corners at one vertex are in one fan when their faces are
//! joined (`partner`) across an edge at that vertex, directly or around the vertex. When two faces would then share
//! an edge (both of its fans) without being joined across it (a third face on a joined edge, two joined pairs, a
//! face reached around a vertex from both sides of a cut), the extra face's corner at the edge's start is cut loose
//! from its neighbours (its joins at that corner are removed from `partner`), and the fans are formed again. Once
//! this returns, giving each fan its own vertex makes every edge used by one face or by two joined faces.
//! Corners joined into fans through `partner` alone, without any cutting.
DisjointSets join_fans(const CornerTable& table, const std::vector<Index>& partner);

//! Empty when no join was cut and the corners at every vertex form one fan (nearly every mesh: no union-find then).
std::vector<Index> fan_of_corners(const CornerTable& table, const EdgeGroups& edges, std::vector<Index>& partner,
                                  std::size_t vertex_count);

//! Vertices (below vertex_count) whose corners form more than one fan through `partner` (which pairs half-edges of
//! one undirected edge, in either direction), found by walking around each vertex; with stop_at_first, 0 or 1.
//! `first_split`, when given, is set to the lowest such vertex (left alone when there is none).
std::size_t count_split_vertices(const CornerTable& table, const std::vector<Index>& partner, std::size_t vertex_count,
                                 bool stop_at_first = false, Index* first_split = nullptr);

}  // namespace surfaced::repair_detail
