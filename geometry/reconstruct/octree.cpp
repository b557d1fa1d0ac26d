#include "geometry/reconstruct/octree.h"

#include <algorithm>
#include <cmath>

namespace surfaced::reconstruct {
namespace {

KeySet make_set(std::vector<std::uint64_t> keys) {  // keys sorted and distinct
    KeySet set;
    set.keys = std::move(keys);
    set.index.assign(set.keys);
    return set;
}

//! Every cell of `cells` and its 26 neighbours inside the grid of n cells per axis, sorted.
std::vector<std::uint64_t> dilate(const std::vector<std::uint64_t>& cells, std::int64_t n) {
    KeyCollector out;
    for (const std::uint64_t key : cells) {
        const std::int64_t i = key_i(key), j = key_j(key), k = key_k(key);
        for (std::int64_t dk = -1; dk <= 1; ++dk)
            for (std::int64_t dj = -1; dj <= 1; ++dj)
                for (std::int64_t di = -1; di <= 1; ++di) {
                    const std::int64_t a = i + di, b = j + dj, c = k + dk;
                    if (a < 0 || b < 0 || c < 0 || a >= n || b >= n || c >= n) continue;
                    out.insert(pack_key(static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b),
                                        static_cast<std::uint32_t>(c)));
                }
    }
    return out.take();
}

//! The corners of `cells`, sorted.
std::vector<std::uint64_t> corners(const std::vector<std::uint64_t>& cells) {
    KeyCollector out;
    for (const std::uint64_t key : cells) {
        const std::uint32_t i = key_i(key), j = key_j(key), k = key_k(key);
        for (std::uint32_t c = 0; c < 8; ++c) out.insert(pack_key(i + (c & 1), j + ((c >> 1) & 1), k + (c >> 2)));
    }
    return out.take();
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

Result<PoissonOctree> build_octree(const std::vector<Vec3>& unit_positions, int min_depth, int max_depth,
                                   const Cancel& cancel) {
    PoissonOctree tree;
    tree.min_depth = min_depth;
    tree.max_depth = max_depth;
    for (int depth = min_depth; depth <= max_depth; ++depth) {
        if (cancel.requested()) return make_error(ErrorCode::Cancelled, "poisson: cancelled while building the octree");
        const std::int64_t n = std::int64_t{1} << depth;
        OctreeLevel level;
        level.depth = depth;
        std::vector<std::uint64_t> cells;
        if (depth == min_depth) {
            // the coarsest level is complete, so the reconstructed function is defined on the whole cube
            cells.reserve(static_cast<std::size_t>(n * n * n));
            for (std::int64_t k = 0; k < n; ++k)
                for (std::int64_t j = 0; j < n; ++j)
                    for (std::int64_t i = 0; i < n; ++i)
                        cells.push_back(pack_key(static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j),
                                                 static_cast<std::uint32_t>(k)));
        } else {
            KeyCollector occupied;
            for (const Vec3& p : unit_positions) occupied.insert(cell_key(p, depth));
            cells = dilate(occupied.take(), n);
        }
        level.support_cells = make_set(dilate(cells, n));
        level.support_vertices = make_set(corners(level.support_cells.keys));
        level.dofs = make_set(corners(cells));
        level.cells = make_set(std::move(cells));
        tree.levels.push_back(std::move(level));
    }
    return tree;
}

}  // namespace surfaced::reconstruct
