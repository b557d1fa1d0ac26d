// Closing small holes of a manifold, consistently oriented mesh with triangles.
#pragma once

#include <cstddef>
#include <span>

#include "geometry/mesh/polygon_mesh.h"

namespace surfaced::repair_detail {

struct HoleFill {
    std::size_t holes = 0;  //!< boundary loops closed
    std::size_t faces = 0;  //!< triangles added (appended after the mesh's faces)
};

//! Closes every boundary loop of at most `max_edges` edges whose projection onto its best-fit plane (the Newell normal
//! of the loop) is a simple polygon, by ear clipping there. A loop is left open when the projection is not simple,
//! ear clipping finds no strictly convex ear, a triangle would have zero area, or a triangle edge would lie on an
//! edge of the mesh other than the loop's own: vertices with the same `place` (same position: copies of one vertex)
//! count as one there, so a filled triangle never coincides with a face or edge of the mesh. A loop that borders a
//! single triangle is left open too (closing it would duplicate the triangle). The triangles
//! wind against the loop, so the mesh stays consistently oriented; with uvs, each triangle corner takes the uv of the
//! boundary corner at its vertex. Work per loop O(n^2) to O(n^3) in its edge count n.
//! \pre every edge has at most two faces, in opposite directions, and every vertex is one fan.
//! `place`: one entry per vertex.
HoleFill fill_holes(PolygonMesh& mesh, std::size_t max_edges, std::span<const Index> place);

}  // namespace surfaced::repair_detail
