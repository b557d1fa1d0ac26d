// Tensor-product Bézier surface patches: exact evaluation, derivatives and normals, and crack-free tessellation
// of a set of patches with a guaranteed chord tolerance.
//
// References:
//  - G. Farin, "Curves and Surfaces for CAGD", 5th ed., ch. 14-16 (tensor-product patches, de Casteljau).
//  - D. Filip, R. Magedson, R. Markot, "Surface algorithms using bounds on derivatives", CAGD 3 (1986): the
//    second-derivative bound used for tolerance-driven segment counts (derivation in bezier_patch.cpp).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "geometry/core/cancel.h"
#include "geometry/core/result.h"
#include "geometry/core/types.h"
#include "geometry/mesh/polygon_mesh.h"

namespace surfaced {

//! A tensor-product Bézier patch of degree degree_u x degree_v, polynomial or rational.
//! `points` holds (degree_u + 1) * (degree_v + 1) control points row-major with u varying fastest (geomview's
//! order): control point (i, j) -- i along u, j along v -- is points[j * (degree_u + 1) + i].
//! `weights`, when not empty, makes the patch rational: one weight > 0 per control point (same order), and the
//! surface is S = sum B_i B_j w_ij P_ij / sum B_i B_j w_ij (evaluated in homogeneous coordinates (w P, w)). The
//! points are the Euclidean control points (not multiplied by their weights).
//! `corner_uvs`, when set, are texture coordinates at the corners (u, v) = (0, 0), (1, 0), (0, 1), (1, 1) (the
//! order of the control net's corners in `points`); tessellation interpolates them bilinearly in (u, v) instead of
//! emitting (u, v) itself as the UVs.
struct BezierPatch {
    int degree_u = 3;
    int degree_v = 3;
    std::vector<Vec3> points;
    std::vector<double> weights;
    std::optional<std::array<Vec2, 4>> corner_uvs;

    int row_size() const { return degree_u + 1; }
    bool rational() const { return !weights.empty(); }
    const Vec3& at(int i, int j) const { return points[static_cast<std::size_t>(j * (degree_u + 1) + i)]; }
    double weight(int i, int j) const {
        return weights.empty() ? 1.0 : weights[static_cast<std::size_t>(j * (degree_u + 1) + i)];
    }
};

//! A collection of patches, e.g. the Utah teapot's 32. Patches meet along edges with identical control points.
struct PatchSet {
    std::vector<BezierPatch> patches;
};

//! Largest degree in either direction accepted by validate() (geomview's BEZ allows 1..6; JSON may go higher).
inline constexpr int kMaxPatchDegree = 15;

//! Largest ratio between the largest and the smallest weight of one rational patch (beyond it the error bound,
//! which divides by the smallest weight, is meaningless and evaluation loses all precision).
inline constexpr double kMaxWeightRatio = 1e12;

//! Degrees in 1..kMaxPatchDegree, the point count matching them, finite coordinates; for rational patches one
//! finite weight > 0 per point with w * P finite, and a largest/smallest weight ratio of at most kMaxWeightRatio.
//! Errors name the patch (ElementKind::None with GeoError::element = patch index) and what is wrong.
Status validate(std::span<const BezierPatch> patches);

//! Point at (u, v) in [0,1]^2 by separable de Casteljau: u on each row, then v on the resulting column.
Vec3 evaluate(const BezierPatch& patch, double u, double v);

//! Position and exact partial derivatives up to second order at (u, v).
struct PatchDerivatives {
    Vec3 position;
    Vec3 du, dv;
    Vec3 duu, duv, dvv;
};
PatchDerivatives evaluate_derivatives(const BezierPatch& patch, double u, double v);

//! Unit normal du x dv at (u, v). Where du x dv vanishes (a collapsed edge such as the teapot lid's apex, or a
//! corner where du and dv are parallel) it returns the limit of the normal as (u, v) is approached from inside
//! the patch, from the first-order Taylor expansion of du x dv; if that vanishes too, from a sample taken a short
//! way inside. Returns (0, 0, 0) only for a patch degenerate everywhere (e.g. all control points equal).
Vec3 unit_normal(const BezierPatch& patch, double u, double v);

//! Upper bound on the distance between the patch and its grid triangulation with nu x nv segments (any diagonal),
//! measured between points of equal parameter: (1/8) (Muu/nu^2 + 2 Muv/(nu nv) + Mvv/nv^2), M from the control net
//! (for rational patches, bounds on the quotient's second derivatives from the homogeneous net's differences and
//! the smallest weight; derivation in bezier_patch.cpp). A guarantee in both cases, not an estimate.
double tessellation_error_bound(const BezierPatch& patch, int nu, int nv);

//! Guaranteed bounds over [0, 1]^2 on the norms of the patch's first and second partial derivatives (patch
//! parameters): the Bernstein-convexity bounds from the net's differences (m max|Du b|, m(m-1) max|D2u b|, ...), and
//! for a rational patch the quotient-rule bounds of bezier_patch.cpp, tightened on 8 x 8 sub-patches. The second
//! derivatives are those tessellation_error_bound uses; the first bound how far S moves for a step in (u, v):
//! |S(p) - S(q)| <= u |p.u - q.u| + v |p.v - q.v|.
struct PatchDerivativeBounds {
    double u = 0, v = 0;
    double uu = 0, uv = 0, vv = 0;
};
PatchDerivativeBounds derivative_bounds(const BezierPatch& patch);

//! Upper bound on the distance from every point of the flat triangle through S(a), S(b), S(c) to the patch (a, b, c
//! in [0, 1]^2). Local and normal-aware, so far tighter than tessellation_error_bound on curved patches: bounds over
//! the triangle's parameter box from that box's own control net (the maximum over its 2 x 2 sub-boxes' nets), with
//! the equal-parameter error split into its component along the normal n0 at the box's centre (bounded through
//! n0 . S_uu, n0 . S_uv, n0 . S_vv) and a tangential drift that is absorbed by moving to another surface point of the
//! box grown by half its size (derivation in bezier_patch.cpp). Where the box touches a patch side the move runs along
//! that side and the drift across it is added; at a patch corner, where du x dv vanishes or the move would leave the
//! grown box, it is the box's equal-parameter bound. A guarantee, not an estimate. `enough`: when the bound from one
//! net over the box is already at most this, it is returned without the sub-boxes (a caller comparing against a
//! threshold passes it; 0 always takes the finer form). Costs a few net subdivisions and one evaluation.
double triangle_distance_bound(const BezierPatch& patch, Vec2 a, Vec2 b, Vec2 c, double enough = 0);

struct TessellationOptions {
    //! When set: the largest allowed distance between the triangles and the surface (in model units); segment
    //! counts are chosen per patch from the control net so that tessellation_error_bound <= tolerance.
    std::optional<double> tolerance;
    //! Without tolerance: this many segments along both directions of every patch.
    int segments = 8;
    //! Ceiling on the segments along one direction of one patch; a tolerance needing more is BudgetExceeded.
    int max_segments = 256;
    //! Merge vertices at bit-identical positions across patches (shared edges, collapsed edges).
    bool weld = true;
    //! Polled between patches by tessellate_patches; when it fires the result is Cancelled.
    Cancel cancel;
};

//! Segment counts of one patch: nu along u, nv along v (the grid has (nu + 1) x (nv + 1) vertices).
struct PatchSegments {
    int nu = 0, nv = 0;
};

//! The plan tessellate_patches follows, cheap to compute (no evaluation): segment counts per patch, made equal
//! along every edge two patches share (same control points, either direction) so that no T-junction or crack can
//! appear, and the resulting guaranteed bound. Use it to check budgets before any work.
struct TessellationPlan {
    std::vector<PatchSegments> segments;  //!< one per patch
    std::uint64_t triangles = 0;          //!< upper bound on output triangles (2 nu nv per patch)
    std::uint64_t vertices = 0;           //!< upper bound on output vertices (before welding)
    double error_bound = 0;               //!< max over patches of tessellation_error_bound
};
//! Errors: InvalidArgument (tolerance not finite and > 0, segments outside 1..max_segments), BudgetExceeded (a
//! tolerance that needs more than max_segments), and validate()'s errors.
Result<TessellationPlan> plan_tessellation(std::span<const BezierPatch> patches, const TessellationOptions& options);

struct PatchTessellation {
    //! Triangles, counter-clockwise around du x dv; per-vertex unit normals (exact surface normals; averaged where
    //! welded vertices come from several patches); face-varying uvs = the patch's own (u, v), or its corner_uvs
    //! interpolated bilinearly at (u, v) when it has them.
    PolygonMesh mesh;
    std::vector<Index> face_patches;  //!< index of the patch each face of `mesh` comes from
    TessellationPlan plan;
};

//! Tessellates every patch on its planned grid. Crack-free: vertices on a shared edge are computed from the edge's
//! control points alone in one canonical direction, so both patches produce bit-identical positions, and with
//! `weld` they become one vertex (the output is watertight where the patch set is). Triangles that collapse to a
//! segment or point (next to a collapsed edge) are dropped. Worst case output: plan.triangles triangles.
Result<PatchTessellation> tessellate_patches(std::span<const BezierPatch> patches, const TessellationOptions& options);

}  // namespace surfaced
