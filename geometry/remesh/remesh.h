// Isotropic remeshing: better-shaped triangles of about one edge length, on the input surface.
//
// References: M. Botsch, L. Kobbelt, "A Remeshing Approach to Multiresolution Modeling", SGP 2004 (the split /
//               collapse / flip / relax / project loop and its 4/3 and 4/5 thresholds).
//             T. Dey, H. Edelsbrunner, S. Guha, D. Nekhayev, "Topology Preserving Edge Contraction", 1999 (the link
//               condition).
//             C. Stimpson, C. Ernst, P. Knupp, P. Pebay, D. Thompson, "The Verdict Geometric Quality Library",
//               SAND2007-1751 (triangle radius ratio R / 2r).
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "geometry/core/cancel.h"
#include "geometry/core/result.h"
#include "geometry/mesh/polygon_mesh.h"

namespace surfaced {

enum class RemeshSmoothing {
    None,        //!< no relaxation: split, collapse, flip and projection only
    Tangential,  //!< area-weighted centroid of the one-ring, moved in the tangent plane only (Botsch-Kobbelt)
    Laplacian,   //!< uniform Laplacian (mean of the neighbours), in 3D; projection pulls it back onto the input
};

struct RemeshOptions {
    //! Target edge length L, absolute (mesh units). When unset: relative_edge_length * the bounding-box diagonal when
    //! that is set, else the input's mean edge length (regularise at about the same density).
    std::optional<double> target_edge_length;
    std::optional<double> relative_edge_length;
    int iterations = 10;  //!< rounds of split, collapse, flip, relax, project; >= 0
    //! An interior edge whose faces' normals differ by more than this angle is a sharp feature: features are only
    //! split or collapsed along themselves, their vertices slide along the input's feature polylines, and feature
    //! corners (not exactly two feature edges, or a turn sharper than this angle or 60 degrees) stay where they are.
    //! Noise is dropped first: chains of feature edges (between corners) shorter than 5 L that are not held at both
    //! ends by a junction of three or more constrained edges or by the boundary, repeatedly, then connected groups of
    //! feature edges shorter than 5 L in all (a scan's dihedral noise). Corners closer than 4/5 L along a constrained
    //! edge may merge, and a loose end of a feature curve may retreat along it. 180 disables features (boundary
    //! corners are still kept).
    double feature_angle_degrees = 60.0;
    //! Boundary edges are constrained like features: boundary vertices stay on the input's boundary polyline,
    //! boundary edges are split and collapsed only along it, and boundary corners stay fixed. Off: boundary
    //! vertices are relaxed like interior ones (the boundary may shrink).
    bool lock_border = true;
    RemeshSmoothing smoothing = RemeshSmoothing::Tangential;
    //! Measure the Hausdorff distance between input and output (mesh_distance, default sampling).
    bool measure_hausdorff = true;
    //! Working faces never exceed this (0: no limit); over it the result is BudgetExceeded.
    std::size_t max_faces = 0;
    Cancel cancel;
};

//! Triangle quality of a mesh (polygons are fan-triangulated for the measure).
struct MeshQuality {
    std::size_t vertices = 0, faces = 0;
    double min_angle_degrees = 0;  //!< smallest interior angle of any triangle
    double share_below_30 = 0;     //!< share of triangles whose smallest angle is below 30 degrees
    double mean_radius_ratio = 0;  //!< Verdict: R / (2 r), 1 for equilateral, >= 1 (capped at 1e30)
    double max_radius_ratio = 0;
    double mean_edge_length = 0;
    double edge_length_stddev = 0;
    //! valence_histogram[k] = vertices with k incident edges (vertices in no face are not counted).
    std::vector<std::size_t> valence_histogram;
    //! Share of vertices with the ideal valence: 6 inside, 4 on a boundary.
    double share_regular = 0;
};

MeshQuality measure_quality(const PolygonMesh& mesh);

struct RemeshResult {
    PolygonMesh mesh;  //!< triangles; no uvs, normals or tags
    double target_edge_length = 0;
    bool triangulated = false;       //!< the input had polygons with more than 3 vertices, triangulated first
    std::size_t feature_edges = 0;   //!< sharp feature edges detected on the (triangulated) input
    std::size_t boundary_edges = 0;  //!< boundary edges of the input
    MeshQuality before, after;
    std::optional<double> hausdorff;  //!< symmetric, between input and output (measure_hausdorff)
};

//! Remeshes a triangle mesh (polygons are triangulated first) towards edges of length L: per iteration, split
//! edges longer than 4/3 W at their midpoints, collapse edges shorter than 4/5 W (when no edge longer than 4/3 W
//! results), flip edges when that brings valences closer to 6 (4 on a boundary) or, at equal valences, makes the two
//! faces Delaunay, move vertices towards their relaxed position and project them back onto the input (the closest
//! point of the input surface, or of the input's feature/boundary polylines for constrained vertices). W, the working
//! target, starts at L and is corrected after each iteration by L / the mean edge length, within [0.8, 1.25] L, so
//! that the mean edge length ends within about 2% of L. Three rounds of flips and relaxation follow, and a last pass
//! flips edges opposite an angle above 170 degrees (caps) where that is allowed.
//!
//! Faces of (almost) zero area (twice the area / longest edge^2 below 1e-6), as CAD exports have them where they
//! close T-junctions, are removed before the features are found and again at the end: a cap's longest edge is
//! flipped (or split at the foot of the opposite corner, which then moves onto it), a needle's short edge collapsed.
//!
//! Guarantees on the output, for manifold, consistently oriented input: the topology (Euler characteristic, number of
//! boundary loops) is unchanged; no operation creates a non-manifold edge or vertex (link condition), a face whose
//! normal turns by more than ~78 degrees from its normal before the operation, or a degenerate face (twice the
//! area / longest edge^2 below 1e-3 unless the faces involved were already that thin, below 1e-6 never); no
//! degenerate face of the input is left unless none of the removals above was allowed; constrained vertices stay on
//! their polylines and corners where they are.
//!
//! \pre validate(mesh) succeeds (validated anyway, its error returned).
//! \return the remeshed mesh and the quality before and after, or InvalidArgument (L not finite and > 0, iterations
//!         < 0, feature angle not in [0, 180]), NonManifold (an edge shared by more than two faces or traversed
//!         twice in one direction, or a vertex where several face fans meet), BudgetExceeded (max_faces), Cancelled.
//! Work: O(F log F) per iteration (projection through an AABB tree of the input).
Result<RemeshResult> remesh(const PolygonMesh& mesh, const RemeshOptions& options);

}  // namespace surfaced
