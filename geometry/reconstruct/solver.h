// Solving the screened Poisson system level by level, coarse to fine (a cascadic multigrid, Kazhdan & Hoppe 2013
// sec. 4.2): on each level the coarser levels' solution is held fixed, its effect moved to the right-hand side
// (the stiffness stencil applied to its values on the level's grid, and its screening at the samples), and the
// level's own coefficients are found by conjugate gradients with a Jacobi preconditioner. The coarse levels fix
// the low frequencies over the whole cube, the fine levels the detail near the samples.
#pragma once

#include <cstddef>
#include <vector>

#include "geometry/core/cancel.h"
#include "geometry/core/result.h"
#include "geometry/reconstruct/octree.h"
#include "geometry/reconstruct/poisson_system.h"

namespace surfaced::reconstruct {

struct SolverOptions {
    double alpha = 4;          //!< screening weight (PoissonOptions::point_weight)
    bool dirichlet = false;    //!< chi = 0 on the cube's boundary; otherwise natural (Neumann) conditions
    int max_iterations = 100;  //!< conjugate-gradient iterations per level, at most
    double tolerance = 1e-4;   //!< stop when |residual| <= tolerance * |right-hand side| on the level
    //! 1: one thread; anything else: a second thread for the products and sums of large levels (bit-identical).
    int threads = 1;
    Cancel cancel;  //!< polled every iteration
};

struct LevelSolveStats {
    int depth = 0;
    std::size_t dofs = 0;
    int iterations = 0;
    double relative_residual = 0;
    double assembly_seconds = 0;  //!< the level's operator and right-hand side (level 0: also b for every level)
    double solve_seconds = 0;     //!< conjugate gradients and the update of the values
};

//! The reconstructed function, as its values at every level's support vertices (PoissonOctree, octree.h). Inside a
//! support cell of level d that has no support child, chi is the trilinear interpolant of those eight values.
struct IndicatorValues {
    std::vector<std::vector<double>> values;  //!< per level, over the level's support vertices
    std::vector<double> at_samples;           //!< chi at each sample
};

//! Errors: Cancelled.
Result<IndicatorValues> solve_cascadic(const PoissonOctree& tree, const OrientedSamples& samples,
                                       const SolverOptions& options, std::vector<LevelSolveStats>* stats = nullptr);

}  // namespace surfaced::reconstruct
