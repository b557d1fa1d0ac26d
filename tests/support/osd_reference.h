// OpenSubdiv Far as the reference: the same refinement our subdivide() does, done by TopologyRefiner +
// PrimvarRefinerReal<double>. Tests and benchmarks only; the service never links OpenSubdiv.
#pragma once

#include <vector>

#include "geometry/mesh/polygon_mesh.h"
#include "geometry/subdivision/subdivide.h"

namespace surfaced::testing {

//! Uniformly refines `mesh` with OpenSubdiv Far and returns the last level (positions in double precision).
PolygonMesh osd_subdivide(const PolygonMesh& mesh, const SubdivisionOptions& options);

struct OsdLimit {
    std::vector<Vec3> positions;
    std::vector<Vec3> normals;  //!< normalize(tan1 x tan2)
};
//! Refines uniformly to `at_level` and applies PrimvarRefiner::Limit there; returns the first `count` vertices.
OsdLimit osd_limit(const PolygonMesh& mesh, const SubdivisionOptions& options, int at_level, std::size_t count);

}  // namespace surfaced::testing
