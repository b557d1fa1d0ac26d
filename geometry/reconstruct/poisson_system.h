// The discrete screened Poisson system on one level of the octree (geometry/reconstruct/octree.h).
//
// Basis: degree-1 B-splines (trilinear "hat" functions), one per corner of an active cell of each level; the
// reconstructed indicator is the sum over all levels, chi = sum_d sum_v x_{d,v} phi_{d,v}. Hats of level d are
// exact combinations of hats of level d+1 (weights 1, 1/2, 1/4, 1/8 by the number of odd coordinates), which is
// what the restriction of the right-hand side below and the level-to-level interpolation in the solver use.
//
// Energy (Kazhdan & Hoppe 2013, eq. 3), in unit-cube coordinates:
//   E(chi) = integral |grad chi - V|^2 + beta * sum_i w_i chi(p_i)^2,   beta = alpha * 2^d * area / sum_i w_i,
// the screening weight scaled by 2^d on level d so that it keeps the same proportion to the Laplacian (whose
// entries shrink like the cell size) on every level; a sample screens the levels down to its splatting depth only
// (assign_splat_depths; the level just finer than a fractional depth D + t with weight t). Its Galerkin system on level d is
//   A_d x = b_d,  A_d(v, w) = integral grad phi_v . grad phi_w + beta sum_i w_i phi_v(p_i) phi_w(p_i),
//                 b_d(v) = integral grad phi_v . V.
// V is splatted from the oriented samples: V = sum_i a_i N_i delta_{p_i}, each delta smoothed into the eight hats of
// the sample's cells on the two levels around its splatting depth (a_i = area * w_i / sum w, the share of the
// surface the sample stands for, assign_area_shares), so V = sum_d sum_w n_{d,w} phi_{d,w} / h_d^3; the integrals
// of products of hats and their derivatives are closed-form 27-point stencils. With outward normals chi increases outwards (chi < iso inside).
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/core/types.h"
#include "geometry/reconstruct/octree.h"

namespace surfaced::reconstruct {

struct OrientedSamples {
    std::vector<Vec3> positions;  //!< unit-cube coordinates
    std::vector<Vec3> normals;    //!< unit, outward
    std::vector<double> weights;  //!< > 0 (confidence; 1 when not used)
    double weight_sum = 0;
    double area = 0;  //!< estimated area of the sampled surface, unit-cube units
    //! The real-valued depth each sample is splatted at (empty: the finest); see assign_splat_depths. Depth
    //! D + t (D integer, 0 <= t < 1) puts 1 - t of the sample's normal on level D and t on level D + 1.
    std::vector<double> splat_depths;
    //! The area each sample's normal stands for, summing to `area` (empty: area * w_i / weight_sum); see
    //! assign_area_shares.
    std::vector<double> area_shares;
};

//! The local sampling density at each sample: the count of samples splatted trilinearly on the corners of level
//! `depth` and interpolated back at the sample (a kernel about two cells wide), about the number of samples per cell
//! of that level around the sample.
std::vector<double> sample_density(const OrientedSamples& samples, int depth);

//! Density-adapted splatting (Kazhdan & Hoppe 2013 sec. 4.1, after Kazhdan et al. 2006), with a continuous depth:
//! each sample goes to the real-valued depth at which a square of the surface a cell wide would hold
//! `samples_per_node` samples, density_depth + log4(1.5 density_i / samples_per_node) (a plane crosses a cell over
//! h^2 / 1.5 on average; on a surface the samples per cell shrink by 4 per level), clamped to
//! [min_depth, max_depth]. `density` is sample_density(samples, density_depth). Where samples are sparse
//! for the finest cells, V is thus smoothed over coarser ones instead of being a set of isolated spikes, and the
//! split between the two bracketing levels avoids the jump of a whole level between neighbouring samples.
void assign_splat_depths(OrientedSamples& samples, const std::vector<double>& density, int density_depth, int min_depth,
                         int max_depth, double samples_per_node);

//! Shares of the area inversely proportional to the local sampling density (after Kazhdan & Hoppe 2013):
//! sample i stands for area * (w_i / density_i) / sum_j (w_j / density_j), density = sample_density(samples, depth)
//! (computed when not given). On an evenly
//! sampled surface every sample gets area * w_i / sum w; where samples crowd, each stands for less, so that V has
//! the same strength per unit of area on densely and sparsely sampled sides.
void assign_area_shares(OrientedSamples& samples, int depth);
void assign_area_shares(OrientedSamples& samples, const std::vector<double>& density);

//! Trilinear weights of the eight corners of p's cell on level `depth` (corner c = bits (x, y, z)).
void corner_weights(const Vec3& p, int depth, std::uint64_t cell, double weights[8]);

//! The 27-point neighbourhoods of a level's dofs, as positions among the level's support vertices (every neighbour of
//! a dof inside the cube is one, octree.h). The position of (i, j + b, k + c) for dof v = (i, j, k) is
//! position(v, (b + 1) + 3 (c + 1)), and its neighbours (i -/+ 1, j + b, k + c) are the positions just before and
//! after it (the keys are sorted with i fastest, and all three are support vertices). Dofs come in runs of
//! consecutive i in one (j, k) row, and so do each of their neighbour rows (all are support vertices), so the
//! positions are stored once per run: a run's first dof's nine, and each dof's offset from it. A row whose j + b or
//! k + c leaves the grid points into a padding of zeros after the support vertices (as long as the longest run), so
//! arrays read through the rows have padded_size() entries. Dofs with i = 0 or i = 2^d (on_edge: 1 and 2) lack the
//! -1 or +1 neighbour and are read with checks.
struct StencilRows {
    std::vector<std::uint32_t> run;    //!< per dof: its run
    std::vector<std::uint32_t> first;  //!< per run: its first dof
    std::vector<std::uint32_t> rows;   //!< 9 per run: the positions of its first dof's neighbour rows
    std::vector<char> on_edge;         //!< per dof: 1 for i = 0, 2 for i = 2^d, else 0
    std::size_t support = 0;           //!< the level's support vertices
    std::size_t longest = 0;           //!< the longest run

    std::size_t padded_size() const { return support + longest + 3; }
    //! The position of dof v's neighbour row q = (b + 1) + 3 (c + 1).
    std::uint32_t position(std::size_t v, int q) const {
        const std::uint32_t r = run[v];
        return rows[9 * std::size_t{r} + static_cast<std::size_t>(q)] + static_cast<std::uint32_t>(v - first[r]);
    }
    std::size_t memory_bytes() const {
        return run.capacity() * 4 + first.capacity() * 4 + rows.capacity() * 4 + on_edge.capacity();
    }
    //! Nine sorted passes (one per row) over the runs' first dofs, on two threads for a large level when `threaded`.
    static StencilRows build(const OctreeLevel& level, bool threaded);
};

//! b_d for every level (indexed like PoissonOctree::levels, each over the level's dofs): the splatted normal field
//! against the level's hats. Splats of the level and finer ones are integrated on their own level and restricted
//! level by level to coarser hats; splats of coarser levels are interpolated to the level's grid and integrated
//! there (both exact, the spaces being nested). `rows`: StencilRows::build of every level.
//! `threaded`: the sorted passes of large levels on two threads (the result does not depend on it).
std::vector<std::vector<double>> divergence_rhs(const PoissonOctree& tree, const OrientedSamples& samples,
                                                const std::vector<StencilRows>& rows, bool threaded = false);

//! The operator A_d of one level, applied without assembling it: the stiffness stencil over a neighbour table and
//! the screening term through the samples. Dofs on the cube's boundary are fixed at zero for Dirichlet conditions.
class LevelSystem {
public:
    //! `rows`: StencilRows::build of the level (the system keeps them). `threaded`: subtract_stiffness of a large
    //! level on two threads (same result).
    LevelSystem(const PoissonOctree& tree, int depth, const OrientedSamples& samples, double alpha, bool dirichlet,
                StencilRows rows, bool threaded = false);

    std::size_t size() const { return fixed_.size(); }
    //! y = A x on the free dofs (0 on fixed ones); the stiffness rows on two threads when `threaded` (each row is
    //! summed alone, so the result does not depend on it).
    void apply(const std::vector<double>& x, std::vector<double>& y, bool threaded = false) const;
    const std::vector<double>& diagonal() const { return diagonal_; }
    const std::vector<char>& fixed() const { return fixed_; }

    //! out[v] -= (stiffness * u)[v], u given at the level's support vertices (a coarser levels' function).
    void subtract_stiffness(const std::vector<double>& support_values, std::vector<double>& out) const;
    //! out[v] -= beta sum_i w_i phi_v(p_i) values[i] (the screening of a coarser levels' function).
    void subtract_screening(const std::vector<double>& sample_values, std::vector<double>& out) const;
    //! sum_c phi_c(p_i) x_c for every sample.
    void evaluate_at_samples(const std::vector<double>& x, std::vector<double>& out) const;

    std::size_t memory_bytes() const;

private:
    const PoissonOctree& tree_;
    const OctreeLevel& level_;
    const OrientedSamples& samples_;
    double h_ = 1;
    double beta_ = 0;
    bool threaded_ = false;
    bool any_fixed_ = false;  //!< whether any dof is fixed (Dirichlet conditions); the products skip the checks if not
    StencilRows rows_;
    //! apply()'s argument spread over the support vertices (zero off the dofs), read through rows_; apply() is
    //! therefore not safe to call concurrently on one LevelSystem
    mutable std::vector<double> spread_;
    std::vector<std::uint32_t> sample_dofs_;   //!< 8 per sample: the corners of its cell
    std::vector<std::uint64_t> sample_cells_;  //!< the cell of each sample on this level
    std::vector<double> sample_weights_;       //!< 8 per screening sample: the trilinear weights of its corners
    std::vector<double> screening_;            //!< beta w_i, times the share of the level at a fractional depth
    //! on levels with many samples per cell: per cell holding samples, its 8 corner dofs and the 8 x 8 screening
    //! matrix of its samples (apply() uses these instead of the samples)
    std::vector<std::uint32_t> cell_dofs_;
    std::vector<double> cell_screening_;
    //! on other levels, with two threads: the dofs samples screen (ascending), where each one's slots start in
    //! screen_slots_, and the slots (8 sample + corner) sorted by dof, in sample order within a dof; apply() gathers
    //! through them into y, after the samples' values are formed in sample_values_ (so not safe concurrently)
    std::vector<std::uint32_t> screen_dofs_;
    std::vector<std::uint32_t> screen_offsets_;
    std::vector<std::uint32_t> screen_slots_;
    mutable std::vector<double> sample_values_;
    std::vector<char> fixed_;
    std::vector<double> diagonal_;
};

}  // namespace surfaced::reconstruct
