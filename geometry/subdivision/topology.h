// Refinement topology: OpenSubdiv Vtr-style relation tables (face-vertices, face-edges, edge-vertices), built once for
// the base mesh and then level by level. Internal to geometry/subdivision.
//
// Numbering follows OpenSubdiv Far with default options so that our output can be compared index for index:
//  * base level: edges in order of first appearance walking faces and their corners, oriented as first walked;
//  * child vertices: from parent vertices, then from faces (Catmull-Clark only), then from edges;
//  * child edges: from faces first (Catmull-Clark: (face point, edge point j); Loop: (edge point j, edge point j-1)),
//    then two per parent edge, (edge point, child of edge vertex 0) and (edge point, child of edge vertex 1);
//  * child faces: grouped by parent face, one per corner (Loop: three corners, then the middle triangle).
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/core/result.h"
#include "geometry/core/types.h"
#include "geometry/mesh/polygon_mesh.h"

namespace surfaced::subdivision {

struct Level {
    Index vertex_count = 0;
    std::vector<Index> face_offsets{0};  //!< size face_count + 1
    std::vector<Index> face_verts;
    std::vector<Index> face_edges;       //!< edge j of a face joins corners j and j+1; parallels face_verts
    std::vector<Index> edge_verts;       //!< two per edge

    Index face_count() const { return static_cast<Index>(face_offsets.size() - 1); }
    Index edge_count() const { return static_cast<Index>(edge_verts.size() / 2); }
};

//! Builds the base level from a validated mesh (edges by first appearance, as OpenSubdiv does).
Level build_base_level(const PolygonMesh& mesh);

//! Child topology of one uniform Catmull-Clark (quad split) or Loop (triangle split) step.
//! `with_edges` = false leaves face_edges/edge_verts empty (enough for the last level).
//! `threaded`: the face and edge loops may run on two threads (results do not depend on it).
Level refine_quads(const Level& parent, bool with_edges, bool threaded = false);
Level refine_triangles(const Level& parent, bool with_edges, bool threaded = false);


}  // namespace surfaced::subdivision
