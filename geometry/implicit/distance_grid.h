// Narrow-band signed distance grids: a triangle mesh or an implicit field sampled on a regular grid of nodes, in the
// form of level_set.h's LevelSetGrid (so the result is a level_set field as it stands). f < 0 inside.
//
// Mesh (mesh_distance_grid): every node within `band` voxels of the surface holds the exact signed Euclidean
// distance to the nearest triangle; every other node holds the background value +-band * voxel_size. The sign is
// the generalized winding number's (inside <=> w >= 1/2, geometry/spatial/winding_number.h), so meshes with holes,
// self-intersections and overlapping shells get a sensible sign:
//  * distances: each triangle visits the nodes of its bounding box grown by the band, restricted to the slab of its
//    plane's band and to the columns within the band of its projection, and keeps the minimum squared distance per
//    node; a node whose distance to the triangle's plane, or to the prism over its projection along one axis,
//    already exceeds its best skips the exact test (the band is thin, so this touches each band node a few times; a
//    closest-point query per node would walk a hierarchy for every node instead);
//  * signs on a closed mesh (every directed edge matched by its reverse once vertices at equal positions are merged,
//    which self-intersecting and overlapping closed shells also satisfy): the winding number is constant on each
//    connected region of space the surface leaves, so the grid edges that cross a triangle are marked (conservatively:
//    a crossing within rounding of an edge's end blocks the edges on both sides) and each connected component of
//    nodes over unmarked edges takes the sign of one winding-number query at its node farthest from the surface
//    (usually two components: inside and outside; the first few queries are exact sums over the triangles, the
//    hierarchy is built only when more are needed);
//  * signs on any other mesh (holes, flipped faces): the winding number is smooth off the surface but not constant.
//    Each row of nodes is split into runs at the x-edges that cross a triangle; a run's two ends are asked, and the
//    nodes between take their side when both are at least 1/4 from 1/2 on one side and none of them is within the
//    band of a boundary edge (where w turns fast), or when a bound on how much w drifts along the run (the
//    Biot-Savart sum over the boundary edges) proves each node from the nearer end; otherwise its middle is asked and
//    each half is treated alike, down to neighbouring nodes. Every node near a hole's rim is thus asked itself.
//
// Field (field_distance_grid): f sampled at every node and clamped to +-band * voxel_size. For a field that bounds
// the distance (FieldKind::ExactDistance or DistanceBound with Lipschitz constant L), after a sample with
// |f| > band * h the next floor((|f| - band * h) / (L h)) nodes along x are known to clamp to the same value and are
// not evaluated.
//
// Both are O(nodes) memory (the output itself, 8 bytes a node) plus, for the mesh, two bytes a node (crossing marks,
// signs) and the runs of the flood fill;
// the node count is known from the bounds and voxel size before any work (distance_grid_layout), checked against
// options.max_nodes, and options.cancel is polled between slabs of nodes and batches of triangles.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>

#include "geometry/core/cancel.h"
#include "geometry/core/result.h"
#include "geometry/core/types.h"
#include "geometry/implicit/field.h"
#include "geometry/implicit/level_set.h"
#include "geometry/mesh/polygon_mesh.h"
#include "geometry/spatial/winding_number.h"

namespace surfaced::implicit {

//! Largest band, in voxels.
inline constexpr int kMaxDistanceBand = 64;

struct DistanceGridOptions {
    double voxel_size = 0;  //!< grid spacing h, > 0
    int band = 3;           //!< voxels: nodes within band * h of the surface get exact distances. 1..kMaxDistanceBand
    //! The grid covers these bounds: its first node at bounds.min, nodes every h up to the first at or beyond
    //! bounds.max. Required for a field; for a mesh nothing means the mesh's box grown by (band + 1) voxels.
    std::optional<Box3> bounds;
    std::uint64_t max_nodes = std::uint64_t{256} * 256 * 256;  //!< BudgetExceeded above it, before any work
    WindingNumberOptions winding;                              //!< how the signs' winding numbers are computed
    Cancel cancel;
};

//! Where the nodes are: dims[a] nodes along axis a, the first at origin, spacing h.
struct DistanceGridLayout {
    std::array<std::size_t, 3> dims{0, 0, 0};
    Vec3 origin;
    double spacing = 0;
    std::uint64_t nodes = 0;
};

struct DistanceGridStats {
    DistanceGridLayout layout;
    std::uint64_t band_nodes = 0;       //!< nodes with |value| < band * h (mesh: within the band; field: not clamped)
    std::uint64_t winding_queries = 0;  //!< hierarchical winding numbers evaluated (mesh)
    //! closed mesh: connected components signed by one query each; other meshes: runs of nodes between crossings
    std::uint64_t components = 0;
    std::uint64_t field_evaluations = 0;  //!< (field)
    bool closed = false;                  //!< the mesh is closed: signs came from components over the whole grid (mesh)
};

//! The mesh's box grown by (band + 1) voxels on every side.
Box3 default_distance_grid_bounds(const Box3& mesh_box, double voxel_size, int band);

//! The grid over `bounds` at `voxel_size`: dims[a] = ceil(extent / h) + 1, at least 2. InvalidArgument for a voxel
//! size that is not a positive finite number or bounds that are empty or not finite; BudgetExceeded when the node
//! count exceeds max_nodes (computed without overflow).
Result<DistanceGridLayout> distance_grid_layout(const Box3& bounds, double voxel_size, std::uint64_t max_nodes);

//! The mesh's narrow-band signed distance grid (see the top of this file). The mesh must pass validate(); polygons
//! are triangulated. InvalidArgument for options out of range or a mesh without faces; BudgetExceeded, Cancelled.
Result<LevelSetGrid> mesh_distance_grid(const PolygonMesh& mesh, const DistanceGridOptions& options,
                                        DistanceGridStats* stats = nullptr);

//! The field sampled on the grid over options.bounds (required), clamped to +-band * voxel_size. InvalidArgument,
//! BudgetExceeded, Cancelled; NonFinite when the field gives NaN at a node.
Result<LevelSetGrid> field_distance_grid(const Field& field, const DistanceGridOptions& options,
                                         DistanceGridStats* stats = nullptr);

}  // namespace surfaced::implicit
