// The faces the joining steps work on: those of the input that are neither degenerate nor duplicates (repair.h steps 2
// and 3), with their vertices welded, their corner table and their edges.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "geometry/mesh/polygon_mesh.h"
#include "geometry/repair/mesh_edges.h"

namespace surfaced::repair_detail {

struct WorkFaces {
    std::vector<Index> offsets{0};
    std::vector<Index> indices;
    std::vector<Index> source;  //!< input face of each working face
    CornerTable table;          //!< over offsets and indices
    EdgeGroups edges;
    std::size_t degenerate = 0;  //!< input faces dropped: a repeated vertex or zero area
    std::size_t duplicate = 0;   //!< input faces dropped: the vertex set of an earlier face

    WorkFaces() = default;
    WorkFaces(const WorkFaces&) = delete;  // the table points into the vectors
    WorkFaces& operator=(const WorkFaces&) = delete;
    WorkFaces(WorkFaces&&) = default;  // moving a vector keeps its buffer
    WorkFaces& operator=(WorkFaces&&) = default;
};

//! The faces of `mesh` in order, each vertex v replaced by weld[v] (unless `weld` is empty), without the faces that
//! repeat a vertex or have zero area, nor those with the vertex set of an earlier face that is kept. Triangles, nearly
//! every face there is, are compared on the edges: a triangle and its duplicates share every edge, so they are found
//! among the faces of each edge by their third vertex, with no table of vertex sets.
WorkFaces clean_faces(const PolygonMesh& mesh, std::span<const Index> weld);

}  // namespace surfaced::repair_detail
