#pragma once

#include <vector>

#include "geometry/core/types.h"
#include "geometry/mesh/polygon_mesh.h"

namespace surfaced {

//! Area-weighted vertex normals (sum of polygon vector areas of incident faces, Newell's method), unit length.
//! A vertex with no incident face or zero total area gets (0, 0, 1). Size = mesh.vertex_count().
std::vector<Vec3> compute_vertex_normals(const PolygonMesh& mesh);

}  // namespace surfaced
