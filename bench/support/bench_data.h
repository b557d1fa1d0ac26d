// Meshes several benchmarks load or build: the Stanford bunny of tests/data/bunny, OpenSubdiv's regression shapes of
// tests/data/opensubdiv-shapes, and icospheres.
#pragma once

#include <string>

#include "geometry/mesh/polygon_mesh.h"

namespace surfaced::bench {

//! The bunny in the repository (34,835 vertices, 69,666 triangles).
inline constexpr const char* kBunnyPath = SURFACED_SOURCE_DIR "/tests/data/bunny/bunny.obj";

//! The bunny, or an empty mesh (and a line on stderr) when the file is missing or unreadable.
PolygonMesh read_bunny();

//! OpenSubdiv's regression shape `name` (tests/data/opensubdiv-shapes/NAME.obj, with its crease and corner tags), or
//! an empty mesh (and a line on stderr) when the file is missing or unreadable.
PolygonMesh read_opensubdiv_shape(const std::string& name);

//! The icosahedron Loop-subdivided `levels` times and projected on the unit sphere (20 * 4^levels triangles).
PolygonMesh icosphere(int levels);

}  // namespace surfaced::bench
