// Isotropic remeshing (Botsch-Kobbelt 2004) on an index halfedge mesh, with the checks a service needs: every
// operation keeps the mesh a manifold with consistently oriented, non-degenerate faces that do not fold over.
//
// Data: pmp-style halfedges. Edge e owns halfedges 2e and 2e + 1 (opposite = h ^ 1); boundary halfedges exist and
// have no face, and a boundary vertex's outgoing halfedge is its boundary one. Elements are marked dead rather than
// removed, and the output is compacted at the end.
//
// Constraints: boundary edges (lock_border) and sharp feature edges of the input are "constrained". A vertex on
// exactly two constrained edges that do not turn sharply is a curve vertex: it is removed only by collapsing along a
// constrained edge, relaxes along its curve and is projected onto the input's constrained polylines. Other vertices
// on constrained edges are corners and never move or disappear.
#include "geometry/remesh/remesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <unordered_map>

#include "geometry/mesh/triangulate.h"
#include "geometry/simplify/mesh_distance.h"

namespace surfaced {
namespace {

constexpr Index kNone = kInvalidIndex;
// An operation (split, collapse, flip, smoothing step) may turn a face's normal by at most acos(0.2) ~ 78 degrees,
// which keeps folds out. The simplifier is stricter (60 degrees): its collapses move vertices much farther.
constexpr double kMinNormalCos = 0.2;
// Thinness = 2 area / longest edge^2. No operation creates a face thinner than this unless the faces it replaces were
// already thinner (slivers of the input may improve, never get worse).
constexpr double kThin = 1e-3;
// Faces thinner than this are degenerate (zero area up to rounding): remove_degenerate_faces removes them, and no
// operation makes one, whatever the faces it replaces.
constexpr double kDegenerate = 1e-6;
// A degenerate face whose corner opposite the longest edge lies within this share of that edge from one of its ends
// is a needle (collapsed), otherwise a cap (flipped, or split and collapsed).
constexpr double kNeedleShare = 0.01;
// remove_degenerate_faces passes over the faces at most this often (one removal can leave a degenerate face behind,
// such as the next cap of a T-junction with several corners on one edge).
constexpr int kDegenerateRounds = 8;
constexpr std::size_t kPollEvery = 4096;
// A boundary or feature polyline turning by more than 60 degrees at a vertex has a corner there, whatever the feature
// angle (cos 60 degrees).
constexpr double kMaxTurnCos = 0.5;

double thinness(const Vec3& a, const Vec3& b, const Vec3& c) {
    const double l = std::max({dot(b - a, b - a), dot(c - b, c - b), dot(a - c, a - c)});
    return l > 0 ? norm(cross(b - a, c - a)) / l : 0.0;
}

Vec3 unit(const Vec3& v) {
    const double n = norm(v);
    return n > 0 ? v * (1.0 / n) : Vec3{};
}

GeoError cancelled() { return make_error(ErrorCode::Cancelled, "remeshing was cancelled"); }

enum VertexKind : std::uint8_t { kFree = 0, kCurve = 1, kCorner = 2 };
// e_constrained_: 0, or why the edge is constrained (operations copy the flag, only its being non-zero matters then)
enum ConstraintKind : std::uint8_t { kBoundaryEdge = 1, kFeatureEdge = 2 };
// Bounds of the working target edge length that run() steers the mean edge length to L with, in L.
constexpr double kMinWorking = 0.8, kMaxWorking = 1.25;
// Within this share of L the mean edge length is left alone; kFinalRelaxations rounds of flips and relaxation end run().
constexpr double kSettled = 0.02;
constexpr int kFinalRelaxations = 3;
// A flip that does not worsen valences is made when the angles opposite the edge exceed pi by this (radians).
constexpr double kDelaunaySlack = 0.05;
// Loose or closed chains of feature edges shorter than this many L are noise, not creases (prune_features).
constexpr double kMinFeatureLength = 5.0;

class Remesher {
public:
    // ---- construction ----------------------------------------------------------------------------------------------

    //! Halfedges from a triangle mesh; refuses edges with more than two faces or traversed twice in one direction, and
    //! vertices where several fans of faces meet.
    Status build(const PolygonMesh& mesh) {
        const std::size_t nv = mesh.vertex_count(), nf = mesh.face_count();
        pos_ = mesh.positions;
        v_out_.assign(nv, kNone);
        v_kind_.assign(nv, kFree);
        v_dead_.assign(nv, 0);
        h_to_.reserve(6 * nf);
        std::unordered_map<std::uint64_t, Index> edge_of;
        edge_of.reserve(3 * nf);
        std::vector<Index> faces_at(nv, 0);
        for (Index f = 0; f < nf; ++f) {
            auto t = mesh.face(f);
            const Index fh = new_face();
            std::array<Index, 3> hs{};
            for (int j = 0; j < 3; ++j) {
                const Index u = t[j], w = t[(j + 1) % 3];
                ++faces_at[u];
                const std::uint64_t key = (std::uint64_t{std::min(u, w)} << 32) | std::max(u, w);
                auto [it, inserted] = edge_of.try_emplace(key, kNone);
                if (inserted) it->second = new_edge(u, w);
                const Index e = it->second;
                const Index h = h_to_[2 * e] == w ? 2 * e : 2 * e + 1;
                if (h_face_[h] != kNone) {
                    const std::string edge = "(" + std::to_string(u) + ", " + std::to_string(w) + ")";
                    return element_error(ErrorCode::NonManifold,
                                         h_face_[h ^ 1] == kNone
                                             ? "edge " + edge + " is traversed in the same direction by face " +
                                                   std::to_string(f) +
                                                   " and another face (inconsistent orientation or a duplicate face)"
                                             : "edge " + edge + " is shared by more than two faces (face " +
                                                   std::to_string(f) + " is one)",
                                         ElementKind::Face, f);
                }
                h_face_[h] = fh;
                hs[j] = h;
            }
            for (int j = 0; j < 3; ++j) link(hs[j], hs[(j + 1) % 3]);
            f_h_[fh] = hs[0];
        }
        // boundary halfedges: linked to the boundary halfedge leaving their end vertex, which must be unique
        std::vector<Index> boundary_out(nv, kNone);
        for (Index h = 0; h < h_to_.size(); ++h) {
            const Index from = h_to_[h ^ 1];
            if (v_out_[from] == kNone) v_out_[from] = h;
            if (h_face_[h] != kNone) continue;
            if (boundary_out[from] != kNone)
                return element_error(
                    ErrorCode::NonManifold,
                    "vertex " + std::to_string(from) + " joins several fans of faces (a non-manifold vertex)",
                    ElementKind::Vertex, from);
            boundary_out[from] = h;
        }
        for (Index h = 0; h < h_to_.size(); ++h)
            if (h_face_[h] == kNone) link(h, boundary_out[h_to_[h]]);
        for (Index v = 0; v < nv; ++v) {
            if (boundary_out[v] != kNone) v_out_[v] = boundary_out[v];
            if (v_out_[v] == kNone) {
                v_dead_[v] = 1;  // in no face: not part of the surface, dropped from the output
                continue;
            }
            // one fan: walking around v meets every face that uses it
            Index count = 0, guard = 0;
            const Index h0 = v_out_[v];
            Index h = h0;
            do {
                if (h_face_[h] != kNone) ++count;
                h = h_next_[h ^ 1];
            } while (h != h0 && ++guard <= faces_at[v] + 1);
            if (count != faces_at[v])
                return element_error(
                    ErrorCode::NonManifold,
                    "vertex " + std::to_string(v) + " joins several fans of faces (a non-manifold vertex)",
                    ElementKind::Vertex, v);
        }
        live_faces_ = nf;
        return Ok{};
    }

    //! Marks boundary (lock_border) and sharp feature edges constrained and classifies vertices; builds the
    //! projection targets from the input.
    void set_constraints(const PolygonMesh& input, const RemeshOptions& options, double length) {
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
    void prune_features(double min_length, double corner_cos) {
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
            if (e_constrained_[e] == kFeatureEdge && group_length[group[h_to_[2 * e]]] < min_length)
                e_constrained_[e] = 0;
    }

    std::size_t feature_edges() const { return feature_edges_; }
    std::size_t boundary_edges() const { return boundary_edges_; }

    //! Removes faces of (almost) zero area, as CAD exports have them: caps (a corner on the opposite edge, such as the
    //! face that closes a T-junction) and needles (two corners together). A cap's longest edge is flipped, which keeps
    //! the surface (the union of the two faces is the same when the corner lies on the edge); where it cannot be
    //! flipped (a boundary or constrained edge, or a flip that would duplicate an edge), the edge is split at the foot
    //! of the corner and the corner collapsed into the new vertex. A needle's short edge is collapsed. Each change
    //! moves the surface by at most the face's height or its short edge, and respects the constraints. Runs before
    //! the constraints are set (so that feature edges are found across the faces that closed T-junctions) and after
    //! the last iteration. \return the degenerate faces that could not be removed.
    std::size_t remove_degenerate_faces() {
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

    // ---- the remeshing loop -----------------------------------------------------------------------------------------

    //! The (4/5, 4/3) band leaves a mesh stable whose edges average anywhere in it (longest-edge bisection of a coarse
    //! grid lands at 1.13 L, of a finer one at 0.88 L), so the thresholds follow a working target that is corrected
    //! after every iteration by the ratio of L to the mean edge length reached (unless within kSettled of L), within
    //! [kMinWorking, kMaxWorking] L; when the mean crosses L the working target goes half way back to L (the mesh
    //! answers a correction over several iterations, and a pure integral correction would overshoot). Then
    //! kFinalRelaxations rounds of flips and relaxation smooth the last splits and collapses.
    Status run(const RemeshOptions& options, double length) {
        double working = length;
        double last_error = 0;
        for (int it = 0; it < options.iterations; ++it) {
            if (options.cancel.requested()) return cancelled();
            const double high = 4.0 / 3.0 * working, low = 4.0 / 5.0 * working;
            if (auto s = split_long_edges(high, options); !s) return s;
            if (auto s = collapse_short_edges(low, high, options); !s) return s;
            if (auto s = equalize_valences(options); !s) return s;
            if (auto s = relax(options); !s) return s;
            const double mean = mean_live_edge_length();
            const double error = mean - length;
            // the mean crossed L: the corrections so far overshoot, take half of them back (in ratio)
            if (error * last_error < 0) working = std::sqrt(working * length);
            last_error = error;
            if (mean > 0 && std::abs(error) > kSettled * length)
                working = std::clamp(working * length / mean, kMinWorking * length, kMaxWorking * length);
        }
        // the last corrections leave fresh splits and collapses: relax them without changing the vertex count
        for (int it = 0; it < std::min(options.iterations, kFinalRelaxations); ++it) {
            if (options.cancel.requested()) return cancelled();
            if (auto s = equalize_valences(options); !s) return s;
            if (auto s = relax(options); !s) return s;
        }
        if (options.iterations > 0) remove_caps();
        remove_degenerate_faces();
        return Ok{};
    }

    PolygonMesh output() const {
        PolygonMesh out;
        std::vector<Index> map(pos_.size(), kNone);
        for (Index v = 0; v < pos_.size(); ++v) {
            if (v_dead_[v]) continue;
            map[v] = static_cast<Index>(out.positions.size());
            out.positions.push_back(pos_[v]);
        }
        out.face_indices.reserve(3 * live_faces_);
        out.face_offsets.reserve(live_faces_ + 1);
        for (Index f = 0; f < f_h_.size(); ++f) {
            if (f_dead_[f]) continue;
            const Index h = f_h_[f];
            out.add_face({map[h_to_[h]], map[h_to_[h_next_[h]]], map[h_to_[h_next_[h_next_[h]]]]});
        }
        return out;
    }

private:
    // ---- elements --------------------------------------------------------------------------------------------------

    Index new_vertex(const Vec3& p, VertexKind kind) {
        pos_.push_back(p);
        v_out_.push_back(kNone);
        v_kind_.push_back(kind);
        v_dead_.push_back(0);
        return static_cast<Index>(pos_.size() - 1);
    }
    //! Edge u-w: halfedge 2e runs u -> w, 2e + 1 runs w -> u; no faces, unlinked.
    Index new_edge(Index u, Index w) {
        h_to_.push_back(w);
        h_to_.push_back(u);
        h_next_.insert(h_next_.end(), {kNone, kNone});
        h_prev_.insert(h_prev_.end(), {kNone, kNone});
        h_face_.insert(h_face_.end(), {kNone, kNone});
        e_constrained_.push_back(0);
        e_dead_.push_back(0);
        return static_cast<Index>(e_dead_.size() - 1);
    }
    Index new_face() {
        f_h_.push_back(kNone);
        f_dead_.push_back(0);
        ++live_faces_;
        return static_cast<Index>(f_h_.size() - 1);
    }
    void link(Index h, Index next) {
        h_next_[h] = next;
        h_prev_[next] = h;
    }

    Index from(Index h) const { return h_to_[h ^ 1]; }
    bool boundary_h(Index h) const { return h_face_[h] == kNone; }
    bool boundary_v(Index v) const { return v_out_[v] != kNone && h_face_[v_out_[v]] == kNone; }
    //! f(h) for each halfedge leaving v, in order around v.
    template <class F>
    void for_out(Index v, F&& f) const {
        const Index h0 = v_out_[v];
        if (h0 == kNone) return;
        Index h = h0;
        do {
            const Index next = h_next_[h ^ 1];  // read before f: collapse() redirects h_to_ of the halfedges it visits
            f(h);
            h = next;
        } while (h != h0);
    }
    double mean_live_edge_length() const {
        double sum = 0;
        std::size_t n = 0;
        for (Index e = 0; e < e_dead_.size(); ++e)
            if (!e_dead_[e]) sum += std::sqrt(length2(e)), ++n;
        return n ? sum / static_cast<double>(n) : 0.0;
    }
    Index constrained_degree(Index v) const {
        Index n = 0;
        for_out(v, [&](Index h) { n += e_constrained_[h >> 1] != 0; });
        return n;
    }
    Index valence(Index v) const {
        Index n = 0;
        for_out(v, [&](Index) { ++n; });
        return n;
    }
    void adjust_out(Index v) {
        for_out(v, [&](Index h) {
            if (h_face_[h] == kNone) v_out_[v] = h;
        });
    }
    double length2(Index e) const {
        const Vec3 d = pos_[h_to_[2 * e]] - pos_[h_to_[2 * e + 1]];
        return dot(d, d);
    }
    std::array<Index, 3> face_vertices(Index f) const {
        const Index h = f_h_[f];
        return {h_to_[h], h_to_[h_next_[h]], h_to_[h_next_[h_next_[h]]]};
    }
    Vec3 face_normal(Index f) const {
        const auto t = face_vertices(f);
        return cross(pos_[t[1]] - pos_[t[0]], pos_[t[2]] - pos_[t[0]]);
    }
    double face_thinness(Index f) const {
        const auto t = face_vertices(f);
        return thinness(pos_[t[0]], pos_[t[1]], pos_[t[2]]);
    }
    //! Would the face (moved, b, c), replacing (old, b, c), stay acceptable: no turn past kMinNormalCos, no thinner
    //! than kThin unless the old one was thinner, and facing the same way as the input under it (`reference`: the sum
    //! of its corners' reference normals)?
    static bool replacement_ok(const Vec3& old_a, const Vec3& new_a, const Vec3& b, const Vec3& c,
                               const Vec3& reference) {
        const Vec3 n_old = cross(b - old_a, c - old_a), n_new = cross(b - new_a, c - new_a);
        const double t_new = thinness(new_a, b, c);
        if (t_new < kThin && (t_new < kDegenerate || t_new < thinness(old_a, b, c))) return false;
        return dot(unit(n_old), unit(n_new)) > kMinNormalCos && dot(n_new, reference) > 0;
    }
    //! Moving v to p (where the input's normal is `ref`) keeps every face around v (except those containing `skip`)
    //! acceptable.
    bool move_ok(Index v, const Vec3& p, const Vec3& ref, Index skip = kNone) const {
        bool ok = true;
        for_out(v, [&](Index h) {
            if (!ok || h_face_[h] == kNone) return;
            const Index b = h_to_[h], c = h_to_[h_next_[h]];
            if (b == skip || c == skip) return;
            if (!replacement_ok(pos_[v], p, pos_[b], pos_[c], ref + v_ref_[b] + v_ref_[c])) ok = false;
        });
        return ok;
    }

    // ---- split ------------------------------------------------------------------------------------------------------

    //! Splits edge e at p; the new vertex is returned. Both faces (where present) become two.
    Index split(Index e, const Vec3& p) {
        const Index h0 = 2 * e, o0 = 2 * e + 1;
        const Index b = h_to_[h0];
        const Index v = new_vertex(p, e_constrained_[e] ? kCurve : kFree);
        v_ref_.push_back(unit(v_ref_[h_to_[h0]] + v_ref_[h_to_[o0]]));
        const Index e1 = new_edge(v, b);
        const Index h1 = 2 * e1, o1 = 2 * e1 + 1;  // v -> b, b -> v
        e_constrained_[e1] = e_constrained_[e];
        h_to_[h0] = v;  // h0: a -> v; o0 becomes v -> a
        if (!boundary_h(h0)) {
            const Index f0 = h_face_[h0], n0 = h_next_[h0], p0 = h_next_[n0];  // b -> c, c -> a
            const Index c = h_to_[n0];
            const Index e2 = new_edge(v, c);
            const Index x = 2 * e2, y = 2 * e2 + 1;  // v -> c, c -> v
            const Index f2 = new_face();
            link(h0, x), link(x, p0), link(p0, h0);
            h_face_[x] = f0;
            f_h_[f0] = h0;
            link(h1, n0), link(n0, y), link(y, h1);
            h_face_[h1] = h_face_[n0] = h_face_[y] = f2;
            f_h_[f2] = h1;
        } else {
            const Index hn = h_next_[h0];
            link(h0, h1), link(h1, hn);
        }
        if (!boundary_h(o0)) {
            const Index f1 = h_face_[o0], n1 = h_next_[o0], p1 = h_next_[n1];  // a -> d, d -> b
            const Index d = h_to_[n1];
            const Index e3 = new_edge(v, d);
            const Index s = 2 * e3, t = 2 * e3 + 1;  // v -> d, d -> v
            const Index f3 = new_face();
            link(o0, n1), link(n1, t), link(t, o0);
            h_face_[t] = f1;
            f_h_[f1] = o0;
            link(o1, s), link(s, p1), link(p1, o1);
            h_face_[o1] = h_face_[s] = h_face_[p1] = f3;
            f_h_[f3] = o1;
        } else {
            const Index op = h_prev_[o0];
            link(op, o1), link(o1, o0);
        }
        v_out_[v] = h1;
        if (v_out_[b] == o0) v_out_[b] = o1;
        adjust_out(v);
        return v;
    }

    //! Longest edge first (Rivara's longest-edge bisection): splitting in index order can keep making thinner
    //! triangles on coarse input (a cube's two triangles per side split towards L << side) and never finish.
    Status split_long_edges(double high, const RemeshOptions& options) {
        const double high2 = high * high;
        std::vector<std::pair<double, Index>> heap;
        for (Index e = 0; e < e_dead_.size(); ++e)
            if (!e_dead_[e] && length2(e) > high2) heap.push_back({length2(e), e});
        std::make_heap(heap.begin(), heap.end());
        std::size_t done = 0;
        while (!heap.empty()) {
            std::pop_heap(heap.begin(), heap.end());
            const auto [stored, e] = heap.back();
            heap.pop_back();
            if (++done % kPollEvery == 0 && options.cancel.requested()) return cancelled();
            const double l2 = length2(e);
            if (l2 <= high2) continue;
            if (l2 < stored) {  // split since it was pushed: its current length is queued again
                heap.push_back({l2, e});
                std::push_heap(heap.begin(), heap.end());
                continue;
            }
            const Index v = split(e, (pos_[h_to_[2 * e]] + pos_[h_to_[2 * e + 1]]) * 0.5);
            if (options.max_faces != 0 && live_faces_ > options.max_faces)
                return make_error(
                    ErrorCode::BudgetExceeded,
                    "remeshing needs more than " + std::to_string(options.max_faces) + " faces at this edge length");
            for_out(v, [&](Index h) {
                const Index f = h >> 1;
                if (length2(f) > high2) {
                    heap.push_back({length2(f), f});
                    std::push_heap(heap.begin(), heap.end());
                }
            });
        }
        return Ok{};
    }

    // ---- collapse ---------------------------------------------------------------------------------------------------

    //! Topology: collapsing h (from(h) into to(h)) keeps a manifold (pmp's is_collapse_ok plus no interior vertex
    //! left with valence 2).
    bool collapse_topology_ok(Index h) {
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
    bool collapse_ok(Index h, double high2) {
        const Index v0 = from(h), v1 = h_to_[h];
        if (v_kind_[v0] == kCorner &&
            !(e_constrained_[h >> 1] && (v_kind_[v1] == kCorner || constrained_degree(v0) == 1)))
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

    void remove_loop(Index h0) {
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
    void collapse(Index h) {
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
    void collapse_keeping_corners(Index h) {
        const bool corner = v_kind_[from(h)] == kCorner;
        const Index v1 = h_to_[h];
        collapse(h);
        if (corner) v_kind_[v1] = kCorner;
    }

    Status collapse_short_edges(double low, double high, const RemeshOptions& options) {
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

    // ---- flip -------------------------------------------------------------------------------------------------------

    int target_valence(Index v) const { return boundary_v(v) ? 4 : 6; }

    bool flip_ok(Index e) {
        const Index h = 2 * e, o = 2 * e + 1;
        if (e_constrained_[e] || boundary_h(h) || boundary_h(o)) return false;
        const Index a = h_to_[o], b = h_to_[h], c = h_to_[h_next_[h]], d = h_to_[h_next_[o]];
        if (c == d) return false;
        bool connected = false;
        for_out(c, [&](Index g) { connected = connected || h_to_[g] == d; });
        if (connected) return false;
        if (valence(a) <= (boundary_v(a) ? 2u : 3u) || valence(b) <= (boundary_v(b) ? 2u : 3u)) return false;
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

    void flip(Index e) {
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
    bool non_delaunay(Index e) const {
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
    Status equalize_valences(const RemeshOptions& options) {
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
    void remove_caps() {
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

    // ---- degenerate faces -------------------------------------------------------------------------------------------

    //! One step of remove_degenerate_faces on face f; false when nothing could be done.
    bool remove_degenerate(Index f) {
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
    bool collapse_degenerate(Index h) {
        const Index v0 = from(h), v1 = h_to_[h];
        if (v_kind_[v0] == kCorner || (v_kind_[v0] == kCurve && !e_constrained_[h >> 1])) return false;
        if (boundary_v(v0) && !(boundary_h(h) || boundary_h(h ^ 1))) return false;
        if (!collapse_topology_ok(h) || !degenerate_move_ok(v0, pos_[v1], v1)) return false;
        collapse(h);
        return true;
    }

    //! Moving v to p, do the faces around v (except those with `skip`) keep their orientation and stay off
    //! degenerate (or no thinner than they were)? Unlike move_ok, a degenerate face's normal is not compared.
    bool degenerate_move_ok(Index v, const Vec3& p, Index skip) const {
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
    bool degenerate_flip_ok(Index e) {
        const Index h = 2 * e, o = 2 * e + 1;
        if (e_constrained_[e] || boundary_h(h) || boundary_h(o)) return false;
        const Index a = h_to_[o], b = h_to_[h], c = h_to_[h_next_[h]], d = h_to_[h_next_[o]];
        if (c == d) return false;
        bool connected = false;
        for_out(c, [&](Index g) { connected = connected || h_to_[g] == d; });
        if (connected) return false;
        if (valence(a) <= (boundary_v(a) ? 2u : 3u) || valence(b) <= (boundary_v(b) ? 2u : 3u)) return false;
        const Vec3 &pa = pos_[a], &pb = pos_[b], &pc = pos_[c], &pd = pos_[d];
        const double t1 = thinness(pa, pb, pc), t2 = thinness(pb, pa, pd);
        const Vec3 reference = t1 >= t2 ? cross(pb - pa, pc - pa) : cross(pa - pb, pd - pb);
        const double t_new = std::min(thinness(pa, pd, pc), thinness(pb, pc, pd));
        if (!(t_new > std::min(t1, t2))) return false;
        for (const Vec3& n : {cross(pd - pa, pc - pa), cross(pc - pb, pd - pb)})
            if (dot(unit(n), unit(reference)) <= kMinNormalCos) return false;
        return true;
    }

    // ---- relax and project ------------------------------------------------------------------------------------------

    Vec3 relaxed(Index v, RemeshSmoothing smoothing) const {
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
    Vec3 project(Index v, const Vec3& p, Vec3& ref) const {
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

    Status relax(const RemeshOptions& options) {
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

    std::vector<Vec3> pos_;
    std::vector<Index> v_out_;
    std::vector<std::uint8_t> v_kind_, v_dead_;
    std::vector<Index> h_to_, h_next_, h_prev_, h_face_;
    std::vector<std::uint8_t> e_constrained_, e_dead_;
    std::vector<Index> f_h_;
    std::vector<std::uint8_t> f_dead_;
    std::size_t live_faces_ = 0;
    std::size_t feature_edges_ = 0, boundary_edges_ = 0;
    std::vector<std::uint32_t> mark_;
    std::uint32_t stamp_ = 0;
    std::unique_ptr<SurfaceDistance> surface_, curves_;
    std::vector<Vec3> input_normals_;  //!< unit normals of the input's triangles
    std::vector<Vec3> v_ref_;          //!< per vertex: the input's unit normal where the vertex lies
};

double mean_edge_length(const PolygonMesh& mesh) {
    double sum = 0;
    std::size_t n = 0;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        auto t = mesh.face(f);
        for (std::size_t j = 0; j < t.size(); ++j) {
            sum += norm(mesh.positions[t[(j + 1) % t.size()]] - mesh.positions[t[j]]);
            ++n;
        }
    }
    return n ? sum / static_cast<double>(n) : 0.0;
}

}  // namespace

MeshQuality measure_quality(const PolygonMesh& mesh) {
    MeshQuality q;
    q.vertices = mesh.vertex_count();
    constexpr double kRatioCap = 1e30;  // Verdict's VERDICT_DBL_MAX
    double min_angle = std::numbers::pi, ratio_sum = 0;
    std::size_t triangles = 0, below = 0;
    std::vector<std::pair<Index, Index>> edges;  // directed, as the faces traverse them
    edges.reserve(mesh.face_indices.size());
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        auto t = mesh.face(f);
        for (std::size_t j = 0; j < t.size(); ++j) edges.push_back({t[j], t[(j + 1) % t.size()]});
        for (std::size_t j = 1; j + 1 < t.size(); ++j) {
            const Vec3 &a = mesh.positions[t[0]], &b = mesh.positions[t[j]], &c = mesh.positions[t[j + 1]];
            const Vec3 corners[3][3] = {{a, b, c}, {b, c, a}, {c, a, b}};
            double smallest = std::numbers::pi;
            for (const auto& k : corners) {
                const Vec3 u = k[1] - k[0], w = k[2] - k[0];
                smallest = std::min(smallest, std::atan2(norm(cross(u, w)), dot(u, w)));
            }
            min_angle = std::min(min_angle, smallest);
            if (smallest < std::numbers::pi / 6) ++below;
            // Verdict radius ratio R / (2 r) = abc s / (8 A^2), s the semi-perimeter
            const double la = norm(b - c), lb = norm(c - a), lc = norm(a - b);
            const double area = 0.5 * norm(cross(b - a, c - a));
            const double s = 0.5 * (la + lb + lc);
            const double denom = 8 * area * area;
            const double ratio = denom > 0 ? std::min(kRatioCap, la * lb * lc * s / denom) : kRatioCap;
            ratio_sum += ratio;
            q.max_radius_ratio = std::max(q.max_radius_ratio, ratio);
            ++triangles;
        }
    }
    q.faces = mesh.face_count();
    if (triangles > 0) {
        q.min_angle_degrees = min_angle * 180.0 / std::numbers::pi;
        q.share_below_30 = static_cast<double>(below) / static_cast<double>(triangles);
        q.mean_radius_ratio = ratio_sum / static_cast<double>(triangles);
    }
    // undirected edges; one used by a single face is a boundary edge
    std::vector<std::pair<Index, Index>> undirected(edges.size());
    for (std::size_t i = 0; i < edges.size(); ++i)
        undirected[i] = {std::min(edges[i].first, edges[i].second), std::max(edges[i].first, edges[i].second)};
    std::sort(undirected.begin(), undirected.end());
    std::vector<Index> valence(mesh.vertex_count(), 0);
    std::vector<std::uint8_t> on_boundary(mesh.vertex_count(), 0);
    double sum = 0, sum2 = 0;
    std::size_t count = 0;
    for (std::size_t i = 0; i < undirected.size();) {
        std::size_t j = i;
        while (j < undirected.size() && undirected[j] == undirected[i]) ++j;
        const auto [u, w] = undirected[i];
        ++valence[u], ++valence[w];
        if (j - i == 1) on_boundary[u] = on_boundary[w] = 1;
        const double l = norm(mesh.positions[u] - mesh.positions[w]);
        sum += l, sum2 += l * l;
        ++count;
        i = j;
    }
    if (count > 0) {
        q.mean_edge_length = sum / static_cast<double>(count);
        q.edge_length_stddev =
            std::sqrt(std::max(0.0, sum2 / static_cast<double>(count) - q.mean_edge_length * q.mean_edge_length));
    }
    std::size_t used = 0, regular = 0;
    for (std::size_t v = 0; v < valence.size(); ++v) {
        if (valence[v] == 0) continue;
        if (q.valence_histogram.size() <= valence[v]) q.valence_histogram.resize(valence[v] + 1, 0);
        ++q.valence_histogram[valence[v]];
        ++used;
        if (valence[v] == (on_boundary[v] ? 4u : 6u)) ++regular;
    }
    q.share_regular = used ? static_cast<double>(regular) / static_cast<double>(used) : 0.0;
    return q;
}

Result<RemeshResult> remesh(const PolygonMesh& mesh, const RemeshOptions& options) {
    if (auto valid = validate(mesh); !valid) return valid.error();
    if (options.iterations < 0)
        return make_error(ErrorCode::InvalidArgument,
                          "iterations must be >= 0, got " + std::to_string(options.iterations));
    if (!(options.feature_angle_degrees >= 0 && options.feature_angle_degrees <= 180))
        return make_error(ErrorCode::InvalidArgument, "the feature angle must be in [0, 180] degrees");
    if (mesh.face_count() == 0) return make_error(ErrorCode::InvalidArgument, "the mesh has no faces");

    RemeshResult result;
    result.triangulated = !mesh.is_triangle_mesh();
    PolygonMesh input = result.triangulated ? triangulate(mesh) : mesh;
    input.uvs.clear();
    input.uv_indices.clear();
    input.normals.clear();
    input.tags = {};

    double length = 0;
    if (options.target_edge_length)
        length = *options.target_edge_length;
    else if (options.relative_edge_length)
        length = *options.relative_edge_length * input.bounds().diagonal();
    else
        length = mean_edge_length(input);
    if (!(std::isfinite(length) && length > 0))
        return make_error(ErrorCode::InvalidArgument, "the target edge length must be finite and > 0");
    result.target_edge_length = length;

    Remesher remesher;
    if (auto built = remesher.build(input); !built) return built.error();
    remesher.remove_degenerate_faces();
    remesher.set_constraints(input, options, length);
    result.feature_edges = remesher.feature_edges();
    result.boundary_edges = remesher.boundary_edges();
    if (auto ran = remesher.run(options, length); !ran) return ran.error();
    result.mesh = remesher.output();
    result.before = measure_quality(input);
    result.after = measure_quality(result.mesh);
    if (options.measure_hausdorff) {
        if (options.cancel.requested()) return cancelled();
        result.hausdorff = mesh_distance(input, result.mesh).hausdorff;
    }
    return result;
}

}  // namespace surfaced
