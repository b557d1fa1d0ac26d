// Meshing the zero level set of an implicit field: dual marching cubes with a QEF vertex per surface component.
//
// References: G. Nielson, "Dual Marching Cubes", IEEE Visualization 2004 (one vertex per marching-cubes patch of a
//             cell, which is what makes the dual mesh manifold where plain dual contouring is not);
//             T. Ju, F. Losasso, S. Schaefer, J. Warren, "Dual Contouring of Hermite Data", SIGGRAPH 2002 (QEF vertex
//             placement that keeps sharp edges and corners);
//             G. Nielson, B. Hamann, "The Asymptotic Decider", IEEE Visualization 1991 (face ambiguities).
//
// The algorithm, per grid cell whose corners do not all have the same sign:
//  1. On each of the cell's six faces the sign changes along the face's edges are joined into segments; a face with
//     four sign changes is resolved by the asymptotic decider on the face's bilinear interpolant, computed from the
//     face's four corner values only, so the two cells sharing the face always agree.
//  2. The segments form closed loops (marching-cubes patches; tunnels inside a cell are not built, every loop is a
//     disc). Each loop gets one vertex, placed by a QEF on the loop's Hermite data (edge crossings found by Illinois
//     regula falsi on the field, normals from Field::gradient), small eigenvalues truncated, clamped into the cell.
//     At a sharp feature (QEF rank >= 2) the Hermite data is re-sampled where the vertex is: one plane per sheet,
//     each moved to the point of its sheet nearest the vertex's foot on it, and the QEF solved again (a few rounds),
//     so that curved creases (a hole's rim) get vertices on the crease, not where tangent planes a cell apart meet;
//     a vertex still off the surface (smooth curved patches: the sag of the mean plane) is moved onto it by Newton
//     steps along the gradient when that keeps it in its cell on a sheet its crossings saw.
//  3. Each grid edge with a sign change gives a quad joining the vertices of the four cells around it that own its
//     crossing, oriented so that normals point out (f < 0 inside). Where both cells sharing an ambiguous face own
//     both of its segments with one vertex each (the case that makes Nielson's dual mesh non-manifold), a vertex is
//     inserted on that face for each segment, so the quads become pentagons and every edge stays shared by two faces.
//  4. Polygons are split into triangles along the diagonal that avoids folds and keeps the best triangle shape;
//     triangles that are still (near) zero-area get their vertices moved towards their patch's mass point.
//
// Guarantees on the output (tests/geometry/implicit_mesh_test.cpp checks each): a triangle mesh in which every edge is
// shared by exactly two faces traversing it in opposite directions (closed and consistently oriented), every vertex
// has one fan of faces (manifold vertices), normals point to f > 0, no triangle has zero area, and every vertex lies
// inside the bounds.
//
// Where the surface meets the bounds: the field is treated as "outside" on and beyond the bounds. We mesh
// g(p) = max(f(p), d_box(p)) with d_box the signed distance to the bounds box, and grid nodes on the bounds count as
// outside (g >= 0), so a surface cut by the bounds is closed by flat caps on the bounds faces (with sharp edges
// where the caps meet the surface). The output is always closed. Give bounds with some margin around the shape to
// mesh it uncut.
//
// Resolution: `resolution` cells along the longest side of the bounds (or `cell_size` when given); the other sides
// get as many cells of (about) the same size, each side divided evenly. Features smaller than a cell may be lost or
// merged (two sheets closer than a cell stay two sheets when the grid sees them, and are never joined by a
// non-manifold edge).
#pragma once

#include <cstdint>

#include "geometry/core/cancel.h"
#include "geometry/core/result.h"
#include "geometry/core/types.h"
#include "geometry/implicit/field.h"
#include "geometry/mesh/polygon_mesh.h"

namespace surfaced::implicit {

enum class MeshFieldMode {
    //! Every grid node is evaluated: cost grows with the volume (resolution^3).
    Uniform,
    //! Adaptive: an octree over the grid skips blocks that provably hold no surface, using the field's distance
    //! bound (a block whose |g(center)| > lipschitz * half-diagonal has no zero inside), so field evaluations grow
    //! with the surface area (about resolution^2), not the volume. Fields of kind General (no usable Lipschitz
    //! bound) cannot be culled and are evaluated like Uniform. The mesh before simplification is the same as the
    //! uniform mode's at the same resolution. Then, when simplify_tolerance > 0, flat regions are coarsened by our
    //! QEM edge collapse (geometry/simplify/qem.h) to that measured Hausdorff distance, which keeps the mesh closed
    //! and manifold (and sharp edges, which QEM's plane quadrics keep). It does not: refine the grid locally beyond `resolution` (detail smaller than a cell is still
    //! lost), or make the node-value array smaller (4 bytes per grid node are still allocated).
    Adaptive,
};

struct MeshFieldOptions {
    //! Cells along the longest side of the bounds; >= 2.
    int resolution = 64;
    //! When > 0: the cell size, instead of resolution.
    double cell_size = 0;
    //! Most grid cells (nx * ny * nz); over it: BudgetExceeded, before the field is evaluated.
    std::uint64_t max_cells = std::uint64_t{256} * 256 * 256;
    MeshFieldMode mode = MeshFieldMode::Uniform;
    //! Adaptive mode only: when > 0, QEM simplification to this measured Hausdorff distance (model units; e.g.
    //! 0.1 * cell size). Vertices on the bounds are locked. Costly: the Hausdorff distance is measured after each
    //! of up to 7 passes (seconds for 10^4..10^5 triangles; see the benchmark). 0: no simplification.
    double simplify_tolerance = 0;
    //! Eigenvalues of the QEF below this fraction of the largest are treated as zero (higher: smoother, fewer
    //! features kept).
    double qef_threshold = 0.05;
    //! Polled between slabs of cells and octree blocks: Cancelled when it fires.
    Cancel cancel;
};

//! The grid mesh_field would use.
struct MeshFieldGrid {
    int nx = 0, ny = 0, nz = 0;
    Vec3 spacing;             //!< cell size along each axis
    std::uint64_t cells = 0;  //!< nx * ny * nz
};

//! What one meshing run did (for headers and the benchmark).
struct MeshFieldStats {
    MeshFieldGrid grid;
    std::uint64_t field_evaluations = 0;  //!< values + gradients (a gradient counts once)
    std::uint64_t surface_cells = 0;      //!< cells with a sign change
    std::uint64_t vertices_before_simplify = 0;
    std::uint64_t triangles_before_simplify = 0;
    std::uint64_t non_manifold_fixes = 0;  //!< ambiguous faces given inserted vertices (step 3 above)
    std::uint64_t degenerate_fixes = 0;    //!< triangles repaired in step 4
};

//! The grid for these bounds and options, without evaluating anything: InvalidArgument (bounds empty or not
//! finite, resolution < 2 or > 65536, cell_size not finite or giving fewer than 2 cells), BudgetExceeded (more
//! than options.max_cells cells).
Result<MeshFieldGrid> mesh_field_grid(const Box3& bounds, const MeshFieldOptions& options);

//! Meshes f = 0 inside `bounds` (see the top of this file for the method and guarantees).
//! \return triangles (no normals, no uvs), possibly empty when the field has no sign change on the grid; or the
//!         errors of mesh_field_grid, Cancelled.
//! Work: uniform O(cells) field values plus O(surface cells) crossings and gradients; memory 4 bytes per grid node
//! plus O(surface cells).
Result<PolygonMesh> mesh_field(const Field& field, const Box3& bounds, const MeshFieldOptions& options,
                               MeshFieldStats* stats = nullptr);

//! For renderers: a copy of the triangle mesh `mesh` with per-vertex normals in which a vertex on a sharp edge
//! (faces meeting at a dihedral angle above `crease_angle_degrees`, i.e. face normals more than that apart) is
//! split into one copy per smooth group of its faces, each with the angle-weighted normal of its group; so cube
//! edges stay sharp when shaded instead of being rounded by normals averaged across them. Copies keep the exact
//! position of the original, so welding by position gives `mesh` back (closed and manifold as it was); faces keep
//! their order and orientation. 180 (or more): no split, smooth normals everywhere; 0: every face flat. Faces that
//! are not triangles, or edges shared by more than two faces, are never joined across (they stay split).
PolygonMesh split_normals_at_creases(const PolygonMesh& mesh, double crease_angle_degrees);

}  // namespace surfaced::implicit
