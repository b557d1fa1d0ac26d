// Trimming a screened Poisson reconstruction: removing the parts of the surface the samples do not support.
//
// The Poisson surface is closed by construction, so where a scan has holes (an open surface, an unscanned base) it
// invents a smooth cap. Following PoissonRecon's SurfaceTrimmer (M. Kazhdan, H. Hoppe, "Screened Poisson Surface
// Reconstruction", 2013), every output vertex gets a sampling-density value on the octree-depth scale and
// the surface is cut along the level `trim` of that value, then small disconnected pieces are dropped.
//
// Density value of a vertex v (docs/reconstruction.md, "Trimming"): with r_k the distance from v to its k-th
// nearest sample (k = `neighbors`), the local sampling density is k / (pi r_k^2) samples per unit area, and a
// square of side h = sqrt(samples_per_node * pi r_k^2 / k) holds `samples_per_node` of them. The value is
// log2(cube_size / h): the octree depth whose cells hold about samples_per_node samples near v. It is close to
// log2(0.5 sqrt(N)) on a uniformly sampled sphere of N samples, and falls by 1 each time the distance to the
// samples doubles, so it is smallest in the middle of holes.
#pragma once

#include <cstddef>
#include <vector>

#include "geometry/core/cancel.h"
#include "geometry/core/result.h"
#include "geometry/mesh/polygon_mesh.h"
#include "geometry/pointcloud/point_cloud.h"
#include "geometry/reconstruct/poisson.h"

namespace surfaced {

struct TrimOptions {
    //! Density level on the octree-depth scale (PoissonRecon's SurfaceTrimmer --trim): the surface where the
    //! vertices' density value is below it is cut away, the triangles crossing the level are split along it.
    //! 0 keeps everything; >= 0 and finite. Useful values lie 0.3 to 1 below the typical value on the scanned
    //! surface (typical_sample_density; TrimReport::sample_density), which is near the depth at which the
    //! octree's cells hold samples_per_node samples.
    double trim = 0;
    //! Small pieces and small holes (PoissonRecon's --aRatio): a region below the level whose area is below this
    //! fraction of the mesh's is kept (a gap between samples does not become a hole), and after the cut,
    //! edge-connected pieces whose area is below this fraction of the remaining total are removed. 0 keeps all
    //! pieces and cuts every region below the level; in [0, 1].
    double island_area = 0.001;
    //! Samples a cell holds at the density value's depth (as PoissonOptions::samples_per_node); > 0.
    double samples_per_node = 1.5;
    //! k of the k-nearest-sample distance the density is measured with; 1..64. More neighbours give smoother
    //! values (the spread on uniformly sampled surface shrinks like 1/sqrt(k)) but blur features smaller than
    //! the k-neighbourhood; 32 keeps the spread near +-0.15 so that a trim 0.5 below the typical value cuts
    //! nothing inside the scan.
    std::size_t neighbors = 32;
};

struct TrimReport {
    std::size_t faces_removed = 0;            //!< input triangles removed wholly or in part (cut along the level)
    std::size_t islands_removed = 0;          //!< pieces removed by island_area
    double min_density = 0, max_density = 0;  //!< range of the vertices' density values (before trimming)
    //! The median density value at the samples themselves: the typical value on the scanned surface. A trim
    //! about 0.5 below it cuts within a cell or two of the scan's edges (docs/reconstruction.md, "Trimming").
    double sample_density = 0;
};

//! Per-vertex density values of `mesh` (see the top of this file), for inspection and for choosing `trim`.
//! Errors: InvalidArgument (empty cloud, cube_size <= 0, samples_per_node or neighbors out of range), Cancelled.
Result<std::vector<double>> vertex_density(const PolygonMesh& mesh, const PointCloud& cloud, double cube_size,
                                           const TrimOptions& options, const Cancel& cancel = {});

//! The typical density value on the scanned surface: the median of the values at (up to 4096 evenly spaced) samples.
//! Errors as vertex_density.
Result<double> typical_sample_density(const PointCloud& cloud, double cube_size, const TrimOptions& options,
                                      const Cancel& cancel = {});

//! Trims `mesh` (normally result.mesh, possibly moved out of `result`; only result.cube_size is read) in place.
//! \pre a triangle mesh; manifold and consistently oriented if the output is to be (reconstruct_poisson's is).
//! The output keeps the orientation, stays manifold, and has a boundary loop around every removed region; vertex
//! positions that survive are unchanged, unused vertices are dropped, new vertices lie on the cut edges. Normals
//! and UVs are dropped (reconstruct_poisson produces neither). Deterministic.
//! Errors: InvalidArgument (an option out of range, an empty cloud), NotTriangleMesh, Cancelled.
Result<TrimReport> trim_reconstruction(PolygonMesh& mesh, const PointCloud& cloud, const PoissonResult& result,
                                       const TrimOptions& options, const Cancel& cancel = {});

}  // namespace surfaced
