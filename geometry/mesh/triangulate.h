#pragma once

#include "geometry/mesh/polygon_mesh.h"

namespace surfaced {

//! Splits every polygon with more than 3 vertices into triangles (fan from the first corner for convex polygons;
//! ear clipping in the polygon's best-fit plane otherwise), carrying uv_indices along. Positions, uvs, normals and
//! vertex order are unchanged; triangles keep the polygon's orientation. Tags are dropped (they describe the
//! polygon mesh). Output has sum(n - 2) triangles.
PolygonMesh triangulate(const PolygonMesh& mesh);

}  // namespace surfaced
