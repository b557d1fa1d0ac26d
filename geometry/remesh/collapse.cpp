// The collapse pass (Remesher::collapse_short_edges): edges shorter than 4/5 of the working target are collapsed
// when the link condition, the constraints and the geometry allow it; Remesher::collapse is the halfedge operation
// it (and degenerate.cpp) uses.
#include "geometry/remesh/remesher.h"

#include <array>

namespace surfaced::remesh_detail {

//! Topology: collapsing h (from(h) into to(h)) keeps a manifold (pmp's is_collapse_ok plus no interior vertex
//! left with valence 2).
bool Remesher::collapse_topology_ok(Index h) {
    const Index o = h ^ 1, v0 = from(h), v1 = h_to_[h];
    Index vl = kNone, vr = kNone;
    if (!boundary_h(h)) {
        const Index h1 = h_next_[h], h2 = h_next_[h1];
        vl = h_to_[h1];
        if (boundary_h(h1 ^ 1) && boundary_h(h2 ^ 1)) return false;
    }
    if (!boundary_h(o)) {
        const Index h1 = h_next_[o], h2 = h_next_[h1];
        vr = h_to_[h1];
        if (boundary_h(h1 ^ 1) && boundary_h(h2 ^ 1)) return false;
    }
    if (vl == vr) return false;
    if (boundary_v(v0) && boundary_v(v1) && !boundary_h(h) && !boundary_h(o)) return false;
    if (vl != kNone && !boundary_v(vl) && valence(vl) <= 3) return false;
    if (vr != kNone && !boundary_v(vr) && valence(vr) <= 3) return false;
    // link condition: the one-rings of v0 and v1 share only vl and vr
    ++stamp_;
    if (mark_.size() < pos_.size()) mark_.resize(pos_.size(), 0);
    for_out(v0, [&](Index g) { mark_[h_to_[g]] = stamp_; });
    bool ok = true;
    for_out(v1, [&](Index g) {
        const Index w = h_to_[g];
        if (mark_[w] == stamp_ && w != vl && w != vr) ok = false;
    });
    return ok;
}

//! Constraints and geometry for removing from(h) into to(h), which stays where it is.
//! A corner goes only along a constrained edge (shorter than 4/5 L, as every edge collapse_short_edges tries) into
//! another corner, or when it is the loose end of a feature curve: corners that close are noise (a scan's ragged
//! creases), and keeping both would keep a needle between them.
bool Remesher::collapse_ok(Index h, double high2) {
    const Index v0 = from(h), v1 = h_to_[h];
    if (v_kind_[v0] == kCorner && !(e_constrained_[h >> 1] && (v_kind_[v1] == kCorner || constrained_degree(v0) == 1)))
        return false;
    if (v_kind_[v0] == kCurve && !e_constrained_[h >> 1]) return false;
    bool ok = true;
    for_out(v0, [&](Index g) {
        const Index w = h_to_[g];
        if (ok && w != v1) {
            const Vec3 d = pos_[w] - pos_[v1];
            if (dot(d, d) > high2) ok = false;
        }
    });
    if (!ok || !move_ok(v0, pos_[v1], v_ref_[v1], v1)) return false;
    return collapse_topology_ok(h);
}

void Remesher::remove_loop(Index h0) {
    const Index h1 = h_next_[h0], o0 = h0 ^ 1, o1 = h1 ^ 1;
    const Index v = h_to_[h0], vh = h_to_[h1];
    const Index fh = h_face_[h0], fo = h_face_[o0];
    const Index on = h_next_[o0], op = h_prev_[o0];
    link(h1, on);
    link(op, h1);
    h_face_[h1] = fo;
    v_out_[v] = h1;
    adjust_out(v);
    v_out_[vh] = o1;
    adjust_out(vh);
    if (fo != kNone && f_h_[fo] == o0) f_h_[fo] = h1;
    if (fh != kNone) {
        f_dead_[fh] = 1;
        --live_faces_;
    }
    e_constrained_[h1 >> 1] |= e_constrained_[h0 >> 1];
    e_dead_[h0 >> 1] = 1;
}

//! Removes from(h); to(h) stays. The faces on either side of the edge disappear.
void Remesher::collapse(Index h) {
    const Index o = h ^ 1, v1 = h_to_[h], v0 = h_to_[o];
    const Index hn = h_next_[h], hp = h_prev_[h], on = h_next_[o], op = h_prev_[o];
    const Index fh = h_face_[h], fo = h_face_[o];
    for_out(v0, [&](Index g) { h_to_[g ^ 1] = v1; });
    link(hp, hn);
    link(op, on);
    if (fh != kNone) f_h_[fh] = hn;
    if (fo != kNone) f_h_[fo] = on;
    if (v_out_[v1] == o) v_out_[v1] = hn;
    adjust_out(v1);
    v_out_[v0] = kNone;
    v_dead_[v0] = 1;
    e_dead_[h >> 1] = 1;
    if (fh != kNone && h_next_[h_next_[hn]] == hn) remove_loop(hn);
    if (fo != kNone && h_next_[h_next_[on]] == on) remove_loop(on);
}

//! collapse(h); a corner removed leaves its corner where it went (a curve vertex that takes in a loose end or a
//! junction is one).
void Remesher::collapse_keeping_corners(Index h) {
    const bool corner = v_kind_[from(h)] == kCorner;
    const Index v1 = h_to_[h];
    collapse(h);
    if (corner) v_kind_[v1] = kCorner;
}

Status Remesher::collapse_short_edges(double low, double high, const RemeshOptions& options) {
    const double low2 = low * low, high2 = high * high;
    for (Index e = 0; e < e_dead_.size(); ++e) {
        if (e % kPollEvery == 0 && options.cancel.requested()) return cancelled();
        if (e_dead_[e] || length2(e) >= low2) continue;
        const Index h = 2 * e, o = 2 * e + 1;  // h removes from(h) = to(o)
        const Index va = h_to_[o], vb = h_to_[h];
        // prefer removing the less constrained vertex, then the one of lower valence
        const auto key = [&](Index v) {
            return std::array<Index, 3>{v_kind_[v], v_kind_[v] == kCorner ? constrained_degree(v) : 0, valence(v)};
        };
        const bool a_first = key(va) <= key(vb);
        const Index first = a_first ? h : o, second = a_first ? o : h;
        if (collapse_ok(first, high2))
            collapse_keeping_corners(first);
        else if (collapse_ok(second, high2))
            collapse_keeping_corners(second);
    }
    return Ok{};
}

}  // namespace surfaced::remesh_detail
