// Tessellation of trimmed B-spline / NURBS surfaces (the loops and their validation: trim_loops.h) with a guaranteed
// chord tolerance e, on the surface and along the trims.
//
// Method.
//  1. The surface is split into its Bézier patches (to_bezier) and each patch gets a grid: the counts plan_tessellation
//     gives for e (bezier_patch.h; counts agree along shared edges) times one common factor, the smallest found by
//     bisection for which every grid cell is within e by the interior bound below, as its two triangles or, where
//     those are over e, as the fan of four about its centre (then of the factors up to a third larger, the one with
//     the fewest triangles: a cell too large by little costs two triangles, not a finer grid). Grid lines are
//     uniform but for the first and last interval, 0.6 of the others (cells on a patch side get
//     triangle_distance_bound's weaker form); the positions depend on the count alone, so patches sharing a side
//     agree on its points.
//  2. Trim curves are flattened in (u, v) to the flatness d = 0.9 e / (2 G), where G bounds |dS| per unit of parameter
//     distance over the whole surface: G = max over patches of sqrt((|S_u| / span_u)^2 + (|S_v| / span_v)^2), with
//     derivative_bounds() (bezier_patch.h). Method: the parameter-space deviation times the first-derivative bound;
//     no sampling. Pieces are first cut where they cross a patch side (at a curve point set exactly on the side), and
//     chords are split (at curve points) until no longer than 0.7 grid spacings of their patch, so that triangles at
//     the trims meet their e/2 (step 4) about as they are.
//  3. Per patch, in (u, v) scaled so that a unit step is about a unit of length on the surface (the control net's mean
//     row and column lengths), a constrained Delaunay triangulation (constrained_triangulation.h) of: the patch corners
//     and grid points on its sides, the interior grid points, and the trim vertices, with every trim chord as a
//     constraint. Grid points closer than 0.4 grid spacings to a trim chord are left out (on a patch side: closer than
//     0.4 spacings along that side to a trim vertex on it), so no sliver forms between a trim and a grid line; the
//     rule on a side depends only on that side, so both patches sharing it drop the same points. A fan cell clear of
//     the trims gets its centre, its spokes and sides constrained (the flips would otherwise join it to a neighbour
//     in triangles over e). Components separated by the trims are kept when inside the trimmed domain.
//  4. Refinement (Chew/Ruppert): a kept triangle is refined by inserting its circumcentre when its bound (below)
//     exceeds e, or e/2 for a triangle with a trim vertex, or when it touches a trim or inserted vertex and its
//     smallest angle on the surface is below min_angle_degrees -- unless its angles in the scaled plane are all at
//     least that and the map from the plane to the surface stretches one direction over twice as much as the other
//     on it (near a pole): the thinness is then the parameterisation's, which points inserted in the plane do not
//     remove. A circumcentre that would cross a trim chord, fall on an edge or encroach on a trim chord is not
//     inserted (a triangle over its size bound then gets its centroid). One beyond or encroaching on a patch side
//     asks for that side's midpoint instead: all patches are triangulated again (up to 6 rounds) with it on the
//     side, in both patches sharing it, so the sides still match and the mesh welds; a side collapsed to one point
//     (a pole) is never split (the triangle gets its centroid when over its size bound, else is left).
//  5. Vertices are shared by exact (u, v); positions and normals are the surface's exact point and unit normal there
//     (unit_normal: limits at poles). Vertices that coincide in 3D (a closed surface's seam, a pole) are welded within
//     1e-10 of the model size, and triangles that collapse are dropped. uvs (face-varying) are the (u, v).
//
// Guarantees (reported in TrimmedTessellation).
//  - Interior: a triangle whose corners lie in one patch is within the smaller of two guaranteed bounds of the
//    surface: with parameter extents H x K (patch units), (1/8)(Muu H^2 + 2 Muv H K + Mvv K^2) at equal parameters
//    (the derivation of bezier_patch.cpp holds for any triangle, its corners' weighted variances being bounded by the
//    extents), and triangle_distance_bound (bezier_patch.h: local, normal component plus a tangential drift absorbed
//    by moving to another surface point of the patch). Every triangle's bound is computed; refinement makes the
//    largest, interior_bound, <= e, and <= e/2 over the triangles with a trim vertex. When refinement stops at its
//    limits first (max_refinement_points, passes, side rounds: e.g. trims crowding a pole of the surface, where the
//    local bound is weak) the bounds are what was reached, above e: bound says so, and a caller that promises e must
//    check it (the API answers 422).
//  - Trims: every point of a trim curve is within d + gap of its polygon in (u, v), hence within G (d + gap) of the
//    image of a polygon point, which lies on an edge of a triangle with a trim vertex, within that triangle's bound:
//    trim_bound = G (d + gap) + (the largest bound of those triangles) <= 0.9 e/2 + e/2 + G gap; the gaps (within the
//    closure tolerance, in parameter units) are not refined away, so on a large model G gap alone can exceed e.
//    Conversely every point of the mesh is within interior_bound of the surface at parameters inside the polygons,
//    which are within d of the trimmed domain. bound = max(interior_bound, trim_bound) <= e.
//  - Trim vertices are points of the trim curves (evaluated, never interpolated), so boundary vertices lie on the trims'
//    3D images. The mesh is watertight inside the trimmed domain (every interior edge is used by two triangles, also
//    across patch sides and welded seams) and open along the trims.
//  - Quality: refinement targets min_angle_degrees (default 20) for triangles touching a trim; the measured smallest
//    angles of the tests are stated in docs/patches-and-curves.md. Grid triangles far from trims keep the grid's shape.
//  - Deterministic: the same input gives the same mesh (no hashing order or threads influence the output).
#pragma once

#include <cstddef>
#include <vector>

#include "geometry/core/cancel.h"
#include "geometry/core/result.h"
#include "geometry/mesh/polygon_mesh.h"
#include "geometry/surfaces/trim_loops.h"

namespace surfaced {

struct TrimmedTessellationOptions {
    double tolerance = 1e-3;          //!< e, model units: the largest distance between mesh and trimmed surface
    double closure_tolerance = 1e-7;  //!< largest gap between consecutive trim curves, relative to the domain
    int max_segments = 256;           //!< grid segments along one direction of one patch (BudgetExceeded beyond)
    std::size_t max_trim_segments = 1'000'000;  //!< chords over all loops
    std::size_t max_triangles = 20'000'000;     //!< output triangles (BudgetExceeded beyond)
    //! Points refinement may insert into one patch's triangulation (step 4); 0: 16 per point of its initial
    //! triangulation + 4096. Refinement also stops after 400 passes and 6 rounds of side splits.
    std::size_t max_refinement_points = 0;
    double min_angle_degrees = 20;  //!< refinement target near the trims, in (0, 30]
    Cancel cancel;                  //!< polled between patches
};

struct TrimmedTessellation {
    //! Triangles counter-clockwise in (u, v) (facing S_u x S_v), unit normals per vertex, uvs = surface parameters.
    PolygonMesh mesh;
    std::vector<TrimPolygon> loops;  //!< the flattened, oriented loops (reversed: orientation was normalised)
    double derivative_bound = 0;     //!< G
    double trim_flatness = 0;        //!< d, parameter units
    double max_gap = 0;              //!< largest end-to-start gap between trim curves, parameter units
    double interior_bound = 0;       //!< max over triangles of their bound
    double trim_bound = 0;           //!< G (d + max_gap) + the largest bound of the triangles with a trim vertex
    double bound =
        0;  //!< max(interior_bound, trim_bound): guaranteed distance; above tolerance only as the header says
    std::size_t refinement_points = 0;  //!< vertices inserted by refinement
};

//! Errors: validate(surface); InvalidArgument (tolerance not finite and > 0, min_angle_degrees outside (0, 30]); the
//! trim errors of trim_loops.h as GeoErrors (to_geo_error; call validate_trims first for the typed error); Internal
//! when rounding makes two trim chords cross after validation; BudgetExceeded (grid segments, trim chords, triangles);
//! Cancelled.
Result<TrimmedTessellation> tessellate(const TrimmedSurface& trimmed, const TrimmedTessellationOptions& options);

}  // namespace surfaced
