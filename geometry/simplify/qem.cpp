// Quadric-error edge collapse (Garland-Heckbert 1997), with the safety checks a service needs: every collapse keeps
// the mesh a manifold with consistently oriented, non-degenerate, non-duplicate faces.
//
// Data: triangles as index triples plus a vertex -> faces list (enough for one-rings; pmp and meshoptimizer use the
// same adjacency for decimation). Candidates sit in a 4-ary heap keyed on quadric cost; an entry remembers the
// version stamps of its endpoints, and an entry whose endpoint changed since it was pushed is stale and skipped
// (lazy invalidation). After a collapse only the edges at the surviving vertex change cost, and those are pushed
// again with its new version.
#include "geometry/simplify/qem.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "geometry/mesh/triangulate.h"
#include "geometry/simplify/mesh_distance.h"
#include "geometry/simplify/quadric.h"

namespace surfaced {
namespace {

using simplify_detail::Quadric;

// A collapse may turn a face's normal by at most acos(0.2) ~ 78 degrees. Garland-Heckbert only forbid flips (0);
// a margin keeps folds out of the output, whose normals are later compared to the input's.
constexpr double kMinNormalCos = 0.2;
// Thinness = 2 area / longest edge^2 (the height over the longest edge, relative to it). A collapse may not create
// a face thinner than kThin unless the face was already thinner (slivers in the input may improve, not worsen), and
// never one thinner than kDegenerate.
constexpr double kThin = 1e-3;
constexpr double kDegenerate = 1e-6;
// An optimal point farther than this many edge lengths from the edge's midpoint comes from an ill-conditioned
// quadric even when the determinant test passed; the fallback placement is safer.
constexpr double kMaxPlacementReach = 4.0;
constexpr int kMaxPasses = 8;
constexpr int kMaxErrorAttempts = 7;

enum VertexFlag : std::uint8_t {
    kAlive = 1,
    kBoundary = 2,  //!< on a boundary edge
    kPinned = 4,    //!< never moves or disappears: locked, lock_border boundary, UV seam, non-manifold boundary
};

double thinness(const Vec3& a, const Vec3& b, const Vec3& c) {
    const double l = std::max({dot(b - a, b - a), dot(c - b, c - b), dot(a - c, a - c)});
    return l > 0 ? norm(cross(b - a, c - a)) / l : 0.0;
}

// 20 bytes: the heap holds a few million of these for a 1M-triangle mesh, and popping is cache-bound.
struct Candidate {
    float cost;  //!< ordering only; the collapse itself is re-evaluated in double when popped
    Index a, b;
    std::uint32_t version_a, version_b;
};
//! A 4-ary min-heap on cost: half the depth of a binary heap, and the four children of a node share a cache line
//! or two. Popping dominates the run time on large meshes (millions of entries).
class CandidateHeap {
public:
    bool empty() const { return items_.empty(); }
    std::size_t size() const { return items_.size(); }
    void clear() { items_.clear(); }
    //! Appends without ordering; call make() before the next pop().
    void append(const Candidate& c) { items_.push_back(c); }
    void make() {
        if (items_.size() < 2) return;
        for (std::size_t i = (items_.size() - 2) / 4 + 1; i-- > 0;) sift_down(i, items_[i]);
    }
    void push(const Candidate& c) {
        items_.push_back(c);
        std::size_t i = items_.size() - 1;
        while (i > 0) {
            const std::size_t parent = (i - 1) / 4;
            if (!(c.cost < items_[parent].cost)) break;
            items_[i] = items_[parent];
            i = parent;
        }
        items_[i] = c;
    }
    Candidate pop() {
        const Candidate top = items_.front();
        const Candidate last = items_.back();
        items_.pop_back();
        if (!items_.empty()) sift_down(0, last);
        return top;
    }
    template <class Pred>
    void erase_if(Pred pred) {
        std::erase_if(items_, pred);
        make();
    }

private:
    void sift_down(std::size_t i, const Candidate c) {
        const std::size_t n = items_.size();
        for (;;) {
            const std::size_t first = 4 * i + 1;
            if (first >= n) break;
            std::size_t best = first;
            const std::size_t end = std::min(first + 4, n);
            for (std::size_t j = first + 1; j < end; ++j)
                if (items_[j].cost < items_[best].cost) best = j;
            if (!(items_[best].cost < c.cost)) break;
            items_[i] = items_[best];
            i = best;
        }
        items_[i] = c;
    }
    std::vector<Candidate> items_;
};

struct Collapse {
    Index keep = kInvalidIndex, remove = kInvalidIndex;
    Vec3 position;
    double s = 0;      //!< position's parameter along keep -> remove, for attribute interpolation
    double cost = 0;   //!< Q(position), the heap key
    double error = 0;  //!< sqrt(Q(position) / weight): a distance
};

class Simplifier {
public:
    Simplifier(const PolygonMesh& mesh, const SimplifyOptions& options) : options_(options) {
        const std::size_t nv = mesh.vertex_count(), nf = mesh.face_count();
        positions_ = mesh.positions;
        faces_.resize(nf);
        face_alive_.assign(nf, 1);
        for (std::size_t f = 0; f < nf; ++f) {
            auto face = mesh.face(f);
            faces_[f] = {face[0], face[1], face[2]};
        }
        if (mesh.has_uvs()) {
            uvs_ = mesh.uvs;
            face_uvs_.resize(nf);
            for (std::size_t f = 0; f < nf; ++f) {
                const Index o = mesh.face_offsets[f];
                face_uvs_[f] = {mesh.uv_indices[o], mesh.uv_indices[o + 1], mesh.uv_indices[o + 2]};
            }
        }
        normals_ = mesh.normals;
        live_faces_ = nf;
        vertex_faces_.resize(nv);
        quadrics_.resize(nv);
        version_.assign(nv, 0);
        flags_.assign(nv, kAlive);
    }

    //! Adjacency, the manifold check, quadrics and pinned vertices.
    Status init() {
        const std::size_t nv = positions_.size();
        {
            std::vector<Index> degree(nv, 0);
            for (const auto& f : faces_)
                for (Index v : f) ++degree[v];
            for (std::size_t v = 0; v < nv; ++v) vertex_faces_[v].reserve(degree[v]);
        }
        for (Index f = 0; f < faces_.size(); ++f)
            for (Index v : faces_[f]) vertex_faces_[v].push_back(f);

        reference_normals_.assign(faces_.size(), Vec3{});
        // face planes, weighted by area so that the metric does not depend on the tessellation density
        for (const auto& f : faces_) {
            const Vec3& p0 = positions_[f[0]];
            Vec3 n = cross(positions_[f[1]] - p0, positions_[f[2]] - p0);
            const double len = norm(n);
            if (!(len > 0)) continue;  // no plane; its edges still get the quadrics of their other faces
            n *= 1.0 / len;
            reference_normals_[&f - faces_.data()] = n;
            const Quadric q = Quadric::from_plane(n, -dot(n, p0), 0.5 * len);
            for (Index v : f) quadrics_[v] += q;
        }

        // Every half-edge must have at most one twin, running the other way; boundary edges get constraint planes.
        std::vector<Index> boundary_edges(nv, 0);
        for (Index f = 0; f < faces_.size(); ++f) {
            for (int j = 0; j < 3; ++j) {
                const Index u = faces_[f][j], w = faces_[f][(j + 1) % 3];
                int same = 0, opposite = 0;
                for (Index g : vertex_faces_[u]) {
                    if (g == f) continue;
                    const int k = corner_of(g, u);
                    if (faces_[g][(k + 1) % 3] == w) ++same;
                    if (faces_[g][(k + 2) % 3] == w) ++opposite;
                }
                if (same > 0 || opposite > 1) {
                    const std::string edge = "(" + std::to_string(u) + ", " + std::to_string(w) + ")";
                    return element_error(ErrorCode::NonManifold,
                                         same > 0 && opposite == 0
                                             ? "edge " + edge + " is traversed in the same direction by face " +
                                                   std::to_string(f) +
                                                   " and another face (inconsistent orientation or a duplicate face)"
                                             : "edge " + edge + " is shared by more than two faces (face " +
                                                   std::to_string(f) + " is one)",
                                         ElementKind::Face, f);
                }
                if (opposite == 0) {
                    flags_[u] |= kBoundary;
                    flags_[w] |= kBoundary;
                    ++boundary_edges[u];
                    ++boundary_edges[w];
                    if (!options_.lock_border) add_boundary_plane(f, j);
                }
            }
        }
        for (std::size_t v = 0; v < nv; ++v) {
            // two boundary fans meeting at one vertex: no collapse there could keep the mesh manifold for sure
            if (boundary_edges[v] > 2) flags_[v] |= kPinned;
            if (options_.lock_border && (flags_[v] & kBoundary)) flags_[v] |= kPinned;
        }
        for (Index v : options_.locked_vertices) flags_[v] |= kPinned;
        // UV seams: a vertex whose corners use different uv indices. Pinning it keeps every seam exactly, and a
        // collapse onto it takes the uv of the chart the collapsing edge lies in.
        if (!face_uvs_.empty()) {
            std::vector<Index> first_uv(nv, kInvalidIndex);
            for (std::size_t f = 0; f < faces_.size(); ++f)
                for (int j = 0; j < 3; ++j) {
                    const Index v = faces_[f][j], uv = face_uvs_[f][j];
                    if (first_uv[v] == kInvalidIndex) first_uv[v] = uv;
                    else if (first_uv[v] != uv) flags_[v] |= kPinned;
                }
        }
        for (std::size_t v = 0; v < nv; ++v)
            if (vertex_faces_[v].empty()) flags_[v] &= static_cast<std::uint8_t>(~kAlive);
        return Ok{};
    }

    //! Collapses edges until at most `target` faces remain or no valid collapse with error <= threshold is left.
    void run(std::size_t target, double threshold) {
        for (int pass = 0; pass < kMaxPasses && live_faces_ > target; ++pass) {
            // Later passes retry collapses that were invalid when popped but may have become valid since.
            heap_.clear();
            for (Index f = 0; f < faces_.size(); ++f) {
                if (!face_alive_[f]) continue;
                for (int j = 0; j < 3; ++j) {
                    const Index u = faces_[f][j], w = faces_[f][(j + 1) % 3];
                    // interior edges appear twice (once per direction); push once, boundary edges always
                    if (u < w || is_boundary_halfedge(f, j)) add_candidate(u, w);
                }
            }
            heap_.make();  // O(n), not n pushes
            std::size_t collapses = 0;
            while (!heap_.empty() && live_faces_ > target) {
                // Stale entries pile up (each collapse outdates the entries at two vertices and adds new ones).
                // Dropping them once they outnumber the live edges keeps the heap small and cache-friendly.
                if (heap_.size() > 2 * live_faces_ + 1024) compact_heap();
                if ((++polls_ & 4095) == 0 && options_.cancel.requested()) {
                    cancelled_ = true;
                    return;
                }
                const Candidate c = heap_.pop();
                if (!(flags_[c.a] & kAlive) || !(flags_[c.b] & kAlive)) continue;
                if (version_[c.a] != c.version_a || version_[c.b] != c.version_b) continue;  // stale
                Collapse collapse;
                if (!evaluate(c.a, c.b, collapse) || collapse.error > threshold) continue;
                if (!is_valid(collapse)) continue;
                apply(collapse);
                max_error_ = std::max(max_error_, collapse.error);
                ++collapses;
            }
            if (collapses == 0) break;
        }
    }

    PolygonMesh extract() const {
        PolygonMesh out;
        std::vector<Index> remap(positions_.size(), kInvalidIndex);
        std::vector<Index> uv_remap(uvs_.size(), kInvalidIndex);
        out.face_offsets.reserve(live_faces_ + 1);
        out.face_indices.reserve(3 * live_faces_);
        for (std::size_t f = 0; f < faces_.size(); ++f) {
            if (!face_alive_[f]) continue;
            for (int j = 0; j < 3; ++j) {
                const Index v = faces_[f][j];
                if (remap[v] == kInvalidIndex) {
                    remap[v] = static_cast<Index>(out.positions.size());
                    out.positions.push_back(positions_[v]);
                    if (!normals_.empty()) out.normals.push_back(normals_[v]);
                }
                out.face_indices.push_back(remap[v]);
                if (!face_uvs_.empty()) {
                    const Index uv = face_uvs_[f][j];
                    if (uv_remap[uv] == kInvalidIndex) {
                        uv_remap[uv] = static_cast<Index>(out.uvs.size());
                        out.uvs.push_back(uvs_[uv]);
                    }
                    out.uv_indices.push_back(uv_remap[uv]);
                }
            }
            out.face_offsets.push_back(static_cast<Index>(out.face_indices.size()));
        }
        return out;
    }

    std::size_t live_faces() const { return live_faces_; }
    double max_error() const { return max_error_; }
    bool cancelled() const { return cancelled_; }

private:
    int corner_of(Index f, Index v) const {
        const auto& t = faces_[f];
        return t[0] == v ? 0 : (t[1] == v ? 1 : 2);
    }
    bool contains(Index f, Index v) const {
        const auto& t = faces_[f];
        return t[0] == v || t[1] == v || t[2] == v;
    }
    bool pinned(Index v) const { return (flags_[v] & kPinned) != 0; }

    bool is_boundary_halfedge(Index f, int j) const {
        const Index u = faces_[f][j], w = faces_[f][(j + 1) % 3];
        for (Index g : vertex_faces_[w])
            if (g != f && faces_[g][(corner_of(g, w) + 1) % 3] == u) return false;
        return true;
    }

    //! Constraint plane through boundary edge j of face f, perpendicular to the face (Garland-Heckbert 1998 sec. 4):
    //! it lets boundary vertices slide along the boundary but resists pulling the boundary inwards.
    void add_boundary_plane(Index f, int j) {
        const Vec3& p0 = positions_[faces_[f][0]];
        const Vec3 face_normal = cross(positions_[faces_[f][1]] - p0, positions_[faces_[f][2]] - p0);
        const Vec3& u = positions_[faces_[f][j]];
        const Vec3 edge = positions_[faces_[f][(j + 1) % 3]] - u;
        Vec3 n = cross(edge, face_normal);
        const double len = norm(n);
        if (!(len > 0)) return;
        n *= 1.0 / len;
        const Quadric q = Quadric::from_plane(n, -dot(n, u), options_.boundary_weight * dot(edge, edge));
        quadrics_[faces_[f][j]] += q;
        quadrics_[faces_[f][(j + 1) % 3]] += q;
    }

    //! Appends edge (a, b) to heap_ without restoring the heap order; false when it cannot collapse at all.
    bool add_candidate(Index a, Index b) {
        Collapse collapse;
        if (!evaluate(a, b, collapse)) return false;
        heap_.append({static_cast<float>(collapse.cost), a, b, version_[a], version_[b]});
        return true;
    }
    void compact_heap() {
        heap_.erase_if([&](const Candidate& c) {
            return !(flags_[c.a] & kAlive) || !(flags_[c.b] & kAlive) || version_[c.a] != c.version_a ||
                   version_[c.b] != c.version_b;
        });
    }
    void push(Index a, Index b) {
        Collapse collapse;
        if (evaluate(a, b, collapse))
            heap_.push({static_cast<float>(collapse.cost), a, b, version_[a], version_[b]});
    }

    //! Placement and cost of collapsing edge (a, b); false when both ends are pinned.
    bool evaluate(Index a, Index b, Collapse& out) const {
        const bool pa = pinned(a), pb = pinned(b);
        if (pa && pb) return false;
        Quadric q = quadrics_[a];
        q += quadrics_[b];
        const Vec3& xa = positions_[a];
        const Vec3& xb = positions_[b];
        if (pa || pb) {
            // a pinned vertex stays where it is and absorbs the other end
            out.keep = pa ? a : b;
            out.remove = pa ? b : a;
            out.position = positions_[out.keep];
            out.s = 0;
        } else {
            out.keep = a;
            out.remove = b;
            const Vec3 d = xb - xa;
            const double len2 = dot(d, d);
            const Vec3 mid = (xa + xb) * 0.5;
            Vec3 x;
            if (q.minimizer(x) && dot(x - mid, x - mid) <= kMaxPlacementReach * kMaxPlacementReach * len2) {
                out.position = x;
                out.s = len2 > 0 ? std::clamp(dot(x - xa, d) / len2, 0.0, 1.0) : 0.5;
            } else {
                // Singular system: the minimum is a line or plane. Best of the endpoints, the midpoint and the
                // minimum of Q along the edge, f(s) = Q(a) + 2 s (A a + b).d + s^2 d^T A d.
                double best = std::numeric_limits<double>::infinity();
                auto consider = [&](double s) {
                    const Vec3 p = xa + d * s;
                    const double e = q.error(p);
                    if (e < best) { best = e; out.position = p; out.s = s; }
                };
                consider(0.0);
                consider(1.0);
                consider(0.5);
                const double dad = dot(d, q.apply_a(d));
                if (dad > 0) {
                    const Vec3 grad = q.apply_a(xa) + Vec3{q.b0, q.b1, q.b2};
                    consider(std::clamp(-dot(grad, d) / dad, 0.0, 1.0));
                }
            }
        }
        out.cost = q.error(out.position);
        out.error = q.weight > 0 ? std::sqrt(out.cost / q.weight) : 0.0;
        return true;
    }

    //! Appends the distinct neighbours of v (over its live faces) to `out`.
    void neighbours(Index v, std::vector<Index>& out) const {
        out.clear();
        for (Index f : vertex_faces_[v])
            for (Index w : faces_[f])
                if (w != v && std::find(out.begin(), out.end(), w) == out.end()) out.push_back(w);
    }

    //! Link condition, geometry (flips, thin faces) and duplicate faces, for the collapse as evaluated.
    bool is_valid(const Collapse& c) {
        const Index k = c.keep, r = c.remove;
        // faces on the edge and their apexes
        shared_.clear();
        apexes_.clear();
        for (Index f : vertex_faces_[r])
            if (contains(f, k)) {
                shared_.push_back(f);
                for (Index w : faces_[f])
                    if (w != k && w != r) apexes_.push_back(w);
            }
        if (shared_.empty() || shared_.size() > 2) return false;
        const bool edge_on_boundary = shared_.size() == 1;
        // An interior edge between two boundary vertices: collapsing it would pinch the surface into a non-manifold
        // vertex (the link condition with the boundary's virtual vertex).
        if (!edge_on_boundary && (flags_[k] & kBoundary) && (flags_[r] & kBoundary)) return false;
        // Link condition (Dey et al.): the common neighbours of k and r are exactly the apexes of the edge's faces.
        neighbours(k, ring_k_);
        neighbours(r, ring_r_);
        for (Index w : ring_r_)
            if (w != k && std::find(ring_k_.begin(), ring_k_.end(), w) != ring_k_.end() &&
                std::find(apexes_.begin(), apexes_.end(), w) == apexes_.end())
                return false;
        // Nothing may be left without faces (a lone triangle, or an apex whose only faces are the edge's).
        if (vertex_faces_[k].size() + vertex_faces_[r].size() <= 2 * shared_.size()) return false;
        for (Index w : apexes_) {
            std::size_t on_edge = 0;
            for (Index f : shared_) on_edge += contains(f, w) ? 1 : 0;
            if (vertex_faces_[w].size() <= on_edge) return false;
        }
        // geometry of every face that survives with a moved or renamed corner
        auto face_ok = [&](Index f, Index moved) {
            const auto& t = faces_[f];
            Vec3 before[3], after[3];
            for (int j = 0; j < 3; ++j) {
                before[j] = positions_[t[j]];
                after[j] = t[j] == moved ? c.position : before[j];
            }
            const Vec3 n0 = cross(before[1] - before[0], before[2] - before[0]);
            const Vec3 n1 = cross(after[1] - after[0], after[2] - after[0]);
            const double t1 = thinness(after[0], after[1], after[2]);
            if (t1 < kDegenerate) return false;
            if (t1 < kThin && t1 < thinness(before[0], before[1], before[2])) return false;
            const double l0 = norm(n0), l1 = norm(n1);
            // a face that had no normal before cannot flip; compare the ones that had
            if (l0 > 0 && dot(n0, n1) < kMinNormalCos * l0 * l1) return false;
            // Small turns add up over many collapses: a face may also never face away from the input face it
            // started as.
            if (reference_normals_[f] != Vec3{} && dot(reference_normals_[f], n1) < kMinNormalCos * l1) return false;
            return true;
        };
        for (Index f : vertex_faces_[r]) {
            if (contains(f, k)) continue;
            if (!face_ok(f, r)) return false;
            // The face becomes (k, x, y): a face already on x, y and k would duplicate it.
            const int j = corner_of(f, r);
            const Index x = faces_[f][(j + 1) % 3], y = faces_[f][(j + 2) % 3];
            for (Index g : vertex_faces_[x])
                if (g != f && contains(g, y) && contains(g, k)) return false;
        }
        if (!pinned(k) || c.position != positions_[k])
            for (Index f : vertex_faces_[k])
                if (!contains(f, r) && !face_ok(f, k)) return false;
        return true;
    }

    void apply(const Collapse& c) {
        const Index k = c.keep, r = c.remove;
        // attributes first, while the edge's faces still exist
        if (!face_uvs_.empty()) {
            Index uv_k = kInvalidIndex, uv_r = kInvalidIndex;
            for (Index f : shared_) {
                uv_k = face_uvs_[f][corner_of(f, k)];
                uv_r = face_uvs_[f][corner_of(f, r)];
                break;
            }
            Index target = uv_k;
            if (!pinned(k)) {
                // neither end is on a seam: one uv each; interpolate along the edge as the position moved
                const Vec2 a = uvs_[uv_k], b = uvs_[uv_r];
                uvs_.push_back({a.x + (b.x - a.x) * c.s, a.y + (b.y - a.y) * c.s});
                target = static_cast<Index>(uvs_.size() - 1);
                for (Index f : vertex_faces_[k]) face_uvs_[f][corner_of(f, k)] = target;
            }
            for (Index f : vertex_faces_[r]) face_uvs_[f][corner_of(f, r)] = target;
        }
        if (!normals_.empty()) {
            Vec3 n = normals_[k] + (normals_[r] - normals_[k]) * c.s;
            const double len = norm(n);
            if (len > 0) normals_[k] = n * (1.0 / len);
        }
        // topology: the edge's faces die, r's other faces move to k
        for (Index f : shared_) {
            face_alive_[f] = 0;
            --live_faces_;
            for (Index w : faces_[f]) {
                if (w == r) continue;
                auto& list = vertex_faces_[w];
                list.erase(std::find(list.begin(), list.end(), f));
            }
        }
        for (Index f : vertex_faces_[r]) {
            if (!face_alive_[f]) continue;
            faces_[f][corner_of(f, r)] = k;
            vertex_faces_[k].push_back(f);
        }
        vertex_faces_[r].clear();
        vertex_faces_[r].shrink_to_fit();
        flags_[k] |= flags_[r] & kBoundary;
        flags_[r] = 0;
        quadrics_[k] += quadrics_[r];
        positions_[k] = c.position;
        ++version_[k];
        ++version_[r];
        // only edges at k changed cost (their quadric or endpoint moved); push them with k's new version
        neighbours(k, ring_k_);
        for (Index w : ring_k_) push(k, w);
    }

    const SimplifyOptions& options_;
    std::uint64_t polls_ = 0;
    bool cancelled_ = false;
    std::vector<Vec3> positions_;
    std::vector<std::array<Index, 3>> faces_;
    std::vector<std::uint8_t> face_alive_;
    std::vector<Vec3> reference_normals_;  //!< unit normal of each input face (0 when it had no area)
    std::vector<Vec2> uvs_;
    std::vector<std::array<Index, 3>> face_uvs_;
    std::vector<Vec3> normals_;
    std::vector<std::vector<Index>> vertex_faces_;
    std::vector<Quadric> quadrics_;
    std::vector<std::uint32_t> version_;
    std::vector<std::uint8_t> flags_;
    std::size_t live_faces_ = 0;
    double max_error_ = 0;
    CandidateHeap heap_;
    // scratch for is_valid/apply (one collapse at a time)
    std::vector<Index> shared_, apexes_, ring_k_, ring_r_;
};

}  // namespace

Result<SimplifyResult> simplify_qem(const PolygonMesh& mesh, const SimplifyOptions& options) {
    if (auto valid = validate(mesh); !valid) return valid.error();
    if (!options.target_faces && !options.ratio && !options.max_error)
        return make_error(ErrorCode::InvalidArgument, "simplification needs target_faces, ratio or max_error");
    if (options.ratio && !(*options.ratio > 0 && *options.ratio <= 1))
        return make_error(ErrorCode::InvalidArgument,
                          "ratio must be in (0, 1], got " + std::to_string(*options.ratio));
    if (options.max_error && !(*options.max_error >= 0 && std::isfinite(*options.max_error)))
        return make_error(ErrorCode::InvalidArgument,
                          "max_error must be a finite distance >= 0, got " + std::to_string(*options.max_error));
    if (!(options.boundary_weight >= 0 && std::isfinite(options.boundary_weight)))
        return make_error(ErrorCode::InvalidArgument, "boundary_weight must be finite and >= 0");
    for (Index v : options.locked_vertices)
        if (v >= mesh.vertex_count())
            return element_error(ErrorCode::IndexOutOfRange,
                                 "locked vertex " + std::to_string(v) + " out of range (" +
                                     std::to_string(mesh.vertex_count()) + " vertices)",
                                 ElementKind::Vertex, v);

    SimplifyResult result;
    result.triangulated = !mesh.is_triangle_mesh();
    PolygonMesh triangulated;
    if (result.triangulated) triangulated = triangulate(mesh);
    const PolygonMesh& input = result.triangulated ? triangulated : mesh;

    const std::size_t input_faces = input.face_count();
    std::size_t target = input_faces;
    if (options.target_faces) target = std::min(target, *options.target_faces);
    if (options.ratio)
        target = std::min(target, static_cast<std::size_t>(std::floor(*options.ratio * static_cast<double>(input_faces))));
    if (!options.target_faces && !options.ratio) target = 0;  // max_error alone: as far as the error allows
    const double diagonal = input.bounds().diagonal();

    Simplifier prototype(input, options);
    if (auto status = prototype.init(); !status) return status.error();

    if (!options.max_error) {
        Simplifier& simplifier = prototype;  // one run: no copy needed
        simplifier.run(target, std::numeric_limits<double>::infinity());
        if (simplifier.cancelled()) return make_error(ErrorCode::Cancelled, "simplification cancelled (deadline or shutdown)");
        result.mesh = simplifier.extract();
        result.achieved_error = simplifier.max_error();
    } else {
        // The quadric estimate is an area-weighted mean distance, not a bound: measure the result and search for the
        // largest estimate threshold whose output is within max_error (bisection once one passes and one fails).
        // The input itself always qualifies, so it is the fallback.
        const double max_error = *options.max_error;
        result.error_measured = true;
        result.mesh = input;
        result.mesh.tags = {};
        result.achieved_error = 0;
        double threshold = max_error, passed = 0, failed = std::numeric_limits<double>::infinity();
        for (int attempt = 0; attempt < kMaxErrorAttempts; ++attempt) {
            if (options.cancel.requested())
                return make_error(ErrorCode::Cancelled, "simplification cancelled (deadline or shutdown)");
            Simplifier simplifier = prototype;
            simplifier.run(target, threshold);
            if (simplifier.cancelled())
                return make_error(ErrorCode::Cancelled, "simplification cancelled (deadline or shutdown)");
            if (simplifier.live_faces() >= result.mesh.face_count() && passed > 0) break;  // no better than kept
            PolygonMesh candidate = simplifier.extract();
            const double measured = mesh_distance(input, candidate).hausdorff;
            if (measured <= max_error) {
                if (candidate.face_count() < result.mesh.face_count()) {
                    result.mesh = std::move(candidate);
                    result.achieved_error = measured;
                }
                passed = threshold;
                if (std::isinf(failed) || simplifier.live_faces() <= target) break;  // nothing larger to try
            } else {
                failed = std::min(threshold, simplifier.max_error());
            }
            // within 15% of the largest failing threshold: more attempts would gain little for their cost
            if (passed > 0 && failed < 1.15 * passed) break;
            threshold = passed > 0 ? std::sqrt(passed * failed)
                                   : failed * std::clamp(0.8 * max_error / measured, 0.05, 0.7);
            if (!(threshold > 0)) break;
        }
    }
    result.faces = result.mesh.face_count();
    result.relative_error = diagonal > 0 ? result.achieved_error / diagonal : 0.0;
    return result;
}

}  // namespace surfaced
