#include "geometry/subdivision/tessellation_decimation.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <queue>
#include <tuple>
#include <unordered_map>
#include <utility>

namespace surfaced::tessellation_detail {
namespace {

//! Rounds of collapses, each followed by a pass of flips.
constexpr int kRounds = 2;
//! A vertex is tried only when a triangle around it has an error ratio below this.
constexpr double kHeadroom = 0.6;

bool on_side(const P2& p, int k) { return k == 0 ? p.t == 0 : k == 1 ? p.s == 1 : k == 2 ? p.t == 1 : p.s == 0; }

double area2(const P2& a, const P2& b, const P2& c) { return (b.s - a.s) * (c.t - a.t) - (b.t - a.t) * (c.s - a.s); }

//! Whether the triangle (a, b, c), oriented as the sign of `sign` says, is not a sliver in the domain: twice its area at least
//! kMinShape times its longest edge squared. The bounds take a triangle's plane from its corners: with its corners
//! (nearly) in line in (s, t), the plane can hold the whole curve through them (a parallel circle of a torus), so
//! that the bound is small while the triangle's inside runs far from the surface.
constexpr double kMinShape = 1e-3;
bool well_shaped(const P2& a, const P2& b, const P2& c, double sign) {
    const auto sq = [](const P2& p, const P2& q) { return (p.s - q.s) * (p.s - q.s) + (p.t - q.t) * (p.t - q.t); };
    return area2(a, b, c) * (sign > 0 ? 1.0 : -1.0) >= kMinShape * std::max({sq(a, b), sq(b, c), sq(c, a)});
}

int corner_of(const DomainTriangle& t, Index v) {
    for (int k = 0; k < 3; ++k)
        if (t.v[std::size_t(k)] == v) return k;
    return -1;
}

//! A collapse of v onto w and what it costs: the largest error ratio of the triangles it creates.
struct Candidate {
    double cost = 0;
    Index v = 0, w = 0;
    std::uint32_t stamp = 0;  //!< v's stamp when it was computed
    bool operator>(const Candidate& o) const { return std::tie(cost, v, w) > std::tie(o.cost, o.v, o.w); }
};

class Decimator {
public:
    Decimator(std::vector<DomainTriangle>& triangles, const std::vector<Vec3>& positions,
              const std::vector<Vec3>& offsets, const std::vector<DecimationDomain>& domains,
              const LimitTessellationOptions& options)
        : tris_(triangles),
          positions_(positions),
          offsets_(offsets),
          domains_(domains),
          options_(options),
          alive_(triangles.size(), true),
          ratio_(triangles.size(), -1.0),
          around_(positions.size()),
          stamp_(positions.size(), 0) {
        for (std::size_t t = 0; t < tris_.size(); ++t)
            for (Index v : tris_[t].v) around_[v].push_back(std::uint32_t(t));
    }

    Result<std::size_t> run() {
        for (Index v = 0; v < Index(positions_.size()); ++v)
            if (auto status = push_best(v); !status) return status.error();
        std::size_t removed = 0, pops = 0;
        while (!queue_.empty()) {
            const Candidate c = queue_.top();
            queue_.pop();
            if ((++pops & 255) == 0 && options_.cancel.requested())
                return make_error(ErrorCode::Cancelled, "tessellation cancelled");
            if (c.stamp != stamp_[c.v] || around_[c.v].empty()) continue;
            std::vector<std::pair<std::uint32_t, P2>> moves;
            auto cost = evaluate(c.v, c.w, &moves);
            if (!cost) return cost.error();
            if (!*cost || **cost > c.cost + 1e-12) {  // its ring changed since: look again
                if (auto status = push_best(c.v); !status) return status.error();
                continue;
            }
            apply(c.v, c.w, moves);
            ++removed;
            // every vertex around w has a new ring
            std::vector<Index> ring = neighbours(c.w);
            ring.push_back(c.w);
            for (Index u : ring)
                if (auto status = push_best(u); !status) return status.error();
        }
        return removed;
    }

    Result<TriangleError> worst() {
        TriangleError out;
        for (std::size_t t = 0; t < tris_.size(); ++t) {
            if (!alive_[t]) continue;
            auto e = error_of(tris_[t]);
            if (!e) return e.error();
            out.bound = std::max(out.bound, e->bound);
            out.sampled = std::max(out.sampled, e->sampled);
        }
        return out;
    }

    void compact() {
        std::size_t k = 0;
        for (std::size_t t = 0; t < tris_.size(); ++t)
            if (alive_[t]) tris_[k++] = tris_[t];
        tris_.resize(k);
    }

    //! Flips the edges inside a domain whose two triangles' larger error ratio falls by flipping (so that the
    //! collapses that follow find more room); returns how many it flipped.
    Result<std::size_t> flip_pass() {
        std::size_t flips = 0;
        for (std::uint32_t t1 = 0; t1 < tris_.size(); ++t1) {
            for (int e = 0; e < 3 && alive_[t1]; ++e) {
                const Index a = tris_[t1].v[std::size_t(e)], b = tris_[t1].v[std::size_t((e + 1) % 3)];
                const Index c = tris_[t1].v[std::size_t((e + 2) % 3)];
                // the other triangle on edge (a, b), in the same domain
                std::uint32_t t2 = t1;
                for (std::uint32_t t : live(a))
                    if (t != t1 && corner_of(tris_[t], b) >= 0) t2 = t;
                if (t2 == t1 || tris_[t2].domain != tris_[t1].domain) continue;
                const DomainTriangle& o = tris_[t2];
                const int kb = corner_of(o, b);
                if (o.v[std::size_t((kb + 1) % 3)] != a) continue;  // not consistently oriented
                const Index d = o.v[std::size_t((kb + 2) % 3)];
                if (c == d) continue;
                const std::vector<Index> nc = neighbours(c);
                if (std::binary_search(nc.begin(), nc.end(), d)) continue;  // (c, d) is an edge already
                const DomainTriangle& t = tris_[t1];
                const P2 pa = t.p[std::size_t(e)], pb = t.p[std::size_t((e + 1) % 3)],
                         pc = t.p[std::size_t((e + 2) % 3)], pd = o.p[std::size_t((kb + 2) % 3)];
                const double sign = area2(pa, pb, pc);
                DomainTriangle n1{t.domain, {a, d, c}, {pa, pd, pc}}, n2{t.domain, {d, b, c}, {pd, pb, pc}};
                if (!well_shaped(pa, pd, pc, sign) || !well_shaped(pd, pb, pc, sign)) continue;
                auto before1 = ratio_of(t1), before2 = ratio_of(t2);
                if (!before1) return before1.error();
                if (!before2) return before2.error();
                auto e1 = error_of(n1), e2 = error_of(n2);
                if (!e1) return e1.error();
                if (!e2) return e2.error();
                const double after = std::max(e1->ratio(options_.tolerance), e2->ratio(options_.tolerance));
                if (!(after < 0.999 * std::max(*before1, *before2))) continue;
                tris_[t1] = n1;
                tris_[t2] = n2;
                ratio_[t1] = e1->ratio(options_.tolerance);
                ratio_[t2] = e2->ratio(options_.tolerance);
                around_[d].push_back(t1);
                around_[c].push_back(t2);
                ++flips;
            }
        }
        return flips;
    }

private:
    Result<double> ratio_of(std::uint32_t t) {
        if (ratio_[t] < 0) {
            auto e = error_of(tris_[t]);
            if (!e) return e.error();
            ratio_[t] = e->ratio(options_.tolerance);
        }
        return ratio_[t];
    }

    //! A triangle's error, computed once: the same candidate triangles come back each time a ring is looked at
    //! again (a vertex's (s, t) in a domain is fixed, so the domain and the vertex ids name the triangle).
    Result<TriangleError> error_of(const DomainTriangle& t) {
        std::array<Index, 3> ids = t.v;
        std::sort(ids.begin(), ids.end());
        const Key key{t.domain, ids[0], ids[1], ids[2]};
        if (const auto found = known_.find(key); found != known_.end()) return found->second;
        const DecimationDomain& d = domains_[t.domain];
        auto e = triangle_error(
            *d.face, d.subface, d.open_sides, t.p[0], t.p[1], t.p[2],
            {OffsetPoint{positions_[t.v[0]], offsets_[t.v[0]]}, OffsetPoint{positions_[t.v[1]], offsets_[t.v[1]]},
             OffsetPoint{positions_[t.v[2]], offsets_[t.v[2]]}},
            true);
        if (e) known_.emplace(key, *e);
        return e;
    }

    struct Key {
        std::uint32_t domain;
        Index a, b, c;
        bool operator==(const Key& o) const { return domain == o.domain && a == o.a && b == o.b && c == o.c; }
    };
    struct KeyHash {
        std::size_t operator()(const Key& k) const {
            std::uint64_t h = k.domain;
            for (Index v : {k.a, k.b, k.c}) h = (h ^ v) * 0x9E3779B97F4A7C15ull;
            return std::size_t(h ^ (h >> 32));
        }
    };
    std::unordered_map<Key, TriangleError, KeyHash> known_;

    //! The live triangles around v (dropping the dead ones from its list).
    const std::vector<std::uint32_t>& live(Index v) {
        auto& list = around_[v];
        list.erase(std::remove_if(list.begin(), list.end(),
                                  [&](std::uint32_t t) { return !alive_[t] || corner_of(tris_[t], v) < 0; }),
                   list.end());
        std::sort(list.begin(), list.end());
        list.erase(std::unique(list.begin(), list.end()), list.end());
        return list;
    }

    std::vector<Index> neighbours(Index v) {
        std::vector<Index> out;
        for (std::uint32_t t : live(v))
            for (Index u : tris_[t].v)
                if (u != v) out.push_back(u);
        std::sort(out.begin(), out.end());
        out.erase(std::unique(out.begin(), out.end()), out.end());
        return out;
    }

    //! The cost of collapsing v onto w (nullopt: not allowed, or a created triangle fails), and the corner each
    //! surviving triangle of v gets.
    Result<std::optional<double>> evaluate(Index v, Index w, std::vector<std::pair<std::uint32_t, P2>>* moves,
                                           double limit = 1.0) {
        const std::vector<std::uint32_t> tv = live(v);
        // w's (s, t) in each domain of the edge's triangles
        std::vector<std::pair<std::uint32_t, P2>> w_at;
        std::vector<Index> opposite;
        for (std::uint32_t t : tv) {
            const int k = corner_of(tris_[t], w);
            if (k < 0) continue;
            w_at.emplace_back(tris_[t].domain, tris_[t].p[std::size_t(k)]);
            for (Index u : tris_[t].v)
                if (u != v && u != w) opposite.push_back(u);
        }
        if (w_at.empty()) return std::optional<double>{};
        // link condition: v's and w's common neighbours are the edge's opposite vertices
        {
            std::sort(opposite.begin(), opposite.end());
            const std::vector<Index> nv = neighbours(v), nw = neighbours(w);
            std::vector<Index> common;
            std::set_intersection(nv.begin(), nv.end(), nw.begin(), nw.end(), std::back_inserter(common));
            if (common != opposite) return std::optional<double>{};
        }
        double cost = 0;
        if (moves) moves->clear();
        for (std::uint32_t t : tv) {
            const DomainTriangle& tri = tris_[t];
            const int kv = corner_of(tri, v);
            const P2 pv = tri.p[std::size_t(kv)];
            const auto found =
                std::find_if(w_at.begin(), w_at.end(), [&](const auto& e) { return e.first == tri.domain; });
            if (found == w_at.end()) return std::optional<double>{};  // w is not next to v in this domain
            const P2 pw = found->second;
            for (int k = 0; k < 4; ++k)  // a vertex on a domain side moves along it only
                if (on_side(pv, k) && !on_side(pw, k)) return std::optional<double>{};
            if (corner_of(tri, w) >= 0) continue;  // removed with the edge
            DomainTriangle moved = tri;
            moved.v[std::size_t(kv)] = w;
            moved.p[std::size_t(kv)] = pw;
            const double before = area2(tri.p[0], tri.p[1], tri.p[2]);
            if (!well_shaped(moved.p[0], moved.p[1], moved.p[2], before)) return std::optional<double>{};
            auto e = error_of(moved);
            if (!e) return e.error();
            const double ratio = e->ratio(options_.tolerance);
            if (!(ratio <= limit)) return std::optional<double>{};
            cost = std::max(cost, ratio);
            if (moves) moves->emplace_back(t, pw);
        }
        return std::optional<double>{cost};
    }

    void apply(Index v, Index w, const std::vector<std::pair<std::uint32_t, P2>>& moves) {
        for (std::uint32_t t : live(v))
            if (corner_of(tris_[t], w) >= 0) alive_[t] = false;
        for (const auto& [t, pw] : moves) {
            DomainTriangle& tri = tris_[t];
            const int kv = corner_of(tri, v);
            tri.v[std::size_t(kv)] = w;
            tri.p[std::size_t(kv)] = pw;
            ratio_[t] = -1;
            around_[w].push_back(t);
        }
        around_[v].clear();
        ++stamp_[v];
    }

    //! Queues v's cheapest allowed collapse, if it has one (older entries for v go stale).
    Status push_best(Index v) {
        ++stamp_[v];
        if (live(v).empty()) return Ok{};
        // removing v enlarges the triangles around it (their bounds grow with the squares of their sizes): with
        // no triangle there below kHeadroom of the tolerance, no collapse of v would pass
        double least = 2;
        for (std::uint32_t t : live(v)) {
            auto r = ratio_of(t);
            if (!r) return r.error();
            least = std::min(least, *r);
        }
        if (least > kHeadroom) return Ok{};
        std::optional<Candidate> best;
        for (Index w : neighbours(v)) {
            auto cost = evaluate(v, w, nullptr, best ? best->cost : 1.0);
            if (!cost) return cost.error();
            if (!*cost) continue;
            const Candidate c{**cost, v, w, stamp_[v]};
            if (!best || *best > c) best = c;
        }
        if (best) queue_.push(*best);
        return Ok{};
    }

    std::vector<DomainTriangle>& tris_;
    const std::vector<Vec3>& positions_;
    const std::vector<Vec3>& offsets_;
    const std::vector<DecimationDomain>& domains_;
    const LimitTessellationOptions& options_;
    std::vector<bool> alive_;
    std::vector<double> ratio_;  //!< per triangle, its error ratio (-1: not known)
    std::vector<std::vector<std::uint32_t>> around_;
    std::vector<std::uint32_t> stamp_;
    std::priority_queue<Candidate, std::vector<Candidate>, std::greater<Candidate>> queue_;
};

}  // namespace

Result<DecimationResult> decimate(std::vector<DomainTriangle>& triangles, const std::vector<Vec3>& positions,
                                  const std::vector<Vec3>& offsets, const std::vector<DecimationDomain>& domains,
                                  const LimitTessellationOptions& options) {
    Decimator decimator(triangles, positions, offsets, domains, options);
    DecimationResult out;
    for (int round = 0; round < kRounds; ++round) {
        auto removed = decimator.run();
        if (!removed) return removed.error();
        out.removed_vertices += *removed;
        if (round > 0 && *removed == 0) break;
        auto flips = decimator.flip_pass();
        if (!flips) return flips.error();
        if (*flips == 0) break;
    }
    auto worst = decimator.worst();
    if (!worst) return worst.error();
    out.worst = *worst;
    decimator.compact();
    return out;
}

}  // namespace surfaced::tessellation_detail
