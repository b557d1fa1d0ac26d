// OpenSubdiv Far as the reference: the same refinement our subdivide() does, done by TopologyRefiner +
// PrimvarRefinerReal<double>. Tests and benchmarks only; the service never links OpenSubdiv.
#pragma once

#include "geometry/mesh/polygon_mesh.h"
#include "geometry/subdivision/subdivide.h"

namespace surfaced::testing {

//! Uniformly refines `mesh` with OpenSubdiv Far and returns the last level (positions in double precision).
PolygonMesh osd_subdivide(const PolygonMesh& mesh, const SubdivisionOptions& options);

}  // namespace surfaced::testing
