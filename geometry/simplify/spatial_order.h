// Vertex numbering in Morton (Z-curve) order of the positions (internal to geometry/simplify): the simplifier numbers
// its vertices so that one-rings lie close together in memory, and, with two threads, so that each half of the
// numbers is one spatial half of the mesh.
#pragma once

#include <vector>

#include "geometry/core/types.h"

namespace surfaced::simplify_detail {

//! A vertex numbering in Morton order of the positions on a 1024^3 grid over their bounds: rank[v] is the new number
//! of vertex v. Collapses visit vertices in heap order, all over the mesh, but each one reads a one-ring, and in this
//! order a one-ring's records lie close together (about 10% fewer cache misses on the bunny and the icosphere, whose
//! subdivision numbering puts neighbours far apart). Radix sort: linear time.
//! `halves`: the first n / 2 numbers go to the vertices below the median plane across the longest side of the bounds
//! (to 1/1024 of it; within that slab by input number), each half in Morton order: the simplifier's two regions are
//! cut there, and a plane crosses fewer faces than the Morton order's own midpoint does (564 against 1,273 on the
//! bunny).
std::vector<Index> spatial_order(const std::vector<Vec3>& positions, bool halves);

}  // namespace surfaced::simplify_detail
