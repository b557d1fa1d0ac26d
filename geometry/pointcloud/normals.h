// Normal estimation for point clouds: PCA of the k nearest neighbours, then a consistent orientation by
// propagation along a minimum spanning tree of the kNN graph (Hoppe, DeRose, Duchamp, McDonald & Stuetzle,
// "Surface reconstruction from unorganized points", SIGGRAPH 1992, sections 3.2-3.3).
#pragma once

#include <cstddef>

#include "geometry/core/cancel.h"
#include "geometry/core/result.h"
#include "geometry/pointcloud/point_cloud.h"

namespace surfaced {

struct NormalEstimationOptions {
    std::size_t k = 16;  //!< neighbours per point, the point itself included; 3 .. 256
    bool orient = true;  //!< make the orientation consistent (orient_normals) after estimating
    Cancel cancel;       //!< polled every few thousand points
};

//! Replaces cloud.normals with unit normals: the eigenvector of the smallest eigenvalue of the covariance of each
//! point's k nearest neighbours (so a normal is only defined up to sign until it is oriented). A point whose
//! neighbourhood is degenerate (all neighbours coincide) gets the normal of its nearest neighbour with a defined
//! one, else +z. With `orient`, orient_normals' propagation runs over the same k - 1 neighbours per point (no
//! second kNN pass). Errors: InvalidArgument (k out of range, fewer than 3 points, invalid cloud), Cancelled.
//! Cost: O(n k log n) time; O(n) extra memory, O(n k) with orient (the graph's edges, 12 bytes each).
Status estimate_normals(PointCloud& cloud, const NormalEstimationOptions& options = {});

struct OrientationOptions {
    std::size_t k = 16;  //!< neighbours defining the graph over which orientation propagates; 2 .. 256
    Cancel cancel;
};

//! Flips cloud.normals (which must be present) so that neighbours agree: for each connected component of the
//! symmetric kNN graph, the point with the largest z is made to face +z (the outside, for the outer surface of a
//! closed shape), then orientation propagates along the minimum spanning tree (Kruskal) of the graph under edge
//! cost 1 - |n_i . n_j|, so it crosses flat regions first and sharp features last. Errors: InvalidArgument,
//! Cancelled. Cost: O(n k log(n k)) time, O(n k) memory.
Status orient_normals(PointCloud& cloud, const OrientationOptions& options = {});

}  // namespace surfaced
