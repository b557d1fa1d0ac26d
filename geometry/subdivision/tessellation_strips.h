// The triangles of one tessellation domain for tessellate_limit (adaptive_tessellation.h): a regular grid when its
// sides carry its inner rates uniformly, else its inner grid joined to each side's points by a transition strip
// (Bfr::Tessellation's layout), and the exact triangle count of either.
//
// A domain's grid can be staggered (chosen per domain, where it takes fewer triangles): every odd row (t = t_j, j odd) has its points at the
// midpoints of the s intervals instead of on the s lines, and each band between two rows is triangulated by
// advancing along s. The triangles are then isosceles (base one interval, apex over its middle) instead of the two
// right triangles of a cell: their circumradius, which the interpolation error grows with, is 0.625 instead of
// 0.707 of a square cell's side, so a bound is met with about 0.78 times the points. Internal to
// geometry/subdivision.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "geometry/subdivision/adaptive_tessellation.h"
#include "geometry/subdivision/tessellation_bounds.h"

namespace surfaced::tessellation_detail {

//! A domain's triangulation in its own (s, t): local points (the boundary ring first: side k's points 0 .. r_k - 1
//! in order, then the inner points row by row) and triangles over them.
struct LocalMesh {
    std::vector<P2> points;
    std::vector<std::array<std::uint32_t, 3>> triangles;
};

//! Whether a grid of nu x nv segments asked to stagger (`asked`) staggers its odd rows: with two segments or more
//! each way.
inline bool staggered(bool asked, int nu, int nv) { return asked && nu >= 2 && nv >= 2; }

//! Line i of n graded lines (`lines` empty: uniform i / n).
inline double line_at(const std::vector<double>& lines, int n, int i) {
    return lines.empty() ? double(i) / n : lines[std::size_t(i)];
}

//! The s of the points of row j (0..nv) of a whole-domain grid, the sides' points included: the s lines, or on an
//! odd row of a staggered grid (`stagger` as staggered() gives it) the ends and the midpoints of the intervals.
std::vector<double> row_s(const std::vector<double>& s_lines, int nu, int nv, int j, bool stagger);

//! Triangulates the band between two rows of points running along s (`bottom` below `top`, each with its points'
//! s), counter-clockwise in (s, t): the row whose next point comes first advances.
void zigzag(std::span<const std::uint32_t> bottom, std::span<const double> bottom_s, std::span<const std::uint32_t> top,
            std::span<const double> top_s, std::vector<std::array<std::uint32_t, 3>>& out);

//! Triangulates the band between two rows of the same number of points at the same s: each cell's two right
//! triangles, on the diagonal from its lower left to its upper right corner.
void cells(std::span<const std::uint32_t> bottom, std::span<const std::uint32_t> top,
           std::vector<std::array<std::uint32_t, 3>>& out);

//! A uniform domain whose sides carry its inner rates: a regular grid, no transition strips.
bool is_grid(const LimitTessellationPlan::Domain& d);

std::uint64_t domain_triangles(const LimitTessellationPlan::Domain& d);

//! The domain's points off its sides, row by row (what triangulate puts after the ring).
std::vector<P2> inner_points(const LimitTessellationPlan::Domain& d);

//! Inner rates of a domain whose sides differ from them: at least 2 so that the inner grid has a point.
void fix_inner(LimitTessellationPlan::Domain& d);

LocalMesh triangulate(const LimitTessellationPlan::Domain& d);

}  // namespace surfaced::tessellation_detail
