// Tangential relaxation and projection onto the input (Remesher::relax): each vertex moves to its relaxed position
// (tangential, Laplacian, or along its curve) and back onto the input surface or its constrained polylines. Also
// Remesher::move_ok, the check that every vertex move passes, collapses included.
#include "geometry/remesh/remesher.h"

#include <array>
#include <cstddef>

namespace surfaced::remesh_detail {

//! Would the face (moved, b, c), replacing (old, b, c), stay acceptable: no turn past kMinNormalCos, no thinner
//! than kThin unless the old one was thinner, and facing the same way as the input under it (`reference`: the sum
//! of its corners' reference normals)?
bool Remesher::replacement_ok(const Vec3& old_a, const Vec3& new_a, const Vec3& b, const Vec3& c,
                              const Vec3& reference) {
    const Vec3 n_old = cross(b - old_a, c - old_a), n_new = cross(b - new_a, c - new_a);
    const double t_new = thinness(new_a, b, c);
    if (t_new < kThin && (t_new < kDegenerate || t_new < thinness(old_a, b, c))) return false;
    return dot(unit(n_old), unit(n_new)) > kMinNormalCos && dot(n_new, reference) > 0;
}

//! Moving v to p (where the input's normal is `ref`) keeps every face around v (except those containing `skip`)
//! acceptable.
bool Remesher::move_ok(Index v, const Vec3& p, const Vec3& ref, Index skip) const {
    bool ok = true;
    for_out(v, [&](Index h) {
        if (!ok || h_face_[h] == kNone) return;
        const Index b = h_to_[h], c = h_to_[h_next_[h]];
        if (b == skip || c == skip) return;
        if (!replacement_ok(pos_[v], p, pos_[b], pos_[c], ref + v_ref_[b] + v_ref_[c])) ok = false;
    });
    return ok;
}

Vec3 Remesher::relaxed(Index v, RemeshSmoothing smoothing) const {
    const Vec3& p = pos_[v];
    if (smoothing == RemeshSmoothing::None) return p;
    if (v_kind_[v] == kCurve) {
        std::array<Index, 2> ends{kNone, kNone};
        int n = 0;
        for_out(v, [&](Index h) {
            if (e_constrained_[h >> 1] && n < 2) ends[n++] = h_to_[h];
        });
        if (n < 2) return p;
        const Vec3 target = (pos_[ends[0]] + pos_[ends[1]]) * 0.5;
        const Vec3 t = unit(pos_[ends[1]] - pos_[ends[0]]);
        return p + t * dot(target - p, t);
    }
    if (smoothing == RemeshSmoothing::Laplacian) {
        Vec3 sum;
        int n = 0;
        for_out(v, [&](Index h) {
            sum += pos_[h_to_[h]];
            ++n;
        });
        return n > 0 ? sum * (1.0 / n) : p;
    }
    // tangential: area-weighted centroid of the incident triangles, moved within the tangent plane
    Vec3 normal, centroid;
    double area = 0;
    for_out(v, [&](Index h) {
        if (h_face_[h] == kNone) return;
        const Vec3 &b = pos_[h_to_[h]], &c = pos_[h_to_[h_next_[h]]];
        const Vec3 n = cross(b - p, c - p);
        const double a = 0.5 * norm(n);
        normal += n;
        centroid += (p + b + c) * (a / 3.0);
        area += a;
    });
    if (!(area > 0)) return p;
    centroid *= 1.0 / area;
    const Vec3 n = unit(normal);
    const Vec3 d = centroid - p;
    return p + d - n * dot(d, n);
}

//! The closest point of the input (of its constrained polylines for a curve vertex) and the input's normal there.
Vec3 Remesher::project(Index v, const Vec3& p, Vec3& ref) const {
    std::size_t triangle = 0;
    if (v_kind_[v] == kCurve) {
        if (!curves_) return p;
        const Vec3 q = curves_->closest_point(p);
        surface_->closest_point(q, &triangle);
        ref = input_normals_[triangle];
        return q;
    }
    const Vec3 q = surface_->closest_point(p, &triangle);
    ref = input_normals_[triangle];
    return q;
}

Status Remesher::relax(const RemeshOptions& options) {
    for (Index v = 0; v < pos_.size(); ++v) {
        if (v % kPollEvery == 0 && options.cancel.requested()) return cancelled();
        if (v_dead_[v] || v_kind_[v] == kCorner) continue;
        Vec3 ref = v_ref_[v];
        const Vec3 target = project(v, relaxed(v, options.smoothing), ref);
        if (!is_finite(target)) continue;
        if (move_ok(v, target, ref)) {
            pos_[v] = target;
            v_ref_[v] = ref;
        }
    }
    return Ok{};
}

}  // namespace surfaced::remesh_detail
