// Grouping half-edges by undirected edge: a counting sort by the lower vertex, then a sort of each (small) bucket by
// the higher vertex. Linear in the corners for meshes of bounded valence.
#include "geometry/repair/mesh_edges.h"

#include <algorithm>
#include <utility>

namespace surfaced::repair_detail {

CornerTable make_corner_table(std::span<const Index> offsets, std::span<const Index> indices) {
    CornerTable table{offsets, indices, std::vector<Index>(indices.size())};
    for (std::size_t f = 0; f + 1 < offsets.size(); ++f)
        for (Index c = offsets[f]; c < offsets[f + 1]; ++c) table.face[c] = static_cast<Index>(f);
    return table;
}

EdgeGroups group_edges(const CornerTable& table, std::size_t vertex_count) {
    const std::size_t n = table.corner_count();
    auto low = [&](Index c) { return std::min(table.indices[c], table.indices[table.next(c)]); };
    auto high = [&](Index c) { return std::max(table.indices[c], table.indices[table.next(c)]); };

    // counting sort of the corners by the lower vertex of their half-edge (stable: corner order within a bucket)
    std::vector<Index> bucket(vertex_count + 1, 0);
    for (Index c = 0; c < n; ++c) ++bucket[low(c) + 1];
    for (std::size_t v = 0; v < vertex_count; ++v) bucket[v + 1] += bucket[v];
    EdgeGroups groups;
    groups.corners.resize(n);
    {
        std::vector<Index> fill(bucket.begin(), bucket.end() - 1);
        for (Index c = 0; c < n; ++c) groups.corners[fill[low(c)]++] = c;
    }
    groups.corner_edge.resize(n);
    groups.vertex_edge.assign(vertex_count + 1, 0);
    groups.begin.reserve(n / 2 + 2);
    std::vector<std::pair<Index, Index>> keyed;  // (higher vertex, corner) of one bucket
    for (std::size_t v = 0; v < vertex_count; ++v) {
        groups.vertex_edge[v] = static_cast<Index>(groups.begin.size());
        const Index b = bucket[v], e = bucket[v + 1];
        if (b == e) continue;
        keyed.clear();
        for (Index i = b; i < e; ++i) keyed.emplace_back(high(groups.corners[i]), groups.corners[i]);
        std::sort(keyed.begin(), keyed.end());
        for (Index i = b; i < e; ++i) {
            const auto [hi, c] = keyed[i - b];
            if (i == b || keyed[i - b - 1].first != hi) groups.begin.push_back(i);
            groups.corners[i] = c;
            groups.corner_edge[c] = static_cast<Index>(groups.begin.size() - 1);
        }
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
