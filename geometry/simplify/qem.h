// Mesh simplification by quadric-error edge collapse.
//
// References: M. Garland, P. Heckbert, "Surface Simplification Using Quadric Error Metrics", SIGGRAPH 1997.
//             M. Garland, P. Heckbert, "Simplifying Surfaces with Color and Texture using Quadric Error Metrics",
//               IEEE Visualization 1998 (boundary constraint planes, sec. 4).
//             T. Dey, H. Edelsbrunner, S. Guha, D. Nekhayev, "Topology Preserving Edge Contraction", 1999 (the link
//               condition).
//             P. Lindstrom, G. Turk, "Fast and Memory Efficient Polygonal Simplification", IEEE Visualization 1998
//               (volume preservation: restore_volume).
//             H. Hoppe, "New Quadric Metric for Simplifying Meshes with Appearance Attributes", 1999 (why attributes
//               are interpolated rather than left at one endpoint).
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "geometry/core/cancel.h"
#include "geometry/core/result.h"
#include "geometry/mesh/polygon_mesh.h"

namespace surfaced {

class BlockPool;  // geometry/core/block_pool.h

struct SimplifyOptions {
    //! Stop criteria; simplification stops at whichever is reached first. At least one must be set.
    std::optional<std::size_t> target_faces;  //!< stop at <= this many triangles
    std::optional<double> ratio;              //!< stop at <= ratio * input triangles; in (0, 1]
    //! Absolute distance (mesh units). The output's symmetric Hausdorff distance to the input, as measured by
    //! mesh_distance() with its default sampling, is <= max_error: collapses whose quadric estimate exceeds the
    //! current threshold are skipped, and when the measured distance is still above max_error the simplification is
    //! redone with a lower threshold (at most a few times; in the end the input itself qualifies).
    std::optional<double> max_error;
    //! Boundary vertices never move and boundary edges are never collapsed: every boundary loop keeps its vertices,
    //! in order, at their positions. Otherwise boundaries are kept by constraint planes (Garland-Heckbert 1998).
    bool lock_border = false;
    //! Weight of a boundary constraint plane, relative to the squared length of its edge (only without lock_border).
    double boundary_weight = 100.0;
    //! Vertices that never move or disappear (indices into the input's positions).
    std::vector<Index> locked_vertices;
    //! Volume restoration (after Lindstrom-Turk 1998), in [0, 1]; 0 (the default) is plain Garland-Heckbert. On a
    //! convex surface the quadric minimum keeps each vertex on the surface while the coarser triangles between them
    //! sag inside, so the output is biased inwards (outwards where concave); each collapse's placement is moved along
    //! A^-1 g, the path of the quadric's minimum under a volume constraint, this fraction of the way to the point
    //! that leaves the volume under the edge's two fans unchanged. 1 keeps the volume (mean signed distance near 0,
    //! lowest RMS distance, but vertices then stand out by the chords' mean sag: Hausdorff grows); 0.5 gives 0.8-0.96
    //! times the RMS distance of 0 on the bench meshes with about the same or a lower Hausdorff distance there
    //! (higher on some coarse outputs). Either costs 0-14% more time. Interior edges only (a fan at a
    //! boundary is not closed).
    double restore_volume = 0;
    //! 1 (the default): one thread. 2 or more: a mesh of 20,000 triangles or more first collapses on two threads,
    //! one spatial half each, in cost order across both to within a factor of two, until the faces on the cut
    //! between the halves plus 5% of the way to the target are left; those then collapse in global order. The result depends only on the mesh and the options (not on timing, nor on whether a second
    //! thread could be started), and is close to but not the same as one thread's.
    int threads = 1;
    //! Polled every few thousand collapse candidates and between max_error attempts; when it fires the result is
    //! Cancelled.
    Cancel cancel;
    //! Not owned; may be shared by concurrent calls. Large arrays (1 MiB or more) are taken from and returned to this
    //! pool, so that repeated simplifications reuse memory whose pages are already faulted in instead of paying the
    //! page faults again. nullptr: every array is allocated and freed per call.
    BlockPool* block_pool = nullptr;
};

struct SimplifyResult {
    PolygonMesh mesh;       //!< triangles; uvs and normals interpolated when the input had them; no tags
    std::size_t faces = 0;  //!< mesh.face_count()
    //! With max_error: the measured symmetric Hausdorff distance to the input (<= max_error). Without: the largest
    //! quadric estimate of the collapses performed, sqrt(Q(p) / sum of plane weights) (an area-weighted RMS distance
    //! to the merged planes; 0 when nothing was collapsed). Absolute, in mesh units.
    double achieved_error = 0;
    double relative_error = 0;    //!< achieved_error / the input's bounding-box diagonal
    bool triangulated = false;    //!< the input had polygons with more than 3 vertices and was triangulated first
    bool error_measured = false;  //!< achieved_error is a measured Hausdorff distance (max_error was given)
};

//! Simplifies a mesh by collapsing edges in order of quadric error, each to the point minimising the sum of the
//! quadrics of its endpoints (Garland-Heckbert), or, when that 3x3 system is singular, to the best of the endpoints,
//! the midpoint and the minimum along the edge.
//!
//! Guarantees on the output, for manifold, consistently oriented input:
//!  * no collapse creates a non-manifold edge or vertex (link condition), a duplicate face, a face whose normal turns
//!    by more than 60 degrees from its normal before the collapse or from the input face it started as (flips and
//!    folds), or a degenerate face (twice the area / longest edge^2 below 1e-3 when it was not already that thin;
//!    below 1e-6 never). Faces of the input that no collapse touches are output as they are, except the input's
//!    degenerate faces (thinness below 1e-6, such as the zero-area faces CAD exports close T-junctions with): once
//!    the target is reached, an edge of each one left is collapsed where the checks allow, so the face count may end
//!    a few faces below the target;
//!  * locked vertices, and boundary vertices with lock_border, keep their index order and positions;
//!  * faces with texture coordinates: vertices on a UV seam (corners with different uv indices) never move, and no
//!    collapse is made along a seam; other collapses interpolate the uv (and vertex normal) along the edge.
//! The face count may stay above target when no valid collapse is left (e.g. a tetrahedron).
//!
//! \pre validate(mesh) succeeds (validated anyway, its error returned).
//! \return the simplified mesh, or InvalidArgument (no stop criterion, ratio outside (0, 1], negative max_error,
//!         restore_volume outside [0, 1], threads < 1, locked vertex out of range), NonManifold (an edge shared by more than two faces, or two faces traversing
//!         an edge in the same direction; the message names the edge and the error the face).
//! Work: O(F log F) per pass (threads 2 takes 0.5-0.65 of one thread's time; restore_volume adds 0-14%); with
//! max_error, up to 7 passes each followed by mesh_distance(). Memory about 180 bytes per input triangle at the peak
//! (init); threads 2 adds 6 (fan room), 8 more with texture coordinates (uv room). With options.block_pool, arrays of
//! 1 MiB or more come from the pool and go back to it after the call.
Result<SimplifyResult> simplify_qem(const PolygonMesh& mesh, const SimplifyOptions& options);

}  // namespace surfaced
