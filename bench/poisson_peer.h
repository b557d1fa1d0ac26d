// CGAL 5.5's Poisson surface reconstruction (Kazhdan et al. 2006 on a Delaunay refinement, meshed by CGAL's
// surface mesher), as the peer of bench/poisson_bench.cpp. CGAL's headers compile in poisson_cgal_peer.cpp only.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace surfaced::bench {

struct CgalPoissonResult {
    std::vector<double> positions;    //!< x, y, z per vertex
    std::vector<unsigned> triangles;  //!< three vertex indices per triangle
    double average_spacing = 0;       //!< CGAL's compute_average_spacing over 6 neighbours: the size parameter
    std::string error;                //!< empty on success
};

//! points and normals: x, y, z per point. sm_radius and sm_distance: CGAL's surface-mesh criteria, relative to the
//! average spacing (CGAL's defaults 30 and 0.375).
CgalPoissonResult cgal_poisson(const std::vector<double>& points, const std::vector<double>& normals, double sm_radius,
                               double sm_distance);

}  // namespace surfaced::bench
