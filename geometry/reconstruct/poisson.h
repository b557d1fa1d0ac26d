// Screened Poisson surface reconstruction: a watertight surface from an oriented point cloud.
//
// Reference: M. Kazhdan, H. Hoppe, "Screened Poisson Surface Reconstruction", ACM Transactions on Graphics 32(3),
//            2013 (and M. Kazhdan, M. Bolitho, H. Hoppe, "Poisson Surface Reconstruction", SGP 2006).
//
// Method (docs/reconstruction.md has the details and measured accuracy):
//  1. The points' bounding cube, enlarged by `scale`, is mapped onto the unit cube and an octree is refined to
//     `depth` around the samples only (octree.h): complete on the coarsest level, the cells holding samples and
//     their neighbours on each finer level.
//  2. The normals are splatted into a vector field V on the finest level, and chi is sought as a sum of trilinear
//     B-splines (degree 1) centred on every level's cell corners minimising the screened Poisson energy
//     |grad chi - V|^2 + alpha * area / sum w * sum_i w_i chi(p_i)^2 (poisson_system.h); each sample's normal stands
//     for a share of the area inversely proportional to the local sampling density.
//  3. The system is solved coarse to fine, conjugate gradients on each level (solver.h).
//  4. The iso-value is the mean of chi at the samples weighted by their area shares, and chi = iso is meshed by marching cubes on the
//     finest level's grid (2^depth cells per side), visiting only the cells the surface can cross, in coarse regions
//     too (extract_surface.h): memory and time grow with the surface, not with the cube's volume.
//  5. Unless fit_to_samples is off, each vertex is moved onto the tangent planes of the samples around it
//     (fit_to_samples.h), which the grid's cell size no longer limits where the cloud is dense and clean.
// The output is a closed, manifold, consistently oriented triangle mesh with normals pointing out of the sampled
// solid. Deterministic: the same cloud and options give the same mesh bit for bit, with one thread or two.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "geometry/core/cancel.h"
#include "geometry/core/result.h"
#include "geometry/mesh/polygon_mesh.h"
#include "geometry/pointcloud/point_cloud.h"

namespace surfaced {

enum class PoissonBoundary {
    Neumann,    //!< natural boundary conditions: chi's normal derivative is free on the cube's faces (default)
    Dirichlet,  //!< chi = 0 on the cube's faces
};

struct PoissonOptions {
    //! Finest octree depth: 2^depth cells across the bounding cube; 2..10. Each level multiplies the surface cells
    //! (time, memory, triangles) by about 4.
    int depth = 8;
    //! Screening weight alpha (PoissonRecon's --pointWeight): how strongly chi is pulled to the iso-value at the
    //! samples; 0 is the unscreened Poisson reconstruction of 2006. >= 0.
    double point_weight = 4;
    //! The area of the sampled surface, which scales V and the screening term, is estimated from the number of
    //! cells holding samples on the deepest level where they hold this many samples on average; > 0.
    double samples_per_node = 1.5;
    PoissonBoundary boundary = PoissonBoundary::Neumann;
    //! Weight each sample by the length of its normal (PoissonRecon's --confidence); otherwise normals are
    //! normalised and every sample weighs 1. Samples of zero weight are ignored.
    bool use_confidence = false;
    //! The bounding cube is the points' bounding box's largest side times this, centred on the box; >= 1.
    double scale = 1.1;
    //! Conjugate-gradient iterations per level, at most, and the relative residual that ends them (the coarser levels
    //! have fixed the low frequencies, so 1e-4 costs no accuracy).
    int max_iterations = 100;
    double tolerance = 1e-4;
    //! 1: everything on the calling thread; anything else (>= 0): a second thread for the finest octree level, the
    //! assembly, the splats, the interpolation between levels, the conjugate gradients and the marching cubes of
    //! large levels (65,536 unknowns or samples; 32,768 cells). The mesh is bit-identical either way.
    int threads = 1;
    //! After meshing, move each vertex onto the tangent planes of the samples around it (fit_to_samples.h): sharp
    //! edges and curved parts follow the samples below the cell size where the cloud is dense enough, and a noisy
    //! cloud's vertices move little. false: the iso-surface of chi as it is (as PoissonRecon gives it).
    bool fit_to_samples = true;
};

struct PoissonStats {
    std::vector<std::size_t> cells;       //!< active octree cells per level, coarsest first
    std::vector<std::size_t> dofs;        //!< unknowns per level
    std::vector<int> iterations;          //!< conjugate-gradient iterations per level
    std::vector<double> residuals;        //!< relative residual reached per level
    std::size_t octree_bytes = 0;         //!< memory of the octree's key sets and values
    std::uint64_t field_evaluations = 0;  //!< grid nodes whose value the extraction interpolated from a coarser level
    std::uint64_t surface_cells = 0;      //!< finest-level cells the surface crosses
    std::size_t extraction_bytes = 0;     //!< peak of the extraction's tables (the output mesh excluded)
    double area_estimate = 0;             //!< of the sampled surface, model units
    //! Wall-clock seconds of the phases: the samples and the octree; the operators and right-hand sides; conjugate
    //! gradients; the surface extraction; the fit of the vertices to the samples.
    double seconds_octree = 0, seconds_system = 0, seconds_solve = 0, seconds_extract = 0, seconds_fit = 0;
};

struct PoissonResult {
    PolygonMesh mesh;      //!< triangles, closed and outward; no normals
    double iso_value = 0;  //!< the level of chi that was meshed
    Vec3 cube_origin;      //!< the bounding cube: origin and side
    double cube_size = 0;
    PoissonStats stats;
};

//! Reconstructs the surface the oriented cloud samples (see the top of this file).
//! \pre the cloud has normals pointing out of the solid (estimate and orient them first: geometry/pointcloud/normals.h).
//! Errors: InvalidArgument (no normals, an option out of range, fewer than 4 samples of positive weight, a zero
//! normal without use_confidence, all points equal), whatever validate(cloud) reports, Cancelled (polled while the
//! octree is built, every solver iteration, and by the mesher).
Result<PoissonResult> reconstruct_poisson(const PointCloud& cloud, const PoissonOptions& options,
                                          const Cancel& cancel = {});

//! Predicted size of a reconstruction, for budgets before any work: octree cells summed over the levels, the finest
//! cells the extraction meshes, and peak bytes. Assumes a closed surface about as large as the bounding cube allows
//! (a sphere filling it); clouds of thin or small parts need less. An estimate, not a bound: for the benchmark's
//! 50,000-point sphere (area 0.83 of that assumption) it predicts 27 / 93 / 357 MiB at depths 6 / 7 / 8 against
//! 32 / 94 / 342 MiB measured (peak heap), for its 1,000,000-point sphere 1,520 / 5,738 MiB at depths 9 / 10
//! against 1,555 / 5,567 MiB.
struct PoissonEstimate {
    std::uint64_t octree_cells = 0;
    std::uint64_t grid_cells = 0;  //!< finest-level cells the surface crosses (no dense grid is built)
    std::uint64_t bytes = 0;
};
PoissonEstimate estimate_poisson(std::size_t points, const PoissonOptions& options);

}  // namespace surfaced
