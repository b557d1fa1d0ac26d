// Quadric-error edge collapse (Garland-Heckbert 1997), with the safety checks a service needs: every collapse keeps
// the mesh a manifold with consistently oriented, non-degenerate, non-duplicate faces.
//
// Data: triangles as index triples, each vertex's faces as a list threaded through the triangles' corners (enough for
// one-rings; pmp and meshoptimizer use the same adjacency for decimation), and per vertex one 128-byte record of
// quadric, position, version and flags. Candidates sit in a 4-ary heap keyed on quadric cost; an entry remembers the
// sum of its endpoints' version stamps, and an entry whose endpoint changed since it was pushed is stale and skipped
// (lazy invalidation). After a collapse only the edges at the surviving vertex change cost, and those are pushed
// again with its new version.
//
// Speed (issue #4; 1.3M-triangle icosphere to 1%, one core): the run is bound by cache and TLB misses, since
// vertices are visited in heap and one-ring order. Measured with perf before the changes: heap pops and compaction
// ~20%, evaluate() ~18% (85% of its calls took the singular-quadric fallback, which evaluated Q at four points),
// is_valid() ~25%, page faults and zeroing of ~260 MB of arrays ~15%. What changed, output unchanged except for
// ties: the vertex records and the heap's sibling groups are cache-line aligned, large arrays ask for transparent
// huge pages, adjacency needs no per-vertex allocation, the fallback evaluates the quadric along the edge as a
// polynomial, rings and link condition use plain scans, candidate vertices are prefetched in batches.
#include "geometry/simplify/qem.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <new>
#include <string>

#if defined(__linux__)
#include <sys/mman.h>
#endif

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

//! Allocates on 64-byte boundaries (so that the heap's groups of four siblings and each VertexData fill whole cache
//! lines), and large arrays on 2 MiB boundaries with transparent huge pages requested where the kernel leaves that to
//! the program (Linux THP "madvise"): the simplifier reads its arrays of hundreds of MB at random, and with 4 KiB pages
//! nearly every access also misses the TLB, and every first touch faults.
template <class T>
struct BlockAllocator {
    using value_type = T;
    BlockAllocator() = default;
    template <class U>
    BlockAllocator(const BlockAllocator<U>&) noexcept {}
    static constexpr std::size_t kHuge = std::size_t{2} << 20;
    static std::size_t alignment(std::size_t n) { return n * sizeof(T) >= 2 * kHuge ? kHuge : 64; }
    T* allocate(std::size_t n) {
        if (n > (std::numeric_limits<std::size_t>::max() >> 2) / sizeof(T)) throw std::bad_array_new_length();
        const std::size_t align = alignment(n);
        const std::size_t bytes = (n * sizeof(T) + align - 1) / align * align;
        void* p = ::operator new(bytes, std::align_val_t{align});
#if defined(__linux__) && defined(MADV_HUGEPAGE)
        if (align == kHuge) ::madvise(p, bytes, MADV_HUGEPAGE);  // advice only: failure changes nothing
#endif
        return static_cast<T*>(p);
    }
    void deallocate(T* p, std::size_t n) noexcept { ::operator delete(p, std::align_val_t{alignment(n)}); }
    template <class U>
    bool operator==(const BlockAllocator<U>&) const noexcept { return true; }
};
template <class T>
using BlockVector = std::vector<T, BlockAllocator<T>>;

// 16 bytes: the heap holds a few million of these for a 1M-triangle mesh, and popping is cache-bound.
struct Candidate {
    float cost;  //!< ordering only; the collapse itself is re-evaluated in double when popped
    Index a, b;
    //! vx_[a].version + vx_[b].version when pushed. Versions only grow (a vertex's also when it dies), so the entry is
    //! current exactly while the sum is unchanged.
    std::uint32_t stamp;
};
static_assert(sizeof(Candidate) == 16);

//! A 4-ary min-heap on cost: half the depth of a binary heap. Storage starts three slots before the root, so node i
//! sits at slot i + 3 and the children 4i+1..4i+4 of every node share one 64-byte line; each level of a sift-down is
//! one cache miss, and the next level's lines are prefetched while the current one is compared. Popping dominates
//! the heap's cost on large meshes (millions of entries).
class CandidateHeap {
public:
    CandidateHeap() { items_.resize(kPad); }
    bool empty() const { return items_.size() == kPad; }
    std::size_t size() const { return items_.size() - kPad; }
    void reserve(std::size_t n) { items_.reserve(n + kPad); }
    void clear() { items_.resize(kPad); }
    //! Appends without ordering; call make() before the next pop().
    void append(const Candidate& c) { items_.push_back(c); }
    void make() {
        const std::size_t n = size();
        if (n < 2) return;
        for (std::size_t i = (n - 2) / 4 + 1; i-- > 0;) sift_down(i, at(i));
    }
    void push(const Candidate& c) {
        items_.push_back(c);
        std::size_t i = size() - 1;
        while (i > 0) {
            const std::size_t parent = (i - 1) / 4;
            if (!(c.cost < at(parent).cost)) break;
            at(i) = at(parent);
            i = parent;
        }
        at(i) = c;
    }
    const Candidate& top() { return at(0); }
    Candidate pop() {
        const Candidate top = at(0);
        const Candidate last = items_.back();
        items_.pop_back();
        if (!empty()) sift_down(0, last);
        return top;
    }
    template <class Pred>
    void erase_if(Pred pred) {
        items_.erase(std::remove_if(items_.begin() + kPad, items_.end(), pred), items_.end());
        make();
    }

private:
    static constexpr std::size_t kPad = 3;
    Candidate& at(std::size_t i) { return items_[i + kPad]; }
    void sift_down(std::size_t i, const Candidate c) {
        const std::size_t n = size();
        for (;;) {
            const std::size_t first = 4 * i + 1;
            if (first >= n) break;
            // the grandchildren: four lines, fetched while this line is compared
            if (16 * i + 5 < n) {
                const Candidate* g = &at(16 * i + 5);
                __builtin_prefetch(g);
                __builtin_prefetch(g + 4);
                __builtin_prefetch(g + 8);
                __builtin_prefetch(g + 12);
            }
            std::size_t best = first;
            const std::size_t end = std::min(first + 4, n);
            for (std::size_t j = first + 1; j < end; ++j)
                if (at(j).cost < at(best).cost) best = j;
            if (!(at(best).cost < c.cost)) break;
            at(i) = at(best);
            i = best;
        }
        at(i) = c;
    }
    std::vector<Candidate, BlockAllocator<Candidate>> items_;
};

struct Collapse {
    Index keep = kInvalidIndex, remove = kInvalidIndex;
    Vec3 position;
    double s = 0;      //!< position's parameter along keep -> remove, for attribute interpolation
    double cost = 0;   //!< Q(position), the heap key
    double error = 0;  //!< sqrt(Q(position) / weight): a distance
};

//! What a collapse reads of a vertex, in one 128-byte block (two cache lines) instead of four arrays: vertices are
//! visited in heap and one-ring order, nearly always a cache miss each.
struct alignas(64) VertexData {
    Quadric q;
    Vec3 p;
    std::uint32_t version = 0;  //!< bumped whenever the vertex moves, changes quadric or dies
    std::uint8_t flags = kAlive;
};
static_assert(sizeof(VertexData) == 128);

//! A live triangle and, per corner, the next corner (3 f + j) around the same vertex: each vertex's faces are a
//! singly linked list threaded through the triangles (no per-vertex allocation; walking it reads the triangles the
//! walk needs anyway).
struct Tri {
    std::array<Index, 3> v;
    std::array<Index, 3> next;
};

class Simplifier {
public:
    Simplifier(const PolygonMesh& mesh, const SimplifyOptions& options) : options_(options) {
        const std::size_t nv = mesh.vertex_count(), nf = mesh.face_count();
        vx_.resize(nv);
        for (std::size_t v = 0; v < nv; ++v) vx_[v].p = mesh.positions[v];
        tris_.resize(nf);
        face_alive_.assign(nf, 1);
        for (std::size_t f = 0; f < nf; ++f) {
            auto face = mesh.face(f);
            tris_[f].v = {face[0], face[1], face[2]};
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
        head_.assign(nv, kInvalidIndex);
        degree_.assign(nv, 0);
    }

    //! Adjacency, the manifold check, quadrics and pinned vertices.
    Status init() {
        const std::size_t nv = vx_.size();
        // threaded back to front, so that every vertex lists its faces in increasing order
        for (Index f = static_cast<Index>(tris_.size()); f-- > 0;)
            for (int j = 3; j-- > 0;) {
                const Index v = tris_[f].v[j];
                tris_[f].next[j] = head_[v];
                head_[v] = 3 * f + static_cast<Index>(j);
                ++degree_[v];
            }

        reference_normals_.assign(tris_.size(), Vec3{});
        // face planes, weighted by area so that the metric does not depend on the tessellation density
        for (std::size_t f = 0; f < tris_.size(); ++f) {
            const auto& t = tris_[f].v;
            const Vec3& p0 = vx_[t[0]].p;
            Vec3 n = cross(vx_[t[1]].p - p0, vx_[t[2]].p - p0);
            const double len = norm(n);
            if (!(len > 0)) continue;  // no plane; its edges still get the quadrics of their other faces
            n *= 1.0 / len;
            reference_normals_[f] = n;
            const Quadric q = Quadric::from_plane(n, -dot(n, p0), 0.5 * len);
            for (Index v : t) vx_[v].q += q;
        }

        // Every half-edge must have at most one twin, running the other way; boundary edges get constraint planes.
        std::vector<Index> boundary_edges(nv, 0);
        boundary_halfedges_.assign(tris_.size(), 0);
        for (Index f = 0; f < tris_.size(); ++f) {
            for (int j = 0; j < 3; ++j) {
                const Index u = tris_[f].v[j], w = tris_[f].v[(j + 1) % 3];
                int same = 0, opposite = 0;
                for (Index c = head_[u]; c != kInvalidIndex; c = next(c)) {
                    const Index g = c / 3;
                    if (g == f) continue;
                    const Index k = c % 3;
                    if (tris_[g].v[(k + 1) % 3] == w) ++same;
                    if (tris_[g].v[(k + 2) % 3] == w) ++opposite;
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
                    boundary_halfedges_[f] |= static_cast<std::uint8_t>(1u << j);
                    vx_[u].flags |= kBoundary;
                    vx_[w].flags |= kBoundary;
                    ++boundary_edges[u];
                    ++boundary_edges[w];
                    if (!options_.lock_border) add_boundary_plane(f, j);
                }
            }
        }
        for (std::size_t v = 0; v < nv; ++v) {
            // two boundary fans meeting at one vertex: no collapse there could keep the mesh manifold for sure
            if (boundary_edges[v] > 2) vx_[v].flags |= kPinned;
            if (options_.lock_border && (vx_[v].flags & kBoundary)) vx_[v].flags |= kPinned;
        }
        for (Index v : options_.locked_vertices) vx_[v].flags |= kPinned;
        // UV seams: a vertex whose corners use different uv indices. Pinning it keeps every seam exactly, and a
        // collapse onto it takes the uv of the chart the collapsing edge lies in.
        if (!face_uvs_.empty()) {
            std::vector<Index> first_uv(nv, kInvalidIndex);
            for (std::size_t f = 0; f < tris_.size(); ++f)
                for (int j = 0; j < 3; ++j) {
                    const Index v = tris_[f].v[j], uv = face_uvs_[f][j];
                    if (first_uv[v] == kInvalidIndex) first_uv[v] = uv;
                    else if (first_uv[v] != uv) vx_[v].flags |= kPinned;
                }
        }
        for (std::size_t v = 0; v < nv; ++v)
            if (degree_[v] == 0) vx_[v].flags &= static_cast<std::uint8_t>(~kAlive);
        return Ok{};
    }

    //! Collapses edges until at most `target` faces remain or no valid collapse with error <= threshold is left.
    void run(std::size_t target, double threshold) {
        // Compaction (below) keeps the heap under 2 live faces + 1024 entries, plus one collapse's pushes.
        heap_.reserve(2 * live_faces_ + 2048);
        for (int pass = 0; pass < kMaxPasses && live_faces_ > target; ++pass) {
            // Later passes retry collapses that were invalid when popped but may have become valid since.
            heap_.clear();
            for (Index f = 0; f < tris_.size(); ++f) {
                if (!face_alive_[f]) continue;
                for (int j = 0; j < 3; ++j) {
                    const Index u = tris_[f].v[j], w = tris_[f].v[(j + 1) % 3];
                    // interior edges appear twice (once per direction); push once, boundary edges always
                    // (the first pass knows the boundary from init)
                    if (u < w || (pass == 0 ? (boundary_halfedges_[f] >> j & 1) != 0 : is_boundary_halfedge(f, j)))
                        add_candidate(u, w);
                }
            }
            heap_.make();  // O(n), not n pushes
            std::size_t collapses = 0, compacted = heap_.size();
            pushes_ = 0;
            while (!heap_.empty() && live_faces_ > target) {
                // Stale entries pile up (each collapse outdates the entries at two vertices and adds new ones).
                // Dropping them once they outnumber the live edges keeps the heap small and cache-friendly. Only
                // after pushes of a quarter of what the last compaction kept, so that a compaction costs at most a
                // few times the pushes since, whatever the mesh (a triangle soup has 3 current entries per face and
                // no stale ones; without that condition every pop compacted: 40,000 triangles took 6.5 s).
                if (heap_.size() > 2 * live_faces_ + 1024 && pushes_ >= compacted / 4) {
                    compact_heap();
                    compacted = heap_.size();
                    pushes_ = 0;
                }
                if ((++polls_ & 4095) == 0 && options_.cancel.requested()) {
                    cancelled_ = true;
                    return;
                }
                const Candidate c = heap_.pop();
                if (!heap_.empty()) prefetch_vertex(heap_.top().a), prefetch_vertex(heap_.top().b);  // the next pop
                if (stamp(c.a, c.b) != c.stamp) continue;  // stale: an endpoint moved, changed or died
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
        std::vector<Index> remap(vx_.size(), kInvalidIndex);
        std::vector<Index> uv_remap(uvs_.size(), kInvalidIndex);
        out.face_offsets.reserve(live_faces_ + 1);
        out.face_indices.reserve(3 * live_faces_);
        for (std::size_t f = 0; f < tris_.size(); ++f) {
            if (!face_alive_[f]) continue;
            for (int j = 0; j < 3; ++j) {
                const Index v = tris_[f].v[j];
                if (remap[v] == kInvalidIndex) {
                    remap[v] = static_cast<Index>(out.positions.size());
                    out.positions.push_back(vx_[v].p);
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
    //! The corner after c around c's vertex (kInvalidIndex at the end of the list).
    Index next(Index c) const { return tris_[c / 3].next[c % 3]; }
    Index& next(Index c) { return tris_[c / 3].next[c % 3]; }
    int corner_of(Index f, Index v) const {
        const auto& t = tris_[f].v;
        return t[0] == v ? 0 : (t[1] == v ? 1 : 2);
    }
    bool contains(Index f, Index v) const {
        const auto& t = tris_[f].v;
        return t[0] == v || t[1] == v || t[2] == v;
    }
    bool pinned(Index v) const { return (vx_[v].flags & kPinned) != 0; }
    std::uint32_t stamp(Index a, Index b) const { return vx_[a].version + vx_[b].version; }
    //! What evaluate() reads of v. Vertices come from the heap and from one-rings in no useful order, so nearly
    //! every access misses the cache; prefetching a batch lets the misses overlap instead of queueing one by one.
    void prefetch_vertex(Index v) const {
        const char* data = reinterpret_cast<const char*>(&vx_[v]);
        __builtin_prefetch(data);
        __builtin_prefetch(data + 64);
    }

    bool is_boundary_halfedge(Index f, int j) const {
        const Index u = tris_[f].v[j], w = tris_[f].v[(j + 1) % 3];
        for (Index c = head_[w]; c != kInvalidIndex; c = next(c)) {
            const Index g = c / 3;
            if (g != f && tris_[g].v[(c % 3 + 1) % 3] == u) return false;
        }
        return true;
    }

    //! Constraint plane through boundary edge j of face f, perpendicular to the face (Garland-Heckbert 1998 sec. 4):
    //! it lets boundary vertices slide along the boundary but resists pulling the boundary inwards.
    void add_boundary_plane(Index f, int j) {
        const auto& t = tris_[f].v;
        const Vec3& p0 = vx_[t[0]].p;
        const Vec3 face_normal = cross(vx_[t[1]].p - p0, vx_[t[2]].p - p0);
        const Vec3& u = vx_[t[j]].p;
        const Vec3 edge = vx_[t[(j + 1) % 3]].p - u;
        Vec3 n = cross(edge, face_normal);
        const double len = norm(n);
        if (!(len > 0)) return;
        n *= 1.0 / len;
        const Quadric q = Quadric::from_plane(n, -dot(n, u), options_.boundary_weight * dot(edge, edge));
        vx_[t[j]].q += q;
        vx_[t[(j + 1) % 3]].q += q;
    }

    //! Appends edge (a, b) to heap_ without restoring the heap order; false when it cannot collapse at all.
    bool add_candidate(Index a, Index b) {
        Collapse collapse;
        if (!evaluate(a, b, collapse)) return false;
        heap_.append({static_cast<float>(collapse.cost), a, b, stamp(a, b)});
        return true;
    }
    void compact_heap() {
        heap_.erase_if([&](const Candidate& c) { return stamp(c.a, c.b) != c.stamp; });
    }
    void push(Index a, Index b) {
        Collapse collapse;
        if (!evaluate(a, b, collapse)) return;
        heap_.push({static_cast<float>(collapse.cost), a, b, stamp(a, b)});
        ++pushes_;
    }

    //! Placement and cost of collapsing edge (a, b); false when both ends are pinned.
    bool evaluate(Index a, Index b, Collapse& out) const {
        const bool pa = pinned(a), pb = pinned(b);
        if (pa && pb) return false;
        Quadric q = vx_[a].q;
        q += vx_[b].q;
        const Vec3& xa = vx_[a].p;
        const Vec3& xb = vx_[b].p;
        if (pa || pb) {
            // a pinned vertex stays where it is and absorbs the other end
            out.keep = pa ? a : b;
            out.remove = pa ? b : a;
            out.position = vx_[out.keep].p;
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
                // minimum of Q along the edge, f(s) = Q(a) + 2 s (A a + b).d + s^2 d^T A d (the polynomial, not Q
                // at each point: two products with A instead of six; clamped at 0 as Quadric::error is, so that
                // rounding noise in flat regions does not decide, and the first candidate wins ties).
                const Vec3 ad = q.apply_a(d);
                const Vec3 grad = q.apply_a(xa) + Vec3{q.b0, q.b1, q.b2};
                const double dad = dot(d, ad);
                const double gd = dot(grad, d);
                const double qa = dot(xa, grad) + q.b0 * xa.x + q.b1 * xa.y + q.b2 * xa.z + q.c;
                double best = std::numeric_limits<double>::infinity(), best_s = 0;
                auto consider = [&](double s) {
                    const double e = std::max(qa + s * (2 * gd + s * dad), 0.0);
                    if (e < best) { best = e; best_s = s; }
                };
                consider(0.0);
                consider(1.0);
                consider(0.5);
                if (dad > 0) consider(std::clamp(-gd / dad, 0.0, 1.0));
                out.position = xa + d * best_s;
                out.s = best_s;
            }
        }
        out.cost = q.error(out.position);
        out.error = q.weight > 0 ? std::sqrt(out.cost / q.weight) : 0.0;
        return true;
    }

    //! Appends the distinct neighbours of v (over its live faces) to `out`.
    void neighbours(Index v, std::vector<Index>& out) const {
        out.clear();
        for (Index c = head_[v]; c != kInvalidIndex; c = next(c))
            for (Index w : tris_[c / 3].v) {
                if (w == v) continue;
                bool seen = false;
                for (std::size_t i = 0; i < out.size() && !seen; ++i) seen = out[i] == w;
                if (!seen) out.push_back(w);
            }
    }
    //! The same set in another order, cheaper: away from boundaries every neighbour follows v in exactly one face
    //! (the edge manifold check of init() and the link condition keep it so).
    void neighbour_set(Index v, std::vector<Index>& out) const {
        if (vx_[v].flags & kBoundary) return neighbours(v, out);
        out.clear();
        for (Index c = head_[v]; c != kInvalidIndex; c = next(c)) out.push_back(tris_[c / 3].v[(c % 3 + 1) % 3]);
    }
    bool is_apex(Index w) const {
        for (Index a : apexes_)
            if (a == w) return true;
        return false;
    }

    //! Link condition, geometry (flips, thin faces) and duplicate faces, for the collapse as evaluated.
    bool is_valid(const Collapse& c) {
        const Index k = c.keep, r = c.remove;
        // faces on the edge and their apexes
        shared_.clear();
        apexes_.clear();
        for (Index corner = head_[r]; corner != kInvalidIndex; corner = next(corner)) {
            const Index f = corner / 3;
            if (contains(f, k)) {
                shared_.push_back(f);
                for (Index w : tris_[f].v)
                    if (w != k && w != r) apexes_.push_back(w);
            }
        }
        if (shared_.empty() || shared_.size() > 2) return false;
        const bool edge_on_boundary = shared_.size() == 1;
        // An interior edge between two boundary vertices: collapsing it would pinch the surface into a non-manifold
        // vertex (the link condition with the boundary's virtual vertex).
        if (!edge_on_boundary && (vx_[k].flags & kBoundary) && (vx_[r].flags & kBoundary)) return false;
        // Nothing may be left without faces (a lone triangle, or an apex whose only faces are the edge's).
        if (degree_[k] + degree_[r] <= 2 * shared_.size()) return false;
        for (Index w : apexes_) {
            std::size_t on_edge = 0;
            for (Index f : shared_) on_edge += contains(f, w) ? 1 : 0;
            if (degree_[w] <= on_edge) return false;
        }
        // Link condition (Dey et al.): the common neighbours of k and r are exactly the apexes of the edge's faces.
        neighbour_set(k, ring_k_);
        neighbour_set(r, ring_r_);
        for (Index w : ring_k_) __builtin_prefetch(&vx_[w].p);
        for (Index w : ring_r_) __builtin_prefetch(&vx_[w].p);
        for (Index w : ring_r_) {
            if (w == k || is_apex(w)) continue;
            for (Index x : ring_k_)
                if (x == w) return false;
        }
        // geometry of every face that survives with a moved or renamed corner
        auto face_ok = [&](Index f, Index moved) {
            const auto& t = tris_[f].v;
            Vec3 before[3], after[3];
            for (int j = 0; j < 3; ++j) {
                before[j] = vx_[t[j]].p;
                after[j] = t[j] == moved ? c.position : before[j];
            }
            // compared squared, without square roots (all sides are >= 0 where squared)
            const Vec3 n1 = cross(after[1] - after[0], after[2] - after[0]);
            const double l1sq = dot(n1, n1);
            const double longest = std::max({dot(after[1] - after[0], after[1] - after[0]),
                                             dot(after[2] - after[1], after[2] - after[1]),
                                             dot(after[0] - after[2], after[0] - after[2])});
            // thinness after (see thinness()) = |n1| / longest: never below kDegenerate, below kThin only if the
            // face was already thinner
            if (!(longest > 0) || l1sq < kDegenerate * kDegenerate * longest * longest) return false;
            if (l1sq < kThin * kThin * longest * longest &&
                std::sqrt(l1sq) / longest < thinness(before[0], before[1], before[2]))
                return false;
            // Small turns add up over many collapses: a face may also never face away from the input face it
            // started as (cos < kMinNormalCos).
            const double cos2 = kMinNormalCos * kMinNormalCos;
            if (reference_normals_[f] != Vec3{}) {
                const double d = dot(reference_normals_[f], n1);
                if (d < 0 || d * d < cos2 * l1sq) return false;
            }
            const Vec3 n0 = cross(before[1] - before[0], before[2] - before[0]);
            const double l0sq = dot(n0, n0);
            // a face that had no normal before cannot flip; compare the ones that had
            if (l0sq > 0) {
                const double d = dot(n0, n1);
                if (d < 0 || d * d < cos2 * l0sq * l1sq) return false;
            }
            return true;
        };
        for (Index corner = head_[r]; corner != kInvalidIndex; corner = next(corner)) {
            const Index f = corner / 3;
            if (contains(f, k)) continue;
            if (!face_ok(f, r)) return false;
            // The face becomes (k, x, y): a face already on x, y and k would duplicate it. x and y would then both
            // be common neighbours of k and r, which the link condition allows only for the apexes.
            const Index j = corner % 3;
            const Index x = tris_[f].v[(j + 1) % 3], y = tris_[f].v[(j + 2) % 3];
            if (!is_apex(x) || !is_apex(y)) continue;
            for (Index cx = head_[x]; cx != kInvalidIndex; cx = next(cx)) {
                const Index g = cx / 3;
                if (g != f && contains(g, y) && contains(g, k)) return false;
            }
        }
        if (!pinned(k) || c.position != vx_[k].p)
            for (Index corner = head_[k]; corner != kInvalidIndex; corner = next(corner)) {
                const Index f = corner / 3;
                if (!contains(f, r) && !face_ok(f, k)) return false;
            }
        return true;
    }

    //! Removes face f from v's list.
    void unlink(Index v, Index f) {
        Index prev = kInvalidIndex;
        for (Index c = head_[v]; c != kInvalidIndex; prev = c, c = next(c))
            if (c / 3 == f) {
                (prev == kInvalidIndex ? head_[v] : next(prev)) = next(c);
                --degree_[v];
                return;
            }
    }

    void apply(const Collapse& c) {
        const Index k = c.keep, r = c.remove;
        // attributes first, while the edge's faces still exist
        if (!face_uvs_.empty()) {
            const Index f0 = shared_.front();
            const Index uv_k = face_uvs_[f0][corner_of(f0, k)];
            const Index uv_r = face_uvs_[f0][corner_of(f0, r)];
            Index target = uv_k;
            if (!pinned(k)) {
                // neither end is on a seam: one uv each; interpolate along the edge as the position moved
                const Vec2 a = uvs_[uv_k], b = uvs_[uv_r];
                uvs_.push_back({a.x + (b.x - a.x) * c.s, a.y + (b.y - a.y) * c.s});
                target = static_cast<Index>(uvs_.size() - 1);
                for (Index corner = head_[k]; corner != kInvalidIndex; corner = next(corner))
                    face_uvs_[corner / 3][corner % 3] = target;
            }
            for (Index corner = head_[r]; corner != kInvalidIndex; corner = next(corner))
                face_uvs_[corner / 3][corner % 3] = target;
        }
        if (!normals_.empty()) {
            Vec3 n = normals_[k] + (normals_[r] - normals_[k]) * c.s;
            const double len = norm(n);
            if (len > 0) normals_[k] = n * (1.0 / len);
        }
        // topology: the edge's faces die, r's other faces move to k (appended to k's list, in r's order)
        for (Index f : shared_) {
            face_alive_[f] = 0;
            --live_faces_;
            for (Index w : tris_[f].v)
                if (w != r) unlink(w, f);
        }
        Index tail = kInvalidIndex;
        for (Index corner = head_[k]; corner != kInvalidIndex; corner = next(corner)) tail = corner;
        for (Index corner = head_[r]; corner != kInvalidIndex;) {
            const Index following = next(corner);
            const Index f = corner / 3;
            if (face_alive_[f]) {
                tris_[f].v[corner % 3] = k;
                (tail == kInvalidIndex ? head_[k] : next(tail)) = corner;
                tail = corner;
                ++degree_[k];
            }
            corner = following;
        }
        if (tail != kInvalidIndex) next(tail) = kInvalidIndex;
        head_[r] = kInvalidIndex;
        degree_[r] = 0;
        vx_[k].flags |= vx_[r].flags & kBoundary;
        vx_[r].flags = 0;
        vx_[k].q += vx_[r].q;
        vx_[k].p = c.position;
        ++vx_[k].version;
        ++vx_[r].version;
        // only edges at k changed cost (their quadric or endpoint moved); push them with k's new stamp
        neighbours(k, ring_k_);
        for (Index w : ring_k_) prefetch_vertex(w);
        for (Index w : ring_k_) push(k, w);
    }

    const SimplifyOptions& options_;
    std::uint64_t polls_ = 0;
    std::size_t pushes_ = 0;  //!< heap pushes since the last compaction
    bool cancelled_ = false;
    BlockVector<VertexData> vx_;
    BlockVector<Tri> tris_;
    std::vector<std::uint8_t> face_alive_;
    std::vector<std::uint8_t> boundary_halfedges_;  //!< per input face, bit j: edge j (v[j] -> v[j+1]) is a boundary
    BlockVector<Vec3> reference_normals_;  //!< unit normal of each input face (0 when it had no area)
    std::vector<Vec2> uvs_;
    std::vector<std::array<Index, 3>> face_uvs_;
    std::vector<Vec3> normals_;
    BlockVector<Index> head_;    //!< first corner (3 f + j) of each vertex's face list
    BlockVector<Index> degree_;  //!< live faces at each vertex
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
    if (input_faces >= kInvalidIndex / 3)  // corners (3 f + j) are Index values
        return make_error(ErrorCode::InvalidArgument,
                          "too many triangles to simplify: " + std::to_string(input_faces));
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
