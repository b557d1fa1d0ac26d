// The simplifier's first phase with threads >= 2 (Simplifier::run_regions): the mesh's two spatial halves collapse at
// once, one thread each, in cost order across both to within a factor of two, until the faces on the cut between them
// and a margin are left to run()'s collapses in global order.
#include <algorithm>
#include <array>
#include <barrier>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <limits>
#include <thread>

#include "geometry/simplify/qem_simplifier.h"

namespace surfaced::simplify_detail {

//! The first phase with threads >= 2: the vertices are cut in two regions by their numbers, which put the vertices on
//! either side of a median plane first and second (spatial_order), so each region is one half of the mesh in space.
//! Vertices on a face with corners in both regions are frozen, and each region's other edges collapse on their own
//! thread with their own heap; a collapse there only reads and writes its region's vertices and faces (a vertex that
//! is not frozen has all its neighbours in its region, and collapses between such vertices keep it so). The two
//! halves advance in epochs: in each, both collapse up to a common cost level (at least twice the last one, and at
//! least the lowest key on top of either heap), so the order across the halves follows the costs to within that
//! factor, and each may remove at most half of the faces still above the floor. Phase one ends at the floor: the
//! target plus the faces on the cut plus 5% of the way, which run() then collapses in global order, from one heap: the
//! workers' current entries and the edges at frozen vertices, evaluated then (serial_.heap, filled here when it
//! returns true). Which collapses are made depends only on the mesh and the options, not on the threads' timing (the
//! epochs' levels and shares are decided while both wait), and is the same when a second thread cannot be had and the
//! halves take turns. Returns whether it ran.
bool Simplifier::run_regions(std::size_t target, double threshold) {
    const Worker& s = serial_;
    if (split_ == vx_.size() || s.live < kRegionsMinimum || s.live <= target) return false;
    // each region worker's room for grown fans and interpolated texture coordinates
    const std::size_t room = fans_.size() / 4 + 1024;
    const std::size_t uv_room = face_uvs_.empty() ? 0 : s.live / 4 + 1024;
    if (fans_.size() + 2 * room >= kInvalidIndex || uvs_.size() + 2 * uv_room >= kInvalidIndex) return false;
    const std::size_t seam = freeze_seam();
    const std::size_t floor = target + seam + (s.live - target) / 20 + 64;
    if (s.live <= floor) {
        thaw();
        return false;
    }
    std::array<Worker, 2> workers{Worker(options_.block_pool), Worker(options_.block_pool)};
    set_up_region_workers(workers, room, uv_room);
    if (const std::exception_ptr failure = run_epochs(workers, floor, threshold)) {
        thaw();
        std::rethrow_exception(failure);
    }
    start_second_phase(workers);
    return true;
}

//! Freezes the vertices of every live face with corners in both regions; returns the number of those faces.
std::size_t Simplifier::freeze_seam() {
    std::size_t seam = 0;
    for (std::size_t f = 0; f < tris_.size(); ++f) {
        if (!face_alive_[f]) continue;
        const auto& t = tris_[f];
        const int region = region_of(t[0]);
        if (region_of(t[1]) == region && region_of(t[2]) == region) continue;
        ++seam;
        for (Index v : t) flags_[v] |= kFrozen;
    }
    return seam;
}

void Simplifier::thaw() {
    for (auto& flag : flags_) flag &= static_cast<std::uint8_t>(~kFrozen);
}

//! Worker i takes region i, the whole mesh's live count, and `room` entries at the end of the fan pool and `uv_room`
//! at the end of the uv list (both grown here), so that neither reallocates while the workers run.
void Simplifier::set_up_region_workers(std::array<Worker, 2>& workers, std::size_t room, std::size_t uv_room) {
    const std::size_t pool = fans_.size(), uv_pool = uvs_.size();
    fans_.resize(pool + 2 * room);
    uvs_.resize(uv_pool + 2 * uv_room);
    for (int i = 0; i < 2; ++i) {
        Worker& w = workers[static_cast<std::size_t>(i)];
        w.region = i;
        w.live = w.stop_at = serial_.live;
        w.fan_next = pool + static_cast<std::size_t>(i) * room;
        w.fan_end = w.fan_next + room;
        w.uv_next = uv_pool + static_cast<std::size_t>(i) * uv_room;
        w.uv_end = w.uv_next + uv_room;
    }
}

//! Between epochs, while both workers wait: false when the phase ends (a worker was cancelled, both are done, or the
//! floor is reached); else sets the next epoch's cost `level` (at least twice the last one unless `first`, and at
//! least the lowest key on top of either heap) and each worker's stop_at, at most half of the faces above the floor.
bool Simplifier::plan_epoch(std::array<Worker, 2>& workers, std::size_t floor, bool first, float& level) {
    const auto current = [this](const Candidate& c) { return is_current(c); };
    std::size_t live = serial_.live;
    bool done = true;
    for (const Worker& w : workers) {
        live -= serial_.live - w.live;
        if (w.cancelled) return false;
        done = done && w.done;
    }
    if (done || live <= floor + 1) return false;
    float lowest = std::numeric_limits<float>::infinity();
    for (Worker& w : workers) {
        if (w.done) continue;
        if (const Candidate* top = w.heap.top(current))
            lowest = std::min(lowest, top->cost);
        else
            w.done = true;
    }
    if (!(lowest < std::numeric_limits<float>::infinity())) return false;
    level = std::max(first ? 0.0f : 2 * level, lowest);
    const std::size_t share = (live - floor) / 2;
    for (Worker& w : workers) w.stop_at = w.live - std::min(w.live, share);
    return true;
}

//! Fills the workers' heaps and runs the epochs until plan_epoch() ends the phase: on two threads that meet at a
//! barrier between epochs, or, when no second thread can be had, taking turns on this one. Returns the first exception
//! either worker threw (the phase stops at the next barrier), or null.
std::exception_ptr Simplifier::run_epochs(std::array<Worker, 2>& workers, std::size_t floor, double threshold) {
    std::array<std::exception_ptr, 2> failures;
    float level = 0;
    bool stop = false, first = true;
    const auto control = [&]() noexcept {
        try {
            if (failures[0] || failures[1] || !plan_epoch(workers, floor, first, level))
                stop = true;
            else
                first = false;
        } catch (...) {
            stop = true;
            if (!failures[0]) failures[0] = std::current_exception();
        }
    };
    const auto fill = [&](int i) noexcept {
        Worker& w = workers[static_cast<std::size_t>(i)];
        try {
            push_edges_by_face(w, 0);
            w.compacted = w.heap.size();
        } catch (...) {
            failures[static_cast<std::size_t>(i)] = std::current_exception();
        }
    };
    const auto epoch = [&](int i) noexcept {
        Worker& w = workers[static_cast<std::size_t>(i)];
        if (w.done || failures[static_cast<std::size_t>(i)]) return;
        try {
            collapse_in_order(w, threshold, level);
        } catch (...) {
            failures[static_cast<std::size_t>(i)] = std::current_exception();
        }
    };
    std::barrier<decltype(control)> sync(2, control);
    const auto loop = [&](int i) noexcept {
        fill(i);
        sync.arrive_and_wait();
        while (!stop) {
            epoch(i);
            sync.arrive_and_wait();
        }
    };
    std::thread other;
    if (options_.threads >= 2 && std::thread::hardware_concurrency() >= 2) {
        try {
            other = std::thread(loop, 1);
        } catch (...) {  // no thread to be had: the halves take turns below
        }
    }
    if (other.joinable()) {
        loop(0);
        other.join();
    } else {
        fill(0);
        fill(1);
        control();
        while (!stop) {
            epoch(0);
            epoch(1);
            control();
        }
    }
    return failures[0] ? failures[0] : failures[1];
}

//! The second phase's heap: the workers' current entries (every edge between vertices that are not frozen) and the
//! edges at frozen vertices, evaluated now (as pass 1 of run() would find them). Then the vertices thaw and the
//! workers' counts become the whole-mesh worker's.
void Simplifier::start_second_phase(std::array<Worker, 2>& workers) {
    Worker& s = serial_;
    const auto current = [this](const Candidate& c) { return is_current(c); };
    s.heap.clear();
    for (Worker& w : workers) s.heap.absorb(w.heap, current);
    for (Index f = 0; f < tris_.size(); ++f) {
        if (!face_alive_[f]) continue;
        const auto& t = tris_[f];
        for (int j = 0; j < 3; ++j) {
            const Index u = t[j], x = t[(j + 1) % 3];
            if (((flags_[u] | flags_[x]) & kFrozen) && is_candidate_halfedge(f, j, 1)) add_candidate(s, u, x);
        }
    }
    thaw();
    std::size_t live = s.live;
    for (const Worker& w : workers) {
        live -= s.live - w.live;
        s.max_error = std::max(s.max_error, w.max_error);
        s.collapses += w.collapses;
        s.cancelled = s.cancelled || w.cancelled;
    }
    s.live = live;
}

}  // namespace surfaced::simplify_detail
