// Small meshes built in code, for tests, examples and the service's built-in samples.
#pragma once

#include "geometry/mesh/polygon_mesh.h"

namespace surfaced::shapes {

PolygonMesh cube();         //!< 8 vertices, 6 quads, outward, unit cube centred at origin
PolygonMesh tetrahedron();  //!< 4 triangles, closed
PolygonMesh octahedron();   //!< 8 triangles, closed
PolygonMesh icosahedron();  //!< 12 vertices, 20 triangles, on the unit sphere
//! (nx x ny) quads on [0,1]^2 at z = 0 (open, one boundary loop); `triangles` splits each quad in two.
PolygonMesh grid(int nx, int ny, bool triangles = false);
//! Torus-like quad mesh with `n` x `m` quads, radii R, r; all vertices valence 4.
PolygonMesh torus(int n, int m, double R = 1.0, double r = 0.35);
//! Torus of 3x... quads with some quads merged/split so that it has valence-3 and valence-5 vertices.
PolygonMesh irregular_torus();
//! A closed mesh mixing triangles, quads and a pentagon (a "house": cube with a pyramid roof and split faces).
PolygonMesh mixed_polygons();
//! An open surface with several boundary loops: a grid with two holes cut out.
PolygonMesh grid_with_holes();

}  // namespace surfaced::shapes
