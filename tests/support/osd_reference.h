// OpenSubdiv Far as the reference: the same refinement our subdivide() does, done by TopologyRefiner +
// PrimvarRefinerReal<double>. Tests and benchmarks only; the service never links OpenSubdiv.
#pragma once

#include <memory>
#include <vector>

#include <opensubdiv/far/topologyRefiner.h>

#include "geometry/mesh/polygon_mesh.h"
#include "geometry/subdivision/subdivide.h"

namespace surfaced::testing {

//! The unrefined Far::TopologyRefiner of `mesh` under `options` (scheme, boundary, creasing, triangle rule, tags,
//! UVs as face-varying channel 0); null when OpenSubdiv rejects the mesh.
std::unique_ptr<OpenSubdiv::Far::TopologyRefiner> make_refiner(const PolygonMesh& mesh,
                                                               const SubdivisionOptions& options);

//! Uniformly refines `mesh` with OpenSubdiv Far and returns the last level (positions in double precision).
PolygonMesh osd_subdivide(const PolygonMesh& mesh, const SubdivisionOptions& options);

struct OsdLimit {
    std::vector<Vec3> positions;
    std::vector<Vec3> normals;  //!< normalize(tan1 x tan2)
};
//! Refines uniformly to `at_level` and applies PrimvarRefiner::Limit there; returns the first `count` vertices.
OsdLimit osd_limit(const PolygonMesh& mesh, const SubdivisionOptions& options, int at_level, std::size_t count);

}  // namespace surfaced::testing
