// Face joining and orientation by union-find with parity: two faces joined across an edge they traverse in the same
// direction need opposite flips, in opposite directions equal flips. Near-linear in the corners.
#include "geometry/repair/glue.h"

#include "geometry/repair/disjoint_sets.h"

namespace surfaced::repair_detail {

namespace {

class Joiner {
public:
    Joiner(const CornerTable& table, bool orient)
        : table_(table),
          orient_(orient),
          sets_(table.offsets.size() - 1),
          partner_(table.corner_count(), kInvalidIndex) {}

    //! Joins the half-edges of corners a and b (same undirected edge) when their faces can agree; false otherwise.
    bool try_join(Index a, Index b) {
        const bool same_direction = table_.indices[a] == table_.indices[b];
        const bool ok = orient_ ? sets_.unite(table_.face(a), table_.face(b), same_direction) : !same_direction;
        if (!ok) return false;
        partner_[a] = b;
        partner_[b] = a;
        return true;
    }

    Gluing finish() {
        Gluing g;
        g.partner = std::move(partner_);
        g.flip.assign(table_.offsets.size() - 1, 0);
        if (orient_)
            for (Index f = 0; f < g.flip.size(); ++f) g.flip[f] = sets_.find(f).second ? 1 : 0;
        return g;
    }

private:
    const CornerTable& table_;
    bool orient_;
    ParitySets sets_;
    std::vector<Index> partner_;
};

//! Every edge used by at most two faces, and by two in opposite directions: all pairs join, no face is reversed.
bool pairs_consistently(const CornerTable& table, const EdgeGroups& edges) {
    for (std::size_t e = 0; e < edges.edge_count(); ++e) {
        const std::size_t size = edges.size(e);
        if (size > 2) return false;
        if (size == 2 &&
            table.indices[edges.corners[edges.begin[e]]] == table.indices[edges.corners[edges.begin[e] + 1]])
            return false;
    }
    return true;
}

}  // namespace

Gluing glue_faces(const CornerTable& table, const EdgeGroups& edges, bool orient) {
    if (pairs_consistently(table, edges)) {  // a clean mesh, or a soup of one: no union-find needed
        Gluing g;
        g.partner.assign(table.corner_count(), kInvalidIndex);
        for (std::size_t e = 0; e < edges.edge_count(); ++e) {
            if (edges.size(e) != 2) continue;
            const Index a = edges.corners[edges.begin[e]], b = edges.corners[edges.begin[e] + 1];
            g.partner[a] = b;
            g.partner[b] = a;
        }
        g.flip.assign(table.offsets.size() - 1, 0);
        return g;
    }
    Joiner joiner(table, orient);
    for (std::size_t e = 0; e < edges.edge_count(); ++e)
        if (edges.size(e) == 2) joiner.try_join(edges.of(e)[0], edges.of(e)[1]);
    // Edges of three or more faces. The unjoined faces seen so far on the edge cannot agree with one another (else
    // they would have been joined), so a new face can agree with all of them or with none: join it to the first.
    std::vector<Index> open;
    for (std::size_t e = 0; e < edges.edge_count(); ++e) {
        if (edges.size(e) <= 2) continue;
        open.clear();
        std::size_t first = 0;
        for (Index c : edges.of(e)) {
            if (first < open.size() && joiner.try_join(open[first], c))
                ++first;
            else
                open.push_back(c);
        }
    }
    return joiner.finish();
}

}  // namespace surfaced::repair_detail
