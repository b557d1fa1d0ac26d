// Bounds on the Catmull-Clark limit surface over parts of a tessellation domain, for tessellate_limit
// (adaptive_tessellation.h): each patch's second-difference B-spline coefficients, their Bernstein bounds over a box
// projected on a triangle's normal, the interpolation-error bound of a triangle from them, and the measured distance
// of a triangle that no patch bounds. Internal to geometry/subdivision.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "geometry/core/result.h"
#include "geometry/core/types.h"
#include "geometry/subdivision/adaptive_tessellation.h"
#include "geometry/subdivision/limit_evaluation.h"

namespace surfaced::tessellation_detail {

struct P2 {
    double s = 0, t = 0;
};

//! Bounds on |S_ss|, |S_st|, |S_tt| over a region.
struct Bounds {
    double uu = 0, uv = 0, vv = 0;
    void include(const Bounds& b, double scale) {
        uu = std::max(uu, b.uu * scale);
        uv = std::max(uv, b.uv * scale);
        vv = std::max(vv, b.vv * scale);
    }
};

//! Bounds on the two signs of n . S_ss and n . S_tt (n a plane's normal) and on |n . S_st| over a region: `up` on
//! n . S_ss, |n . S_st|, n . S_tt (from above); `down` on -n . S_ss, |n . S_st|, -n . S_tt. A side's uu or vv is
//! negative where the surface curves the other way throughout, and then takes back part of the mixed term: with
//! uu + k uv and vv + uv / k (triangle_bound) both at most 0 that side is 0, as on a convex patch whose mixed
//! derivative is small against the others. Where the surface is saddle-shaped (S_ss and S_tt curve to opposite
//! sides of the plane) each sign has one direction's term only.
struct SignedBounds {
    Bounds up, down;
    void include(const SignedBounds& b, double scale) {
        up.include(b.up, scale);
        down.include(b.down, scale);
    }
    //! Bounds on |n . S_ss|, |n . S_st|, |n . S_tt|.
    Bounds magnitude() const {
        Bounds m = up;
        m.include(down, 1.0);
        return m;
    }
    //! Bounds known only in magnitude.
    static SignedBounds symmetric(const Bounds& m) { return {m, m}; }
};

//! A uniform bicubic B-spline patch's differences over its [0, 1]^2. S_s is a B-spline (quadratic in s, cubic in t)
//! of the first differences along s, S_ss a linear-by-cubic one of the second differences, S_st a biquadratic one of
//! the mixed differences; B-spline bases are >= 0 and sum to 1, so each derivative lies in the convex hull of its
//! coefficients: its norm, and its component along any direction, are bounded by theirs.
struct PatchData {
    std::array<Vec3, 12> du, dv;
    std::array<Vec3, 8> uu, vv;
    std::array<Vec3, 9> uv;
    Vec3 a0, b0;   //!< mean first differences along s and t (the centres used for the tangent cones)
    Bounds m;      //!< |S_ss|, |S_st|, |S_tt| over the patch
    Bounds plane;  //!< the same, for the component normal to any plane whose normal is in the patch's normal cone
    Vec3 n0;       //!< the unit normal a0 x b0 (zero when it has none)
};

PatchData patch_data(const std::array<Vec3, 16>& p);

//! Segments (nu, nv) with (1/8)(A/nu^2 + 2B/(nu nv) + C/nv^2) <= tolerance: each half <= tolerance / 2 when
//! nu >= sqrt((A + B) / (4 tol)) and nv >= sqrt((B + C) / (4 tol)) (2B/(nu nv) <= B/nu^2 + B/nv^2).
std::pair<double, double> rates_for(const Bounds& m, double tolerance);

//! (1/2) max over the triangle of sum l_i Q(p_i - x): Q is bounded by the diagonal form a ds^2 + c dt^2 with
//! a = Muu + k Muv, c = Mvv + Muv / k (2|ds dt| <= k ds^2 + dt^2 / k), k the box's aspect; in coordinates scaled
//! by (sqrt a, sqrt c) the maximum is the squared circumradius when the circumcentre is inside, else a quarter of
//! the longest edge squared.
double triangle_bound(const Bounds& m, const P2& p0, const P2& p1, const P2& p2);

//! The same for a scalar whose second derivatives have signed bounds: with d_i = p_i - x, the interpolant minus the
//! scalar at x is (1/2) sum l_i d_i^T H_i d_i, H_i a weighted mean of the Hessian along [x, p_i], so it lies between
//! -(1/2) sum l_i Q_down(d_i) and (1/2) sum l_i Q_up(d_i), each side bounded as above: the larger of the two sides'
//! bounds. `dominant` (when given) receives the bounds of the larger side.
double triangle_bound(const SignedBounds& m, const P2& p0, const P2& p1, const P2& p2, Bounds* dominant = nullptr);

//! The quad sub-face tile width of an N-gon in Bfr's parameterization (limit_evaluation.h).
int subface_columns(std::size_t n);

//! One base face's prepared surface and the bounds of its patches.
struct FaceData {
    std::optional<LimitFaceSurface> surface;
    std::vector<PatchData> patches;
    std::size_t size = 0;
    //! The largest distance a vertex moves off the surface (LimitTessellationOptions::straddle times the
    //! tolerance; 0: vertices on the surface).
    double lift = 0;
    //! With a lift: per face edge and corner, whether the surface is only C0 there (an infinitely sharp crease or
    //! corner, an open boundary): vertices on them stay on S.
    std::vector<bool> fixed_edge, fixed_vertex;
};

//! A tessellation vertex: `position` is S at its domain point moved by `offset` (along the normal there).
struct OffsetPoint {
    Vec3 position, offset;
};

//! Where a vertex whose limit sample is `sample` goes: moved by `lift` along the normal towards the convex side
//! where both principal curvatures have one sign (the chords there lie on one side of the surface; moved, the
//! triangles' distance to it is split between both sides), not at all on a saddle whose smaller curvature is at
//! least kSaddleTaper of the larger (the chords already cross it, by amounts that depend on the triangles' extent
//! along each principal direction, unknown when the vertex is placed), linearly in between. `sample` needs its
//! second derivatives; without them (at an irregular vertex) the vertex stays on the surface.
Vec3 straddle_offset(const LimitSample& sample, double lift);
//! See straddle_offset: the ratio of a saddle's principal curvatures (smaller / larger) from which vertices stay.
inline constexpr double kSaddleTaper = 0.05;

//! Patches narrower than this (deeper than kBoundedDepth in the domain) are sampled, not bounded: their bounds grow
//! without limit towards an extraordinary vertex of valence > 4 (curvature diverges there), which would drive the
//! rates of the whole domain.
constexpr double kBoundedWidth = 1.0 / (1 << kBoundedDepth);

//! What a region of a domain overlaps: the largest patch bounds (scaled to the domain) and whether it reaches a
//! leaf without a patch.
struct Overlap {
    Bounds m;
    bool uncovered = false;
    P2 uncovered_lo{1, 1}, uncovered_hi{0, 0};  //!< the box of the uncovered parts (when uncovered)
    void uncover(double s0, double t0, double w) {
        uncovered = true;
        uncovered_lo = {std::min(uncovered_lo.s, s0), std::min(uncovered_lo.t, t0)};
        uncovered_hi = {std::max(uncovered_hi.s, s0 + w), std::max(uncovered_hi.t, t0 + w)};
    }
    struct Piece {
        std::uint32_t patch;
        double s0, t0, w;  //!< the patch's square in the domain
    };
    std::vector<Piece> patches;
};

//! Adds to `out` what the box [lo, hi] overlaps (with positive area) below tree node `node`, whose square in the
//! domain is [s0, s0 + w] x [t0, t0 + w].
void query(const FaceData& fd, std::size_t node, double s0, double t0, double w, const P2& lo, const P2& hi,
           Overlap& out);

//! Root node of a domain in its face's tree.
std::size_t domain_root(const FaceData& fd, int subface);

//! Face (u, v) of domain (s, t).
std::pair<double, double> face_uv(std::size_t n, int subface, double s, double t);

Overlap overlap_of(const FaceData& fd, int subface, const P2& a, const P2& b, const P2& c);

//! Bounds on |n . S_ss|, |n . S_st|, |n . S_tt| over the box [s0, s1] x [t0, t1] of a patch's [0, 1]^2 (patch
//! units): the Bernstein coefficients of the three derivatives (linear x cubic, biquadratic, cubic x linear
//! B-splines of the patch's differences) over the box. Never above `along`'s bounds over the whole patch.
Bounds along_in_box(const PatchData& p, const Vec3& n, double s0, double s1, double t0, double t1);

//! along_in_box with the signs of n . S_ss and n . S_tt kept apart (the smallest and largest Bernstein coefficient).
SignedBounds signed_in_box(const PatchData& p, const Vec3& n, double s0, double s1, double t0, double t1);

//! Second-derivative bounds of the component of S along the unit normal `m` of a triangle's plane, over the parts
//! of the patches `o` holds inside the box [lo, hi] (the rest is `o.uncovered`), for triangle_bound: the distance
//! from S(x) to the plane of the triangle of S at its corners is |m . (S(x) - T(x))|, the interpolation error of
//! the scalar m . S, whose second derivatives are bounded by the Bernstein coefficients, over the box, of the
//! patches' differences projected on m. Only the surface's bending away from the plane counts, not the
//! parameterization's tangential non-uniformity. Without a normal (a degenerate triangle): the bounds on |S_xx|.
SignedBounds plane_bounds(const FaceData& fd, const Overlap& o, const std::optional<Vec3>& m, const P2& lo,
                          const P2& hi);

//! Bounds on |S_ss|, |S_st|, |S_tt| (the full vectors) over the box [lo, hi]: the norm of the per-axis bounds. For a
//! triangle with an edge on an open boundary, where a point of S whose projection falls outside the triangle has no
//! neighbour to be near: the distance to the triangle is at most |S(x) - T(x)|, bounded by these.
Bounds full_bounds(const FaceData& fd, const Overlap& o, const P2& lo, const P2& hi);

//! plane_bounds over a triangle's bounding box.
SignedBounds plane_bounds(const FaceData& fd, const Overlap& o, const std::optional<Vec3>& m, const P2& a, const P2& b,
                          const P2& c);

//! Unit normal of the triangle (a, b, c), if it has one.
std::optional<Vec3> unit_normal(const Vec3& a, const Vec3& b, const Vec3& c);

//! S at domain point p, and the vertex there (the same, moved by straddle_offset with the face's lift).
Result<Vec3> position_at(const FaceData& fd, int subface, const P2& p);
Result<OffsetPoint> corner_at(const FaceData& fd, int subface, const P2& p);

//! The bound on the distance from S to the plane of a triangle whose corners are moved off S: with the plane's unit
//! normal m, m . S minus its interpolant between the corners' S lies in [-up, down] (triangle_bound of `m`'s two
//! sides), and the corners' offsets add their components along m, interpolated; without a normal (`normal` empty,
//! `m` then bounds |S - T| in every direction) the offsets' largest length is added. `dominant` as triangle_bound.
double offset_bound(const SignedBounds& m, const P2& p0, const P2& p1, const P2& p2, const std::optional<Vec3>& normal,
                    const std::array<Vec3, 3>& offsets, Bounds* dominant = nullptr);

//! A triangle's error measured where no patch bounds it.
struct SampledError {
    //! The largest distance from S(x) to the plane of the triangle's vertices, over the points x of a barycentric
    //! grid of step 1/6 of the triangle in (s, t) and its corners. (Not |S(x) - T(x)|: at an extraordinary vertex the
    //! parameterization is singular, and the parametric difference falls only as fast as the triangle shrinks.)
    double measured = 0;
    //! What the triangle is held to: the same with the surface's own bending away from the chords (m . S minus its
    //! interpolant between the corners' S, m the plane's normal) taken kSampledSafety times, against samples missing
    //! its peak; the vertices' offsets (straddle_offset) are known exactly. kSampledSafety x `measured` without
    //! offsets.
    double check = 0;
};

//! The sampled error of the triangle (a, b, c) of a domain whose vertices are `corners`, or, without them, the
//! vertices corner_at places there. `whole_distance`: the distance to the triangle itself rather than to its plane
//! (a triangle with an edge on an open boundary or a fold, where nothing beyond that edge is near the samples whose
//! projections fall outside it).
Result<SampledError> sampled_error(const FaceData& fd, int subface, const P2& a, const P2& b, const P2& c,
                                   const std::array<OffsetPoint, 3>& corners, bool whole_distance = false);
Result<SampledError> sampled_error(const FaceData& fd, int subface, const P2& a, const P2& b, const P2& c);

//! What one triangle of a domain is held to: `bound`, the guaranteed bound on its distance to the surface (0 when
//! not guaranteed), and where no patch bounds it (everywhere when not guaranteed) the sampled error: `sampled` as
//! measured, `check` as tested (SampledError).
struct TriangleError {
    double bound = 0, sampled = 0, check = 0;
    //! The larger of bound / tolerance and check / tolerance: at most 1 passes.
    double ratio(double tolerance) const { return std::max(bound, check) / tolerance; }
};

//! The error of the triangle (a, b, c) of a domain, whose vertices are `corners` (read only when `guaranteed`): bounded over the patches its
//! bounding box overlaps with its own plane (with the full second derivatives when it has an edge on a side
//! `open_sides` marks as an open boundary of the mesh), and sampled where it reaches a part no patch bounds.
Result<TriangleError> triangle_error(const FaceData& fd, int subface, const std::array<bool, 4>& open_sides,
                                     const P2& a, const P2& b, const P2& c, const std::array<OffsetPoint, 3>& corners,
                                     bool guaranteed);

}  // namespace surfaced::tessellation_detail
