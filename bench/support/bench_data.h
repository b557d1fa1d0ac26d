// Meshes several benchmarks load or build: the Stanford bunny that Debian's glmark2-data ships, and icospheres.
#pragma once

#include "geometry/mesh/polygon_mesh.h"

namespace surfaced::bench {

//! Where Debian's glmark2-data installs the bunny (34,834 vertices, 69,451 triangles).
inline constexpr const char* kBunnyPath = "/usr/share/glmark2/models/bunny.obj";

//! The bunny, or an empty mesh (and a line on stderr) when the file is missing or unreadable.
PolygonMesh read_bunny();

//! The icosahedron Loop-subdivided `levels` times and projected on the unit sphere (20 * 4^levels triangles).
PolygonMesh icosphere(int levels);

}  // namespace surfaced::bench
