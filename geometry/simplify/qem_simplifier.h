// The edge-collapse simplifier behind simplify_qem() (internal to geometry/simplify): its per-vertex and per-face
// records, the state of one collapsing loop (Worker), and class Simplifier. qem.cpp defines the set-up, the collapse
// loop and its checks; qem_regions.cpp the first phase with two threads (Simplifier::run_regions).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <vector>

#include "geometry/core/block_pool.h"
#include "geometry/core/result.h"
#include "geometry/mesh/polygon_mesh.h"
#include "geometry/simplify/candidate_heap.h"
#include "geometry/simplify/qem.h"
#include "geometry/simplify/quadric.h"

namespace surfaced::simplify_detail {

//! threads >= 2: meshes with fewer live faces than this run on one thread (starting one would cost more than it saves).
inline constexpr std::size_t kRegionsMinimum = 20000;

enum VertexFlag : std::uint8_t {
    kAlive = 1,
    kBoundary = 2,  //!< on a boundary edge
    kPinned = 4,    //!< never moves or disappears: locked, lock_border boundary, UV seam, non-manifold boundary
    kFrozen = 8,    //!< run_regions(): on a face with corners in both regions; left to the second phase
};

struct Collapse {
    Index keep = kInvalidIndex, remove = kInvalidIndex;
    Vec3 position;
    //! position's parameter along keep -> remove, for attribute interpolation; < 0: the projection of position
    double s = 0;
    double cost = 0;    //!< Q(position), the heap key
    double weight = 0;  //!< the summed quadric's weight
    double error = 0;   //!< sqrt(cost / weight): a distance (set by the caller, only for collapses popped)
};

//! What one collapsing loop owns: its heap, scratch and counters. One for the whole mesh, or with threads >= 2 one per
//! region of the first phase (Simplifier::run_regions), each touching only its region's vertices and faces.
struct Worker {
    explicit Worker(BlockPool* pool) : heap(pool) {}
    int region = -1;          //!< -1: the whole mesh
    std::size_t live = 0;     //!< live faces of the whole mesh as this worker sees them (its own collapses counted)
    std::size_t stop_at = 0;  //!< collapse while live > stop_at
    double max_error = 0;
    std::size_t collapses = 0;
    std::uint64_t polls = 0;
    std::size_t pushes = 0;     //!< heap pushes since the last compaction
    std::size_t compacted = 0;  //!< heap size after the last compaction
    bool cancelled = false;
    bool done = false;  //!< region workers: nothing left to do (heap empty, or no room for a new fan block)
    //! Region workers place grown fans in [fan_next, fan_end) of the pool and interpolated texture coordinates in
    //! [uv_next, uv_end) of the uv list, neither of which may reallocate meanwhile.
    std::size_t fan_next = 0, fan_end = 0, uv_next = 0, uv_end = 0;
    CandidateHeap heap;
    // scratch for is_valid/apply (one collapse at a time)
    std::vector<Index> shared, apexes, ring_k, ring_r;
};

//! What a collapse reads of a vertex, in one 128-byte block (two cache lines) instead of several arrays: vertices
//! are visited in heap and one-ring order, nearly always a cache miss each.
struct alignas(64) VertexData {
    Quadric q;
    Vec3 p;
    //! The vertex's live faces are fans_[fan, fan + degree), in the order they joined; `capacity` entries from `fan`
    //! belong to it. A fan is read in one piece, so all its triangles can be fetched at once (a list threaded through
    //! the triangles is a chain of dependent cache misses).
    Index fan = 0, degree = 0, capacity = 0;
};
static_assert(sizeof(VertexData) == 128);

//! A triangle and the unit normal of the input face it started as (0 when that had no area), which every
//! collapse that changes the face compares against: one fetch gives both. Float is ample for a cosine bound.
struct Tri {
    std::array<Index, 3> v;
    std::array<float, 3> normal;
    Index& operator[](int j) { return v[static_cast<std::size_t>(j)]; }
    Index operator[](int j) const { return v[static_cast<std::size_t>(j)]; }
    const Index* begin() const { return v.data(); }
    const Index* end() const { return v.data() + 3; }
};
static_assert(sizeof(Tri) == 24);

//! Quadric-error edge collapse on one triangle mesh: construct, init(), then run() (on a copy per threshold when
//! several are tried) and extract().
class Simplifier {
public:
    //! \pre mesh is a valid triangle mesh
    Simplifier(const PolygonMesh& mesh, const SimplifyOptions& options);

    //! Adjacency, the manifold check, quadrics and pinned vertices.
    Status init();
    //! Collapses edges until at most `target` faces remain or no valid collapse with error <= threshold is left.
    //! With threads >= 2, a first phase runs on two regions at once (run_regions).
    void run(std::size_t target, double threshold);
    PolygonMesh extract() const;

    std::size_t live_faces() const { return serial_.live; }
    double max_error() const { return serial_.max_error; }
    bool cancelled() const { return serial_.cancelled; }

private:
    //! A half-edge u -> (the next vertex of u's fan slot i) that is not simply interior (init)
    struct OddHalfedge {
        Index u, i;
        int same, opposite;  //!< other faces with the half-edge in the same direction, and in the opposite one
    };
    using FanEnds = BlockVector<std::array<Index, 2>>;  //!< per fan slot: the corner's next and previous vertex

    // set-up (init), in qem.cpp
    Status build_fans(FanEnds& ends);
    void add_face_planes();
    std::array<std::vector<OddHalfedge>, 2> find_odd_halfedges(const FanEnds& ends) const;
    Status classify_odd_halfedges(const std::array<std::vector<OddHalfedge>, 2>& odd, const FanEnds& ends,
                                  BlockVector<Index>& boundary_edges);
    void pin_vertices(const BlockVector<Index>& boundary_edges);
    //! init's parts for two threads: the vertices [lo, hi) of part 0 or 1 (as run_regions() cuts them)
    std::array<Index, 2> part_range(int part) const {
        return part == 0 ? std::array<Index, 2>{0, split_}
                         : std::array<Index, 2>{split_, static_cast<Index>(vx_.size())};
    }

    // the first phase with threads >= 2, in qem_regions.cpp
    bool run_regions(std::size_t target, double threshold);
    std::size_t freeze_seam();
    void thaw();
    void set_up_region_workers(std::array<Worker, 2>& workers, std::size_t room, std::size_t uv_room);
    bool plan_epoch(std::array<Worker, 2>& workers, std::size_t floor, bool first, float& level);
    std::exception_ptr run_epochs(std::array<Worker, 2>& workers, std::size_t floor, double threshold);
    void start_second_phase(std::array<Worker, 2>& workers);
    int region_of(Index v) const { return v < split_ ? 0 : 1; }

    // small accessors, for both files
    const Index* fan_of(Index v) const { return fans_.data() + vx_[v].fan; }
    Index* fan_of(Index v) { return fans_.data() + vx_[v].fan; }
    int corner_of(Index f, Index v) const {
        const auto& t = tris_[f];
        return t[0] == v ? 0 : (t[1] == v ? 1 : 2);
    }
    bool contains(Index f, Index v) const {
        const auto& t = tris_[f];
        return t[0] == v || t[1] == v || t[2] == v;
    }
    bool pinned(Index v) const { return (flags_[v] & kPinned) != 0; }
    std::uint32_t stamp(Index a, Index b) const { return version_[a] + version_[b]; }
    //! Whether candidate c is current (no endpoint changed since it was pushed).
    bool is_current(const Candidate& c) const { return stamp(c.a, c.b) == c.stamp; }

    // the collapse loop and the candidates, in qem.cpp
    void collapse_in_order(Worker& w, double threshold, float level);
    void collapse_degenerate_faces(Worker& w, double threshold);
    void push_edges_by_face(Worker& w, int pass);
    bool add_candidate(Worker& w, Index a, Index b);
    bool is_candidate_halfedge(Index f, int j, int pass) const;
    Index input_index(Index v) const;
    void add_boundary_plane(Index f, int j);

    // One collapse's evaluation, checks and update, defined in qem.cpp and called there only: inline, so that the
    // compiler may inline them into the collapse loop.
    inline void prefetch_vertex(Index v) const;
    inline void prefetch_fan(Index v) const;
    inline bool is_boundary_halfedge(Index f, int j) const;
    inline bool owns(const Worker& worker, Index u, Index w) const;
    inline void compact_heap(Worker& w);
    inline void push(Worker& w, Index a, Index b);
    inline bool evaluate(Index a, Index b, Collapse& out, bool restore = false) const;
    inline void restore_volume(Index a, Index b, const Quadric& q, Collapse& out) const;
    inline void neighbours(Index v, std::vector<Index>& out) const;
    inline void neighbour_set(Index v, std::vector<Index>& out) const;
    inline static bool is_apex(const Worker& worker, Index w);
    inline bool is_valid(Worker& wk, const Collapse& c);
    inline bool keeps_manifold(Worker& wk, Index k, Index r) const;
    inline bool face_ok(Index f, Index moved, const Vec3& position) const;
    inline void unlink(Index v, Index f);
    inline void apply(Worker& wk, const Collapse& c);

    //! An empty array whose large blocks come from options_.block_pool.
    template <class T>
    BlockVector<T> pooled() const {
        return BlockVector<T>(BlockAllocator<T>(options_.block_pool));
    }

    const SimplifyOptions& options_;
    const bool volume_ = options_.restore_volume > 0;  //!< volume restoration on (restore_volume)
    //! threads >= 2 on a mesh of kRegionsMinimum faces or more: vertices below split_ are the first half (numbered
    //! so by spatial_order), for init's two parts and run_regions(); else the vertex count (one part)
    const Index split_;
    std::vector<Index> rank_;  //!< rank_[input vertex] = its number here (spatial_order)
    BlockVector<VertexData> vx_ = pooled<VertexData>();
    BlockVector<std::uint8_t> flags_ = pooled<std::uint8_t>();  //!< VertexFlag bits per vertex
    //! Bumped whenever the vertex moves, changes quadric or dies. Apart from the records: every candidate popped is
    //! checked against it, most of them stale, and 4 bytes per vertex stay in cache where 128 would not.
    BlockVector<std::uint32_t> version_ = pooled<std::uint32_t>();
    BlockVector<Tri> tris_ = pooled<Tri>();
    BlockVector<Index> fans_ = pooled<Index>();  //!< every vertex's faces (VertexData::fan, degree, capacity)
    BlockVector<std::uint8_t> face_alive_ = pooled<std::uint8_t>();
    //! per input face, bit j: edge j (v[j] -> v[j+1]) is a boundary
    BlockVector<std::uint8_t> boundary_halfedges_ = pooled<std::uint8_t>();
    std::vector<Vec2> uvs_;
    std::vector<std::array<Index, 3>> face_uvs_;
    std::vector<Vec3> normals_;
    Worker serial_{options_.block_pool};  //!< the whole-mesh worker: run()'s passes, and the counts after them
};

}  // namespace surfaced::simplify_detail
