// Grouping half-edges by undirected edge: a counting sort by the lower vertex, then a sort of each (small) bucket by
// the higher vertex. Linear in the corners for meshes of bounded valence.
#include "geometry/repair/mesh_edges.h"

#include <algorithm>
#include <cstdint>
#include <utility>

namespace surfaced::repair_detail {

CornerTable make_corner_table(std::span<const Index> offsets, std::span<const Index> indices) {
    CornerTable table{offsets, indices, {}, true};
    for (std::size_t f = 0; f + 1 < offsets.size() && table.triangles; ++f)
        table.triangles = offsets[f + 1] == 3 * (f + 1);
    if (table.triangles) return table;
    table.corner_faces.resize(indices.size());
    for (std::size_t f = 0; f + 1 < offsets.size(); ++f)
        for (Index c = offsets[f]; c < offsets[f + 1]; ++c) table.corner_faces[c] = static_cast<Index>(f);
    return table;
}

EdgeGroups group_edges(const CornerTable& table, std::size_t vertex_count) {
    const std::size_t n = table.corner_count();
    const std::span<const Index> offsets = table.offsets, indices = table.indices;
    // f(corner, lower vertex, higher vertex) for every half-edge, in corner order
    auto for_each_halfedge = [&](auto&& f) {
        for (std::size_t face = 0; face + 1 < offsets.size(); ++face) {
            const Index b = offsets[face], e = offsets[face + 1];
            for (Index c = b; c < e; ++c) {
                const Index u = indices[c], w = indices[c + 1 == e ? b : c + 1];
                f(c, std::min(u, w), std::max(u, w));
            }
        }
    };
    // counting sort of the half-edges by their lower vertex (stable: corner order within a bucket), each as
    // (higher vertex << 32 | corner), so that sorting a bucket's words sorts it by higher vertex, then corner
    std::vector<Index> fill(vertex_count + 1, 0);
    for_each_halfedge([&](Index, Index lo, Index) { ++fill[lo + 1]; });
    for (std::size_t v = 0; v < vertex_count; ++v) fill[v + 1] += fill[v];
    std::vector<std::uint64_t> keyed(n);
    for_each_halfedge([&](Index c, Index lo, Index hi) { keyed[fill[lo]++] = (std::uint64_t{hi} << 32) | c; });
    // fill[v] is now the end of bucket v, the start of bucket v + 1
    EdgeGroups groups;
    groups.corners.resize(n);
    groups.vertex_edge.resize(vertex_count + 1);
    groups.begin.reserve(n / 2 + 2);
    Index b = 0;
    for (std::size_t v = 0; v < vertex_count; ++v) {
        groups.vertex_edge[v] = static_cast<Index>(groups.begin.size());
        const Index e = fill[v];
        std::uint64_t* bucket = keyed.data();
        if (e - b <= 32) {  // insertion sort: a vertex is the lower end of a few edges
            for (Index i = b + 1; i < e; ++i) {
                const std::uint64_t w = bucket[i];
                Index j = i;
                for (; j > b && bucket[j - 1] > w; --j) bucket[j] = bucket[j - 1];
                bucket[j] = w;
            }
        } else {
            std::sort(bucket + b, bucket + e);
        }
        for (Index i = b; i < e; ++i) {
            const auto c = static_cast<Index>(bucket[i]);
            if (i == b || (bucket[i] >> 32) != (bucket[i - 1] >> 32)) groups.begin.push_back(i);
            groups.corners[i] = c;
        }
        b = e;
    }
    groups.vertex_edge[vertex_count] = static_cast<Index>(groups.begin.size());
    groups.begin.push_back(static_cast<Index>(n));
    return groups;
}

Index EdgeGroups::find(const CornerTable& table, Index a, Index b) const {
    const Index lo = std::min(a, b), hi = std::max(a, b);
    for (Index e = vertex_edge[lo]; e < vertex_edge[lo + 1]; ++e) {
        const Index c = corners[begin[e]];
        if (std::max(table.indices[c], table.indices[table.next(c)]) == hi) return e;
    }
    return kInvalidIndex;
}

}  // namespace surfaced::repair_detail
