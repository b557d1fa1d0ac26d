// The sparse octree of the Poisson reconstruction, stored level by level. Coordinates are in the unit cube [0, 1]^3
// (the caller maps its bounding cube onto it). Level d has 2^d cells per axis, cell (i, j, k) covering
// [i, i+1] x [j, j+1] x [k, k+1] * 2^-d, and vertices (i, j, k) with 0 <= i, j, k <= 2^d.
//
// Which cells exist:
//  - the coarsest level (min_depth) is complete;
//  - on a finer level d, the active cells are the cells holding a sample and their 26 neighbours (the 1-ring).
//    The 1-ring of a cell lies inside the 1-ring of its parent, so every active cell's parent is active: the levels
//    form an octree, refined to max_depth around the samples only, whose neighbourhoods are complete (the 2:1-like
//    condition the basis functions need: every function centred on an active cell's corner has its whole support
//    on the level's grid, and every sample's cell has all its neighbours).
// Each level carries four sets, each as a sorted key list with a RowIndex from key to position:
//  - cells: the active cells (without an index: nothing looks them up);
//  - dofs: the corners of the active cells, one trilinear "hat" basis function each (the unknowns of the level);
//  - support cells: the active cells and their 1-ring, i.e. every cell on which a level function is non-zero, and
//    support vertices: their corners, where the solver keeps the values of the reconstructed function. A support
//    cell's parent is a support cell of the coarser level (same argument as above), which is what lets values be
//    carried from one level to the next by trilinear interpolation.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "geometry/core/cancel.h"
#include "geometry/core/result.h"
#include "geometry/core/two_parts.h"
#include "geometry/core/types.h"
#include "geometry/reconstruct/key_map.h"

namespace surfaced::reconstruct {

struct KeySet {
    std::vector<std::uint64_t> keys;  //!< sorted, distinct
    RowIndex index;                   //!< key -> position in keys

    KeySet() = default;
    // the index points into `keys`: a copy or a move re-indexes (a moved vector keeps its buffer, a copy does not)
    KeySet(const KeySet& other) : keys(other.keys) { reindex(other); }
    KeySet(KeySet&& other) noexcept : keys(std::move(other.keys)), index(std::move(other.index)) { index.rebind(keys); }
    KeySet& operator=(const KeySet& other) {
        keys = other.keys;
        reindex(other);
        return *this;
    }
    KeySet& operator=(KeySet&& other) noexcept {
        keys = std::move(other.keys);
        index = std::move(other.index);
        index.rebind(keys);
        return *this;
    }

    std::size_t size() const { return keys.size(); }
    std::uint32_t find(std::uint64_t key) const { return index.find(key); }
    std::size_t memory_bytes() const { return keys.capacity() * 8 + index.memory_bytes(); }

private:
    void reindex(const KeySet& other) {
        index = other.index;
        index.rebind(keys);
    }
};

struct OctreeLevel {
    int depth = 0;
    KeySet cells;
    KeySet dofs;
    KeySet support_cells;
    KeySet support_vertices;
};

struct PoissonOctree {
    int min_depth = 0;
    int max_depth = 0;
    std::vector<OctreeLevel> levels;  //!< levels[d - min_depth]

    const OctreeLevel& level(int depth) const { return levels[static_cast<std::size_t>(depth - min_depth)]; }
    std::size_t memory_bytes() const;
};

//! The cell of level `depth` containing p (unit-cube coordinates, clamped into the cube).
std::uint64_t cell_key(const Vec3& p, int depth);

//! Values at a level's support vertices interpolated to the next finer level's support vertices (a fine vertex is a
//! coarse vertex, or the midpoint of 2, 4 or 8 of them); exact for the coarse level's trilinear functions. T: double
//! or Vec3. Scattered from the coarse vertices, one sorted pass per row offset (b, c): coarse vertex (i, j, k) feeds
//! the fine vertices (2i - 1 .. 2i + 1, 2j + b, 2k + c), consecutive keys that grow with the coarse key; no hashing.
//! Each fine value sums its coarse ones in (k, j, i) order.
//! `out` is resized to the fine level's support vertices (its capacity kept, so a buffer can be reused).
//! `threaded`: the passes in two parts on two threads for a large level (the same sums either way).
template <class T>
void interpolate_to_finer(const OctreeLevel& coarse, const std::vector<T>& coarse_values, const OctreeLevel& fine,
                          std::vector<T>& out, bool threaded = false) {
    out.assign(fine.support_vertices.size(), T{});
    const std::uint32_t limit = std::uint32_t{1} << fine.depth;
    const std::vector<std::uint64_t>& coarse_keys = coarse.support_vertices.keys;
    const std::vector<std::uint64_t>& fine_keys = fine.support_vertices.keys;
    // rows +1, 0, -1 on each axis, k outermost: a fine vertex sums its lower coarse neighbour before the upper.
    // A fine row (J, K) is written by the passes whose offsets have J's and K's parities only, so the passes split
    // into two parts that never write the same row: offsets with equal parities (both even or both odd) and the
    // others; each part keeps the passes' order, so the sums do not depend on whether the parts run concurrently.
    run_two_parts(threaded && coarse_keys.size() >= (std::size_t{1} << 16), [&](int part) {
        for (int oc = 1; oc >= -1; --oc)
            for (int ob = 1; ob >= -1; --ob) {
                if (((ob != 0) == (oc != 0)) != (part == 0)) continue;
                std::size_t position = 0;
                for (std::size_t c = 0; c < coarse_keys.size(); ++c) {
                    const std::uint64_t key = coarse_keys[c];
                    const std::int64_t j = 2 * std::int64_t{key_j(key)} + ob, k = 2 * std::int64_t{key_k(key)} + oc;
                    if (j < 0 || k < 0 || j > limit || k > limit) continue;
                    const std::uint32_t i = 2 * key_i(key);
                    const std::uint64_t centre =
                        pack_key(i, static_cast<std::uint32_t>(j), static_cast<std::uint32_t>(k));
                    const std::uint64_t first = i > 0 ? centre - 1 : centre;
                    while (position < fine_keys.size() && fine_keys[position] < first) ++position;
                    // (2i + 1, ...) with 2i = limit would be i = limit + 1, which no fine key has
                    for (std::size_t u = position; u < fine_keys.size() && fine_keys[u] <= centre + 1; ++u)
                        out[u] += coarse_values[c];
                }
            }
    });
    for (std::size_t u = 0; u < out.size(); ++u) {
        const std::uint64_t key = fine_keys[u];
        const int odd = static_cast<int>(key_i(key) % 2 + key_j(key) % 2 + key_k(key) % 2);
        if (odd > 0) out[u] = out[u] * (odd == 1 ? 0.5 : odd == 2 ? 0.25 : 0.125);
    }
}
template <class T>
std::vector<T> interpolate_to_finer(const OctreeLevel& coarse, const std::vector<T>& coarse_values,
                                    const OctreeLevel& fine, bool threaded = false) {
    std::vector<T> out;
    interpolate_to_finer(coarse, coarse_values, fine, out, threaded);
    return out;
}

//! Builds the octree for samples given in unit-cube coordinates. 1 <= min_depth <= max_depth <= 20.
//! With `threaded`, the finest level's support sets are built on a second thread while its dofs and the coarser
//! levels are built on this one (the same octree either way). Errors: Cancelled.
Result<PoissonOctree> build_octree(const std::vector<Vec3>& unit_positions, int min_depth, int max_depth,
                                   const Cancel& cancel, bool threaded = false);

}  // namespace surfaced::reconstruct
