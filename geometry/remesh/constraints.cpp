// Boundary and feature classification (Remesher::set_constraints, prune_features): which input edges are constrained
// (boundary, sharp features, minus the feature noise pruned), which vertices are curve vertices or corners, and the
// projection targets taken from the input (its surface, its constrained polylines, its normals). Set once, before the
// first iteration; every pass then obeys them.
#include "geometry/remesh/remesher.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <numbers>
#include <vector>

namespace surfaced::remesh_detail {

// A boundary or feature polyline turning by more than 60 degrees at a vertex has a corner there, whatever the feature
// angle (cos 60 degrees).
constexpr double kMaxTurnCos = 0.5;
// Loose or closed chains of feature edges shorter than this many L are noise, not creases (prune_features).
constexpr double kMinFeatureLength = 5.0;

//! Marks boundary (lock_border) and sharp feature edges constrained and classifies vertices; builds the
//! projection targets from the input.
void Remesher::set_constraints(const PolygonMesh& input, const RemeshOptions& options, double length) {
    const double cos_feature = std::cos(options.feature_angle_degrees * std::numbers::pi / 180.0);
    const bool features = options.feature_angle_degrees < 180.0;
    for (Index e = 0; e < e_dead_.size(); ++e) {
        const Index h = 2 * e, o = 2 * e + 1;
        if (h_face_[h] == kNone || h_face_[o] == kNone) {
            ++boundary_edges_;
            if (options.lock_border) e_constrained_[e] = kBoundaryEdge;
            continue;
        }
        if (!features) continue;
        const Index fa = h_face_[h], fb = h_face_[o];
        if (face_thinness(fa) < kThin || face_thinness(fb) < kThin) continue;  // no reliable normal
        if (dot(unit(face_normal(fa)), unit(face_normal(fb))) < cos_feature) e_constrained_[e] = kFeatureEdge;
    }
    if (features) prune_features(kMinFeatureLength * length, std::max(cos_feature, kMaxTurnCos));
    for (const std::uint8_t c : e_constrained_) feature_edges_ += c == kFeatureEdge;
    for (Index v = 0; v < pos_.size(); ++v) {
        if (v_dead_[v]) continue;
        Index n = 0;
        std::array<Index, 2> ends{kNone, kNone};
        for_out(v, [&](Index h) {
            if (!e_constrained_[h >> 1]) return;
            if (n < 2) ends[n] = h_to_[h];
            ++n;
        });
        if (n == 0) continue;
        if (n != 2) {
            v_kind_[v] = kCorner;
            continue;
        }
        // the curve turns by pi - angle(w1 - v, w2 - v); sharper than the feature angle (at most kMaxTurn, so that
        // a boundary keeps its corners with features off) is a corner
        const double c = dot(unit(pos_[ends[0]] - pos_[v]), unit(pos_[ends[1]] - pos_[v]));
        v_kind_[v] = -c < std::max(cos_feature, kMaxTurnCos) ? kCorner : kCurve;
    }
    surface_ = std::make_unique<SurfaceDistance>(input);
    // reference normals: the input's triangle normals (SurfaceDistance numbers the triangles in face order), and
    // per vertex the normal of the input where it was last projected (the input's vertex normal to begin with)
    input_normals_.resize(input.face_count());
    v_ref_.assign(pos_.size(), Vec3{});
    for (std::size_t f = 0; f < input.face_count(); ++f) {
        auto t = input.face(f);
        const Vec3& p0 = input.positions[t[0]];
        const Vec3 n = cross(input.positions[t[1]] - p0, input.positions[t[2]] - p0);
        input_normals_[f] = unit(n);
        for (Index v : t) v_ref_[v] += n;
    }
    // vertices made by remove_degenerate_faces: the normal of the faces around them
    for (Index v = static_cast<Index>(input.vertex_count()); v < pos_.size(); ++v)
        if (!v_dead_[v])
            for_out(v, [&](Index h) {
                if (!boundary_h(h)) v_ref_[v] += face_normal(h_face_[h]);
            });
    for (Vec3& n : v_ref_) n = unit(n);
    // constrained polylines as degenerate triangles (a, b, b): SurfaceDistance's closest point handles them
    PolygonMesh curves;
    curves.positions = pos_;
    for (Index e = 0; e < e_dead_.size(); ++e)
        if (e_constrained_[e]) curves.add_face({h_to_[2 * e + 1], h_to_[2 * e], h_to_[2 * e]});
    if (curves.face_count() > 0) curves_ = std::make_unique<SurfaceDistance>(curves);
}

//! Drops the feature edges that look like noise rather than a crease (a scan's dihedral noise at the default
//! feature angle): chains of feature edges (between vertices not on exactly two constrained edges) that are
//! shorter than min_length and either hang loose (an end on no other constrained edge) or close on themselves,
//! repeatedly, since dropping one may leave another loose; then whole groups of connected feature edges shorter than
//! min_length in all. Chains between two junctions (a cube's edges between its corners) stay whatever their length.
void Remesher::prune_features(double min_length, double corner_cos) {
    const std::size_t nv = pos_.size();
    std::vector<Index> degree(nv, 0);
    for (Index e = 0; e < e_dead_.size(); ++e)
        if (e_constrained_[e]) ++degree[h_to_[2 * e]], ++degree[h_to_[2 * e + 1]];
    std::vector<Index> chain;
    // the other constrained edge at a vertex on exactly two, seen from halfedge h arriving there, when the curve
    // goes on there without turning into a corner
    auto next_constrained = [&](Index h) {
        const Index v = h_to_[h];
        Index found = kNone;
        if (degree[v] != 2) return found;
        for_out(v, [&](Index g) {
            if (e_constrained_[g >> 1] && (g >> 1) != (h >> 1)) found = g;
        });
        if (found == kNone || e_constrained_[found >> 1] != kFeatureEdge) return kNone;
        const double c = dot(unit(pos_[h_to_[h ^ 1]] - pos_[v]), unit(pos_[h_to_[found]] - pos_[v]));
        return -c < corner_cos ? kNone : found;
    };
    // a chain end that holds it: a junction of three or more constrained edges, or where it runs into the
    // boundary (a loose end or a sharp turn does not)
    auto holds = [&](Index v) {
        if (degree[v] >= 3) return true;
        bool boundary = false;
        for_out(v, [&](Index g) { boundary = boundary || e_constrained_[g >> 1] == kBoundaryEdge; });
        return boundary;
    };
    std::vector<std::uint32_t> seen(e_dead_.size(), 0);
    std::uint32_t pass = 0;
    for (bool changed = true; changed;) {
        changed = false;
        ++pass;
        for (Index e = 0; e < e_dead_.size(); ++e) {
            if (e_constrained_[e] != kFeatureEdge || seen[e] == pass) continue;
            // walk back to the start of e's chain (or around its loop), then forward along it
            Index start = 2 * e;
            bool closed = false;
            for (;;) {
                const Index g = next_constrained(start ^ 1);  // leaves from(start), away from start
                if (g == kNone) break;
                if ((g >> 1) == e) {
                    closed = true;
                    break;
                }
                start = g ^ 1;
            }
            chain.clear();
            double total = 0;
            Index h = start;
            for (;;) {
                chain.push_back(h >> 1);
                seen[h >> 1] = pass;
                total += std::sqrt(length2(h >> 1));
                const Index g = next_constrained(h);
                if (g == kNone || (g >> 1) == (start >> 1)) break;
                h = g;
            }
            if (total >= min_length || (!closed && holds(h_to_[start ^ 1]) && holds(h_to_[h]))) continue;
            for (const Index c : chain) {
                e_constrained_[c] = 0;
                --degree[h_to_[2 * c]], --degree[h_to_[2 * c + 1]];
            }
            changed = true;
        }
    }
    // connected groups of feature edges (through any vertex) shorter than min_length in all
    std::vector<Index> group(nv, kNone), stack;
    std::vector<double> group_length;
    for (Index e = 0; e < e_dead_.size(); ++e) {
        if (e_constrained_[e] != kFeatureEdge || group[h_to_[2 * e]] != kNone) continue;
        const auto id = static_cast<Index>(group_length.size());
        group_length.push_back(0);
        group[h_to_[2 * e]] = id;
        stack.assign(1, h_to_[2 * e]);
        while (!stack.empty()) {
            const Index v = stack.back();
            stack.pop_back();
            for_out(v, [&](Index g) {
                if (e_constrained_[g >> 1] != kFeatureEdge) return;
                if (v < h_to_[g]) group_length[id] += std::sqrt(length2(g >> 1));
                if (group[h_to_[g]] == kNone) {
                    group[h_to_[g]] = id;
                    stack.push_back(h_to_[g]);
                }
            });
        }
    }
    for (Index e = 0; e < e_dead_.size(); ++e)
        if (e_constrained_[e] == kFeatureEdge && group_length[group[h_to_[2 * e]]] < min_length) e_constrained_[e] = 0;
}

}  // namespace surfaced::remesh_detail
