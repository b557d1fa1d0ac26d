// The iso-surface chi = iso of the solved indicator function (solver.h), meshed on the finest level's grid
// (2^max_depth cells per side) without a dense grid: only the grid cells the surface can cross are visited.
//
// Where chi is known cheaply: at the finest level's support vertices chi is stored (IndicatorValues), and inside a
// support cell of level d that has no support child chi is the trilinear interpolant of level d's values at its
// corners (a "leaf"). So the finest cells whose corners change sign are found in two ways:
//  1. the finest level's support vertices are scanned in key order, each with its +x, +y and +z neighbours (found
//     by walking the sorted keys, no hashing); an edge whose ends differ in sign gives the four cells around it;
//  2. the finest cells outside the finest level's support lie in the non-support children of coarser leaves, where
//     chi is one trilinear function: such a child is subdivided down to finest cells, skipping every sub-cube whose
//     corners (interpolated from the leaf's, with a rounding margin) share one sign, since a trilinear function lies
//     between its corner values. So coarse regions are meshed at the finest resolution too, and there is no level
//     transition to stitch.
// Each cell found is then meshed by marching cubes: a vertex on every grid edge whose ends differ in sign, keyed by
// the edge, at the crossing of the linear interpolation of the end values (exact: chi is linear along every grid
// edge); on each cell face the crossings are joined into segments, a face with four crossings resolved by the
// asymptotic decider on the face's four values (so the two cells sharing a face agree); the segments, oriented with
// the inside on their right seen from outside the cell, form loops, each a polygon triangulated inside the cell
// (3 vertices: a triangle; 4: along the shorter diagonal; more: a fan around the loop's centroid, a vertex of its
// own). Every grid node has one value (the stored one, or the interpolant of the finest leaf containing it,
// computed once in each half of the cells, the same in both), so cells sharing a face or an edge see the same signs
// and the same vertices (the halves' vertices on shared edges are merged by edge): the output is closed,
// every edge is shared by two triangles traversing it in opposite directions, every vertex has one fan, and the
// triangles' normals point to chi > iso (out of the sampled solid). Grid nodes on the cube's faces count as
// outside, so a surface leaving the cube is closed by caps on its faces.
//
// Work and memory grow with the surface (cells crossed and their neighbours), not with the cube's volume.
#pragma once

#include <cstdint>

#include "geometry/core/cancel.h"
#include "geometry/core/result.h"
#include "geometry/mesh/polygon_mesh.h"
#include "geometry/reconstruct/octree.h"
#include "geometry/reconstruct/solver.h"

namespace surfaced::reconstruct {

struct ExtractionStats {
    std::uint64_t candidate_cells = 0;     //!< finest cells examined
    std::uint64_t surface_cells = 0;       //!< of which the surface crosses
    std::uint64_t interpolated_nodes = 0;  //!< node values interpolated from a coarser leaf (not stored)
    std::uint64_t bytes = 0;               //!< peak of the extraction's own tables (the mesh excluded)
};

//! Meshes chi = iso on the finest level (see the top of this file); positions are in the octree's unit cube.
//! `threaded`: the marching cubes of the two halves of the cells on two threads (the same mesh either way).
//! Errors: Cancelled (polled between blocks of cells).
Result<PolygonMesh> extract_surface(const PoissonOctree& tree, const IndicatorValues& chi, double iso,
                                    const Cancel& cancel, ExtractionStats* stats = nullptr, bool threaded = false);

}  // namespace surfaced::reconstruct
