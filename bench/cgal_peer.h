// CGAL's Garland-Heckbert edge-collapse simplification as a benchmark peer, behind a plain C++ interface so that
// CGAL's (and Boost's and Eigen's) heavy headers are compiled in one translation unit only (cgal_peer.cpp). Bench only:
// never linked into the service.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace surfaced::bench {

struct CgalSimplifyResult {
    std::vector<double> positions;    //!< x, y, z per vertex (only the vertices still used)
    std::vector<unsigned> triangles;  //!< three indices into positions per triangle
    double seconds = 0;               //!< arrays in to arrays out: build the CGAL::Surface_mesh, collapse, extract
    double collapse_seconds = 0;      //!< edge_collapse() alone (includes the quadric initialisation)
    std::size_t rejected_faces = 0;   //!< input triangles Surface_mesh::add_face refused (non-manifold there)
    std::string error;                //!< empty on success
};

//! Simplifies the triangles (x, y, z per vertex; three indices per triangle) to at most `target_faces` triangles with
//! CGAL::Surface_mesh_simplification::edge_collapse and GarlandHeckbert_plane_policies (classic plane quadrics,
//! boundary edges weighted by CGAL's default discontinuity multiplier) on a CGAL::Surface_mesh over
//! Simple_cartesian<double>, stopping on the face count.
CgalSimplifyResult cgal_simplify(const std::vector<double>& positions, const std::vector<unsigned>& triangles,
                                 std::size_t target_faces);

//! CGAL's version string ("5.5.1").
std::string cgal_version();

}  // namespace surfaced::bench
