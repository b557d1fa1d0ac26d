// Open seams: boundaries that are only open because their vertices were never welded (a triangle soup, a
// flat-shaded export that gives every face its own corners). Manifold-only operations accept such a mesh, but they
// would treat every face as a separate piece; repair_mesh's weld closes them.
#pragma once

#include <cstddef>

#include "geometry/mesh/polygon_mesh.h"

namespace surfaced {

//! The vertices on boundary edges that exact welding would merge into another vertex on a boundary edge (per group
//! of vertices at one position, the members on boundary edges minus one). 0 for a mesh without coincident vertices,
//! found in about the time of one sort of the positions; the edges are looked at only around coincident vertices.
//! \pre every index names a vertex and positions are finite (validate()).
std::size_t count_open_seam_vertices(const PolygonMesh& mesh);

}  // namespace surfaced
