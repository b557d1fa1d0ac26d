// Fans by union-find over corners joined across edges, and the cuts that keep two unjoined faces from sharing an edge.
#include "geometry/repair/fans.h"

#include <algorithm>
#include <array>
#include <utility>

namespace surfaced::repair_detail {

DisjointSets join_fans(const CornerTable& table, const std::vector<Index>& partner) {
    DisjointSets fans(table.corner_count());
    for (Index c = 0; c < table.corner_count(); ++c) {
        const Index p = partner[c];
        if (p == kInvalidIndex || p < c) continue;
        if (table.indices[p] == table.indices[c]) {  // same direction: the face is to be reversed
            fans.unite(c, p);
            fans.unite(table.next(c), table.next(p));
        } else {
            fans.unite(c, table.next(p));
            fans.unite(table.next(c), p);
        }
    }
    return fans;
}

namespace {

void unjoin(std::vector<Index>& partner, Index c) {
    const Index p = partner[c];
    if (p == kInvalidIndex) return;
    partner[p] = kInvalidIndex;
    partner[c] = kInvalidIndex;
}

//! Cuts the corners of edge e that share both fans with another of its faces without being joined to it. True when
//! something was cut.
bool cut_shared(const CornerTable& table, std::span<const Index> corners, DisjointSets& fans,
                std::vector<Index>& partner, std::vector<std::array<Index, 3>>& keyed) {
    keyed.clear();
    for (Index c : corners) {
        const Index n = table.next(c);
        Index lo = fans.find(c), hi = fans.find(n);
        if (table.indices[c] > table.indices[n]) std::swap(lo, hi);
        keyed.push_back({lo, hi, c});
    }
    std::sort(keyed.begin(), keyed.end());
    bool cut = false;
    for (std::size_t b = 0, e = 0; b < keyed.size(); b = e) {
        e = b + 1;
        while (e < keyed.size() && keyed[e][0] == keyed[b][0] && keyed[e][1] == keyed[b][1]) ++e;
        if (e - b == 1) continue;
        // keep one joined pair of the group (or its first face) on the edge; cut the others loose
        Index keep_a = keyed[b][2], keep_b = kInvalidIndex;
        for (std::size_t i = b; i < e && keep_b == kInvalidIndex; ++i)
            for (std::size_t j = i + 1; j < e; ++j)
                if (partner[keyed[i][2]] == keyed[j][2]) {
                    keep_a = keyed[i][2];
                    keep_b = keyed[j][2];
                    break;
                }
        if (e - b == 2 && keep_b != kInvalidIndex) continue;
        for (std::size_t i = b; i < e; ++i) {
            const Index c = keyed[i][2];
            if (c == keep_a || c == keep_b) continue;
            unjoin(partner, c);
            unjoin(partner, table.prev(c));
            cut = true;
        }
    }
    return cut;
}

}  // namespace

std::size_t count_split_vertices(const CornerTable& table, const std::vector<Index>& partner, std::size_t vertex_count,
                                 bool stop_at_first, Index* first_split) {
    std::vector<Index> corners(vertex_count, 0), first(vertex_count);
    for (Index c = 0; c < table.corner_count(); ++c)
        if (corners[table.indices[c]]++ == 0) first[table.indices[c]] = c;
    // The corner of q's face at v, where q's half-edge has v at one end, and whether q is that corner's outgoing
    // half-edge (else its incoming one).
    auto at = [&](Index q, Index v) {
        return table.indices[q] == v ? std::pair{q, true} : std::pair{table.next(q), false};
    };
    std::size_t split = 0;
    for (Index v = 0; v < vertex_count; ++v) {
        const Index count = corners[v];
        if (count <= 1) continue;
        // each corner at v has two half-edges at v, each joined to at most one other corner's: the fans are paths and
        // cycles; walk the one of v's first corner, leaving it through its outgoing half-edge, then (when that ends
        // at a boundary) through its incoming one
        const Index start = first[v];
        Index visited = 1;
        bool closed = false;
        for (int direction = 0; direction < 2 && !closed && visited <= count; ++direction) {
            Index d = start;
            bool out = direction == 0;
            for (;;) {
                const Index q = partner[out ? d : table.prev(d)];
                if (q == kInvalidIndex) break;
                const auto [next, arrived_out] = at(q, v);
                if (next == start) {
                    closed = true;
                    break;
                }
                if (++visited > count) break;  // cannot happen with consistent partners; stop all the same
                d = next;
                out = !arrived_out;
            }
        }
        if (visited != count) {
            if (split == 0 && first_split) *first_split = v;
            ++split;
            if (stop_at_first) return split;
        }
    }
    return split;
}

std::vector<Index> fan_of_corners(const CornerTable& table, const EdgeGroups& edges, std::vector<Index>& partner,
                                  std::size_t vertex_count) {
    bool cuts_possible = false;
    for (std::size_t e = 0; e < edges.edge_count() && !cuts_possible; ++e) {
        const auto corners = edges.of(e);
        cuts_possible = corners.size() > 2 || (corners.size() == 2 && partner[corners[0]] != corners[1]);
    }
    if (!cuts_possible && count_split_vertices(table, partner, vertex_count, true) == 0) return {};
    std::vector<std::array<Index, 3>> keyed;
    for (;;) {
        DisjointSets fans = join_fans(table, partner);
        bool cut = false;
        for (std::size_t e = 0; e < edges.edge_count(); ++e) {
            const auto corners = edges.of(e);
            if (corners.size() < 2) continue;
            if (corners.size() == 2 && partner[corners[0]] == corners[1]) continue;
            cut |= cut_shared(table, corners, fans, partner, keyed);
        }
        if (!cut) {
            std::vector<Index> fan(table.corner_count());
            for (Index c = 0; c < fan.size(); ++c) fan[c] = fans.find(c);
            return fan;
        }
    }
}

}  // namespace surfaced::repair_detail
