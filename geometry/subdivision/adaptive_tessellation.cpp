#include "geometry/subdivision/adaptive_tessellation.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <utility>

#include "geometry/core/format_number.h"
#include "geometry/spatial/closest_point.h"

namespace surfaced {
namespace {

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

//! Bounds on the component along a unit direction n: |n . S_xx| <= max |n . coefficient|.
Bounds along(const PatchData& p, const Vec3& n) {
    Bounds b;
    for (const Vec3& d : p.uu) b.uu = std::max(b.uu, std::abs(dot(n, d)));
    for (const Vec3& d : p.vv) b.vv = std::max(b.vv, std::abs(dot(n, d)));
    for (const Vec3& d : p.uv) b.uv = std::max(b.uv, std::abs(dot(n, d)));
    return b;
}

//! min(M, Mn + delta M) componentwise: the bound on |m . S_xx| for a unit m within delta of n (|m . v| <= |v| and
//! |m . v| <= |n . v| + |m - n| |v|).
Bounds tilted(const Bounds& m, const Bounds& mn, double delta) {
    return {std::min(m.uu, mn.uu + delta * m.uu), std::min(m.uv, mn.uv + delta * m.uv),
            std::min(m.vv, mn.vv + delta * m.vv)};
}

//! |m - n| for unit vectors at an angle whose sine is at most `sine` (< 1; the angle below 90 degrees).
double chord_of_sine(double sine) {
    if (!(sine < 1)) return 2.0;
    return std::sqrt(std::max(0.0, 2.0 - 2.0 * std::sqrt(1.0 - sine * sine)));
}

PatchData patch_data(const std::array<Vec3, 16>& p) {
    PatchData d;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 3; ++c) {
            d.du[std::size_t(3 * r + c)] = p[4 * r + c + 1] - p[4 * r + c];
            d.dv[std::size_t(3 * r + c)] = p[4 * (c + 1) + r] - p[4 * c + r];
        }
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 2; ++c) {
            d.uu[std::size_t(2 * r + c)] = p[4 * r + c] - 2.0 * p[4 * r + c + 1] + p[4 * r + c + 2];
            d.vv[std::size_t(2 * r + c)] = p[4 * c + r] - 2.0 * p[4 * (c + 1) + r] + p[4 * (c + 2) + r];
        }
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            d.uv[std::size_t(3 * r + c)] =
                p[4 * (r + 1) + c + 1] - p[4 * (r + 1) + c] - p[4 * r + c + 1] + p[4 * r + c];
    for (const Vec3& v : d.uu) d.m.uu = std::max(d.m.uu, norm(v));
    for (const Vec3& v : d.vv) d.m.vv = std::max(d.m.vv, norm(v));
    for (const Vec3& v : d.uv) d.m.uv = std::max(d.m.uv, norm(v));
    for (std::size_t i = 0; i < 12; ++i) {
        d.a0 += d.du[i] * (1.0 / 12);
        d.b0 += d.dv[i] * (1.0 / 12);
    }
    // normal cone: S_s = a0 + da, S_t = b0 + db with |da| <= ra, |db| <= rb, so |S_s x S_t - a0 x b0| <= e
    double ra = 0, rb = 0;
    for (std::size_t i = 0; i < 12; ++i) {
        ra = std::max(ra, norm(d.du[i] - d.a0));
        rb = std::max(rb, norm(d.dv[i] - d.b0));
    }
    const Vec3 n0 = cross(d.a0, d.b0);
    const double length = norm(n0);
    const double e = norm(d.a0) * rb + ra * norm(d.b0) + ra * rb;
    d.plane = d.m;
    if (length > 0) {
        d.n0 = n0 * (1.0 / length);
        d.plane = tilted(d.m, along(d, d.n0), chord_of_sine(e / length));
    }
    return d;
}

//! Segments (nu, nv) with (1/8)(A/nu^2 + 2B/(nu nv) + C/nv^2) <= tolerance: each half <= tolerance / 2 when
//! nu >= sqrt((A + B) / (4 tol)) and nv >= sqrt((B + C) / (4 tol)) (2B/(nu nv) <= B/nu^2 + B/nv^2).
std::pair<double, double> rates_for(const Bounds& m, double tolerance) {
    return {std::max(1.0, std::ceil(std::sqrt((m.uu + m.uv) / (4.0 * tolerance)))),
            std::max(1.0, std::ceil(std::sqrt((m.uv + m.vv) / (4.0 * tolerance))))};
}

//! (1/2) max over the triangle of sum l_i Q(p_i - x): Q is bounded by the diagonal form a ds^2 + c dt^2 with
//! a = Muu + k Muv, c = Mvv + Muv / k (2|ds dt| <= k ds^2 + dt^2 / k), k the box's aspect; in coordinates scaled
//! by (sqrt a, sqrt c) the maximum is the squared circumradius when the circumcentre is inside, else a quarter of
//! the longest edge squared.
double triangle_bound(const Bounds& m, const P2& p0, const P2& p1, const P2& p2) {
    const double ds = std::max({p0.s, p1.s, p2.s}) - std::min({p0.s, p1.s, p2.s});
    const double dt = std::max({p0.t, p1.t, p2.t}) - std::min({p0.t, p1.t, p2.t});
    const double k = ds > 0 && dt > 0 ? dt / ds : 1.0;
    const double a = std::sqrt(m.uu + k * m.uv), c = std::sqrt(m.vv + m.uv / k);
    const double x0 = a * p0.s, y0 = c * p0.t, x1 = a * p1.s, y1 = c * p1.t, x2 = a * p2.s, y2 = c * p2.t;
    const double l0 = (x1 - x2) * (x1 - x2) + (y1 - y2) * (y1 - y2);
    const double l1 = (x0 - x2) * (x0 - x2) + (y0 - y2) * (y0 - y2);
    const double l2 = (x0 - x1) * (x0 - x1) + (y0 - y1) * (y0 - y1);
    const double longest = std::max({l0, l1, l2});
    const double twice_area = std::abs((x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0));
    double value;
    if (longest >= l0 + l1 + l2 - longest || twice_area <= 0)
        value = longest / 4.0;
    else
        value = l0 * l1 * l2 / (4.0 * twice_area * twice_area);  // R^2 = l0 l1 l2 / (16 area^2)
    return 0.5 * value;
}

//! The quad sub-face tile width of an N-gon in Bfr's parameterization (limit_evaluation.h).
int subface_columns(std::size_t n) {
    return n < 10 ? 2 + (n > 4 ? 1 : 0) : 1 + static_cast<int>(std::sqrt(static_cast<float>(n - 1)));
}

//! One base face's prepared surface and the bounds of its patches.
struct FaceData {
    std::optional<LimitFaceSurface> surface;
    std::vector<PatchData> patches;
    std::size_t size = 0;
};

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

void query(const FaceData& fd, std::size_t node, double s0, double t0, double w, const P2& lo, const P2& hi,
           Overlap& out) {
    if (hi.s <= s0 || lo.s >= s0 + w || hi.t <= t0 || lo.t >= t0 + w) return;  // positive-area overlap only
    const LimitFaceSurface::Node& n = fd.surface->nodes()[node];
    if (n.patch >= 0 && w < kBoundedWidth) {
        out.uncover(s0, t0, w);
        return;
    }
    if (n.patch >= 0) {
        out.m.include(fd.patches[static_cast<std::size_t>(n.patch)].m, 1.0 / (w * w));
        out.patches.push_back({std::uint32_t(n.patch), s0, t0, w});
        return;
    }
    if (n.first_child < 0) {
        out.uncover(s0, t0, w);
        return;
    }
    const double h = 0.5 * w;
    const auto c = static_cast<std::size_t>(n.first_child);
    query(fd, c, s0, t0, h, lo, hi, out);
    query(fd, c + 1, s0 + h, t0, h, lo, hi, out);
    query(fd, c + 2, s0 + h, t0 + h, h, lo, hi, out);
    query(fd, c + 3, s0, t0 + h, h, lo, hi, out);
}

//! Root node of a domain in its face's tree.
std::size_t domain_root(const FaceData& fd, int subface) {
    return subface < 0 ? 0 : static_cast<std::size_t>(fd.surface->nodes()[0].first_child + subface);
}

//! Face (u, v) of domain (s, t).
std::pair<double, double> face_uv(std::size_t n, int subface, double s, double t) {
    if (subface < 0) return {s, t};
    const int columns = subface_columns(n);
    return {subface % columns + 0.5 * s, subface / columns + 0.5 * t};
}

Overlap overlap_of(const FaceData& fd, int subface, const P2& a, const P2& b, const P2& c) {
    Overlap o;
    const P2 lo{std::min({a.s, b.s, c.s}), std::min({a.t, b.t, c.t})};
    const P2 hi{std::max({a.s, b.s, c.s}), std::max({a.t, b.t, c.t})};
    query(fd, domain_root(fd, subface), 0.0, 0.0, 1.0, lo, hi, o);
    return o;
}

//! Bernstein coefficients over [a, b] (within [0, 1]) of the uniform B-spline basis functions of degree d (1..3)
//! of one span: out[i][j] is basis i's j-th coefficient. A polynomial lies in the convex hull of its Bernstein
//! coefficients over an interval, which shrinks to its range as the interval does.
using Basis = std::array<std::array<double, 4>, 4>;
Basis bernstein_of_basis(int d, double a, double b) {
    // power coefficients (in x) of each basis function, times d!
    static constexpr double kPower[4][4][4] = {{},
                                               {{1, -1, 0, 0}, {0, 1, 0, 0}},
                                               {{1, -2, 1, 0}, {1, 2, -2, 0}, {0, 0, 1, 0}},
                                               {{1, -3, 3, -1}, {4, 0, -6, 3}, {1, 3, 3, -3}, {0, 0, 0, 1}}};
    static constexpr double kFactorial[4] = {1, 1, 2, 6};
    static constexpr double kBinomial[4][4] = {{1, 0, 0, 0}, {1, 1, 0, 0}, {1, 2, 1, 0}, {1, 3, 3, 1}};
    const double h = b - a;
    const double ap[4] = {1.0, a, a * a, a * a * a}, hp[4] = {1.0, h, h * h, h * h * h};
    Basis out{};
    for (int i = 0; i <= d; ++i) {
        // q(y) = N_i(a + h y) in powers of y
        double q[4] = {0, 0, 0, 0};
        for (int k = 0; k <= d; ++k) {
            const double c = kPower[d][i][k] / kFactorial[d];
            // (a + h y)^k = sum_l C(k, l) a^(k - l) h^l y^l
            for (int l = 0; l <= k; ++l) q[l] += c * kBinomial[k][l] * ap[k - l] * hp[l];
        }
        // power to Bernstein: b_j = sum_{l <= j} C(j, l) / C(d, l) q_l
        for (int j = 0; j <= d; ++j) {
            double v = 0;
            for (int l = 0; l <= j; ++l) v += kBinomial[j][l] / kBinomial[d][l] * q[l];
            out[std::size_t(i)][std::size_t(j)] = v;
        }
    }
    return out;
}

//! max |sum_ij c[i][j] B_i(s) C_j(t)| over the box, from the Bernstein coefficients: c are the B-spline
//! coefficients (ds + 1 along s, dt + 1 along t, c[i + (ds + 1) j]), bs and bt the bases' Bernstein coefficients.
double box_max(const double* c, int ds, int dt, const Basis& bs, const Basis& bt) {
    double worst = 0;
    for (int js = 0; js <= ds; ++js)
        for (int jt = 0; jt <= dt; ++jt) {
            double v = 0;
            for (int i = 0; i <= ds; ++i)
                for (int j = 0; j <= dt; ++j)
                    v +=
                        c[i + (ds + 1) * j] * bs[std::size_t(i)][std::size_t(js)] * bt[std::size_t(j)][std::size_t(jt)];
            worst = std::max(worst, std::abs(v));
        }
    return worst;
}

//! Bounds on |n . S_ss|, |n . S_st|, |n . S_tt| over the box [s0, s1] x [t0, t1] of a patch's [0, 1]^2 (patch
//! units): the Bernstein coefficients of the three derivatives (linear x cubic, biquadratic, cubic x linear
//! B-splines of the patch's differences) over the box. Never above `along`'s bounds over the whole patch.
Bounds along_in_box(const PatchData& p, const Vec3& n, double s0, double s1, double t0, double t1) {
    double uu[8], vv[8], uv[9];
    // uu[2r + c]: c along s (linear), r along t (cubic); vv[2r + c]: r along s (cubic), c along t (linear);
    // uv[3r + c]: c along s, r along t (quadratic both)
    for (std::size_t i = 0; i < 8; ++i) uu[i] = dot(n, p.uu[i]);
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 2; ++c) vv[r + 4 * c] = dot(n, p.vv[std::size_t(2 * r + c)]);
    for (std::size_t i = 0; i < 9; ++i) uv[i] = dot(n, p.uv[i]);
    // the whole span is the common case (a patch inside the box): its bases once
    static const std::array<Basis, 4> kWhole = {Basis{}, bernstein_of_basis(1, 0.0, 1.0),
                                                bernstein_of_basis(2, 0.0, 1.0), bernstein_of_basis(3, 0.0, 1.0)};
    const auto basis = [](int d, double lo, double hi) {
        return lo == 0.0 && hi == 1.0 ? kWhole[std::size_t(d)] : bernstein_of_basis(d, lo, hi);
    };
    const Basis s1b = basis(1, s0, s1), s2b = basis(2, s0, s1), s3b = basis(3, s0, s1);
    const Basis t1b = basis(1, t0, t1), t2b = basis(2, t0, t1), t3b = basis(3, t0, t1);
    return {box_max(uu, 1, 3, s1b, t3b), box_max(uv, 2, 2, s2b, t2b), box_max(vv, 3, 1, s3b, t1b)};
}

//! Second-derivative bounds of the component of S along the unit normal `m` of a triangle's plane, over the parts
//! of the patches `o` holds inside the box [lo, hi] (the rest is `o.uncovered`), for triangle_bound: the distance
//! from S(x) to the plane of the triangle of S at its corners is |m . (S(x) - T(x))|, the interpolation error of
//! the scalar m . S, whose second derivatives are bounded by the Bernstein coefficients, over the box, of the
//! patches' differences projected on m. Only the surface's bending away from the plane counts, not the
//! parameterization's tangential non-uniformity. Without a normal (a degenerate triangle): the bounds on |S_xx|.
Bounds plane_bounds(const FaceData& fd, const Overlap& o, const std::optional<Vec3>& m, const P2& lo, const P2& hi) {
    if (!m) return o.m;
    Bounds out;
    for (const auto& piece : o.patches) {
        const double inv = 1.0 / piece.w;
        const double s0 = std::clamp((lo.s - piece.s0) * inv, 0.0, 1.0),
                     s1 = std::clamp((hi.s - piece.s0) * inv, 0.0, 1.0);
        const double t0 = std::clamp((lo.t - piece.t0) * inv, 0.0, 1.0),
                     t1 = std::clamp((hi.t - piece.t0) * inv, 0.0, 1.0);
        out.include(along_in_box(fd.patches[piece.patch], *m, s0, s1, t0, t1), inv * inv);
    }
    return out;
}

//! Bounds on |S_ss|, |S_st|, |S_tt| (the full vectors) over the box [lo, hi]: the norm of the per-axis bounds. For a
//! triangle with an edge on an open boundary, where a point of S whose projection falls outside the triangle has no
//! neighbour to be near: the distance to the triangle is at most |S(x) - T(x)|, bounded by these.
Bounds full_bounds(const FaceData& fd, const Overlap& o, const P2& lo, const P2& hi) {
    Bounds axis[3];
    for (int k = 0; k < 3; ++k) {
        Vec3 e{};
        (k == 0 ? e.x : k == 1 ? e.y : e.z) = 1.0;
        axis[k] = plane_bounds(fd, o, e, lo, hi);
    }
    const auto len = [](double a, double b, double c) { return std::sqrt(a * a + b * b + c * c); };
    return {len(axis[0].uu, axis[1].uu, axis[2].uu), len(axis[0].uv, axis[1].uv, axis[2].uv),
            len(axis[0].vv, axis[1].vv, axis[2].vv)};
}

//! plane_bounds over a triangle's bounding box.
Bounds plane_bounds(const FaceData& fd, const Overlap& o, const std::optional<Vec3>& m, const P2& a, const P2& b,
                    const P2& c) {
    return plane_bounds(fd, o, m, {std::min({a.s, b.s, c.s}), std::min({a.t, b.t, c.t})},
                        {std::max({a.s, b.s, c.s}), std::max({a.t, b.t, c.t})});
}

//! Unit normal of the triangle (a, b, c), if it has one.
std::optional<Vec3> unit_normal(const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 n = cross(b - a, c - a);
    const double length = norm(n);
    if (!(length > 0) || !std::isfinite(length)) return std::nullopt;
    return n * (1.0 / length);
}

//! S at domain point p.
Result<Vec3> position_at(const FaceData& fd, int subface, const P2& p) {
    const auto [u, v] = face_uv(fd.size, subface, p.s, p.t);
    auto sample = fd.surface->evaluate(u, v);
    if (!sample) return sample.error();
    return sample->position;
}

//! Measured max distance from S(x) to the plane of the triangle of S at the corners, over the non-corner points x of
//! a barycentric grid of step 1/6 of the triangle in (s, t). (Not |S(x) - T(x)|: at an extraordinary vertex the parameterization
//! is singular, and the parametric difference falls only as fast as the triangle shrinks.)
Result<double> sampled_error(const FaceData& fd, int subface, const P2& a, const P2& b, const P2& c) {
    const auto at = [&](const P2& p) -> Result<Vec3> {
        const auto [u, v] = face_uv(fd.size, subface, p.s, p.t);
        auto sample = fd.surface->evaluate(u, v);
        if (!sample) return sample.error();
        return sample->position;
    };
    auto sa = at(a), sb = at(b), sc = at(c);
    if (!sa) return sa.error();
    if (!sb) return sb.error();
    if (!sc) return sc.error();
    // distance to the triangle's plane: a point whose projection falls just outside the triangle is near its
    // neighbour's, which the distance to this triangle alone (its edge) would overstate by the tangential offset
    const Vec3 n = cross(*sb - *sa, *sc - *sa);
    const double area2 = norm(n);
    constexpr int kSteps = 6;
    double worst = 0;
    for (int i = 0; i <= kSteps; ++i)
        for (int j = 0; i + j <= kSteps; ++j) {
            const int k = kSteps - i - j;
            if (i == kSteps || j == kSteps || k == kSteps) continue;
            const double li = double(i) / kSteps, lj = double(j) / kSteps, lk = double(k) / kSteps;
            const P2 x{li * a.s + lj * b.s + lk * c.s, li * a.t + lj * b.t + lk * c.t};
            auto s = at(x);
            if (!s) return s.error();
            const double d = area2 > 0 ? std::abs(dot(*s - *sa, n)) / area2
                                       : norm(*s - triangle_closest_point(*s, *sa, *sb, *sc).point);
            worst = std::max(worst, d);
        }
    return worst;
}

//! A domain's triangulation in its own (s, t): local points (the boundary ring first: side k's points 0 .. r_k - 1
//! in order, then the inner grid row by row) and triangles over them.
struct LocalMesh {
    std::vector<P2> points;
    std::vector<std::array<std::uint32_t, 3>> triangles;
};

//! A uniform domain whose sides carry its inner rates: a regular grid, no transition strips.
bool is_grid(const LimitTessellationPlan::Domain& d) {
    for (const auto& lines : d.side_lines)
        if (!lines.empty()) return false;
    return d.s_lines.empty() && d.t_lines.empty() && d.side[0] == d.nu && d.side[2] == d.nu && d.side[1] == d.nv &&
           d.side[3] == d.nv;
}

std::uint64_t domain_triangles(const LimitTessellationPlan::Domain& d) {
    const bool grid = is_grid(d);
    const auto nu = static_cast<std::uint64_t>(d.nu), nv = static_cast<std::uint64_t>(d.nv);
    if (grid) return 2 * nu * nv;
    std::uint64_t sum = 0;
    for (int k = 0; k < 4; ++k) sum += static_cast<std::uint64_t>(d.side[k]);
    return 2 * (nu - 2) * (nv - 2) + sum + 2 * (nu - 2) + 2 * (nv - 2);
}

//! Inner rates of a domain whose sides differ from them: at least 2 so that the inner grid has a point.
void fix_inner(LimitTessellationPlan::Domain& d) {
    const bool grid = is_grid(d);
    if (!grid) {
        d.nu = std::max(d.nu, 2);
        d.nv = std::max(d.nv, 2);
    }
}

LocalMesh triangulate(const LimitTessellationPlan::Domain& d) {
    LocalMesh out;
    const int r[4] = {d.side[0], d.side[1], d.side[2], d.side[3]};
    const std::uint32_t offset[4] = {0, std::uint32_t(r[0]), std::uint32_t(r[0] + r[1]),
                                     std::uint32_t(r[0] + r[1] + r[2])};
    const std::uint32_t ring = std::uint32_t(r[0] + r[1] + r[2] + r[3]);
    for (int i = 0; i < r[0]; ++i) out.points.push_back({d.side_at(0, i), 0.0});
    for (int i = 0; i < r[1]; ++i) out.points.push_back({1.0, d.side_at(1, i)});
    for (int i = 0; i < r[2]; ++i) out.points.push_back({1.0 - d.side_at(2, i), 1.0});
    for (int i = 0; i < r[3]; ++i) out.points.push_back({0.0, 1.0 - d.side_at(3, i)});
    const auto on_side = [&](int k, int i) { return (offset[k] + std::uint32_t(i)) % ring; };
    const int nu = d.nu, nv = d.nv;
    const auto inner = [&](int i, int j) { return ring + std::uint32_t((j - 1) * (nu - 1) + (i - 1)); };
    for (int j = 1; j < nv; ++j)
        for (int i = 1; i < nu; ++i) out.points.push_back({d.s_at(i), d.t_at(j)});
    const bool grid = is_grid(d);
    if (grid) {
        const auto at = [&](int i, int j) -> std::uint32_t {
            if (j == 0) return on_side(0, i);
            if (i == nu) return on_side(1, j);
            if (j == nv) return on_side(2, nu - i);
            if (i == 0) return on_side(3, nv - j);
            return inner(i, j);
        };
        for (int j = 0; j < nv; ++j)
            for (int i = 0; i < nu; ++i) {
                out.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
                out.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
            }
        return out;
    }
    // inner grid
    for (int j = 1; j + 1 < nv; ++j)
        for (int i = 1; i + 1 < nu; ++i) {
            out.triangles.push_back({inner(i, j), inner(i + 1, j), inner(i + 1, j + 1)});
            out.triangles.push_back({inner(i, j), inner(i + 1, j + 1), inner(i, j + 1)});
        }
    // one transition strip per side, between the side's points and the inner grid's outermost row, both running
    // from corner to corner; positions along the side decide which advances (the inner row is on the left)
    for (int k = 0; k < 4; ++k) {
        std::vector<std::pair<std::uint32_t, double>> in;
        if (k == 0)
            for (int i = 1; i < nu; ++i) in.emplace_back(inner(i, 1), d.s_at(i));
        if (k == 1)
            for (int j = 1; j < nv; ++j) in.emplace_back(inner(nu - 1, j), d.t_at(j));
        if (k == 2)
            for (int i = nu - 1; i >= 1; --i) in.emplace_back(inner(i, nv - 1), 1.0 - d.s_at(i));
        if (k == 3)
            for (int j = nv - 1; j >= 1; --j) in.emplace_back(inner(1, j), 1.0 - d.t_at(j));
        const int a = r[k], b = static_cast<int>(in.size()) - 1;
        int io = 0, ii = 0;
        while (io < a || ii < b) {
            const bool outer = ii == b || (io < a && d.side_at(k, io + 1) <= in[std::size_t(ii + 1)].second);
            if (outer) {
                out.triangles.push_back({on_side(k, io), on_side(k, io + 1), in[std::size_t(ii)].first});
                ++io;
            } else {
                out.triangles.push_back({on_side(k, io), in[std::size_t(ii + 1)].first, in[std::size_t(ii)].first});
                ++ii;
            }
        }
    }
    return out;
}

//! Bins of a domain direction for graded grids: as fine as the shallowest patches that are sampled rather than
//! bounded, so that every bounded patch covers whole bins.
constexpr int kBins = 1 << kBoundedDepth;
//! Segments per unit length a direction needs, per bin.
using Density = std::array<double, kBins>;

//! The points along a base edge (or along one half of an edge of an N-gon, whose midpoint is a vertex) or along a
//! spoke: graded by a density over the slot's own parameter, 0 to 1 in its canonical direction (an edge's first face's
//! direction; a spoke from its edge midpoint to the centre). Every domain side on it reads the same points.
struct Slot {
    Density rho{};
    int count = 1;
    std::vector<double> lines;  //!< count + 1 values from 0 to 1; empty: uniform
    double at(int i) const { return lines.empty() ? double(i) / count : lines[std::size_t(i)]; }
};

//! The part [q0, q1] of a domain side (its fraction from corner k to corner k + 1) that a slot covers; reversed: the
//! slot's parameter runs from q1 down to q0.
struct SidePart {
    std::size_t slot = 0;
    double q0 = 0, q1 = 1;
    bool reversed = false;
};

struct EdgeUse {
    std::size_t edge;
    bool forward;  //!< the face runs along the edge's canonical direction
};

//! Everything the plan and the execution share.
struct Context {
    Context(const LimitSurfaceEvaluator& e, const PolygonMesh& b, const LimitTessellationOptions& o)
        : evaluator(e), base(b), options(o) {}
    const LimitSurfaceEvaluator& evaluator;
    const PolygonMesh& base;
    const LimitTessellationOptions& options;
    std::vector<FaceData> faces;
    std::vector<bool> hole;
    std::vector<std::array<Index, 2>> edges;     //!< canonical (v0, v1)
    std::vector<std::size_t> edge_owner;         //!< first non-hole face on the edge
    std::vector<std::uint32_t> edge_owner_side;  //!< its corner index there
    std::vector<std::vector<EdgeUse>> face_edges;
    std::vector<std::size_t> first_domain;  //!< per face, its first domain (domains of a face are contiguous)
    std::vector<std::size_t> first_spoke;   //!< per face, index of its spoke 0 (N-gons)
    std::size_t spokes = 0;
    std::vector<int> edge_faces;         //!< per edge, how many non-hole faces use it (1: an open boundary)
    std::vector<bool> halved;            //!< per edge: an N-gon uses it, so its midpoint is a vertex (two slots)
    std::vector<std::size_t> edge_slot;  //!< per edge, its first slot (halves in canonical order)
    std::size_t first_spoke_slot = 0;
    std::vector<Slot> slots;

    std::size_t spoke_slot(std::size_t face, std::size_t j) const { return first_spoke_slot + first_spoke[face] + j; }
    //! Segments of edge e, and the canonical index of its midpoint when it is halved.
    int edge_count(std::size_t e) const {
        return slots[edge_slot[e]].count + (halved[e] ? slots[edge_slot[e] + 1].count : 0);
    }
    //! Canonical fraction of edge e's point i.
    double edge_at(std::size_t e, int i) const {
        const Slot& a = slots[edge_slot[e]];
        if (!halved[e]) return a.at(i);
        return i <= a.count ? 0.5 * a.at(i) : 0.5 + 0.5 * slots[edge_slot[e] + 1].at(i - a.count);
    }
    //! The slots along side k of a domain, in the side's order.
    std::array<SidePart, 2> side_parts(const LimitTessellationPlan::Domain& d, int k, int& parts) const {
        const std::size_t f = d.face, n = faces[f].size;
        parts = 1;
        if (d.subface < 0) {
            const EdgeUse& use = face_edges[f][std::size_t(k)];
            const std::size_t s0 = edge_slot[use.edge];
            if (!halved[use.edge]) return {SidePart{s0, 0.0, 1.0, !use.forward}, SidePart{}};
            parts = 2;
            if (use.forward) return {SidePart{s0, 0.0, 0.5, false}, SidePart{s0 + 1, 0.5, 1.0, false}};
            return {SidePart{s0 + 1, 0.0, 0.5, true}, SidePart{s0, 0.5, 1.0, true}};
        }
        const auto j = std::size_t(d.subface), prev = (j + n - 1) % n;
        if (k == 1) return {SidePart{spoke_slot(f, j), 0.0, 1.0, false}, SidePart{}};
        if (k == 2) return {SidePart{spoke_slot(f, prev), 0.0, 1.0, true}, SidePart{}};
        // side 0: the first half of edge j in the face's direction; side 3: the second half of the previous edge
        const EdgeUse& use = face_edges[f][k == 0 ? j : prev];
        const std::size_t s0 = edge_slot[use.edge];
        const bool first = (k == 0) == use.forward;  // canonical first half
        return {SidePart{first ? s0 : s0 + 1, 0.0, 1.0, !use.forward}, SidePart{}};
    }
};

Status check_budget(std::uint64_t triangles, const LimitTessellationOptions& options) {
    if (options.max_triangles > 0 && triangles > options.max_triangles)
        return make_error(ErrorCode::BudgetExceeded, "tolerance " + shortest_text(options.tolerance) + " needs " +
                                                         std::to_string(triangles) + " triangles; the limit is " +
                                                         std::to_string(options.max_triangles));
    return Ok{};
}

GeoError too_many_segments(double needed, const LimitTessellationOptions& options, std::size_t face) {
    return element_error(ErrorCode::BudgetExceeded,
                         "tolerance " + shortest_text(options.tolerance) + " needs " +
                             std::to_string(static_cast<long long>(needed)) + " segments on face " +
                             std::to_string(face) + "; max_segments is " + std::to_string(options.max_segments),
                         ElementKind::Face, static_cast<std::int64_t>(face));
}

//! Grid lines from 0 to 1 spaced in proportion to 1 / rho (the spacing in bin b at most 1 / rho[b]): their count
//! of segments, and the lines (empty when they are uniform: rho constant, or one segment).
std::pair<int, std::vector<double>> grid_lines(const Density& rho) {
    double total = 0;
    for (double r : rho) total += r / kBins;
    const int n = std::max(1, int(std::ceil(total * (1.0 - 1e-12))));
    if (n == 1 || std::all_of(rho.begin(), rho.end(), [&](double r) { return r == rho[0]; })) return {n, {}};
    std::vector<double> lines(std::size_t(n) + 1, 0.0);
    lines[std::size_t(n)] = 1.0;
    int bin = 0;
    double before = 0;  // the integral of rho up to the start of `bin`
    for (int i = 1; i < n; ++i) {
        const double target = total * i / n;
        while (bin < kBins - 1 && before + rho[std::size_t(bin)] / kBins < target) {
            before += rho[std::size_t(bin)] / kBins;
            ++bin;
        }
        lines[std::size_t(i)] =
            std::clamp(double(bin) / kBins + (target - before) / rho[std::size_t(bin)], lines[std::size_t(i - 1)], 1.0);
    }
    return {n, lines};
}

//! Raises the density over [lo, hi) to `rho`.
void raise(Density& density, double lo, double hi, double rho) {
    const int b0 = std::clamp(int(std::floor(lo * kBins)), 0, kBins - 1);
    const int b1 = std::clamp(int(std::ceil(hi * kBins)), b0 + 1, kBins);
    for (int b = b0; b < b1; ++b) density[std::size_t(b)] = std::max(density[std::size_t(b)], rho);
}

//! A graded domain's grid: lines along s and t from densities.
struct Graded {
    Density rs{}, rt{};
    int nu = 1, nv = 1;
    std::vector<double> s_lines, t_lines;
};

Status regrade(Graded& g, const LimitTessellationOptions& options, std::size_t face) {
    std::tie(g.nu, g.s_lines) = grid_lines(g.rs);
    std::tie(g.nv, g.t_lines) = grid_lines(g.rt);
    if (std::max(g.nu, g.nv) > options.max_segments) return too_many_segments(std::max(g.nu, g.nv), options, face);
    return Ok{};
}

//! Gives domain `d` the grid of `g`.
void apply(const Graded& g, LimitTessellationPlan::Domain& d) {
    d.s_lines = g.s_lines;
    d.t_lines = g.t_lines;
    d.nu = g.nu;
    d.nv = g.nv;
    fix_inner(d);
}

//! The ratio (bound / tolerance) a graded grid's coarsening aims its cells at.
constexpr double kCoarsenTarget = 0.97;
//! How many times a graded grid within the tolerance is coarsened.
constexpr int kCoarsenRounds = 3;

//! How much to shrink a failing triangle of parameter extents (hs, ht) whose bound is `ratio` times the tolerance:
//! per direction, by the share of the bound that direction carries (the bound is a quadratic form in the extents).
std::pair<double, double> shrink(const Bounds& m, double hs, double ht, double ratio) {
    const double cu = m.uu * hs * hs + m.uv * hs * ht, cv = m.vv * ht * ht + m.uv * hs * ht;
    double fs = 1.05, ft = 1.05;
    if (cu + cv > 0) {
        fs = std::max(1.0, std::sqrt(2.0 * ratio * cu / (cu + cv)));
        ft = std::max(1.0, std::sqrt(2.0 * ratio * cv / (cu + cv)));
    }
    if (std::max(fs, ft) < 1.05) fs = ft = 1.05;
    return {std::min(fs, 8.0), std::min(ft, 8.0)};
}

//! The graded grid one domain needs: the bounded patches give the densities (their normal-cone plane bounds), then
//! every cell's two triangles are bounded with their own planes (sampled where no patch bounds them) and the
//! densities raised over the cells that exceed the tolerance, until none does.
Result<Graded> graded_demand(const FaceData& fd, std::size_t face, int subface,
                             const LimitTessellationOptions& options) {
    const double tol = options.tolerance;
    const std::size_t root = domain_root(fd, subface);
    Graded g;
    g.rs.fill(1.0);
    g.rt.fill(1.0);
    {
        std::vector<std::tuple<std::size_t, double, double, double>> stack{{root, 0.0, 0.0, 1.0}};
        while (!stack.empty()) {
            const auto [node, s0, t0, w] = stack.back();
            stack.pop_back();
            if (w < kBoundedWidth) continue;
            const auto& n = fd.surface->nodes()[node];
            if (n.patch >= 0) {
                // a first guess, not a bound: the second derivatives along the patch's mean normal (the checks
                // below bound every cell with its triangles' own planes and raise the densities where needed)
                const PatchData& pd = fd.patches[std::size_t(n.patch)];
                Bounds m;
                m.include(norm(pd.n0) > 0 ? along_in_box(pd, pd.n0, 0, 1, 0, 1) : pd.plane, 1.0 / (w * w));
                const auto [ru, rv] = rates_for(m, tol);
                raise(g.rs, s0, s0 + w, ru);
                raise(g.rt, t0, t0 + w, rv);
            } else if (n.first_child >= 0) {
                const double h = 0.5 * w;
                const auto c = std::size_t(n.first_child);
                stack.emplace_back(c, s0, t0, h);
                stack.emplace_back(c + 1, s0 + h, t0, h);
                stack.emplace_back(c + 2, s0 + h, t0 + h, h);
                stack.emplace_back(c + 3, s0, t0 + h, h);
            }
        }
    }
    std::optional<Graded> best;  // the smallest grid within the tolerance so far
    int coarsenings = 0;
    for (int iteration = 0;; ++iteration) {
        if (auto status = regrade(g, options, face); !status) return status.error();
        if (iteration > 40) break;
        const int nu = g.nu, nv = g.nv;
        const auto s_at = [&](int i) { return g.s_lines.empty() ? double(i) / nu : g.s_lines[std::size_t(i)]; };
        const auto t_at = [&](int j) { return g.t_lines.empty() ? double(j) / nv : g.t_lines[std::size_t(j)]; };
        // the output has at least this domain's grid: refuse before evaluating more than the budget allows
        if (auto status = check_budget(2 * std::uint64_t(nu) * std::uint64_t(nv), options); !status)
            return status.error();
        std::vector<Vec3> grid;  // S at the grid points, for the triangles' planes
        grid.reserve(std::size_t(nu + 1) * std::size_t(nv + 1));
        for (int j = 0; j <= nv; ++j)
            for (int i = 0; i <= nu; ++i) {
                auto p = position_at(fd, subface, {s_at(i), t_at(j)});
                if (!p) return p.error();
                grid.push_back(*p);
            }
        const auto at = [&](int i, int j) { return grid[std::size_t(j) * std::size_t(nu + 1) + std::size_t(i)]; };
        Density next_s = g.rs, next_t = g.rt;
        Density worst_s{}, worst_t{};  // per bin, the largest ratio (bound / tolerance) of the cells over it
        bool fail = false;
        for (int j = 0; j < nv; ++j)
            for (int i = 0; i < nu; ++i) {
                const P2 lo{s_at(i), t_at(j)}, hi{s_at(i + 1), t_at(j + 1)};
                const double hs = hi.s - lo.s, ht = hi.t - lo.t;
                const P2 c01{lo.s, hi.t}, c10{hi.s, lo.t};
                Overlap o;
                query(fd, root, 0.0, 0.0, 1.0, lo, hi, o);
                const std::optional<Vec3> n_lower = unit_normal(at(i, j), at(i + 1, j), at(i + 1, j + 1)),
                                          n_upper = unit_normal(at(i, j), at(i + 1, j + 1), at(i, j + 1));
                const Bounds lower = plane_bounds(fd, o, n_lower, lo, c10, hi);
                const Bounds upper = plane_bounds(fd, o, n_upper, lo, hi, c01);
                const double rl = triangle_bound(lower, lo, c10, hi) / tol,
                             ru = triangle_bound(upper, lo, hi, c01) / tol;
                double fs = 1, ft = 1, cell_ratio = std::max(rl, ru);
                if (rl > 1 || ru > 1) {
                    // a patch that fails on its own (a narrow band of high curvature inside a coarse cell) refines
                    // the grid around itself, by as much as the cell would need; the whole cell only when none does
                    bool local = false;
                    for (const auto& piece : o.patches) {
                        Overlap one;
                        one.m.include(fd.patches[piece.patch].m, 1.0 / (piece.w * piece.w));
                        one.patches = {piece};
                        Bounds m = plane_bounds(fd, one, n_lower, lo, c10, hi);
                        const Bounds mu = plane_bounds(fd, one, n_upper, lo, hi, c01);
                        const double r =
                            std::max(triangle_bound(m, lo, c10, hi), triangle_bound(mu, lo, hi, c01)) / tol;
                        if (r <= 1) continue;
                        local = true;
                        m.include(mu, 1.0);
                        const auto [ps, pt] = shrink(m, hs, ht, r);
                        const double ws = 0.5 * hs / ps, wt = 0.5 * ht / pt;
                        raise(next_s, std::max(lo.s, piece.s0 - ws), std::min(hi.s, piece.s0 + piece.w + ws), ps / hs);
                        raise(next_t, std::max(lo.t, piece.t0 - wt), std::min(hi.t, piece.t0 + piece.w + wt), pt / ht);
                        fail = true;
                    }
                    if (!local) {
                        Bounds m = lower;
                        m.include(upper, 1.0);
                        std::tie(fs, ft) = shrink(m, hs, ht, std::max(rl, ru));
                    }
                }
                if (o.uncovered) {  // the parts no patch bounds (deep at irregular vertices) are sampled
                    double e = 0;
                    for (const auto& [p, q] : {std::pair{c10, hi}, std::pair{hi, c01}}) {
                        auto sampled = sampled_error(fd, subface, lo, p, q);
                        if (!sampled) return sampled.error();
                        e = std::max(e, *sampled);
                    }
                    const double ratio = e / (tol / kSampledSafety);
                    cell_ratio = std::max(cell_ratio, ratio);
                    if (ratio > 1) {
                        // the cells next to the uncovered parts shrink by f: the density rises over a cell's width
                        // around them, not over the whole cell (a coarse cell that reaches an irregular vertex
                        // would otherwise refine everything it spans)
                        const double f = std::min(4.0, std::max(1.1, std::sqrt(ratio)));
                        const double ws = 0.5 * hs / f, wt = 0.5 * ht / f;
                        fail = true;
                        raise(next_s, std::max(lo.s, o.uncovered_lo.s - ws), std::min(hi.s, o.uncovered_hi.s + ws),
                              f / hs);
                        raise(next_t, std::max(lo.t, o.uncovered_lo.t - wt), std::min(hi.t, o.uncovered_hi.t + wt),
                              f / ht);
                    }
                }
                if (fs > 1 || ft > 1) {
                    fail = true;
                    raise(next_s, lo.s, hi.s, fs / hs);
                    raise(next_t, lo.t, hi.t, ft / ht);
                }
                raise(worst_s, lo.s, hi.s, cell_ratio);
                raise(worst_t, lo.t, hi.t, cell_ratio);
            }
        if (!fail) {
            // the raises overshoot (a factor at least 1.05, lines rounded up): once every cell is within the
            // tolerance, the densities fall where the cells over a bin all have room (the bounds go with the
            // squares of the cells' sizes); the refinement above then repairs what that breaks, and the smallest
            // grid that passed is kept
            if (!best || std::uint64_t(nu) * std::uint64_t(nv) < std::uint64_t(best->nu) * std::uint64_t(best->nv))
                best = g;
            if (coarsenings == kCoarsenRounds) break;
            ++coarsenings;
            bool lower = false;
            for (int b = 0; b < kBins; ++b)
                for (auto [rho, worst] : {std::pair{&g.rs, &worst_s}, std::pair{&g.rt, &worst_t}}) {
                    const double f = std::sqrt(std::max((*worst)[std::size_t(b)], 0.0625) / kCoarsenTarget);
                    if (f >= 1) continue;
                    (*rho)[std::size_t(b)] = std::max(1.0, (*rho)[std::size_t(b)] * f);
                    lower = true;
                }
            if (!lower) break;
            continue;
        }
        g.rs = next_s;
        g.rt = next_t;
        if (options.cancel.requested()) return make_error(ErrorCode::Cancelled, "tessellation cancelled");
    }
    if (best) return *best;
    return g;
}

//! The rates one domain needs on a regular grid: bounded cells within the tolerance, sampled cells within
//! tolerance / kSampledSafety. Returns (nu, nv).
Result<std::pair<int, int>> domain_demand(const FaceData& fd, std::size_t face, int subface,
                                          const LimitTessellationOptions& options) {
    const double tol = options.tolerance;
    const std::size_t root = domain_root(fd, subface);
    const bool bounded = options.guaranteed;
    // start from the patches down to two levels (their normal cones' plane bounds), then check every cell's two
    // triangles against the patches they overlap
    Overlap coarse;
    {
        std::vector<std::pair<std::size_t, double>> stack{{root, 1.0}};
        int depth = 0;
        while (!stack.empty() && depth <= 2) {
            std::vector<std::pair<std::size_t, double>> next;
            for (const auto& [node, w] : stack) {
                const auto& n = fd.surface->nodes()[node];
                if (n.patch >= 0) coarse.m.include(fd.patches[std::size_t(n.patch)].plane, 1.0 / (w * w));
                if (n.first_child >= 0)
                    for (int c = 0; c < 4; ++c) next.emplace_back(std::size_t(n.first_child + c), 0.5 * w);
            }
            stack = std::move(next);
            ++depth;
        }
    }
    auto [fu, fv] = rates_for(coarse.m, tol);
    int nu = int(fu), nv = int(fv);
    if (!bounded) {  // the bound overestimates: start below it and let the measurements decide
        nu = std::max(1, nu / 4);
        nv = std::max(1, nv / 4);
    }
    for (int iteration = 0;; ++iteration) {
        if (std::max(nu, nv) > options.max_segments) return too_many_segments(std::max(nu, nv), options, face);
        if (iteration > 40) break;
        double worst_ratio = 0;  // largest bound / tolerance
        bool bounded_fail = false, sampled_fail = false;
        std::vector<Vec3> grid;  // S at the grid points, for the triangles' planes
        if (bounded) {
            grid.reserve(std::size_t(nu + 1) * std::size_t(nv + 1));
            for (int j = 0; j <= nv; ++j)
                for (int i = 0; i <= nu; ++i) {
                    auto p = position_at(fd, subface, {double(i) / nu, double(j) / nv});
                    if (!p) return p.error();
                    grid.push_back(*p);
                }
        }
        const auto at = [&](int i, int j) { return grid[std::size_t(j) * std::size_t(nu + 1) + std::size_t(i)]; };
        for (int j = 0; j < nv; ++j)
            for (int i = 0; i < nu; ++i) {
                const P2 lo{double(i) / nu, double(j) / nv}, hi{double(i + 1) / nu, double(j + 1) / nv};
                Overlap o;
                query(fd, root, 0.0, 0.0, 1.0, lo, hi, o);
                // the patches a cell overlaps bound it; the parts no patch bounds (deep at irregular vertices) are
                // sampled as well
                if (bounded) {
                    const P2 c01{lo.s, hi.t}, c10{hi.s, lo.t};
                    const Bounds lower =
                        plane_bounds(fd, o, unit_normal(at(i, j), at(i + 1, j), at(i + 1, j + 1)), lo, c10, hi);
                    const Bounds upper =
                        plane_bounds(fd, o, unit_normal(at(i, j), at(i + 1, j + 1), at(i, j + 1)), lo, hi, c01);
                    worst_ratio = std::max({worst_ratio, triangle_bound(lower, lo, c10, hi) / tol,
                                            triangle_bound(upper, lo, hi, c01) / tol});
                }
                if ((o.uncovered || !bounded) && !sampled_fail) {
                    const P2 c01{lo.s, hi.t}, c10{hi.s, lo.t};
                    for (const auto& [p, q] : {std::pair{c10, hi}, std::pair{hi, c01}}) {
                        auto e = sampled_error(fd, subface, lo, p, q);
                        if (!e) return e.error();
                        if (*e > tol / kSampledSafety) sampled_fail = true;
                    }
                }
            }
        bounded_fail = worst_ratio > 1;
        if (!bounded_fail && !sampled_fail) break;
        int next_u = nu, next_v = nv;
        if (bounded_fail) {  // the bounds fall with the square of the cell size
            const double scale = std::min(1e3, std::sqrt(worst_ratio));
            next_u = std::max(nu, int(std::ceil(nu * scale)));
            next_v = std::max(nv, int(std::ceil(nv * scale)));
        }
        if (sampled_fail || (next_u == nu && next_v == nv)) {
            next_u = std::max(next_u, nu + std::max(1, nu / 4));
            next_v = std::max(next_v, nv + std::max(1, nv / 4));
        }
        nu = next_u;
        nv = next_v;
        if (options.cancel.requested()) return make_error(ErrorCode::Cancelled, "tessellation cancelled");
    }
    return std::pair<int, int>{nu, nv};
}

//! Builds edges, prepares every face, and plans.
Result<LimitTessellationPlan> plan(Context& cx) {
    const PolygonMesh& base = cx.base;
    const LimitTessellationOptions& options = cx.options;
    if (!std::isfinite(options.tolerance) || options.tolerance <= 0)
        return make_error(ErrorCode::InvalidArgument, "tolerance must be a finite number > 0");
    if (options.max_segments < 1 || options.max_segments > 4096)
        return make_error(ErrorCode::InvalidArgument, "max_segments must be in [1, 4096]");
    const std::size_t face_count = base.face_count();
    cx.hole.assign(face_count, false);
    for (Index h : base.tags.holes)
        if (h < face_count) cx.hole[h] = true;
    cx.faces.resize(face_count);
    cx.face_edges.resize(face_count);
    cx.first_domain.assign(face_count + 1, 0);
    cx.first_spoke.assign(face_count + 1, 0);

    // edges in order of first use, and each face's domains
    LimitTessellationPlan out;
    std::map<std::pair<Index, Index>, std::size_t> edge_ids;
    for (std::size_t f = 0; f < face_count; ++f) {
        cx.first_domain[f] = out.domains.size();
        cx.first_spoke[f] = cx.spokes;
        if (cx.hole[f]) continue;
        const auto fv = base.face(f);
        const std::size_t n = fv.size();
        for (std::size_t k = 0; k < n; ++k) {
            const Index a = fv[k], b = fv[(k + 1) % n];
            const auto key = std::minmax(a, b);
            auto [it, inserted] = edge_ids.emplace(std::pair{key.first, key.second}, cx.edges.size());
            if (inserted) {
                cx.edges.push_back({a, b});
                cx.edge_owner.push_back(f);
                cx.edge_owner_side.push_back(std::uint32_t(k));
                cx.edge_faces.push_back(0);
                cx.halved.push_back(false);
            }
            cx.face_edges[f].push_back({it->second, cx.edges[it->second][0] == a});
            ++cx.edge_faces[it->second];
            if (n != 4) cx.halved[it->second] = true;
        }
        if (n == 4) {
            out.domains.push_back({std::uint32_t(f), -1, 1, 1, {1, 1, 1, 1}, {}, {}, {}});
        } else {
            for (std::size_t j = 0; j < n; ++j)
                out.domains.push_back({std::uint32_t(f), std::int32_t(j), 1, 1, {1, 1, 1, 1}, {}, {}, {}});
            cx.spokes += n;
        }
    }
    cx.first_domain[face_count] = out.domains.size();
    cx.first_spoke[face_count] = cx.spokes;
    // slots: each edge's (two for a halved one), then each spoke's; and a face to name in errors
    std::vector<std::size_t> slot_face;
    cx.edge_slot.resize(cx.edges.size());
    for (std::size_t e = 0; e < cx.edges.size(); ++e) {
        cx.edge_slot[e] = slot_face.size();
        slot_face.insert(slot_face.end(), cx.halved[e] ? 2 : 1, cx.edge_owner[e]);
    }
    cx.first_spoke_slot = slot_face.size();
    for (std::size_t f = 0; f < face_count; ++f)
        slot_face.insert(slot_face.end(), cx.first_spoke[f + 1] - cx.first_spoke[f], f);
    cx.slots.assign(slot_face.size(), Slot{});
    for (Slot& slot : cx.slots) slot.rho.fill(1.0);
    out.edge_rates.assign(cx.edges.size(), 1);

    // raises the slots along side k of domain d, over its fractions [lo, hi], to rho segments per unit of the side
    const auto raise_side = [&](const LimitTessellationPlan::Domain& d, int k, double lo, double hi, double rho) {
        int parts = 0;
        const auto sides = cx.side_parts(d, k, parts);
        for (int p = 0; p < parts; ++p) {
            const SidePart& part = sides[std::size_t(p)];
            const double a = std::max(lo, part.q0), b = std::min(hi, part.q1);
            if (!(b > a)) continue;
            const double w = part.q1 - part.q0;
            double x0 = (a - part.q0) / w, x1 = (b - part.q0) / w;
            if (part.reversed) std::tie(x0, x1) = std::pair{1.0 - x1, 1.0 - x0};
            raise(cx.slots[part.slot].rho, x0, x1, rho * w);
        }
    };
    // the sides follow the domain's inner densities (s along sides 0 and 2, t along 1 and 3; sides 2 and 3 run
    // backwards), so that an edge is fine only where a face on it is
    const auto push_density = [&](const LimitTessellationPlan::Domain& d, const Density& rs, const Density& rt) {
        for (int k = 0; k < 4; ++k)
            for (int b = 0; b < kBins; ++b) {
                const Density& rho = k % 2 == 0 ? rs : rt;
                raise_side(d, k, double(b) / kBins, double(b + 1) / kBins, rho[std::size_t(k < 2 ? b : kBins - 1 - b)]);
            }
    };
    const auto update_slots = [&]() -> Status {
        // measured rates never raise a side, so a halved edge keeps equal halves at the larger rate (the sides
        // stay at least as fine as every inner grid next to them)
        for (std::size_t e = 0; e < cx.edges.size() && !options.guaranteed; ++e)
            if (cx.halved[e]) {
                Density& a = cx.slots[cx.edge_slot[e]].rho;
                Density& b = cx.slots[cx.edge_slot[e] + 1].rho;
                const double top =
                    std::max(*std::max_element(a.begin(), a.end()), *std::max_element(b.begin(), b.end()));
                a.fill(top);
                b.fill(top);
            }
        for (std::size_t i = 0; i < cx.slots.size(); ++i) {
            Slot& slot = cx.slots[i];
            std::tie(slot.count, slot.lines) = grid_lines(slot.rho);
            if (slot.count > options.max_segments) return too_many_segments(slot.count, options, slot_face[i]);
        }
        for (std::size_t e = 0; e < cx.edges.size(); ++e) out.edge_rates[e] = cx.edge_count(e);
        return Ok{};
    };

    // demands
    std::vector<Graded> grades(out.domains.size());
    std::uint64_t demanded = 0;
    for (std::size_t f = 0; f < face_count; ++f) {
        if (cx.hole[f]) continue;
        if (options.cancel.requested()) return make_error(ErrorCode::Cancelled, "tessellation cancelled");
        auto surface = cx.evaluator.face_surface(f, kTreeLevels);
        if (!surface) return surface.error();
        FaceData& fd = cx.faces[f];
        fd.surface = std::move(surface.value());
        fd.size = base.face_size(f);
        fd.patches.resize(fd.surface->patch_count());
        for (std::size_t p = 0; p < fd.patches.size(); ++p) fd.patches[p] = patch_data(fd.surface->patch_points(p));
        for (std::size_t di = cx.first_domain[f]; di < cx.first_domain[f + 1]; ++di) {
            auto& d = out.domains[di];
            if (options.guaranteed) {
                auto demand = graded_demand(fd, f, d.subface, options);
                if (!demand) return demand.error();
                d.nu = demand->nu;
                d.nv = demand->nv;
                d.s_lines = demand->s_lines;
                d.t_lines = demand->t_lines;
                grades[di] = std::move(demand.value());
                push_density(d, grades[di].rs, grades[di].rt);
                // rates only grow from here: the grids so far are a lower bound on the output
                demanded += 2 * std::uint64_t(d.nu) * std::uint64_t(d.nv);
                if (auto status = check_budget(demanded, options); !status) return status.error();
            } else {
                auto demand = domain_demand(fd, f, d.subface, options);
                if (!demand) return demand.error();
                d.nu = demand->first;
                d.nv = demand->second;
                Density rs, rt;
                rs.fill(double(d.nu));
                rt.fill(double(d.nv));
                push_density(d, rs, rt);
            }
        }
    }
    if (auto status = update_slots(); !status) return status.error();

    // sides, then the transition check: every triangle of the actual layout bounded (or sampled) within tolerance.
    // A graded domain's failing triangles raise its densities where they lie and, in a transition strip, the density
    // of that side's edge or spoke over the part the triangle spans (then every domain on it is checked again); a
    // uniform domain's raise its inner rates.
    const auto count = [&] {
        std::uint64_t triangles = 0;
        for (auto& d : out.domains) triangles += domain_triangles(d);
        return triangles;
    };
    // each side's points from its slots: a side of a quad on a halved edge runs over both halves
    const auto set_sides = [&](LimitTessellationPlan::Domain& d) {
        for (int k = 0; k < 4; ++k) {
            int parts = 0;
            const auto sides = cx.side_parts(d, k, parts);
            std::vector<double> lines{0.0};
            for (int p = 0; p < parts; ++p) {
                const SidePart& part = sides[std::size_t(p)];
                const Slot& slot = cx.slots[part.slot];
                for (int i = 1; i <= slot.count; ++i) {
                    const double x = part.reversed ? 1.0 - slot.at(slot.count - i) : slot.at(i);
                    lines.push_back(part.q0 + (part.q1 - part.q0) * x);
                }
            }
            const int r = int(lines.size()) - 1;
            d.side[k] = r;
            bool uniform = true;
            for (int i = 0; i <= r && uniform; ++i) uniform = std::abs(lines[std::size_t(i)] - double(i) / r) <= 1e-12;
            if (uniform) lines.clear();
            d.side_lines[std::size_t(k)] = std::move(lines);
        }
        fix_inner(d);
    };
    for (auto& d : out.domains) set_sides(d);
    if (auto status = check_budget(count(), options); !status) return status.error();
    std::vector<bool> dirty(out.domains.size(), true);
    std::vector<double> domain_bound(out.domains.size(), 0.0), domain_sampled(out.domains.size(), 0.0);
    for (int pass = 0;; ++pass) {
        bool any = false;
        for (std::size_t di = 0; di < out.domains.size(); ++di) {
            if (!dirty[di]) continue;
            dirty[di] = false;
            auto& d = out.domains[di];
            if (options.cancel.requested()) return make_error(ErrorCode::Cancelled, "tessellation cancelled");
            const FaceData& fd = cx.faces[d.face];
            Graded& g = grades[di];
            Density next_s = g.rs, next_t = g.rt;
            for (int attempt = 0;; ++attempt) {
                const LocalMesh local = triangulate(d);
                std::vector<Vec3> positions;  // S at the local points, for the triangles' planes
                if (options.guaranteed) {
                    positions.reserve(local.points.size());
                    for (const P2& q : local.points) {
                        auto p = position_at(fd, d.subface, q);
                        if (!p) return p.error();
                        positions.push_back(*p);
                    }
                }
                const std::uint32_t ring = std::uint32_t(d.side[0] + d.side[1] + d.side[2] + d.side[3]);
                double bound = 0, sampled = 0;
                bool inner_fail = false;
                for (const auto& tri : local.triangles) {
                    const P2 &a = local.points[tri[0]], &b = local.points[tri[1]], &c = local.points[tri[2]];
                    const Overlap o = overlap_of(fd, d.subface, a, b, c);
                    double e = 0, tb = 0;
                    if (o.uncovered || !options.guaranteed) {
                        auto measured = sampled_error(fd, d.subface, a, b, c);
                        if (!measured) return measured.error();
                        e = *measured;
                        sampled = std::max(sampled, e);
                    }
                    // an edge on an open boundary: the full bound (no neighbour beyond it)
                    bool open_edge = false;
                    for (int k = 0; k < 4 && options.guaranteed; ++k) {
                        if (d.subface >= 0 && (k == 1 || k == 2)) continue;
                        const std::size_t fe = d.subface < 0 ? std::size_t(k)
                                               : k == 0      ? std::size_t(d.subface)
                                                             : (std::size_t(d.subface) + fd.size - 1) % fd.size;
                        if (cx.edge_faces[cx.face_edges[d.face][fe].edge] != 1) continue;
                        int on = 0;
                        for (const P2* q : {&a, &b, &c})
                            on += k == 0 ? q->t == 0 : k == 1 ? q->s == 1 : k == 2 ? q->t == 1 : q->s == 0;
                        open_edge = open_edge || on >= 2;
                    }
                    if (options.guaranteed && open_edge) {
                        tb = triangle_bound(full_bounds(fd, o, {std::min({a.s, b.s, c.s}), std::min({a.t, b.t, c.t})},
                                                        {std::max({a.s, b.s, c.s}), std::max({a.t, b.t, c.t})}),
                                            a, b, c);
                        bound = std::max(bound, tb);
                    } else if (options.guaranteed) {
                        tb = triangle_bound(
                            plane_bounds(fd, o, unit_normal(positions[tri[0]], positions[tri[1]], positions[tri[2]]), a,
                                         b, c),
                            a, b, c);
                        bound = std::max(bound, tb);
                    }
                    const double ratio = std::max(tb / options.tolerance, e / (options.tolerance / kSampledSafety));
                    if (!options.guaranteed || ratio <= 1) continue;
                    // graded: refine where the triangle lies, and its side when it is in a transition strip
                    const double f = std::min(4.0, std::max(1.1, std::sqrt(ratio)));
                    const double lo_s = std::min({a.s, b.s, c.s}), hi_s = std::max({a.s, b.s, c.s});
                    const double lo_t = std::min({a.t, b.t, c.t}), hi_t = std::max({a.t, b.t, c.t});
                    raise(next_s, lo_s, hi_s, f / std::max(hi_s - lo_s, 1e-9));
                    raise(next_t, lo_t, hi_t, f / std::max(hi_t - lo_t, 1e-9));
                    inner_fail = true;
                    // the strip's side: the side every ring vertex of the triangle lies on (a corner is on two)
                    bool on_ring = false;
                    for (std::uint32_t v : tri) on_ring = on_ring || v < ring;
                    int side = -1;
                    for (int k = 0; k < 4 && side < 0 && on_ring; ++k) {
                        bool all = true;
                        for (std::uint32_t v : tri) {
                            if (v >= ring) continue;
                            const P2& q = local.points[v];
                            const bool on = k == 0 ? q.t == 0 : k == 1 ? q.s == 1 : k == 2 ? q.t == 1 : q.s == 0;
                            all = all && on;
                        }
                        if (all) side = k;
                    }
                    if (side >= 0) {
                        // the triangle's span along the side (sides 2 and 3 run backwards)
                        const double lo = side == 0 ? lo_s : side == 1 ? lo_t : side == 2 ? 1.0 - hi_s : 1.0 - hi_t;
                        const double hi = side == 0 ? hi_s : side == 1 ? hi_t : side == 2 ? 1.0 - lo_s : 1.0 - lo_t;
                        raise_side(d, side, lo, hi, f / std::max(hi - lo, 1e-9));
                    }
                }
                const bool ok = bound <= options.tolerance && sampled <= options.tolerance / kSampledSafety;
                if (options.guaranteed) {
                    domain_bound[di] = bound;
                    domain_sampled[di] = sampled;
                    if (ok || pass >= 30) break;
                    any = true;
                    if (inner_fail) {
                        g.rs = next_s;
                        g.rt = next_t;
                        if (auto status = regrade(g, options, d.face); !status) return status.error();
                        apply(g, d);
                        dirty[di] = true;
                    }
                    break;
                }
                if (ok || attempt >= 40 || std::max(d.nu, d.nv) >= options.max_segments) {
                    domain_bound[di] = bound;
                    domain_sampled[di] = sampled;
                    break;
                }
                d.nu = std::min(options.max_segments, d.nu + std::max(1, d.nu / 8));
                d.nv = std::min(options.max_segments, d.nv + std::max(1, d.nv / 8));
                fix_inner(d);
            }
        }
        if (!any) break;
        if (auto status = update_slots(); !status) return status.error();
        for (std::size_t di = 0; di < out.domains.size(); ++di) {
            auto& d = out.domains[di];
            const int before[4] = {d.side[0], d.side[1], d.side[2], d.side[3]};
            const auto lines_before = d.side_lines;
            set_sides(d);
            for (int k = 0; k < 4; ++k)
                if (d.side[k] != before[k] || d.side_lines[std::size_t(k)] != lines_before[std::size_t(k)])
                    dirty[di] = true;
        }
        if (auto status = check_budget(count(), options); !status) return status.error();
    }
    for (std::size_t di = 0; di < out.domains.size(); ++di) {
        out.error_bound = std::max(out.error_bound, domain_bound[di]);
        out.sampled_error = std::max(out.sampled_error, domain_sampled[di]);
    }
    out.triangles = count();
    if (auto status = check_budget(out.triangles, options); !status) return status.error();

    // vertices: base vertices and edge points once, N-gon centres and spoke points once, inner points per domain
    std::vector<bool> used(base.vertex_count(), false);
    std::uint64_t vertices = 0;
    for (std::size_t f = 0; f < face_count; ++f)
        if (!cx.hole[f])
            for (Index v : base.face(f))
                if (!used[v]) {
                    used[v] = true;
                    ++vertices;
                }
    for (int r : out.edge_rates) vertices += std::uint64_t(r - 1);
    for (std::size_t f = 0; f < face_count; ++f)
        if (!cx.hole[f] && cx.faces[f].size != 4) ++vertices;
    for (std::size_t sp = 0; sp < cx.spokes; ++sp)
        vertices += std::uint64_t(cx.slots[cx.first_spoke_slot + sp].count - 1);
    for (const auto& d : out.domains) vertices += std::uint64_t(d.nu - 1) * std::uint64_t(d.nv - 1);
    out.vertices = vertices;
    return out;
}

//! Face (u, v) of the point at fraction a along the face's edge k (corner k to corner k + 1).
std::pair<double, double> edge_uv(std::size_t n, std::size_t k, double a) {
    if (n == 4) {
        static constexpr double kCorners[5][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0}};
        return {kCorners[k][0] + a * (kCorners[k + 1][0] - kCorners[k][0]),
                kCorners[k][1] + a * (kCorners[k + 1][1] - kCorners[k][1])};
    }
    if (a <= 0.5) return face_uv(n, int(k), 2.0 * a, 0.0);
    return face_uv(n, int((k + 1) % n), 0.0, 2.0 * (1.0 - a));
}

}  // namespace

Result<LimitTessellationPlan> plan_limit_tessellation(const LimitSurfaceEvaluator& evaluator, const PolygonMesh& base,
                                                      const LimitTessellationOptions& options) {
    Context cx(evaluator, base, options);
    return plan(cx);
}

Result<LimitTessellation> tessellate_limit(const LimitSurfaceEvaluator& evaluator, const PolygonMesh& base,
                                           const LimitTessellationOptions& options) {
    if (evaluator.face_count() != base.face_count())
        return make_error(ErrorCode::InvalidArgument, "the evaluator was created from another mesh");
    Context cx(evaluator, base, options);
    auto planned = plan(cx);
    if (!planned) return planned.error();
    LimitTessellation out;
    out.plan = std::move(planned.value());
    const LimitTessellationPlan& p = out.plan;
    const std::size_t face_count = base.face_count();

    // 1. vertex ids and where each is evaluated
    std::vector<LimitSite>& sites = out.sites;
    sites.reserve(p.vertices);
    std::vector<Index> vertex_id(base.vertex_count(), kInvalidIndex);
    for (std::size_t f = 0; f < face_count; ++f) {
        if (cx.hole[f]) continue;
        const auto fv = base.face(f);
        for (std::size_t k = 0; k < fv.size(); ++k)
            if (vertex_id[fv[k]] == kInvalidIndex) {
                vertex_id[fv[k]] = Index(sites.size());
                const auto [u, v] = edge_uv(fv.size(), k, 0.0);
                sites.push_back({std::uint32_t(f), u, v});
            }
    }
    std::vector<std::vector<Index>> edge_points(cx.edges.size());
    for (std::size_t e = 0; e < cx.edges.size(); ++e) {
        const int r = p.edge_rates[e];
        auto& pts = edge_points[e];
        pts.push_back(vertex_id[cx.edges[e][0]]);
        const std::size_t f = cx.edge_owner[e];
        for (int i = 1; i < r; ++i) {
            pts.push_back(Index(sites.size()));
            const auto [u, v] = edge_uv(base.face_size(f), cx.edge_owner_side[e], cx.edge_at(e, i));
            sites.push_back({std::uint32_t(f), u, v});
        }
        pts.push_back(vertex_id[cx.edges[e][1]]);
    }
    std::vector<std::vector<Index>> spoke_points(cx.spokes);
    for (std::size_t f = 0; f < face_count; ++f) {
        if (cx.hole[f] || base.face_size(f) == 4) continue;
        const std::size_t n = base.face_size(f);
        const Index centre = Index(sites.size());
        const auto [cu, cv] = face_uv(n, 0, 1.0, 1.0);
        sites.push_back({std::uint32_t(f), cu, cv});
        for (std::size_t j = 0; j < n; ++j) {
            const std::size_t sp = cx.first_spoke[f] + j;
            const Slot& slot = cx.slots[cx.spoke_slot(f, j)];
            const int r = slot.count;
            const auto& use = cx.face_edges[f][j];
            const int half = cx.slots[cx.edge_slot[use.edge]].count;  // the midpoint's canonical index
            auto& pts = spoke_points[sp];
            pts.push_back(edge_points[use.edge][std::size_t(half)]);
            for (int i = 1; i < r; ++i) {
                pts.push_back(Index(sites.size()));
                const auto [u, v] = face_uv(n, int(j), 1.0, slot.at(i));
                sites.push_back({std::uint32_t(f), u, v});
            }
            pts.push_back(centre);
        }
    }
    std::vector<Index> first_inner(p.domains.size());
    for (std::size_t di = 0; di < p.domains.size(); ++di) {
        const auto& d = p.domains[di];
        first_inner[di] = Index(sites.size());
        for (int j = 1; j < d.nv; ++j)
            for (int i = 1; i < d.nu; ++i) {
                const auto [u, v] = face_uv(cx.faces[d.face].size, d.subface, d.s_at(i), d.t_at(j));
                sites.push_back({d.face, u, v});
            }
    }

    // 2. evaluate every vertex once, face by face
    PolygonMesh& mesh = out.mesh;
    mesh.positions.resize(sites.size());
    mesh.normals.resize(sites.size());
    {
        std::vector<std::vector<Index>> by_face(face_count);
        for (std::size_t i = 0; i < sites.size(); ++i) by_face[sites[i].face].push_back(Index(i));
        for (std::size_t f = 0; f < face_count; ++f) {
            if (by_face[f].empty()) continue;
            if (options.cancel.requested()) return make_error(ErrorCode::Cancelled, "tessellation cancelled");
            for (Index i : by_face[f]) {
                auto sample = cx.faces[f].surface->evaluate(sites[i].u, sites[i].v);
                if (!sample) return sample.error();
                mesh.positions[i] = sample->position;
                mesh.normals[i] = sample->normal;
            }
        }
    }

    // 3. triangles (and UVs) per domain
    const bool uvs = base.has_uvs();
    mesh.face_offsets.reserve(p.triangles + 1);
    mesh.face_indices.reserve(3 * p.triangles);
    out.face_of_triangle.reserve(p.triangles);
    for (std::size_t di = 0; di < p.domains.size(); ++di) {
        const auto& d = p.domains[di];
        const std::size_t f = d.face, n = base.face_size(f);
        const LocalMesh local = triangulate(d);
        // side point ids in traversal order
        std::array<std::vector<Index>, 4> side;
        const auto edge_range = [&](std::size_t k, int from, int count) {
            // `count` points from face-direction index `from` of face edge k
            const auto& use = cx.face_edges[f][k];
            const auto& pts = edge_points[use.edge];
            const int r = p.edge_rates[use.edge];
            std::vector<Index> ids;
            for (int i = 0; i < count; ++i) {
                const int fi = from + i;
                ids.push_back(pts[std::size_t(use.forward ? fi : r - fi)]);
            }
            return ids;
        };
        if (d.subface < 0) {
            for (std::size_t k = 0; k < 4; ++k) side[k] = edge_range(k, 0, d.side[k] + 1);
        } else {
            const auto j = std::size_t(d.subface), prev = (j + n - 1) % n;
            side[0] = edge_range(j, 0, d.side[0] + 1);
            // the previous edge's second half in the face's direction: from its midpoint to corner j
            const auto& use = cx.face_edges[f][prev];
            const int mid = cx.slots[cx.edge_slot[use.edge] + (use.forward ? 0 : 1)].count;
            side[3] = edge_range(prev, mid, d.side[3] + 1);
            side[1] = spoke_points[cx.first_spoke[f] + j];
            side[2] = spoke_points[cx.first_spoke[f] + prev];
            std::reverse(side[2].begin(), side[2].end());
        }
        std::vector<Index> ids;
        ids.reserve(local.points.size());
        for (int k = 0; k < 4; ++k)
            for (int i = 0; i < d.side[k]; ++i) ids.push_back(side[std::size_t(k)][std::size_t(i)]);
        for (int i = 0; i < (d.nu - 1) * (d.nv - 1); ++i) ids.push_back(first_inner[di] + Index(i));
        // corner UVs of the domain: the face's, or for a sub-face its corner, edge midpoints and the centre
        std::array<Vec2, 4> corner_uv{};
        if (uvs) {
            const auto uv_at = [&](std::size_t k) { return base.uvs[base.uv_indices[base.face_offsets[f] + k]]; };
            if (d.subface < 0) {
                for (std::size_t k = 0; k < 4; ++k) corner_uv[k] = uv_at(k);
            } else {
                const auto j = std::size_t(d.subface);
                const auto mid = [](const Vec2& a, const Vec2& b) {
                    return Vec2{0.5 * (a.x + b.x), 0.5 * (a.y + b.y)};
                };
                Vec2 centre{};
                for (std::size_t k = 0; k < n; ++k) {
                    centre.x += uv_at(k).x / double(n);
                    centre.y += uv_at(k).y / double(n);
                }
                corner_uv = {uv_at(j), mid(uv_at(j), uv_at((j + 1) % n)), centre,
                             mid(uv_at(j), uv_at((j + n - 1) % n))};
            }
        }
        for (const auto& tri : local.triangles) {
            const Index t[3] = {ids[tri[0]], ids[tri[1]], ids[tri[2]]};
            mesh.add_face(std::span<const Index>(t, 3));
            out.face_of_triangle.push_back(Index(f));
            if (uvs)
                for (std::uint32_t c : tri) {
                    const P2& q = local.points[c];
                    mesh.uv_indices.push_back(Index(mesh.uvs.size()));
                    const double w[4] = {(1 - q.s) * (1 - q.t), q.s * (1 - q.t), q.s * q.t, (1 - q.s) * q.t};
                    Vec2 uv{};
                    for (int k = 0; k < 4; ++k) {
                        uv.x += w[k] * corner_uv[std::size_t(k)].x;
                        uv.y += w[k] * corner_uv[std::size_t(k)].y;
                    }
                    mesh.uvs.push_back(uv);
                }
        }
    }
    out.achieved_error = std::max(p.error_bound, p.sampled_error);
    return out;
}

}  // namespace surfaced
