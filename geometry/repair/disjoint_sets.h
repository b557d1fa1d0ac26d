// Union-find over dense indices, for the repair steps: plain sets (fans, components) and sets whose members carry a
// parity relative to each other (face orientation: "these two faces need opposite flips").
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "geometry/core/types.h"

namespace surfaced::repair_detail {

//! Disjoint sets; the root of a set is always its lowest member (unite links the higher root under the lower), so
//! results depend only on the unions made, not on their order.
class DisjointSets {
public:
    explicit DisjointSets(std::size_t n) : parent_(n) {
        for (std::size_t i = 0; i < n; ++i) parent_[i] = static_cast<Index>(i);
    }
    Index find(Index x) {
        while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
        return x;
    }
    void unite(Index a, Index b) {
        a = find(a);
        b = find(b);
        if (a < b)
            parent_[b] = a;
        else if (b < a)
            parent_[a] = b;
    }

private:
    std::vector<Index> parent_;
};

//! Disjoint sets whose members have a parity relative to their root; unite(a, b, p) records parity(a) ^ parity(b)
//! == p. The root of a set is its lowest member and has parity 0.
class ParitySets {
public:
    explicit ParitySets(std::size_t n) : parent_(n), parity_(n, 0) {
        for (std::size_t i = 0; i < n; ++i) parent_[i] = static_cast<Index>(i);
    }
    //! Root of x and the parity of x relative to it.
    std::pair<Index, bool> find(Index x) {
        Index root = x;
        bool p = false;
        while (parent_[root] != root) {
            p ^= parity_[root] != 0;
            root = parent_[root];
        }
        // path compression: point every node on the way at the root, with its parity to the root
        bool px = p;
        while (parent_[x] != x && parent_[x] != root) {
            const Index up = parent_[x];
            const bool p_up = px ^ (parity_[x] != 0);
            parent_[x] = root;
            parity_[x] = px ? 1 : 0;
            x = up;
            px = p_up;
        }
        return {root, p};
    }
    //! Joins the sets of a and b so that parity(a) ^ parity(b) == p. False (and nothing changes) when they are in one
    //! set already with the other relative parity.
    bool unite(Index a, Index b, bool p) {
        const auto [ra, pa] = find(a);
        const auto [rb, pb] = find(b);
        if (ra == rb) return (pa ^ pb) == p;
        const bool link = p ^ pa ^ pb;  // parity(ra) ^ parity(rb) that satisfies the constraint
        if (ra < rb) {
            parent_[rb] = ra;
            parity_[rb] = link ? 1 : 0;
        } else {
            parent_[ra] = rb;
            parity_[ra] = link ? 1 : 0;
        }
        return true;
    }

private:
    std::vector<Index> parent_;
    std::vector<std::uint8_t> parity_;
};

}  // namespace surfaced::repair_detail
