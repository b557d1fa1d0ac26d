// Mesh invariants used across tests.
#pragma once

#include <cstdint>
#include <string>

#include "geometry/mesh/polygon_mesh.h"

namespace surfaced::testing {

struct EdgeStats {
    std::size_t edges = 0;
    std::size_t boundary_edges = 0;      //!< used by one face
    std::size_t non_manifold_edges = 0;  //!< used by more than two faces
    std::size_t inconsistent_edges = 0;  //!< two faces traverse it in the same direction (orientation flip)
};
EdgeStats edge_stats(const PolygonMesh& mesh);

//! V - E + F.
std::int64_t euler_characteristic(const PolygonMesh& mesh);
//! Number of boundary loops (connected chains of boundary edges).
std::size_t boundary_loop_count(const PolygonMesh& mesh);
//! Closed, manifold, consistently oriented.
bool is_watertight(const PolygonMesh& mesh);
//! Signed volume by the divergence theorem (fan-triangulated faces).
double signed_volume(const PolygonMesh& mesh);
//! Vertices of a triangle mesh whose faces do not form a single fan (the faces around the vertex, joined across the
//! edges at it, are not one cycle or open chain), plus vertices no face uses. 0 for a manifold mesh.
std::size_t non_manifold_vertices(const PolygonMesh& mesh);
//! Reads a file into a string (binary); fails the test (ADD_FAILURE) and returns "" when missing.
std::string read_file(const std::string& path);

}  // namespace surfaced::testing
