// Vertex welding for repair_mesh: which vertex each vertex merges into.
#pragma once

#include <span>
#include <vector>

#include "geometry/core/types.h"

namespace surfaced::repair_detail {

//! For each vertex, the vertex it merges into: itself when it stays, otherwise a lower index. With tolerance 0,
//! vertices with exactly equal coordinates (0.0 == -0.0) merge into the first of them. With tolerance > 0, vertices
//! are visited in index order and each merges into the lowest-indexed kept vertex within `tolerance` (Euclidean,
//! inclusive), or is kept; kept vertices are therefore more than `tolerance` apart, and a merged vertex is within
//! `tolerance` of its target (not necessarily of every other vertex merged into it). Expected linear time (a hash of
//! positions, or of grid cells `tolerance` wide). Positions must be finite.
std::vector<Index> weld_targets(std::span<const Vec3> positions, double tolerance);

}  // namespace surfaced::repair_detail
