// The grids of tessellate_limit's domains (adaptive_tessellation.h): densities per 1/32 of a domain direction, the
// graded grid lines they give, and the grid one domain needs, graded from bounds (guaranteed) or uniform from measured
// distances; the budget errors they share with the planning. Internal to geometry/subdivision.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "geometry/core/result.h"
#include "geometry/subdivision/adaptive_tessellation.h"
#include "geometry/subdivision/tessellation_bounds.h"

namespace surfaced::tessellation_detail {

//! Bins of a domain direction for graded grids: as fine as the shallowest patches that are sampled rather than
//! bounded, so that every bounded patch covers whole bins.
constexpr int kBins = 1 << kBoundedDepth;

//! Segments per unit length a direction needs, per bin.
using Density = std::array<double, kBins>;

//! BudgetExceeded when `triangles` is above options.max_triangles (0: no limit).
Status check_budget(std::uint64_t triangles, const LimitTessellationOptions& options);

//! The BudgetExceeded error of a rate above options.max_segments, naming `face`.
GeoError too_many_segments(double needed, const LimitTessellationOptions& options, std::size_t face);

//! Grid lines from 0 to 1 spaced in proportion to 1 / rho (the spacing in bin b at most 1 / rho[b]): their count
//! of segments, and the lines (empty when they are uniform: rho constant, or one segment).
std::pair<int, std::vector<double>> grid_lines(const Density& rho);

//! Raises the density over [lo, hi) to `rho`.
void raise(Density& density, double lo, double hi, double rho);

//! A graded domain's grid: lines along s and t from densities.
struct Graded {
    Density rs{}, rt{};
    int nu = 1, nv = 1;
    std::vector<double> s_lines, t_lines;
    bool staggered = false;  //!< odd rows at the midpoints (tessellation_strips.h)
};

//! The lines of `g` from its densities; BudgetExceeded above options.max_segments.
Status regrade(Graded& g, const LimitTessellationOptions& options, std::size_t face);

//! Gives domain `d` the grid of `g`.
void apply(const Graded& g, LimitTessellationPlan::Domain& d);

//! The graded grid one domain needs: the bounded patches give the densities (each patch's second derivatives along
//! its mean normal, an estimate), then every cell's two triangles are bounded with their own planes (sampled where
//! no patch bounds them) and the densities raised where a cell exceeds the tolerance (around a patch whose own bound
//! fails, else over the cell), until none does; the grid is then coarsened where every cell over a bin has room and
//! refined again (six times), then one line fewer is tried along s, then along t, while the grid passes; the
//! smallest grid within the tolerance is kept. This is done for the plain and the staggered layout
//! (tessellation_strips.h), and the one with fewer triangles is returned (the staggered one only from
//! kStaggerFrom segments each way, and never when it alone would exceed the budget).
Result<Graded> graded_demand(const FaceData& fd, std::size_t face, int subface,
                             const LimitTessellationOptions& options);

//! The rates one domain needs on a regular grid: bounded cells within the tolerance, sampled cells within
//! tolerance / kSampledSafety. Returns (nu, nv).
Result<std::pair<int, int>> domain_demand(const FaceData& fd, std::size_t face, int subface,
                                          const LimitTessellationOptions& options);

}  // namespace surfaced::tessellation_detail
