// Removal of faces of (almost) zero area (Remesher::remove_degenerate_faces), as CAD exports have them where they
// close T-junctions: caps are flipped or split, needles collapsed. It runs before the constraints are set and at the
// end, with its own checks, since a degenerate face has no normal for the usual ones to compare.
#include "geometry/remesh/remesher.h"

#include <algorithm>

namespace surfaced::remesh_detail {

// A degenerate face whose corner opposite the longest edge lies within this share of that edge from one of its ends
// is a needle (collapsed), otherwise a cap (flipped, or split and collapsed).
constexpr double kNeedleShare = 0.01;
// remove_degenerate_faces passes over the faces at most this often (one removal can leave a degenerate face behind,
// such as the next cap of a T-junction with several corners on one edge).
constexpr int kDegenerateRounds = 8;

//! Removes faces of (almost) zero area, as CAD exports have them: caps (a corner on the opposite edge, such as the
//! face that closes a T-junction) and needles (two corners together). A cap's longest edge is flipped, which keeps
//! the surface (the union of the two faces is the same when the corner lies on the edge); where it cannot be
//! flipped (a boundary or constrained edge, or a flip that would duplicate an edge), the edge is split at the foot
//! of the corner and the corner collapsed into the new vertex. A needle's short edge is collapsed. Each change
//! moves the surface by at most the face's height or its short edge, and respects the constraints. Runs before
//! the constraints are set (so that feature edges are found across the faces that closed T-junctions) and after
//! the last iteration. \return the degenerate faces that could not be removed.
std::size_t Remesher::remove_degenerate_faces() {
    if (v_ref_.size() < pos_.size()) v_ref_.resize(pos_.size(), Vec3{});
    for (int round = 0; round < kDegenerateRounds; ++round) {
        bool changed = false;
        for (Index f = 0; f < f_h_.size(); ++f)
            if (!f_dead_[f] && face_thinness(f) < kDegenerate) changed = remove_degenerate(f) || changed;
        if (!changed) break;
    }
    std::size_t left = 0;
    for (Index f = 0; f < f_h_.size(); ++f) left += !f_dead_[f] && face_thinness(f) < kDegenerate;
    return left;
}

//! One step of remove_degenerate_faces on face f; false when nothing could be done.
bool Remesher::remove_degenerate(Index f) {
    Index g = f_h_[f];  // the longest edge a -> b, c opposite
    for (Index k = h_next_[g]; k != f_h_[f]; k = h_next_[k])
        if (length2(k >> 1) > length2(g >> 1)) g = k;
    const Index a = from(g), b = h_to_[g], c = h_to_[h_next_[g]];
    const Vec3 ab = pos_[b] - pos_[a];
    const double l2 = dot(ab, ab);
    const double t = l2 > 0 ? dot(pos_[c] - pos_[a], ab) / l2 : 0.0;
    if (t < kNeedleShare || t > 1 - kNeedleShare) {
        // a needle: c next to a (edge c -> a) or to b (edge b -> c); either end may be the one removed
        const Index h = t < 0.5 ? h_prev_[g] : h_next_[g];
        return collapse_degenerate(h) || collapse_degenerate(h ^ 1);
    }
    if (degenerate_flip_ok(g >> 1)) {
        flip(g >> 1);
        return true;
    }
    // a cap on an edge that cannot flip: split it at the foot of c, then move c there (c is free, so the edges
    // around it are not constrained, and the split edge's other face, if any, has no edge to c)
    if (v_kind_[c] != kFree || boundary_v(c)) return false;
    if (!boundary_h(g ^ 1)) {
        const Index d = h_to_[h_next_[g ^ 1]];
        bool connected = false;
        for_out(c, [&](Index k) { connected = connected || h_to_[k] == d; });
        if (connected) return false;
    }
    for (Index v : {a, b})
        if (!boundary_v(v) && valence(v) < 4) return false;
    const Vec3 foot = pos_[a] + ab * t;
    if (!degenerate_move_ok(c, foot, kNone)) return false;
    const Index m = split(g >> 1, foot);
    Index h = kNone;  // c -> m
    for_out(c, [&](Index k) {
        if (h_to_[k] == m) h = k;
    });
    if (h == kNone || !collapse_topology_ok(h)) return true;  // split only; the needles left are tried next round
    collapse(h);
    return true;
}

//! Removes from(h) into to(h) to get rid of a needle: the removed vertex is free, or on a constrained curve
//! along it; it stays on the boundary when it was on it.
bool Remesher::collapse_degenerate(Index h) {
    const Index v0 = from(h), v1 = h_to_[h];
    if (v_kind_[v0] == kCorner || (v_kind_[v0] == kCurve && !e_constrained_[h >> 1])) return false;
    if (boundary_v(v0) && !(boundary_h(h) || boundary_h(h ^ 1))) return false;
    if (!collapse_topology_ok(h) || !degenerate_move_ok(v0, pos_[v1], v1)) return false;
    collapse(h);
    return true;
}

//! Moving v to p, do the faces around v (except those with `skip`) keep their orientation and stay off
//! degenerate (or no thinner than they were)? Unlike move_ok, a degenerate face's normal is not compared.
bool Remesher::degenerate_move_ok(Index v, const Vec3& p, Index skip) const {
    bool ok = true;
    for_out(v, [&](Index h) {
        if (!ok || boundary_h(h)) return;
        const Index b = h_to_[h], c = h_to_[h_next_[h]];
        if (b == skip || c == skip) return;
        const Vec3 &pb = pos_[b], &pc = pos_[c];
        const double t_old = thinness(pos_[v], pb, pc), t_new = thinness(p, pb, pc);
        if (t_new < kDegenerate && t_new < t_old) ok = false;
        if (t_old >= kDegenerate &&
            dot(unit(cross(pb - pos_[v], pc - pos_[v])), unit(cross(pb - p, pc - p))) <= kMinNormalCos)
            ok = false;
    });
    return ok;
}

//! flip_ok for an edge with a degenerate face on one side: the new faces must be thicker than the thinner old one
//! and face like the thicker one (a degenerate face has no normal to compare with).
bool Remesher::degenerate_flip_ok(Index e) {
    if (!flippable(e)) return false;
    const Index a = h_to_[2 * e + 1], b = h_to_[2 * e], c = h_to_[h_next_[2 * e]], d = h_to_[h_next_[2 * e + 1]];
    const Vec3 &pa = pos_[a], &pb = pos_[b], &pc = pos_[c], &pd = pos_[d];
    const double t1 = thinness(pa, pb, pc), t2 = thinness(pb, pa, pd);
    const Vec3 reference = t1 >= t2 ? cross(pb - pa, pc - pa) : cross(pa - pb, pd - pb);
    const double t_new = std::min(thinness(pa, pd, pc), thinness(pb, pc, pd));
    if (!(t_new > std::min(t1, t2))) return false;
    for (const Vec3& n : {cross(pd - pa, pc - pa), cross(pc - pb, pd - pb)})
        if (dot(unit(n), unit(reference)) <= kMinNormalCos) return false;
    return true;
}

}  // namespace surfaced::remesh_detail
