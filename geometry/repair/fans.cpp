// Fans by union-find over corners joined across edges, and the cuts that keep two unjoined faces from sharing an edge.
#include "geometry/repair/fans.h"

#include <algorithm>
#include <array>

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

std::vector<Index> fan_of_corners(const CornerTable& table, const EdgeGroups& edges, std::vector<Index>& partner) {
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
