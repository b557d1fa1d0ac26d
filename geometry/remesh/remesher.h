// The remesher behind remesh() (internal to geometry/remesh): class Remesher, an index halfedge mesh with the
// operations of isotropic remeshing (Botsch-Kobbelt 2004), and the thresholds they share. Each group of members is
// defined in the file named at it, so that each operation can be read on its own; remesh.cpp runs the loop.
//
// Every operation keeps the mesh a manifold with consistently oriented, non-degenerate faces that do not fold over.
//
// Data: pmp-style halfedges. Edge e owns halfedges 2e and 2e + 1 (opposite = h ^ 1); boundary halfedges exist and
// have no face, and a boundary vertex's outgoing halfedge is its boundary one. Elements are marked dead rather than
// removed, and the output is compacted at the end.
//
// Constraints: boundary edges (lock_border) and sharp feature edges of the input are "constrained". A vertex on
// exactly two constrained edges that do not turn sharply is a curve vertex: it is removed only by collapsing along a
// constrained edge, relaxes along its curve and is projected onto the input's constrained polylines. Other vertices
// on constrained edges are corners and never move or disappear.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "geometry/core/result.h"
#include "geometry/mesh/polygon_mesh.h"
#include "geometry/remesh/remesh.h"
#include "geometry/simplify/mesh_distance.h"

namespace surfaced::remesh_detail {

inline constexpr Index kNone = kInvalidIndex;
// An operation (split, collapse, flip, smoothing step) may turn a face's normal by at most acos(0.2) ~ 78 degrees,
// which keeps folds out. The simplifier is stricter (60 degrees): its collapses move vertices much farther.
inline constexpr double kMinNormalCos = 0.2;
// Thinness = 2 area / longest edge^2. No operation creates a face thinner than this unless the faces it replaces were
// already thinner (slivers of the input may improve, never get worse).
inline constexpr double kThin = 1e-3;
// Faces thinner than this are degenerate (zero area up to rounding): remove_degenerate_faces removes them, and no
// operation makes one, whatever the faces it replaces.
inline constexpr double kDegenerate = 1e-6;
inline constexpr std::size_t kPollEvery = 4096;

inline double thinness(const Vec3& a, const Vec3& b, const Vec3& c) {
    const double l = std::max({dot(b - a, b - a), dot(c - b, c - b), dot(a - c, a - c)});
    return l > 0 ? norm(cross(b - a, c - a)) / l : 0.0;
}

inline Vec3 unit(const Vec3& v) {
    const double n = norm(v);
    return n > 0 ? v * (1.0 / n) : Vec3{};
}

inline GeoError cancelled() { return make_error(ErrorCode::Cancelled, "remeshing was cancelled"); }

enum VertexKind : std::uint8_t { kFree = 0, kCurve = 1, kCorner = 2 };
// e_constrained_: 0, or why the edge is constrained (operations copy the flag, only its being non-zero matters then)
enum ConstraintKind : std::uint8_t { kBoundaryEdge = 1, kFeatureEdge = 2 };

class Remesher {
public:
    // ---- construction and output (halfedges.cpp) ------------------------------------------------------------------

    Status build(const PolygonMesh& mesh);
    PolygonMesh output() const;

    // ---- boundary and feature classification (constraints.cpp) -----------------------------------------------------

    void set_constraints(const PolygonMesh& input, const RemeshOptions& options, double length);
    void prune_features(double min_length, double corner_cos);
    std::size_t feature_edges() const { return feature_edges_; }
    std::size_t boundary_edges() const { return boundary_edges_; }

    // ---- degenerate faces (degenerate.cpp) --------------------------------------------------------------------------

    std::size_t remove_degenerate_faces();

    // ---- the remeshing loop (remesh.cpp) ----------------------------------------------------------------------------

    Status run(const RemeshOptions& options, double length);

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

    // ---- split (split.cpp) ------------------------------------------------------------------------------------------

    Index split(Index e, const Vec3& p);
    Status split_long_edges(double high, const RemeshOptions& options);

    // ---- collapse (collapse.cpp) ------------------------------------------------------------------------------------

    bool collapse_topology_ok(Index h);
    bool collapse_ok(Index h, double high2);
    void remove_loop(Index h0);
    void collapse(Index h);
    void collapse_keeping_corners(Index h);
    Status collapse_short_edges(double low, double high, const RemeshOptions& options);

    // ---- flip (flip.cpp) --------------------------------------------------------------------------------------------

    int target_valence(Index v) const { return boundary_v(v) ? 4 : 6; }
    //! The topology allows flipping e: an interior, unconstrained edge whose flip makes no existing edge and leaves
    //! both of its ends a valence above 3 (2 on a boundary).
    bool flippable(Index e);
    bool flip_ok(Index e);
    void flip(Index e);
    bool non_delaunay(Index e) const;
    Status equalize_valences(const RemeshOptions& options);
    void remove_caps();

    // ---- degenerate faces (degenerate.cpp) --------------------------------------------------------------------------

    bool remove_degenerate(Index f);
    bool collapse_degenerate(Index h);
    bool degenerate_move_ok(Index v, const Vec3& p, Index skip) const;
    bool degenerate_flip_ok(Index e);

    // ---- relax and project; the check every vertex move passes (relax.cpp) -------------------------------------------

    static bool replacement_ok(const Vec3& old_a, const Vec3& new_a, const Vec3& b, const Vec3& c,
                               const Vec3& reference);
    bool move_ok(Index v, const Vec3& p, const Vec3& ref, Index skip = kNone) const;
    Vec3 relaxed(Index v, RemeshSmoothing smoothing) const;
    Vec3 project(Index v, const Vec3& p, Vec3& ref) const;
    Status relax(const RemeshOptions& options);

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

}  // namespace surfaced::remesh_detail
