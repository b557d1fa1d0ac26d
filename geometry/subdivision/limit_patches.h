// The Catmull-Clark limit surface as bicubic Bézier patches a client can evaluate or tessellate itself (the role of
// OpenSubdiv's Far::PatchTable, exported).
//
// Layout. Every base face is cut into the squares of one uniform isolation level L in its (u, v) domain (Bfr's
// parameterization, limit_evaluation.h): a quad into 4^L squares, an N-gon's quad sub-faces into 4^(L-1) each, so that
// along every edge both neighbours have 2^L pieces and patches meet edge to edge (no T-junctions; the patches form a
// conforming quad layout that tessellate_patches() welds watertight).
//  * Where the limit surface over a square is one bicubic B-spline patch (regular regions, infinitely sharp creases
//    and corners) the square's patch is that B-spline converted to Bézier form and cut to the square: the exact limit
//    surface, up to rounding.
//  * The remaining squares (next to irregular vertices, and along semi-sharp features sharper than L) are
//    approximated: the bicubic Bézier patch interpolating the exact limit surface on a 4 x 4 grid of the square
//    (parameters 0, 1/3, 2/3, 1). Shared boundaries interpolate the same exact points, so neighbours agree.
//    Their error is bounded, not sampled (`max_error`): the face's surface is prepared 10 levels deeper than the
//    square, so that the square is covered by B-spline patches (the surface itself) except for leaves 2^-10 of its
//    side wide at irregular vertices. Over each such patch the difference of the two surfaces is a bicubic
//    polynomial whose largest Bézier control point bounds it (split into quarters where that is not within 1% of a
//    value it takes); over each remaining leaf the limit surface lies in the convex hull of the control points of
//    the faces around it (every rule of the scheme is a convex combination), so the approximation's farthest point
//    from a centre plus the hull's farthest point bound the distance there. Against dense exact samples the bound
//    is 1.00 to 1.12 times the largest distance found, on the regression shapes. It shrinks with L by the
//    subdominant eigenvalue of the vertex's subdivision matrix per level (about 2.4x at valence 3).
// L is given, or chosen as the smallest in [L_min, max_levels] whose bound is within `tolerance` (L_min is 1 when the
// mesh has N-gons, else 0).
//
// Crack-free output. Corner points and shared boundary rows are computed in different faces (different rounding):
// positions closer than 1e-9 of the bounding-box diagonal are made bit-identical, corners first, then each shared
// edge's two inner control points, so that tessellate_patches() sees shared edges as shared.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "geometry/core/cancel.h"
#include "geometry/core/result.h"
#include "geometry/subdivision/limit_evaluation.h"
#include "geometry/surfaces/bezier_patch.h"

namespace surfaced {

struct LimitPatchOptions {
    //! The isolation level; unset: the smallest reaching `tolerance`.
    std::optional<int> levels;
    //! Largest allowed distance between an approximated patch and the limit surface (model units, bounded); used
    //! when `levels` is unset. Must be finite and > 0 then.
    double tolerance = 1e-3;
    //! Highest level tried (and allowed); 0..10.
    int max_levels = 6;
    //! Ceiling on the number of patches; a level needing more is BudgetExceeded (before any patch is made).
    std::uint64_t max_patches = 1'000'000;
    Cancel cancel;
};

struct LimitPatchSet {
    std::vector<BezierPatch> patches;            //!< bicubic, polynomial
    std::vector<std::uint32_t> faces;            //!< the base face of each patch
    std::vector<std::array<double, 3>> squares;  //!< (u0, v0, size): the patch's square in its face's (u, v)
    std::vector<bool> exact;                     //!< true: the limit surface itself; false: an approximation
    int levels = 0;                              //!< the isolation level used
    std::size_t approximate_count = 0;           //!< patches with exact false
    double max_error = 0;  //!< bound on the distance of every approximated patch to the limit surface
};

//! Number of patches at isolation level `levels`: 4^levels per quad, N 4^(levels-1) per N-gon (an upper bound: holes
//! have none).
std::uint64_t limit_patch_count(const PolygonMesh& mesh, int levels);

//! The smallest isolation level the mesh allows: 1 when it has a face that is not a quad, else 0.
int min_limit_patch_level(const PolygonMesh& mesh);

//! The limit surface of `evaluator` (Catmull-Clark; created from `mesh` with the request's subdivision options) as
//! patches. Unsupported for a Loop evaluator (its patches are triangular box splines, not bicubic).
//! Errors: InvalidArgument (levels outside [min level, max_levels], max_levels outside 0..10, tolerance not finite
//! and > 0 when levels is unset), BudgetExceeded (max_patches; or no level up to max_levels reaches the tolerance),
//! Cancelled, and the evaluator's errors.
Result<LimitPatchSet> limit_patches(const LimitSurfaceEvaluator& evaluator, const PolygonMesh& mesh,
                                    const LimitPatchOptions& options);

}  // namespace surfaced
