#include "geometry/reconstruct/octree.h"

#include <algorithm>
#include <cmath>

#include "geometry/core/two_parts.h"

namespace surfaced::reconstruct {
namespace {

KeySet make_set(std::vector<std::uint64_t> keys, bool indexed = true) {  // keys sorted and distinct
    KeySet set;
    set.keys = std::move(keys);
    if (indexed) set.index.assign(set.keys);
    return set;
}

//! The union of `keys` shifted along `axis` by every offset in [lo, hi], keeping coordinates in [0, limit]: a merge
//! of the (up to three) shifted copies, each still sorted, so linear and without hashing. Sorted and distinct.
std::vector<std::uint64_t> shift_union(const std::vector<std::uint64_t>& keys, int axis, int lo, int hi,
                                       std::int64_t limit) {
    const int streams = hi - lo + 1;
    const std::uint64_t step = std::uint64_t{1} << (21 * axis);
    std::size_t pos[3] = {0, 0, 0};
    auto coordinate = [&](std::uint64_t key) { return static_cast<std::int64_t>((key >> (21 * axis)) & 0x1fffff); };
    auto valid = [&](int s, std::size_t p) {
        const std::int64_t c = coordinate(keys[p]) + lo + s;
        return c >= 0 && c <= limit;
    };
    for (int s = 0; s < streams; ++s)
        while (pos[s] < keys.size() && !valid(s, pos[s])) ++pos[s];
    std::vector<std::uint64_t> out;
    out.reserve(keys.size() + keys.size() / 2);
    while (true) {
        int best = -1;
        std::uint64_t best_key = 0;
        for (int s = 0; s < streams; ++s) {
            if (pos[s] >= keys.size()) continue;
            const std::uint64_t k = keys[pos[s]] + static_cast<std::uint64_t>(lo + s) * step;
            if (best < 0 || k < best_key) {
                best = s;
                best_key = k;
            }
        }
        if (best < 0) break;
        if (out.empty() || out.back() != best_key) out.push_back(best_key);
        ++pos[best];
        while (pos[best] < keys.size() && !valid(best, pos[best])) ++pos[best];
    }
    return out;
}

//! Every cell of `cells` and its 26 neighbours inside the grid of n cells per axis, sorted (a box dilation is three
//! one-axis dilations).
std::vector<std::uint64_t> dilate(const std::vector<std::uint64_t>& cells, std::int64_t n) {
    std::vector<std::uint64_t> out = shift_union(cells, 0, -1, 1, n - 1);
    out = shift_union(out, 1, -1, 1, n - 1);
    return shift_union(out, 2, -1, 1, n - 1);
}

//! The corners of `cells`, sorted.
std::vector<std::uint64_t> corners(const std::vector<std::uint64_t>& cells) {
    std::vector<std::uint64_t> out = shift_union(cells, 0, 0, 1, 0x1fffff);
    out = shift_union(out, 1, 0, 1, 0x1fffff);
    return shift_union(out, 2, 0, 1, 0x1fffff);
}

}  // namespace

std::uint64_t cell_key(const Vec3& p, int depth) {
    const double n = std::ldexp(1.0, depth);
    std::uint32_t idx[3];
    for (int a = 0; a < 3; ++a) {
        const double v = std::floor(p[a] * n);
        idx[a] = static_cast<std::uint32_t>(std::clamp(v, 0.0, n - 1));
    }
    return pack_key(idx[0], idx[1], idx[2]);
}

std::size_t PoissonOctree::memory_bytes() const {
    std::size_t bytes = 0;
    for (const OctreeLevel& l : levels)
        bytes += l.cells.memory_bytes() + l.dofs.memory_bytes() + l.support_cells.memory_bytes() +
                 l.support_vertices.memory_bytes();
    return bytes;
}

namespace {

//! The active cells of level `depth`: the whole grid on the coarsest level, else the cells holding a sample and
//! their 1-ring.
std::vector<std::uint64_t> active_cells(const std::vector<Vec3>& unit_positions, int depth, bool coarsest) {
    const std::int64_t n = std::int64_t{1} << depth;
    std::vector<std::uint64_t> cells;
    if (coarsest) {
        // the coarsest level is complete, so the reconstructed function is defined on the whole cube
        cells.reserve(static_cast<std::size_t>(n * n * n));
        for (std::int64_t k = 0; k < n; ++k)
            for (std::int64_t j = 0; j < n; ++j)
                for (std::int64_t i = 0; i < n; ++i)
                    cells.push_back(pack_key(static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j),
                                             static_cast<std::uint32_t>(k)));
        return cells;
    }
    // samples in space order (poisson.cpp) come in runs of one cell: keep each run's key, then sort
    std::vector<std::uint64_t> occupied;
    for (const Vec3& p : unit_positions) {
        const std::uint64_t key = cell_key(p, depth);
        if (occupied.empty() || occupied.back() != key) occupied.push_back(key);
    }
    std::sort(occupied.begin(), occupied.end());
    occupied.erase(std::unique(occupied.begin(), occupied.end()), occupied.end());
    return dilate(occupied, n);
}

//! The support sets of a level from its active cells (the larger share of a level's work).
void add_support(OctreeLevel& level, const std::vector<std::uint64_t>& cells) {
    level.support_cells = make_set(dilate(cells, std::int64_t{1} << level.depth));
    level.support_vertices = make_set(corners(level.support_cells.keys));
}

}  // namespace

Result<PoissonOctree> build_octree(const std::vector<Vec3>& unit_positions, int min_depth, int max_depth,
                                   const Cancel& cancel, bool threaded) {
    PoissonOctree tree;
    tree.min_depth = min_depth;
    tree.max_depth = max_depth;
    tree.levels.resize(static_cast<std::size_t>(max_depth - min_depth + 1));
    for (int depth = min_depth; depth <= max_depth; ++depth) tree.levels[std::size_t(depth - min_depth)].depth = depth;
    if (cancel.requested()) return make_error(ErrorCode::Cancelled, "poisson: cancelled while building the octree");
    // the finest level holds most of the cells: its support sets on one part; its dofs and every coarser level on
    // the other (about as much work); each level is built from the samples alone, so the result does not depend on
    // whether the parts run concurrently
    OctreeLevel& finest = tree.levels.back();
    std::vector<std::uint64_t> finest_cells = active_cells(unit_positions, max_depth, max_depth == min_depth);
    bool cancelled = false;
    run_two_parts(threaded, [&](int part) {
        if (part == 0) {
            add_support(finest, finest_cells);
            return;
        }
        finest.dofs = make_set(corners(finest_cells));
        for (int depth = min_depth; depth < max_depth; ++depth) {
            if (cancel.requested()) {
                cancelled = true;
                return;
            }
            OctreeLevel& level = tree.levels[std::size_t(depth - min_depth)];
            std::vector<std::uint64_t> cells = active_cells(unit_positions, depth, depth == min_depth);
            add_support(level, cells);
            level.dofs = make_set(corners(cells));
            level.cells = make_set(std::move(cells), false);  // only ever walked in order
        }
    });
    finest.cells = make_set(std::move(finest_cells), false);
    if (cancelled) return make_error(ErrorCode::Cancelled, "poisson: cancelled while building the octree");
    return tree;
}

}  // namespace surfaced::reconstruct
