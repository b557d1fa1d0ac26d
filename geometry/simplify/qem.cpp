// simplify_qem(): quadric-error edge collapse (Garland-Heckbert 1997) with the checks a service needs: every collapse
// keeps the mesh a manifold of consistently oriented, non-degenerate, non-duplicate faces. This file: the Simplifier's
// set-up (adjacency, manifold check, quadrics), its collapse loop, the checks and update of one collapse, and the
// max_error search; the two-thread first phase is in qem_regions.cpp.
//
// Data layout: collapses pop candidates in cost order and read one-rings, so on large meshes they touch vertices all
// over the mesh and are bound by cache misses. Hence what a collapse reads of a vertex is one cache-line-aligned
// record; the version stamps that mark stale heap entries are a separate 4-byte array that stays in cache; each
// vertex's faces are one contiguous fan, fetched together; vertices are renumbered in Morton order so that a one-ring
// lies close in memory (messages and the output use the input's numbers); large arrays are on huge pages.
#include "geometry/simplify/qem.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "geometry/core/two_parts.h"
#include "geometry/mesh/triangulate.h"
#include "geometry/simplify/mesh_distance.h"
#include "geometry/simplify/qem_simplifier.h"
#include "geometry/simplify/spatial_order.h"

namespace surfaced {
namespace simplify_detail {
namespace {

// A collapse may turn a face's normal by at most acos(0.5) = 60 degrees. Garland-Heckbert only forbid flips (0);
// a margin keeps folds out of the output, whose normals are later compared to the input's.
constexpr double kMinNormalCos = 0.5;
// Thinness = 2 area / longest edge^2 (the height over the longest edge, relative to it). A collapse may not create
// a face thinner than kThin unless the face was already thinner (slivers in the input may improve, not worsen), and
// never one thinner than kDegenerate.
constexpr double kThin = 1e-3;
constexpr double kDegenerate = 1e-6;
// An optimal point farther than this many edge lengths from the edge's midpoint comes from an ill-conditioned
// quadric even when the determinant test passed; the fallback placement is safer.
constexpr double kMaxPlacementReach = 4.0;
constexpr int kMaxPasses = 8;
//! Room left in each fan at the start, so that most collapses append the removed vertex's faces in place.
constexpr Index kFanSlack = 2;

}  // namespace

Simplifier::Simplifier(const PolygonMesh& mesh, const SimplifyOptions& options)
    : options_(options),
      split_(static_cast<Index>(options.threads >= 2 && mesh.face_count() >= kRegionsMinimum ? mesh.vertex_count() / 2
                                                                                             : mesh.vertex_count())),
      rank_(spatial_order(mesh.positions, split_ < mesh.vertex_count())) {
    const std::size_t nv = mesh.vertex_count(), nf = mesh.face_count();
    vx_.resize(nv);
    for (std::size_t v = 0; v < nv; ++v) vx_[rank_[v]].p = mesh.positions[v];
    flags_.assign(nv, kAlive);
    version_.assign(nv, 0);
    tris_.resize(nf);
    face_alive_.assign(nf, 1);
    for (std::size_t f = 0; f < nf; ++f) {
        const Index* face = mesh.face_indices.data() + mesh.face_offsets[f];
        tris_[f].v = {rank_[face[0]], rank_[face[1]], rank_[face[2]]};
    }
    if (mesh.has_uvs()) {
        uvs_ = mesh.uvs;
        face_uvs_.resize(nf);
        for (std::size_t f = 0; f < nf; ++f) {
            const Index o = mesh.face_offsets[f];
            face_uvs_[f] = {mesh.uv_indices[o], mesh.uv_indices[o + 1], mesh.uv_indices[o + 2]};
        }
    }
    if (!mesh.normals.empty()) {
        normals_.resize(nv);
        for (std::size_t v = 0; v < nv; ++v) normals_[rank_[v]] = mesh.normals[v];
    }
    serial_.live = nf;
}

// With threads >= 2 the face planes and the manifold check run on two threads, one per half of the vertex numbers
// (part_range, as run_regions() cuts them): each adds planes only to its own vertices, in face order as on one thread,
// so the quadrics come out bit for bit the same; the half-edges needing more than the common interior test are
// collected per half and handled afterwards in vertex order, as on one thread.
Status Simplifier::init() {
    FanEnds ends = pooled<std::array<Index, 2>>();
    if (auto status = build_fans(ends); !status) return status;
    // the manifold check comes before the face planes, so that a mesh refused as non-manifold (which repair "auto"
    // then repairs) is refused without computing them; boundary planes are added after the face planes all the same
    const auto odd = find_odd_halfedges(ends);
    BlockVector<Index> boundary_edges = pooled<Index>();  //!< per vertex
    boundary_edges.assign(vx_.size(), 0);
    const bool refused = std::any_of(odd.begin(), odd.end(), [](const std::vector<OddHalfedge>& list) {
        return std::any_of(list.begin(), list.end(), [](const OddHalfedge& h) { return h.same > 0 || h.opposite > 1; });
    });
    if (refused) return classify_odd_halfedges(odd, ends, boundary_edges);
    add_face_planes();
    if (auto status = classify_odd_halfedges(odd, ends, boundary_edges); !status) return status;
    pin_vertices(boundary_edges);
    return Ok{};
}

//! Fans: every vertex lists its faces in increasing order, with kFanSlack spare entries. Degrees and fill cursors are
//! counted in a compact array (4 bytes a vertex stay in cache where the 128-byte records do not), and beside each fan
//! slot go (`ends`) the corner's next and previous vertex, the ends of the vertex's outgoing and incoming edges, so
//! that the manifold check reads them in order instead of every triangle again.
Status Simplifier::build_fans(FanEnds& ends) {
    const std::size_t nv = vx_.size(), nf = tris_.size();
    std::vector<Index> cursor(nv, 0);
    for (const auto& t : tris_)
        for (Index v : t) ++cursor[v];
    std::size_t total = 0;
    for (std::size_t v = 0; v < nv; ++v) {
        VertexData& x = vx_[v];
        x.fan = static_cast<Index>(total);
        x.degree = cursor[v];
        x.capacity = x.degree + kFanSlack;
        cursor[v] = static_cast<Index>(total);
        total += x.capacity;
    }
    if (total >= kInvalidIndex) return make_error(ErrorCode::InvalidArgument, "mesh too large to simplify");
    fans_.reserve(total + total / 4);
    fans_.resize(total);
    ends.resize(total);
    for (Index f = 0; f < nf; ++f) {
        const auto& t = tris_[f];
        for (int j = 0; j < 3; ++j) {
            const Index slot = cursor[t[j]]++;
            fans_[slot] = f;
            ends[slot] = {t[(j + 1) % 3], t[(j + 2) % 3]};
        }
    }
    return Ok{};
}

//! Face planes, weighted by area so that the metric does not depend on the tessellation density.
void Simplifier::add_face_planes() {
    const std::size_t nf = tris_.size();
    run_two_parts(split_ < vx_.size(), [&](int part) {
        const auto [lo, hi] = part_range(part);
        if (lo == hi) return;
        const auto mine = [lo = lo, hi = hi](Index v) { return v >= lo && v < hi; };
        for (std::size_t f = 0; f < nf; ++f) {
            const auto& t = tris_[f];
            if (!mine(t[0]) && !mine(t[1]) && !mine(t[2])) continue;
            const Vec3& p0 = vx_[t[0]].p;
            Vec3 n = cross(vx_[t[1]].p - p0, vx_[t[2]].p - p0);
            const double len = norm(n);
            if (mine(t[0])) tris_[f].normal = {0.0f, 0.0f, 0.0f};
            if (!(len > 0)) continue;  // no plane; its edges still get the quadrics of their other faces
            n *= 1.0 / len;
            if (mine(t[0]))
                tris_[f].normal = {static_cast<float>(n.x), static_cast<float>(n.y), static_cast<float>(n.z)};
            const Quadric q = Quadric::from_plane(n, -dot(n, p0), 0.5 * len);
            for (Index v : t)
                if (mine(v)) vx_[v].q += q;
        }
    });
}

//! Every half-edge u -> w must have at most one twin, running the other way. Checked per vertex u on its fan: the
//! faces' vertices after u (outgoing edges) and before u (incoming). Returns, per part, the half-edges that are not
//! simply interior, in vertex order.
std::array<std::vector<Simplifier::OddHalfedge>, 2> Simplifier::find_odd_halfedges(const FanEnds& ends) const {
    std::array<std::vector<OddHalfedge>, 2> odd;
    run_two_parts(split_ < vx_.size(), [&](int part) {
        const auto [lo, hi] = part_range(part);
        for (Index u = lo; u < hi; ++u) {
            const std::array<Index, 2>* edge = ends.data() + vx_[u].fan;
            const Index degree = vx_[u].degree;
            for (Index i = 0; i < degree; ++i) {
                const Index w = edge[i][0];
                // other faces with u -> w (same direction) and with w -> u (opposite); a face's own incoming
                // edge never ends at w (validated: no face repeats a vertex)
                int same = -1, opposite = 0;
                for (Index x = 0; x < degree; ++x) {
                    same += edge[x][0] == w;
                    opposite += edge[x][1] == w;
                }
                if (same == 0 && opposite == 1) continue;  // an interior edge, as nearly all are
                odd[static_cast<std::size_t>(part)].push_back({u, i, same, opposite});
            }
        }
    });
    return odd;
}

//! Boundary edges (no twin) get their flags and, without lock_border, constraint planes; an edge with more than one
//! twin or a twin in the same direction is an error, which names the first offending half-edge in face order,
//! whatever the vertex order.
Status Simplifier::classify_odd_halfedges(const std::array<std::vector<OddHalfedge>, 2>& odd, const FanEnds& ends,
                                          BlockVector<Index>& boundary_edges) {
    boundary_halfedges_.assign(tris_.size(), 0);
    std::size_t first_bad = std::numeric_limits<std::size_t>::max();
    bool bad_orientation = false;
    for (const auto& list : odd)
        for (const auto& [u, i, same, opposite] : list) {
            const Index f = fan_of(u)[i];
            const Index w = ends[vx_[u].fan + i][0];
            const int j = corner_of(f, u);
            if (same > 0 || opposite > 1) {
                const std::size_t halfedge = 3 * std::size_t{f} + static_cast<std::size_t>(j);
                if (halfedge < first_bad) {
                    first_bad = halfedge;
                    bad_orientation = same > 0 && opposite == 0;
                }
                continue;
            }
            boundary_halfedges_[f] |= static_cast<std::uint8_t>(1u << j);
            flags_[u] |= kBoundary;
            flags_[w] |= kBoundary;
            ++boundary_edges[u];
            ++boundary_edges[w];
            if (!options_.lock_border) add_boundary_plane(f, j);
        }
    if (first_bad == std::numeric_limits<std::size_t>::max()) return Ok{};
    const Index f = static_cast<Index>(first_bad / 3);
    const int j = static_cast<int>(first_bad % 3);
    const std::string edge = "(" + std::to_string(input_index(tris_[f][j])) + ", " +
                             std::to_string(input_index(tris_[f][(j + 1) % 3])) + ")";
    return element_error(
        ErrorCode::NonManifold,
        bad_orientation ? "edge " + edge + " is traversed in the same direction by face " + std::to_string(f) +
                              " and another face (inconsistent orientation or a duplicate face)"
                        : "edge " + edge + " is shared by more than two faces (face " + std::to_string(f) + " is one)",
        ElementKind::Face, f);
}

//! Pinned vertices (kPinned), and dead ones: vertices without faces.
void Simplifier::pin_vertices(const BlockVector<Index>& boundary_edges) {
    const std::size_t nv = vx_.size(), nf = tris_.size();
    for (std::size_t v = 0; v < nv; ++v) {
        // two boundary fans meeting at one vertex: no collapse there could keep the mesh manifold for sure
        if (boundary_edges[v] > 2) flags_[v] |= kPinned;
        if (options_.lock_border && (flags_[v] & kBoundary)) flags_[v] |= kPinned;
    }
    for (Index v : options_.locked_vertices) flags_[rank_[v]] |= kPinned;
    // UV seams: a vertex whose corners use different uv indices. Pinning it keeps every seam exactly, and a
    // collapse onto it takes the uv of the chart the collapsing edge lies in.
    if (!face_uvs_.empty()) {
        std::vector<Index> first_uv(nv, kInvalidIndex);
        for (std::size_t f = 0; f < nf; ++f)
            for (int j = 0; j < 3; ++j) {
                const Index v = tris_[f][j], uv = face_uvs_[f][j];
                if (first_uv[v] == kInvalidIndex)
                    first_uv[v] = uv;
                else if (first_uv[v] != uv)
                    flags_[v] |= kPinned;
            }
    }
    for (std::size_t v = 0; v < nv; ++v)
        if (vx_[v].degree == 0) flags_[v] &= static_cast<std::uint8_t>(~kAlive);
}

void Simplifier::run(std::size_t target, double threshold) {
    Worker& w = serial_;
    int first_pass = 0;
    // after the regions, w.heap holds every live edge already (run_regions)
    bool filled = options_.threads >= 2 && run_regions(target, threshold);
    if (filled) first_pass = 1;
    if (w.cancelled) return;
    for (int pass = first_pass; pass < first_pass + kMaxPasses && w.live > target; ++pass) {
        // Later passes retry collapses that were invalid when popped but may have become valid since.
        if (!filled) {
            w.heap.clear();
            push_edges_by_face(w, pass);
        }
        filled = false;
        w.stop_at = target;
        w.compacted = w.heap.size();
        w.pushes = 0;
        const std::size_t before = w.collapses;
        collapse_in_order(w, threshold, std::numeric_limits<float>::infinity());
        if (w.cancelled || w.collapses == before) break;
    }
    if (!w.cancelled) collapse_degenerate_faces(w, threshold);
}

//! The faces of the input with (almost) zero area (CAD exports close T-junctions with them) cost nothing to collapse,
//! but a target reached early leaves some: one edge of each degenerate face left is collapsed, shortest first, with
//! the usual checks (so the output may end a few faces below the target). A face no collapse can remove stays.
void Simplifier::collapse_degenerate_faces(Worker& w, double threshold) {
    constexpr int kRounds = 4;  // a collapse can leave a neighbouring degenerate face collapsible only afterwards
    for (int round = 0; round < kRounds; ++round) {
        bool changed = false;
        for (std::size_t f = 0; f < tris_.size(); ++f) {
            if (!face_alive_[f]) continue;
            const Tri& t = tris_[f];
            const Vec3 &p0 = vx_[t[0]].p, &p1 = vx_[t[1]].p, &p2 = vx_[t[2]].p;
            std::array<std::pair<double, int>, 3> edges{
                {{dot(p1 - p0, p1 - p0), 0}, {dot(p2 - p1, p2 - p1), 1}, {dot(p0 - p2, p0 - p2), 2}}};
            std::sort(edges.begin(), edges.end());
            const double longest = edges[2].first;
            if (longest > 0 && norm(cross(p1 - p0, p2 - p0)) >= kDegenerate * longest) continue;
            for (const auto& [length2, j] : edges) {
                Collapse collapse;
                if (!evaluate(t[j], t[(j + 1) % 3], collapse, volume_)) continue;
                collapse.error = collapse.weight > 0 ? std::sqrt(collapse.cost / collapse.weight) : 0.0;
                if (collapse.error > threshold || !is_valid(w, collapse)) continue;
                apply(w, collapse);
                w.max_error = std::max(w.max_error, collapse.error);
                ++w.collapses;
                changed = true;
                break;
            }
        }
        if (!changed) break;
    }
}

PolygonMesh Simplifier::extract() const {
    PolygonMesh out;
    std::vector<Index> remap(vx_.size(), kInvalidIndex);
    std::vector<Index> uv_remap(uvs_.size(), kInvalidIndex);
    out.face_offsets.reserve(serial_.live + 1);
    out.face_indices.reserve(3 * serial_.live);
    for (std::size_t f = 0; f < tris_.size(); ++f) {
        if (!face_alive_[f]) continue;
        for (int j = 0; j < 3; ++j) {
            const Index v = tris_[f][j];
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

//! Collapses w's candidates in cost order while w.live > w.stop_at, up to heap keys of `level`, skipping those
//! whose error exceeds `threshold`; stops early when w.cancelled or (region workers) w.done is set.
void Simplifier::collapse_in_order(Worker& w, double threshold, float level) {
    const auto current = [this](const Candidate& c) { return is_current(c); };
    const std::size_t parts = w.region < 0 ? 1 : 2;
    while (w.live > w.stop_at) {
        // Stale entries pile up (each collapse outdates the entries at two vertices and adds new ones).
        // Dropping them once they outnumber the live edges keeps the heap small and cache-friendly. Only
        // after pushes of a quarter of what the last compaction kept, so that a compaction costs at most a
        // few times the pushes since, whatever the mesh (a triangle soup has 3 current entries per face and
        // no stale ones: without that condition every pop would compact it).
        // Compaction keeps the heap under 2 live faces + 1024 entries, plus one collapse's pushes.
        if (w.heap.size() > 2 * (w.live / parts) + 1024 && w.pushes >= w.compacted / 4) {
            compact_heap(w);
            w.compacted = w.heap.size();
            w.pushes = 0;
        }
        if ((++w.polls & 4095) == 0 && options_.cancel.requested()) {
            w.cancelled = true;
            return;
        }
        const Candidate* top = w.heap.top(current);
        if (!top) {
            w.done = true;
            return;
        }
        if (top->cost > level) return;
        const Candidate c = w.heap.pop();
        if (const Candidate* next = w.heap.top(current)) prefetch_vertex(next->a), prefetch_vertex(next->b);
        if (!current(c)) continue;  // stale: an endpoint moved, changed or died
        if (volume_) prefetch_fan(c.a), prefetch_fan(c.b);
        Collapse collapse;
        if (!evaluate(c.a, c.b, collapse, volume_)) continue;
        collapse.error = collapse.weight > 0 ? std::sqrt(collapse.cost / collapse.weight) : 0.0;
        if (collapse.error > threshold) continue;
        if (w.region >= 0) {
            // a region worker's room must hold the largest fan block this collapse could need, and a uv
            const std::size_t degree = std::size_t{vx_[collapse.keep].degree} + vx_[collapse.remove].degree;
            if (w.fan_end - w.fan_next < degree + std::max<std::size_t>(4, degree / 2) ||
                (!face_uvs_.empty() && w.uv_next == w.uv_end)) {
                w.heap.push(c);  // for the second phase
                w.done = true;
                return;
            }
        }
        if (!is_valid(w, collapse)) continue;
        apply(w, collapse);
        w.max_error = std::max(w.max_error, collapse.error);
        ++w.collapses;
    }
}

//! The input's number of vertex v (for messages only: a linear search).
Index Simplifier::input_index(Index v) const {
    return static_cast<Index>(std::find(rank_.begin(), rank_.end(), v) - rank_.begin());
}

//! What evaluate() reads of v. Vertices come from the heap and from one-rings in no useful order, so nearly
//! every access misses the cache; prefetching a batch lets the misses overlap instead of queueing one by one.
void Simplifier::prefetch_vertex(Index v) const {
    const char* data = reinterpret_cast<const char*>(&vx_[v]);
    __builtin_prefetch(data);
    __builtin_prefetch(data + 64);
}

//! The triangles of v's fan (v's record must be at hand).
void Simplifier::prefetch_fan(Index v) const {
    const Index* fan = fan_of(v);
    for (Index i = 0, n = vx_[v].degree; i < n; ++i) __builtin_prefetch(&tris_[fan[i]]);
}

bool Simplifier::is_boundary_halfedge(Index f, int j) const {
    const Index u = tris_[f][j], w = tris_[f][(j + 1) % 3];
    const Index* fan = fan_of(w);
    for (Index i = 0, n = vx_[w].degree; i < n; ++i) {
        const Index g = fan[i];
        if (g != f && tris_[g][(corner_of(g, w) + 1) % 3] == u) return false;
    }
    return true;
}

//! Constraint plane through boundary edge j of face f, perpendicular to the face (Garland-Heckbert 1998 sec. 4):
//! it lets boundary vertices slide along the boundary but resists pulling the boundary inwards.
void Simplifier::add_boundary_plane(Index f, int j) {
    const auto& t = tris_[f];
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

//! Whether half-edge j of face f stands for its edge in the heap: interior edges appear twice (once per
//! direction) and are pushed once, boundary edges always (the first pass knows the boundary from init).
bool Simplifier::is_candidate_halfedge(Index f, int j, int pass) const {
    const Index u = tris_[f][j], w = tris_[f][(j + 1) % 3];
    return u < w || (pass == 0 ? (boundary_halfedges_[f] >> j & 1) != 0 : is_boundary_halfedge(f, j));
}

//! Whether edge (u, w) is for worker `worker`: every edge for the whole-mesh worker; for a region worker the
//! edges between its region's vertices that are not frozen (run_regions).
bool Simplifier::owns(const Worker& worker, Index u, Index w) const {
    return worker.region < 0 || (region_of(u) == worker.region && !((flags_[u] | flags_[w]) & kFrozen));
}

//! Fills w's heap with every live edge it owns, in face order.
void Simplifier::push_edges_by_face(Worker& w, int pass) {
    for (Index f = 0; f < tris_.size(); ++f) {
        if (!face_alive_[f]) continue;
        const auto& t = tris_[f];
        for (int j = 0; j < 3; ++j) {
            const Index u = t[j], x = t[(j + 1) % 3];
            if (owns(w, u, x) && is_candidate_halfedge(f, j, pass)) add_candidate(w, u, x);
        }
    }
}

//! Appends edge (a, b) to w's heap without restoring the heap order; false when it cannot collapse at all.
bool Simplifier::add_candidate(Worker& w, Index a, Index b) {
    Collapse collapse;
    if (!evaluate(a, b, collapse)) return false;
    w.heap.push({static_cast<float>(collapse.cost), a, b, stamp(a, b)});
    return true;
}

void Simplifier::compact_heap(Worker& w) {
    w.heap.erase_if([&](const Candidate& c) { return !is_current(c); });
}

void Simplifier::push(Worker& w, Index a, Index b) {
    if (!owns(w, a, b)) return;
    Collapse collapse;
    if (!evaluate(a, b, collapse)) return;
    w.heap.push({static_cast<float>(collapse.cost), a, b, stamp(a, b)});
    ++w.pushes;
}

//! Placement and cost of collapsing edge (a, b); false when both ends are pinned. `restore`: with volume
//! restoration (restore_volume()), for the collapse about to be made; heap keys are the costs without it.
bool Simplifier::evaluate(Index a, Index b, Collapse& out, bool restore) const {
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
            out.s = -1;  // found by apply() when attributes need it: most evaluations only want the cost
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
                if (e < best) {
                    best = e;
                    best_s = s;
                }
            };
            consider(0.0);
            consider(1.0);
            consider(0.5);
            if (dad > 0) consider(std::clamp(-gd / dad, 0.0, 1.0));
            out.position = xa + d * best_s;
            out.s = best_s;
        }
        if (restore && !((flags_[a] | flags_[b]) & kBoundary)) restore_volume(a, b, q, out);
    }
    out.cost = q.error(out.position);
    out.weight = q.weight;
    return true;
}

//! Moves out.position towards the point on the line out.position + t A^-1 g (where Q is least for each volume)
//! at which collapsing (a, b) leaves the volume under the two fans unchanged, restore_volume of the way. Volume
//! change x 6 = g.(p - xa) - (xb - xa).G_b, with g = G_a + G_b - the edge's two faces' cross products (twice the
//! vector area of the two fans, whose boundary the collapse keeps) and G the sums of the fans' cross products.
//! Closed fans only: an interior edge between interior vertices (the caller checks the boundary flags). Only for
//! the collapse about to be made, its fans computed here: ordering the heap by the plain cost instead gives the
//! same errors on the bench meshes (RMS within 2%), and keeping fan areas per vertex for every evaluation cost
//! 25-70% more time.
void Simplifier::restore_volume(Index a, Index b, const Quadric& q, Collapse& out) const {
    const Vec3& xa = vx_[a].p;
    const Vec3 d = vx_[b].p - xa;
    Vec3 ga{0, 0, 0}, gb{0, 0, 0}, edge_faces{0, 0, 0};
    int shared = 0;
    for (const Index v : {a, b}) {
        const Index* fan = fan_of(v);
        Vec3& sum = v == a ? ga : gb;
        for (Index i = 0, n = vx_[v].degree; i < n; ++i) {
            const Tri& t = tris_[fan[i]];
            const Vec3 cr = cross(vx_[t[1]].p - vx_[t[0]].p, vx_[t[2]].p - vx_[t[0]].p);
            sum += cr;
            if (v == a && (t[0] == b || t[1] == b || t[2] == b)) edge_faces += cr, ++shared;
        }
    }
    if (shared != 2) return;
    const Vec3 g = ga + gb - edge_faces;
    const double change = dot(out.position - xa, g) - dot(d, gb);
    Vec3 dir = g;
    if (Vec3 u; q.solve(g, u) && dot(u, g) > 0) dir = u;
    const double dg = dot(dir, g);
    if (!(dg > 0)) return;
    const Vec3 p = out.position - dir * (options_.restore_volume * change / dg);
    const Vec3 mid = xa + d * 0.5;
    if (!is_finite(p) || dot(p - mid, p - mid) > kMaxPlacementReach * kMaxPlacementReach * dot(d, d)) return;
    out.position = p;
    out.s = -1;
}

//! Appends the distinct neighbours of v (over its live faces) to `out`.
void Simplifier::neighbours(Index v, std::vector<Index>& out) const {
    out.clear();
    const Index* fan = fan_of(v);
    for (Index i = 0, n = vx_[v].degree; i < n; ++i)
        for (Index w : tris_[fan[i]]) {
            if (w == v) continue;
            bool seen = false;
            for (std::size_t k = 0; k < out.size() && !seen; ++k) seen = out[k] == w;
            if (!seen) out.push_back(w);
        }
}

//! The same set in another order, cheaper: away from boundaries every neighbour follows v in exactly one face
//! (the edge manifold check of init() and the link condition keep it so).
void Simplifier::neighbour_set(Index v, std::vector<Index>& out) const {
    if (flags_[v] & kBoundary) return neighbours(v, out);
    out.clear();
    const Index* fan = fan_of(v);
    for (Index i = 0, n = vx_[v].degree; i < n; ++i) out.push_back(tris_[fan[i]][(corner_of(fan[i], v) + 1) % 3]);
}

bool Simplifier::is_apex(const Worker& worker, Index w) {
    for (Index a : worker.apexes)
        if (a == w) return true;
    return false;
}

//! Link condition, geometry (flips, thin faces) and duplicate faces, for the collapse as evaluated.
bool Simplifier::is_valid(Worker& wk, const Collapse& c) {
    const Index k = c.keep, r = c.remove;
    if (!keeps_manifold(wk, k, r)) return false;
    // geometry of every face that survives with a moved or renamed corner
    const Index* fan_r = fan_of(r);
    const Index* fan_k = fan_of(k);
    const Index degree_r = vx_[r].degree, degree_k = vx_[k].degree;
    for (Index i = 0; i < degree_r; ++i) {
        const Index f = fan_r[i];
        if (contains(f, k)) continue;
        if (!face_ok(f, r, c.position)) return false;
        // The face becomes (k, x, y): a face already on x, y and k would duplicate it. x and y would then both
        // be common neighbours of k and r, which the link condition allows only for the apexes.
        const int j = corner_of(f, r);
        const Index x = tris_[f][(j + 1) % 3], y = tris_[f][(j + 2) % 3];
        if (!is_apex(wk, x) || !is_apex(wk, y)) continue;
        const Index* fan_x = fan_of(x);
        for (Index m = 0, n = vx_[x].degree; m < n; ++m) {
            const Index g = fan_x[m];
            if (g != f && contains(g, y) && contains(g, k)) return false;
        }
    }
    if (!pinned(k) || c.position != vx_[k].p)
        for (Index i = 0; i < degree_k; ++i) {
            const Index f = fan_k[i];
            if (!contains(f, r) && !face_ok(f, k, c.position)) return false;
        }
    return true;
}

//! Whether collapsing r into k keeps the mesh a manifold with every vertex on a face: the edge has one or two faces,
//! and the link condition holds. Fills wk's scratch for the checks after it and for apply(): shared (the edge's
//! faces), apexes (their third corners), ring_k and ring_r (the neighbours of k and of r).
bool Simplifier::keeps_manifold(Worker& wk, Index k, Index r) const {
    prefetch_fan(r);
    prefetch_fan(k);
    const Index* fan_r = fan_of(r);
    const Index degree_r = vx_[r].degree, degree_k = vx_[k].degree;
    // faces on the edge and their apexes
    wk.shared.clear();
    wk.apexes.clear();
    for (Index i = 0; i < degree_r; ++i) {
        const Index f = fan_r[i];
        if (contains(f, k)) {
            wk.shared.push_back(f);
            for (Index w : tris_[f])
                if (w != k && w != r) wk.apexes.push_back(w);
        }
    }
    if (wk.shared.empty() || wk.shared.size() > 2) return false;
    const bool edge_on_boundary = wk.shared.size() == 1;
    // An interior edge between two boundary vertices: collapsing it would pinch the surface into a non-manifold
    // vertex (the link condition with the boundary's virtual vertex).
    if (!edge_on_boundary && (flags_[k] & kBoundary) && (flags_[r] & kBoundary)) return false;
    // Nothing may be left without faces (a lone triangle, or an apex whose only faces are the edge's).
    if (degree_k + degree_r <= 2 * wk.shared.size()) return false;
    for (Index w : wk.apexes) {
        std::size_t on_edge = 0;
        for (Index f : wk.shared) on_edge += contains(f, w) ? 1 : 0;
        if (vx_[w].degree <= on_edge) return false;
    }
    // Link condition (Dey et al.): the common neighbours of k and r are exactly the apexes of the edge's faces.
    neighbour_set(k, wk.ring_k);
    neighbour_set(r, wk.ring_r);
    // the whole records: is_valid's face checks read positions (second line), and apply() evaluates the edges to
    // every one of these vertices (quadric, both lines)
    for (Index w : wk.ring_k) prefetch_vertex(w);
    for (Index w : wk.ring_r) prefetch_vertex(w);
    for (Index w : wk.ring_r) {
        if (w == k || is_apex(wk, w)) continue;
        for (Index x : wk.ring_k)
            if (x == w) return false;
    }
    return true;
}

//! Geometry of face f once its corner `moved` is at `position`: (moved, o1, o2) in the face's order. Compared
//! squared, without square roots where the sides are >= 0.
bool Simplifier::face_ok(Index f, Index moved, const Vec3& position) const {
    constexpr double cos2 = kMinNormalCos * kMinNormalCos;
    const Tri& t = tris_[f];
    const int j = corner_of(f, moved);
    const Vec3& o1 = vx_[t[(j + 1) % 3]].p;
    const Vec3& o2 = vx_[t[(j + 2) % 3]].p;
    const Vec3& m0 = vx_[moved].p;
    const Vec3 e = o2 - o1, a1 = o1 - position, b1 = o2 - position;
    const Vec3 n1 = cross(a1, b1);
    const double l1sq = dot(n1, n1);
    const double ee = dot(e, e);
    const double longest = std::max({dot(a1, a1), dot(b1, b1), ee});
    // thinness after = |n1| / longest (see kThin): never below kDegenerate, below kThin only if the face
    // was already thinner
    if (!(longest > 0) || l1sq < kDegenerate * kDegenerate * longest * longest) return false;
    const Vec3 a0 = o1 - m0, b0 = o2 - m0;
    const Vec3 n0 = cross(a0, b0);
    const double l0sq = dot(n0, n0);
    if (l1sq < kThin * kThin * longest * longest) {
        const double longest0 = std::max({dot(a0, a0), dot(b0, b0), ee});
        const double thin0 = longest0 > 0 ? std::sqrt(l0sq) / longest0 : 0.0;
        if (std::sqrt(l1sq) / longest < thin0) return false;
    }
    // Small turns add up over many collapses: a face may also never face away from the input face it
    // started as (cos < kMinNormalCos).
    if (t.normal[0] != 0 || t.normal[1] != 0 || t.normal[2] != 0) {
        const double d = dot(Vec3{t.normal[0], t.normal[1], t.normal[2]}, n1);
        if (d < 0 || d * d < cos2 * l1sq) return false;
    }
    // a face that had no normal before cannot flip; compare the ones that had
    if (l0sq > 0) {
        const double d = dot(n0, n1);
        if (d < 0 || d * d < cos2 * l0sq * l1sq) return false;
    }
    return true;
}

//! Removes face f from v's fan, keeping the order of the others.
void Simplifier::unlink(Index v, Index f) {
    Index* fan = fan_of(v);
    const Index n = vx_[v].degree;
    for (Index i = 0; i < n; ++i)
        if (fan[i] == f) {
            std::copy(fan + i + 1, fan + n, fan + i);
            --vx_[v].degree;
            return;
        }
}

void Simplifier::apply(Worker& wk, const Collapse& c) {
    const Index k = c.keep, r = c.remove;
    // attributes first, while the edge's faces still exist
    double s = c.s;
    if (s < 0 && (!face_uvs_.empty() || !normals_.empty())) {
        const Vec3 d = vx_[r].p - vx_[k].p;
        const double len2 = dot(d, d);
        s = len2 > 0 ? std::clamp(dot(c.position - vx_[k].p, d) / len2, 0.0, 1.0) : 0.5;
    }
    if (!face_uvs_.empty()) {
        const Index f0 = wk.shared.front();
        const Index uv_k = face_uvs_[f0][corner_of(f0, k)];
        const Index uv_r = face_uvs_[f0][corner_of(f0, r)];
        Index target = uv_k;
        if (!pinned(k)) {
            // neither end is on a seam: one uv each; interpolate along the edge as the position moved
            const Vec2 a = uvs_[uv_k], b = uvs_[uv_r];
            const Vec2 uv{a.x + (b.x - a.x) * s, a.y + (b.y - a.y) * s};
            if (wk.region < 0) {
                uvs_.push_back(uv);
                target = static_cast<Index>(uvs_.size() - 1);
            } else {
                uvs_[wk.uv_next] = uv;  // room checked before the collapse (collapse_in_order)
                target = static_cast<Index>(wk.uv_next++);
            }
            const Index* fan = fan_of(k);
            for (Index i = 0, n = vx_[k].degree; i < n; ++i) face_uvs_[fan[i]][corner_of(fan[i], k)] = target;
        }
        const Index* fan = fan_of(r);
        for (Index i = 0, n = vx_[r].degree; i < n; ++i) face_uvs_[fan[i]][corner_of(fan[i], r)] = target;
    }
    if (!normals_.empty()) {
        Vec3 n = normals_[k] + (normals_[r] - normals_[k]) * s;
        const double len = norm(n);
        if (len > 0) normals_[k] = n * (1.0 / len);
    }
    // topology: the edge's faces die, r's other faces move to k (appended to k's fan, in r's order)
    for (Index f : wk.shared) {
        face_alive_[f] = 0;
        --wk.live;
        for (Index w : tris_[f])
            if (w != r) unlink(w, f);
    }
    VertexData& xk = vx_[k];
    VertexData& xr = vx_[r];
    Index moved = 0;  // r's faces that stay, compacted to the front of r's fan
    {
        Index* fan = fan_of(r);
        for (Index i = 0; i < xr.degree; ++i) {
            const Index f = fan[i];
            if (!face_alive_[f]) continue;
            tris_[f][corner_of(f, r)] = k;
            fan[moved++] = f;
        }
    }
    const Index degree = xk.degree + moved;
    if (degree <= xk.capacity) {
        std::copy(fans_.begin() + xr.fan, fans_.begin() + xr.fan + moved, fans_.begin() + xk.fan + xk.degree);
    } else if (degree <= xr.capacity) {
        // r's block is big enough: k's faces go in front of r's there, and k takes the block
        std::copy_backward(fans_.begin() + xr.fan, fans_.begin() + xr.fan + moved, fans_.begin() + xr.fan + degree);
        std::copy(fans_.begin() + xk.fan, fans_.begin() + xk.fan + xk.degree, fans_.begin() + xr.fan);
        std::swap(xk.fan, xr.fan);
        std::swap(xk.capacity, xr.capacity);
    } else {
        // a new block at the end, with room to grow
        const Index capacity = degree + std::max<Index>(4, degree / 2);
        std::size_t start = wk.fan_next;
        if (wk.region < 0) {
            start = fans_.size();
            fans_.resize(start + capacity);
        } else {
            wk.fan_next += capacity;  // room checked before the collapse (collapse_in_order)
        }
        std::copy(fans_.begin() + xk.fan, fans_.begin() + xk.fan + xk.degree, fans_.begin() + start);
        std::copy(fans_.begin() + xr.fan, fans_.begin() + xr.fan + moved, fans_.begin() + start + xk.degree);
        xk.fan = static_cast<Index>(start);
        xk.capacity = capacity;
    }
    xk.degree = degree;
    xr.degree = 0;
    flags_[k] |= flags_[r] & kBoundary;
    flags_[r] = 0;
    xk.q += xr.q;
    xk.p = c.position;
    ++version_[k];
    ++version_[r];
    // Only edges at k changed cost (their quadric or endpoint moved): push them with k's new stamp. k's ring is
    // now its ring and r's before the collapse (is_valid), less k and r; the two shared only the apexes (link
    // condition). Their records were fetched for the checks.
    for (Index w : wk.ring_k)
        if (w != r) push(wk, k, w);
    for (Index w : wk.ring_r)
        if (w != k && !is_apex(wk, w)) push(wk, k, w);
}

}  // namespace simplify_detail

namespace {
constexpr int kMaxErrorAttempts = 7;  //!< max_error: simplifications tried at most, each measured
}  // namespace

using simplify_detail::Simplifier;

Result<SimplifyResult> simplify_qem(const PolygonMesh& mesh, const SimplifyOptions& options) {
    if (auto valid = validate(mesh); !valid) return valid.error();
    if (!options.target_faces && !options.ratio && !options.max_error)
        return make_error(ErrorCode::InvalidArgument, "simplification needs target_faces, ratio or max_error");
    if (options.ratio && !(*options.ratio > 0 && *options.ratio <= 1))
        return make_error(ErrorCode::InvalidArgument, "ratio must be in (0, 1], got " + std::to_string(*options.ratio));
    if (options.max_error && !(*options.max_error >= 0 && std::isfinite(*options.max_error)))
        return make_error(ErrorCode::InvalidArgument,
                          "max_error must be a finite distance >= 0, got " + std::to_string(*options.max_error));
    if (!(options.restore_volume >= 0 && options.restore_volume <= 1))
        return make_error(ErrorCode::InvalidArgument,
                          "restore_volume must be in [0, 1], got " + std::to_string(options.restore_volume));
    if (options.threads < 1)
        return make_error(ErrorCode::InvalidArgument, "threads must be >= 1, got " + std::to_string(options.threads));
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
        return make_error(ErrorCode::InvalidArgument, "too many triangles to simplify: " + std::to_string(input_faces));
    std::size_t target = input_faces;
    if (options.target_faces) target = std::min(target, *options.target_faces);
    if (options.ratio)
        target =
            std::min(target, static_cast<std::size_t>(std::floor(*options.ratio * static_cast<double>(input_faces))));
    if (!options.target_faces && !options.ratio) target = 0;  // max_error alone: as far as the error allows
    const double diagonal = input.bounds().diagonal();

    Simplifier prototype(input, options);
    if (auto status = prototype.init(); !status) return status.error();

    if (!options.max_error) {
        Simplifier& simplifier = prototype;  // one run: no copy needed
        simplifier.run(target, std::numeric_limits<double>::infinity());
        if (simplifier.cancelled())
            return make_error(ErrorCode::Cancelled, "simplification cancelled (deadline or shutdown)");
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
            threshold =
                passed > 0 ? std::sqrt(passed * failed) : failed * std::clamp(0.8 * max_error / measured, 0.05, 0.7);
            if (!(threshold > 0)) break;
        }
    }
    result.faces = result.mesh.face_count();
    result.relative_error = diagonal > 0 ? result.achieved_error / diagonal : 0.0;
    return result;
}

}  // namespace surfaced
