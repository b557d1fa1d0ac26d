// The triangles of one tessellation domain for tessellate_limit (adaptive_tessellation.h): a regular grid when its
// sides carry its inner rates uniformly, else its inner grid joined to each side's points by a transition strip
// (Bfr::Tessellation's layout), and the exact triangle count of either. Internal to geometry/subdivision.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "geometry/subdivision/adaptive_tessellation.h"
#include "geometry/subdivision/tessellation_bounds.h"

namespace surfaced::tessellation_detail {

//! A domain's triangulation in its own (s, t): local points (the boundary ring first: side k's points 0 .. r_k - 1
//! in order, then the inner grid row by row) and triangles over them.
struct LocalMesh {
    std::vector<P2> points;
    std::vector<std::array<std::uint32_t, 3>> triangles;
};

//! A uniform domain whose sides carry its inner rates: a regular grid, no transition strips.
bool is_grid(const LimitTessellationPlan::Domain& d);

std::uint64_t domain_triangles(const LimitTessellationPlan::Domain& d);

//! Inner rates of a domain whose sides differ from them: at least 2 so that the inner grid has a point.
void fix_inner(LimitTessellationPlan::Domain& d);

LocalMesh triangulate(const LimitTessellationPlan::Domain& d);

}  // namespace surfaced::tessellation_detail
