// The flip pass (Remesher::equalize_valences): flips towards valence 6 (4 on a boundary) or, at equal valences, to
// the Delaunay diagonal; and Remesher::remove_caps, the last pass that flips away angles near 180 degrees.
#include "geometry/remesh/remesher.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numbers>

namespace surfaced::remesh_detail {

// A flip that does not worsen valences is made when the angles opposite the edge exceed pi by this (radians).
constexpr double kDelaunaySlack = 0.05;

bool Remesher::flippable(Index e) {
    const Index h = 2 * e, o = 2 * e + 1;
    if (e_constrained_[e] || boundary_h(h) || boundary_h(o)) return false;
    const Index a = h_to_[o], b = h_to_[h], c = h_to_[h_next_[h]], d = h_to_[h_next_[o]];
    if (c == d) return false;
    bool connected = false;
    for_out(c, [&](Index g) { connected = connected || h_to_[g] == d; });
    if (connected) return false;
    return valence(a) > (boundary_v(a) ? 2u : 3u) && valence(b) > (boundary_v(b) ? 2u : 3u);
}

bool Remesher::flip_ok(Index e) {
    if (!flippable(e)) return false;
    const Index a = h_to_[2 * e + 1], b = h_to_[2 * e], c = h_to_[h_next_[2 * e]], d = h_to_[h_next_[2 * e + 1]];
    const Vec3 &pa = pos_[a], &pb = pos_[b], &pc = pos_[c], &pd = pos_[d];
    const Vec3 m1 = unit(cross(pb - pa, pc - pa)), m2 = unit(cross(pa - pb, pd - pb));
    const Vec3 n1 = unit(cross(pd - pa, pc - pa)), n2 = unit(cross(pc - pb, pd - pb));
    for (const Vec3* n : {&n1, &n2})
        for (const Vec3* m : {&m1, &m2})
            if (dot(*n, *m) <= kMinNormalCos) return false;
    if (dot(n1, v_ref_[a] + v_ref_[d] + v_ref_[c]) <= 0 || dot(n2, v_ref_[b] + v_ref_[c] + v_ref_[d]) <= 0)
        return false;
    const double t_old = std::min(thinness(pa, pb, pc), thinness(pb, pa, pd));
    const double t_new = std::min(thinness(pa, pd, pc), thinness(pb, pc, pd));
    return t_new >= kThin || (t_new >= kDegenerate && t_new >= t_old);
}

void Remesher::flip(Index e) {
    const Index h = 2 * e, o = 2 * e + 1;
    const Index a = h_to_[o], b = h_to_[h];
    const Index hn = h_next_[h], hp = h_next_[hn], on = h_next_[o], op = h_next_[on];
    const Index c = h_to_[hn], d = h_to_[on];
    const Index fh = h_face_[h], fo = h_face_[o];
    h_to_[h] = c;  // h: d -> c in (a, d, c)
    h_to_[o] = d;  // o: c -> d in (b, c, d)
    link(h, hp), link(hp, on), link(on, h);
    link(o, op), link(op, hn), link(hn, o);
    h_face_[on] = fh;
    h_face_[hn] = fo;
    f_h_[fh] = h;
    f_h_[fo] = o;
    if (v_out_[a] == h) v_out_[a] = on;
    if (v_out_[b] == o) v_out_[b] = hn;
}

//! Angles opposite edge e (at c and d) adding up to more than pi: the other diagonal is the Delaunay one, and
//! flipping to it raises the smallest angle of the pair.
bool Remesher::non_delaunay(Index e) const {
    const Index a = h_to_[2 * e + 1], b = h_to_[2 * e];
    const Index c = h_to_[h_next_[2 * e]], d = h_to_[h_next_[2 * e + 1]];
    auto angle = [&](Index at) {
        const Vec3 u = pos_[a] - pos_[at], w = pos_[b] - pos_[at];
        return std::atan2(norm(cross(u, w)), dot(u, w));
    };
    return angle(c) + angle(d) > std::numbers::pi + kDelaunaySlack;
}

//! Flips to even out valences (6 inside, 4 on a boundary), and flips that leave the valences as far from ideal
//! as before when that makes the pair of faces Delaunay (valence flips alone leave needles where ties block them).
Status Remesher::equalize_valences(const RemeshOptions& options) {
    for (Index e = 0; e < e_dead_.size(); ++e) {
        if (e % kPollEvery == 0 && options.cancel.requested()) return cancelled();
        if (e_dead_[e]) continue;
        const Index h = 2 * e, o = 2 * e + 1;
        if (boundary_h(h) || boundary_h(o) || e_constrained_[e]) continue;
        const Index a = h_to_[o], b = h_to_[h], c = h_to_[h_next_[h]], d = h_to_[h_next_[o]];
        const int da = static_cast<int>(valence(a)) - target_valence(a);
        const int db = static_cast<int>(valence(b)) - target_valence(b);
        const int dc = static_cast<int>(valence(c)) - target_valence(c);
        const int dd = static_cast<int>(valence(d)) - target_valence(d);
        const int before = std::abs(da) + std::abs(db) + std::abs(dc) + std::abs(dd);
        const int after = std::abs(da - 1) + std::abs(db - 1) + std::abs(dc + 1) + std::abs(dd + 1);
        if ((after < before || (after == before && non_delaunay(e))) && flip_ok(e)) flip(e);
    }
    return Ok{};
}

//! Caps (an angle near 180 degrees) that the valence flips left, typically a curve vertex in the middle of the
//! long edge of a triangle on a slightly bent feature: flipping that edge splits the cap (pmp's remove_caps).
void Remesher::remove_caps() {
    constexpr double kCapCos = -0.985;  // about 170 degrees
    for (Index e = 0; e < e_dead_.size(); ++e) {
        if (e_dead_[e] || e_constrained_[e] || boundary_h(2 * e) || boundary_h(2 * e + 1)) continue;
        const Index a = h_to_[2 * e + 1], b = h_to_[2 * e];
        const Index c = h_to_[h_next_[2 * e]], d = h_to_[h_next_[2 * e + 1]];
        const double cos_c = dot(unit(pos_[a] - pos_[c]), unit(pos_[b] - pos_[c]));
        const double cos_d = dot(unit(pos_[a] - pos_[d]), unit(pos_[b] - pos_[d]));
        if (std::min(cos_c, cos_d) < kCapCos && flip_ok(e)) flip(e);
    }
}

}  // namespace surfaced::remesh_detail
