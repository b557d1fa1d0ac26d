#include "geometry/subdivision/tessellation_bounds.h"

#include <algorithm>
#include <cstring>
#include <cmath>
#include <limits>

#include "geometry/spatial/closest_point.h"

namespace surfaced::tessellation_detail {
namespace {

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
std::pair<double, double> box_range(const double* c, int ds, int dt, const Basis& bs, const Basis& bt) {
    // the tensor product's coefficients one direction at a time: along s for each t row, then along t
    double along_s[4][4];  // [js][j]
    for (int j = 0; j <= dt; ++j)
        for (int js = 0; js <= ds; ++js) {
            double v = 0;
            for (int i = 0; i <= ds; ++i) v += c[i + (ds + 1) * j] * bs[std::size_t(i)][std::size_t(js)];
            along_s[js][j] = v;
        }
    double low = std::numeric_limits<double>::infinity(), high = -low;
    for (int js = 0; js <= ds; ++js)
        for (int jt = 0; jt <= dt; ++jt) {
            double v = 0;
            for (int j = 0; j <= dt; ++j) v += along_s[js][j] * bt[std::size_t(j)][std::size_t(jt)];
            low = std::min(low, v);
            high = std::max(high, v);
        }
    return {low, high};
}

double box_max(const double* c, int ds, int dt, const Basis& bs, const Basis& bt) {
    const auto [low, high] = box_range(c, ds, dt, bs, bt);
    return std::max(-low, high);
}

}  // namespace

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

std::pair<double, double> rates_for(const Bounds& m, double tolerance) {
    return {std::max(1.0, std::ceil(std::sqrt((m.uu + m.uv) / (4.0 * tolerance)))),
            std::max(1.0, std::ceil(std::sqrt((m.uv + m.vv) / (4.0 * tolerance))))};
}

double triangle_bound(const Bounds& m, const P2& p0, const P2& p1, const P2& p2) {
    const double ds = std::max({p0.s, p1.s, p2.s}) - std::min({p0.s, p1.s, p2.s});
    const double dt = std::max({p0.t, p1.t, p2.t}) - std::min({p0.t, p1.t, p2.t});
    const double k = ds > 0 && dt > 0 ? dt / ds : 1.0;
    const double a = std::sqrt(std::max(0.0, m.uu + k * m.uv)), c = std::sqrt(std::max(0.0, m.vv + m.uv / k));
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

double triangle_bound(const SignedBounds& m, const P2& p0, const P2& p1, const P2& p2, Bounds* dominant) {
    const double up = triangle_bound(m.up, p0, p1, p2), down = triangle_bound(m.down, p0, p1, p2);
    if (dominant) *dominant = up >= down ? m.up : m.down;
    return std::max(up, down);
}

int subface_columns(std::size_t n) {
    return n < 10 ? 2 + (n > 4 ? 1 : 0) : 1 + static_cast<int>(std::sqrt(static_cast<float>(n - 1)));
}

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

std::size_t domain_root(const FaceData& fd, int subface) {
    return subface < 0 ? 0 : static_cast<std::size_t>(fd.surface->nodes()[0].first_child + subface);
}

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

namespace {

//! The Bernstein bases of degrees 1 to 3 over one interval [a, b] of a span.
struct IntervalBases {
    double a = -1, b = -1;
    Basis d1, d2, d3;
};

//! interval_bases' memory: the bounds of neighbouring triangles ask for the same intervals (they share grid lines)
//! over and over, so a few recent ones per thread, one table per direction (s and t are looked up together).
using IntervalCache = std::array<IntervalBases, 64>;

const IntervalBases& interval_bases(double a, double b, IntervalCache& cache) {
    static const IntervalBases kWhole{0.0, 1.0, bernstein_of_basis(1, 0.0, 1.0), bernstein_of_basis(2, 0.0, 1.0),
                                      bernstein_of_basis(3, 0.0, 1.0)};
    if (a == 0.0 && b == 1.0) return kWhole;  // the common case: a patch inside the box
    std::uint64_t ka, kb;
    std::memcpy(&ka, &a, sizeof ka);
    std::memcpy(&kb, &b, sizeof kb);
    IntervalBases& entry = cache[((ka * 0x9E3779B97F4A7C15ull) ^ (kb * 0xC2B2AE3D27D4EB4Full)) >> 58];
    if (entry.a != a || entry.b != b)
        entry = {a, b, bernstein_of_basis(1, a, b), bernstein_of_basis(2, a, b), bernstein_of_basis(3, a, b)};
    return entry;
}

//! A patch's second derivatives projected on a direction n, with the Bernstein bases of the sub-box
//! [s0, s1] x [t0, t1] of its domain: what the unsigned and the signed bounds over that box are taken from.
struct ProjectedBox {
    // uu[2r + c]: c along s (linear), r along t (cubic); vv[r + 4c]: r along s (cubic), c along t (linear);
    // uv[3r + c]: c along s, r along t (quadratic both)
    double uu[8], vv[8], uv[9];
    const IntervalBases *s, *t;  //!< valid until the next project_in_box on this thread
};

ProjectedBox project_in_box(const PatchData& p, const Vec3& n, double s0, double s1, double t0, double t1) {
    thread_local IntervalCache s_cache, t_cache;
    ProjectedBox b;
    for (std::size_t i = 0; i < 8; ++i) b.uu[i] = dot(n, p.uu[i]);
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 2; ++c) b.vv[r + 4 * c] = dot(n, p.vv[std::size_t(2 * r + c)]);
    for (std::size_t i = 0; i < 9; ++i) b.uv[i] = dot(n, p.uv[i]);
    b.s = &interval_bases(s0, s1, s_cache);
    b.t = &interval_bases(t0, t1, t_cache);
    return b;
}

}  // namespace

Bounds along_in_box(const PatchData& p, const Vec3& n, double s0, double s1, double t0, double t1) {
    const ProjectedBox b = project_in_box(p, n, s0, s1, t0, t1);
    return {box_max(b.uu, 1, 3, b.s->d1, b.t->d3), box_max(b.uv, 2, 2, b.s->d2, b.t->d2),
            box_max(b.vv, 3, 1, b.s->d3, b.t->d1)};
}

SignedBounds signed_in_box(const PatchData& p, const Vec3& n, double s0, double s1, double t0, double t1) {
    const ProjectedBox b = project_in_box(p, n, s0, s1, t0, t1);
    const auto [uu_low, uu_high] = box_range(b.uu, 1, 3, b.s->d1, b.t->d3);
    const auto [vv_low, vv_high] = box_range(b.vv, 3, 1, b.s->d3, b.t->d1);
    const double mixed = box_max(b.uv, 2, 2, b.s->d2, b.t->d2);
    SignedBounds out;
    out.up = {uu_high, mixed, vv_high};
    out.down = {-uu_low, mixed, -vv_low};
    return out;
}

SignedBounds plane_bounds(const FaceData& fd, const Overlap& o, const std::optional<Vec3>& m, const P2& lo,
                          const P2& hi) {
    if (!m) return SignedBounds::symmetric(o.m);
    if (o.patches.empty()) return {};
    constexpr double kLowest = -std::numeric_limits<double>::infinity();
    SignedBounds out{{kLowest, 0, kLowest}, {kLowest, 0, kLowest}};
    for (const auto& piece : o.patches) {
        const double inv = 1.0 / piece.w;
        const double s0 = std::clamp((lo.s - piece.s0) * inv, 0.0, 1.0),
                     s1 = std::clamp((hi.s - piece.s0) * inv, 0.0, 1.0);
        const double t0 = std::clamp((lo.t - piece.t0) * inv, 0.0, 1.0),
                     t1 = std::clamp((hi.t - piece.t0) * inv, 0.0, 1.0);
        out.include(signed_in_box(fd.patches[piece.patch], *m, s0, s1, t0, t1), inv * inv);
    }
    return out;
}

Bounds full_bounds(const FaceData& fd, const Overlap& o, const P2& lo, const P2& hi) {
    Bounds axis[3];
    for (int k = 0; k < 3; ++k) {
        Vec3 e{};
        (k == 0 ? e.x : k == 1 ? e.y : e.z) = 1.0;
        axis[k] = plane_bounds(fd, o, e, lo, hi).magnitude();
    }
    const auto len = [](double a, double b, double c) { return std::sqrt(a * a + b * b + c * c); };
    return {len(axis[0].uu, axis[1].uu, axis[2].uu), len(axis[0].uv, axis[1].uv, axis[2].uv),
            len(axis[0].vv, axis[1].vv, axis[2].vv)};
}

SignedBounds plane_bounds(const FaceData& fd, const Overlap& o, const std::optional<Vec3>& m, const P2& a, const P2& b,
                          const P2& c) {
    return plane_bounds(fd, o, m, {std::min({a.s, b.s, c.s}), std::min({a.t, b.t, c.t})},
                        {std::max({a.s, b.s, c.s}), std::max({a.t, b.t, c.t})});
}

std::optional<Vec3> unit_normal(const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 n = cross(b - a, c - a);
    const double length = norm(n);
    if (!(length > 0) || !std::isfinite(length)) return std::nullopt;
    return n * (1.0 / length);
}

Vec3 straddle_offset(const LimitSample& sample, double lift) {
    if (!(lift > 0) || !sample.exact) return {};
    const Vec3& n = sample.normal;
    const double e = dot(sample.du, sample.du), f = dot(sample.du, sample.dv), g = dot(sample.dv, sample.dv);
    const double l = dot(sample.duu, n), m = dot(sample.duv, n), k = dot(sample.dvv, n);
    const double det = e * g - f * f;
    if (!(det > 0)) return {};
    const double mean2 = (e * k - 2 * f * m + g * l) / det;  // k1 + k2
    const double gauss = (l * k - m * m) / det;              // k1 k2
    const double largest = 0.5 * (std::abs(mean2) + std::sqrt(std::max(0.0, mean2 * mean2 - 4 * gauss)));
    if (!(largest > 0) || !std::isfinite(largest)) return {};
    // on a saddle the chords already cross the surface, by amounts that depend on the triangles' extent along each
    // principal direction, which is not known here: no offset once the smaller curvature, of the other sign,
    // reaches kSaddleTaper of the larger (linear in between, so that rounding does not flip a vertex)
    const double ratio = gauss / (largest * largest);  // k_small / k_large, in [-1, 1]
    const double share = std::clamp(1 + ratio / kSaddleTaper, 0.0, 1.0);
    // n . S curves towards -n where k1 + k2 < 0 there: the chords lie on the -n side, the vertex moves to +n
    return n * (mean2 < 0 ? lift * share : -lift * share);
}

Result<Vec3> position_at(const FaceData& fd, int subface, const P2& p) {
    const auto [u, v] = face_uv(fd.size, subface, p.s, p.t);
    auto sample = fd.surface->evaluate(u, v);
    if (!sample) return sample.error();
    return sample->position;
}

namespace {

//! The smallest and largest component along n of a triangle's corner offsets (what they add to the distance to its
//! plane, interpolated, lies between them).
std::pair<double, double> along(const Vec3& n, const std::array<Vec3, 3>& offsets) {
    const double a = dot(n, offsets[0]), b = dot(n, offsets[1]), c = dot(n, offsets[2]);
    return {std::min({a, b, c}), std::max({a, b, c})};
}

//! Whether domain point p lies on one of the face's fixed edges or vertices (FaceData::fixed_edge).
bool on_fixed(const FaceData& fd, int subface, const P2& p) {
    if (fd.fixed_edge.empty()) return false;
    const std::size_t n = fd.size;
    if (subface < 0) {
        const bool on[4] = {p.t == 0, p.s == 1, p.t == 1, p.s == 0};
        const bool at[4] = {on[3] && on[0], on[0] && on[1], on[1] && on[2], on[2] && on[3]};
        for (std::size_t k = 0; k < 4; ++k)
            if ((on[k] && fd.fixed_edge[k]) || (at[k] && fd.fixed_vertex[k])) return true;
        return false;
    }
    // an N-gon's sub-face j: side t = 0 is the first half of edge j, s = 0 the second half of edge j - 1
    const auto j = std::size_t(subface), prev = (j + n - 1) % n;
    return (p.t == 0 && fd.fixed_edge[j]) || (p.s == 0 && fd.fixed_edge[prev]) ||
           (p.s == 0 && p.t == 0 && fd.fixed_vertex[j]);
}

}  // namespace

Result<OffsetPoint> corner_at(const FaceData& fd, int subface, const P2& p) {
    const auto [u, v] = face_uv(fd.size, subface, p.s, p.t);
    const bool moves = fd.lift > 0 && !on_fixed(fd, subface, p);
    auto sample = fd.surface->evaluate(u, v, moves);
    if (!sample) return sample.error();
    const Vec3 offset = moves ? straddle_offset(*sample, fd.lift) : Vec3{};
    return OffsetPoint{sample->position + offset, offset};
}

double offset_bound(const SignedBounds& m, const P2& p0, const P2& p1, const P2& p2, const std::optional<Vec3>& normal,
                    const std::array<Vec3, 3>& offsets, Bounds* dominant) {
    const double up = triangle_bound(m.up, p0, p1, p2), down = triangle_bound(m.down, p0, p1, p2);
    if (!normal) {
        const double longest = std::max({norm(offsets[0]), norm(offsets[1]), norm(offsets[2])});
        if (dominant) *dominant = up >= down ? m.up : m.down;
        return std::max(up, down) + longest;
    }
    const auto [low, high] = along(*normal, offsets);
    // the distance m . (S - T) lies in [-up - high, down - low]
    const double below = std::abs(up + high), above = std::abs(down - low);
    if (dominant) *dominant = below >= above ? m.up : m.down;
    return std::max(below, above);
}

Result<SampledError> sampled_error(const FaceData& fd, int subface, const P2& a, const P2& b, const P2& c,
                                   const std::array<OffsetPoint, 3>& corners, bool whole_distance) {
    const auto at = [&](const P2& p) -> Result<Vec3> {
        const auto [u, v] = face_uv(fd.size, subface, p.s, p.t);
        auto sample = fd.surface->evaluate(u, v);
        if (!sample) return sample.error();
        return sample->position;
    };
    // S at the corners, and the plane of the vertices
    const std::array<Vec3, 3> on{corners[0].position - corners[0].offset, corners[1].position - corners[1].offset,
                                 corners[2].position - corners[2].offset};
    const auto normal =
        whole_distance ? std::nullopt : unit_normal(corners[0].position, corners[1].position, corners[2].position);
    // with a plane: m . (S(x) - T(x)) = bend(x) - lift(x), bend = m . S(x) minus its interpolant between the corners'
    // S (the part the samples may miss the peak of), lift = the corners' offsets along m, interpolated
    const std::array<Vec3, 3> offsets{corners[0].offset, corners[1].offset, corners[2].offset};
    const auto [lift_low, lift_high] = normal ? along(*normal, offsets) : std::pair{0.0, 0.0};
    const double longest_offset = std::max({norm(offsets[0]), norm(offsets[1]), norm(offsets[2])});
    double bend_low = 0, bend_high = 0;
    double measured = std::max(std::abs(lift_low), std::abs(lift_high));  // at the corners
    constexpr int kSteps = 6;
    for (int i = 0; i <= kSteps; ++i)
        for (int j = 0; i + j <= kSteps; ++j) {
            const int k = kSteps - i - j;
            if (i == kSteps || j == kSteps || k == kSteps) continue;
            const double li = double(i) / kSteps, lj = double(j) / kSteps, lk = double(k) / kSteps;
            const P2 x{li * a.s + lj * b.s + lk * c.s, li * a.t + lj * b.t + lk * c.t};
            auto sx = at(x);
            if (!sx) return sx.error();
            if (normal) {
                // distance to the plane: a point whose projection falls just outside the triangle is near its
                // neighbour's, which the distance to this triangle alone (its edge) would overstate
                const double bend = dot(*normal, *sx - (on[0] * li + on[1] * lj + on[2] * lk));
                const double lift = dot(*normal, offsets[0] * li + offsets[1] * lj + offsets[2] * lk);
                bend_low = std::min(bend_low, bend);
                bend_high = std::max(bend_high, bend);
                measured = std::max(measured, std::abs(bend - lift));
            } else {
                const Vec3 q =
                    triangle_closest_point(*sx, corners[0].position, corners[1].position, corners[2].position).point;
                measured = std::max(measured, norm(*sx - q));
            }
        }
    SampledError out;
    out.measured = measured;
    out.check = normal ? std::max(std::abs(kSampledSafety * bend_low - lift_high),
                                  std::abs(kSampledSafety * bend_high - lift_low))
                       : kSampledSafety * measured + longest_offset;
    return out;
}

Result<SampledError> sampled_error(const FaceData& fd, int subface, const P2& a, const P2& b, const P2& c) {
    std::array<OffsetPoint, 3> corners;
    const P2* points[3] = {&a, &b, &c};
    for (std::size_t k = 0; k < 3; ++k) {
        auto corner = corner_at(fd, subface, *points[k]);
        if (!corner) return corner.error();
        corners[k] = *corner;
    }
    return sampled_error(fd, subface, a, b, c, corners);
}

Result<TriangleError> triangle_error(const FaceData& fd, int subface, const std::array<bool, 4>& open_sides,
                                     const P2& a, const P2& b, const P2& c, const std::array<OffsetPoint, 3>& corners,
                                     bool guaranteed) {
    TriangleError out;
    const Overlap o = overlap_of(fd, subface, a, b, c);
    // an edge on an open boundary (or a fold): the full distance (no neighbour beyond it)
    bool open_edge = false;
    for (int k = 0; k < 4; ++k) {
        if (!open_sides[std::size_t(k)]) continue;
        int on = 0;
        for (const P2* q : {&a, &b, &c}) on += k == 0 ? q->t == 0 : k == 1 ? q->s == 1 : k == 2 ? q->t == 1 : q->s == 0;
        open_edge = open_edge || on >= 2;
    }
    if (o.uncovered || !guaranteed) {
        auto measured =
            guaranteed ? sampled_error(fd, subface, a, b, c, corners, open_edge) : sampled_error(fd, subface, a, b, c);
        if (!measured) return measured.error();
        out.sampled = measured->measured;
        out.check = measured->check;
    }
    if (!guaranteed) return out;
    const P2 lo{std::min({a.s, b.s, c.s}), std::min({a.t, b.t, c.t})};
    const P2 hi{std::max({a.s, b.s, c.s}), std::max({a.t, b.t, c.t})};
    const std::array<Vec3, 3> offsets{corners[0].offset, corners[1].offset, corners[2].offset};
    if (open_edge) {
        out.bound = offset_bound(SignedBounds::symmetric(full_bounds(fd, o, lo, hi)), a, b, c, std::nullopt, offsets);
    } else {
        const auto n = unit_normal(corners[0].position, corners[1].position, corners[2].position);
        out.bound = offset_bound(plane_bounds(fd, o, n, lo, hi), a, b, c, n, offsets);
    }
    return out;
}

}  // namespace surfaced::tessellation_detail
