// Uniform subdivision: Catmull-Clark and Loop, our own implementation of OpenSubdiv's (Sdc) rules.
//
// References: E. Catmull, J. Clark, "Recursively generated B-spline surfaces on arbitrary topological meshes", 1978.
//             C. Loop, "Smooth subdivision surfaces based on triangles", MS thesis, 1987.
//             OpenSubdiv 3 documentation, "Subdivision Surfaces" (Sdc options, boundary interpolation).
#pragma once

#include <cstdint>

#include "geometry/core/cancel.h"
#include "geometry/core/result.h"
#include "geometry/mesh/polygon_mesh.h"

namespace surfaced {

enum class SubdivisionScheme { CatmullClark, Loop };

//! Loop's smooth vertex weights.
enum class LoopWeights {
    Loop,    //!< Loop's original beta, as OpenSubdiv (default)
    Warren,  //!< Warren's 3/(8n): a slightly different surface, does NOT match OpenSubdiv
};

//! How semi-sharp edge sharpness decays from level to level (OpenSubdiv's Sdc::Options::CreasingMethod).
enum class CreaseMethod {
    Uniform,  //!< CREASE_UNIFORM: every child edge gets sharpness - 1
    Chaikin,  //!< CREASE_CHAIKIN: 3/4 own + 1/4 the average of the other semi-sharp edges at the end vertex, - 1
};

//! Catmull-Clark edge rule next to triangles (OpenSubdiv's Sdc::Options::TriangleSubdivision).
enum class TriangleRule {
    Catmark,  //!< TRI_SUB_CATMARK: the ordinary rule
    Smooth,   //!< TRI_SUB_SMOOTH: modified edge weights next to triangles, for rounder results
};

//! How face-varying data (texture coordinates) is interpolated: OpenSubdiv's Sdc::Options::FVarLinearInterpolation.
//! "Linear" parts keep their values (corners) or interpolate linearly (boundaries); the rest is smoothed like
//! positions, treating UV seams as boundaries of the UV layout.
enum class UvInterpolation {
    None,          //!< FVAR_LINEAR_NONE: smooth everywhere, seams as smooth boundary curves
    CornersOnly,   //!< FVAR_LINEAR_CORNERS_ONLY: keep UV corners (a UV region with one face at a vertex)
    CornersPlus1,  //!< FVAR_LINEAR_CORNERS_PLUS1: also junctions where three or more UV regions meet (USD default)
    CornersPlus2,  //!< FVAR_LINEAR_CORNERS_PLUS2: also darts and a region's neighbour at a corner
    Boundaries,    //!< FVAR_LINEAR_BOUNDARIES: linear along seams and boundaries, smooth inside
    All,           //!< FVAR_LINEAR_ALL: bilinear everywhere
};

struct SubdivisionOptions {
    SubdivisionScheme scheme = SubdivisionScheme::CatmullClark;
    int levels = 1;  //!< uniform refinement levels, >= 0
    //! Boundary rule. When `use_mesh_boundary_tag` is true and the mesh carries `tags.boundary`, that wins.
    BoundaryInterpolation boundary = BoundaryInterpolation::EdgeOnly;
    bool use_mesh_boundary_tag = true;
    CreaseMethod crease_method = CreaseMethod::Uniform;
    TriangleRule triangle_rule = TriangleRule::Catmark;  //!< Catmull-Clark only
    LoopWeights loop_weights = LoopWeights::Loop;        //!< Loop only
    //! Apply mesh.tags creases (edge sharpness), corners (vertex sharpness) and holes. Sharpness >= 10 is infinite.
    bool use_mesh_tags = true;
    //! Project the refined vertices onto the limit surface and return exact limit normals (from limit tangents)
    //! in mesh.normals. Where a semi-sharp feature has not decayed at `levels` (sharpness > levels), the limit is
    //! taken after refining past it, so it is exact there too (OpenSubdiv's PrimvarRefiner::Limit is not).
    bool limit_surface = false;
    //! Texture coordinates (mesh.uvs/uv_indices, when present) are refined with this rule and returned face-varying.
    //! With limit_surface they are the refined values (not projected to their limit).
    UvInterpolation uv_interpolation = UvInterpolation::CornersPlus1;
    //! 1: refine on the calling thread; anything else: use a second thread for large levels (0 = decide). The
    //! result is bit-identical either way.
    int threads = 1;
    //! Polled before each level's topology, positions and sharpness; when it fires the result is Cancelled.
    Cancel cancel;
};

//! Sharpness at or above this is infinitely sharp (OpenSubdiv's Sdc::Crease::SHARPNESS_INFINITE).
inline constexpr float kInfiniteSharpness = 10.0f;

//! Refines `mesh` uniformly `options.levels` times.
//!
//! Output order matches OpenSubdiv Far's uniform refinement with default options (TopologyRefiner::RefineUniform,
//! orderVerticesFromFacesFirst = false): per level, child vertices of parent vertices first, then of faces, then of
//! edges; child faces grouped by parent face in parent order.
//!
//! \pre validate_for_subdivision(mesh) succeeded (the function validates anyway and returns its error); faces that
//! repeat a vertex are refined as OpenSubdiv refines them.
//! Hole faces (mesh.tags.holes) stay in the topology (they shape their neighbours) but their children are not
//! output; vertices keep OpenSubdiv's numbering, so a vertex used only by holes is still present.
//! \return the refined mesh, or NotTriangleMesh (Loop on a non-triangle, naming the face), InvalidArgument (a crease
//!         between vertices that share no edge), InvalidArgument (levels < 0), BudgetExceeded (over 2^32 indices),
//!         Cancelled (options.cancel fired).
//! Worst case output: predicted_face_count(mesh, scheme, levels) faces.
Result<PolygonMesh> subdivide(const PolygonMesh& mesh, const SubdivisionOptions& options);

//! The input check `subdivide` applies: validate()'s checks (offsets, at least 3 vertices per face, indices in range,
//! finite coordinates, attribute sizes, tag indices and sharpness), except that a face may use a vertex more than once
//! (`[0, 1, 2, 2]`). OpenSubdiv refines such faces, and so do we: a corner followed by the same vertex gets a
//! degenerate edge of its own, an edge a face uses twice gets a second instance, and both are non-manifold
//! (infinitely sharp, their vertices sharpened). The error names the face, vertex or tag (GeoError::element).
Status validate_for_subdivision(const PolygonMesh& mesh);

//! Number of faces `subdivide` will produce, without refining (saturates at UINT64_MAX). Used for budgets.
std::uint64_t predicted_face_count(const PolygonMesh& mesh, SubdivisionScheme scheme, int levels);

//! Extra levels `subdivide` refines internally to evaluate the limit surface exactly (0 when limit_surface is off):
//! enough for every semi-sharp sharpness to decay, and one for Catmull-Clark at level 0 with non-quads.
//! The work is that of subdividing to levels + this; budgets should use predicted_face_count at that level.
int limit_extra_levels(const PolygonMesh& mesh, const SubdivisionOptions& options);

//! Number of vertices the refined mesh will have (exact for manifold input; an upper bound otherwise).
std::uint64_t predicted_vertex_count(const PolygonMesh& mesh, SubdivisionScheme scheme, int levels);

}  // namespace surfaced
