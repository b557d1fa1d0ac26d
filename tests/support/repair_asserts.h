// What a repaired mesh must satisfy (geometry/repair/repair.h's guarantees), checked with plain maps, independently
// of geometry/repair: shared by the repair tests on meshes built in code and on the file corpus.
#pragma once

#include <array>
#include <cstddef>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "geometry/mesh/polygon_mesh.h"
#include "geometry/repair/repair.h"

namespace surfaced::testing {

//! Undirected edge (lower index first) -> the faces that use it.
using EdgeFaces = std::map<std::pair<Index, Index>, std::vector<std::size_t>>;
EdgeFaces faces_by_edge(const PolygonMesh& mesh);

//! Vertices whose faces do not form one fan (connected through shared edges at the vertex).
std::size_t multi_fan_vertices(const PolygonMesh& mesh, const EdgeFaces& edges);
//! Faces with a repeated vertex or a zero vector area.
std::size_t zero_area_faces(const PolygonMesh& mesh);
//! Faces with the same vertex set as an earlier face.
std::size_t same_vertex_set_faces(const PolygonMesh& mesh);
//! Directed edges (a -> b) that more than one face traverses.
std::size_t repeated_directed_edges(const PolygonMesh& mesh);
//! Signed volumes of the closed components (faces connected through shared edges, no boundary edge).
std::vector<double> closed_component_volumes(const PolygonMesh& mesh, const EdgeFaces& edges);

//! Everything repair_mesh guarantees. `oriented`: the outward check applies (RepairOptions::orient).
void expect_repaired(const PolygonMesh& mesh, bool oriented = true);
//! The counts relate input and output sizes as repair.h says.
void expect_counts_add_up(const PolygonMesh& in, const RepairResult& result);

//! A face as its corner positions, rotated to start at the smallest (a face up to its starting corner).
using FaceCorners = std::vector<std::array<double, 3>>;
FaceCorners corner_positions(const PolygonMesh& mesh, std::size_t f);
//! Every face of the mesh as corner_positions: the surface, whatever the vertex numbering. `ignore_winding`: each
//! face also up to its direction (the smaller of the two rotated corner lists).
std::multiset<FaceCorners> surface_faces(const PolygonMesh& mesh, bool ignore_winding = false);

}  // namespace surfaced::testing
