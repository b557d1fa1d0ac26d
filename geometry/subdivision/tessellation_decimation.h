// Bounded vertex removal for tessellate_limit (adaptive_tessellation.h). A domain's graded grid spans whole lines:
// a band of high curvature along one side makes its lines cross the flat rest of the domain as well. Removing
// vertices by half-edge collapses, each accepted only when every triangle it creates still passes the same test as
// the grids' (triangle_error within the tolerance), keeps those lines only where they are needed.
//
// A collapse moves a vertex v onto a neighbour w and removes the triangles on the edge vw. It keeps the output
// valid: every triangle stays inside one domain and keeps its orientation in that domain's (s, t); a vertex on a
// domain side (a base edge or a spoke) moves only along that side, onto a neighbour on it in every domain it is in,
// so the sides stay shared by index and the output stays watertight; domain corners (base vertices, an N-gon's
// centre and edge midpoints) never move; the link condition keeps the surface manifold. Collapses go cheapest first
// (the smallest largest error ratio of the triangles they create), in two rounds, each followed by a pass of edge
// flips inside a domain that lower the larger error ratio of an edge's two triangles. Internal to
// geometry/subdivision.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "geometry/core/result.h"
#include "geometry/core/types.h"
#include "geometry/subdivision/adaptive_tessellation.h"
#include "geometry/subdivision/tessellation_bounds.h"

namespace surfaced::tessellation_detail {

//! One output triangle: its domain, its vertex ids and their (s, t) in that domain.
struct DomainTriangle {
    std::uint32_t domain = 0;
    std::array<Index, 3> v{};
    std::array<P2, 3> p{};
};

//! What a domain's triangles are bounded with.
struct DecimationDomain {
    const FaceData* face = nullptr;
    int subface = -1;
    std::array<bool, 4> open_sides{};
};

struct DecimationResult {
    std::size_t removed_vertices = 0;
    TriangleError worst;  //!< the largest bound and sampled error over the triangles left
};

//! Removes vertices from `triangles` (whose corners are `positions`, `offsets` off the surface) while every triangle stays within
//! options.tolerance; the triangles that remain are left in `triangles`, in their original order. Errors:
//! Cancelled, and the evaluator's.
Result<DecimationResult> decimate(std::vector<DomainTriangle>& triangles, const std::vector<Vec3>& positions,
                                  const std::vector<Vec3>& offsets, const std::vector<DecimationDomain>& domains,
                                  const LimitTessellationOptions& options);

}  // namespace surfaced::tessellation_detail
