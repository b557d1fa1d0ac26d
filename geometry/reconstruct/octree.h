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
// Each level carries three sets, each as a sorted key list with a KeyMap from key to position:
//  - cells: the active cells;
//  - dofs: the corners of the active cells, one trilinear "hat" basis function each (the unknowns of the level);
//  - support cells: the active cells and their 1-ring, i.e. every cell on which a level function is non-zero, and
//    support vertices: their corners, where the solver keeps the values of the reconstructed function. A support
//    cell's parent is a support cell of the coarser level (same argument as above), which is what lets values be
//    carried from one level to the next by trilinear interpolation.
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/core/cancel.h"
#include "geometry/core/result.h"
#include "geometry/core/types.h"
#include "geometry/reconstruct/key_map.h"

namespace surfaced::reconstruct {

struct KeySet {
    std::vector<std::uint64_t> keys;  //!< sorted, distinct
    KeyMap index;                     //!< key -> position in keys

    std::size_t size() const { return keys.size(); }
    std::uint32_t find(std::uint64_t key) const { return index.find(key); }
    std::size_t memory_bytes() const { return keys.capacity() * 8 + index.memory_bytes(); }
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

//! Builds the octree for samples given in unit-cube coordinates. 1 <= min_depth <= max_depth <= 20.
//! Errors: Cancelled.
Result<PoissonOctree> build_octree(const std::vector<Vec3>& unit_positions, int min_depth, int max_depth,
                                   const Cancel& cancel);

}  // namespace surfaced::reconstruct
