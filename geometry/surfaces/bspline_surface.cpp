// B-spline and NURBS surfaces. Everything works per direction on the (p + 1) x (q + 1) control points local to one
// knot span pair, in homogeneous coordinates (w P, w) for NURBS: evaluation is O(p^2 + q^2 + p q) whatever the net's
// size. Knot insertion and Bézier extraction carry each point's Euclidean position along with its homogeneous form, so
// that points insertion does not touch are copied exactly and a convex combination of identical points is that point
// exactly (a pole row stays one point to the bit, which the tessellator needs to recognise a collapsed edge).
#include "geometry/surfaces/bspline_surface.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <tuple>
#include <string>

#include "geometry/core/format_number.h"
#include "geometry/curves/bspline.h"

namespace surfaced {
namespace {

constexpr std::size_t kLocal = static_cast<std::size_t>(kMaxBSplineSurfaceDegree) + 1;

std::string num(double v) { return shortest_text(v); }

const char* knot_name(SurfaceDirection d) { return d == SurfaceDirection::U ? "knots_u" : "knots_v"; }

//! A control point during insertion: homogeneous (w P, w) and its Euclidean position e, kept exact where possible.
struct Node {
    Vec3 hp;
    double w = 1;
    Vec3 e;
};

Node lerp(const Node& a, const Node& b, double alpha) {
    if (alpha == 0.0) return a;  // exact at the ends (blossoms at repeated knots)
    if (alpha == 1.0) return b;
    Node out;
    out.hp = (1.0 - alpha) * a.hp + alpha * b.hp;
    out.w = (1.0 - alpha) * a.w + alpha * b.w;
    out.e = a.e == b.e ? a.e : out.hp * (1.0 / out.w);
    return out;
}

Node node(const BSplineSurface& s, int i, int j) {
    const double w = s.weight(i, j);
    const Vec3& p = s.at(i, j);
    return {s.rational() ? w * p : p, w, p};
}

//! One Boehm insertion of t into span k (U[k] <= t <= U[k+1], U[k] < U[k+1]) of a degree-p curve with points P.
void insert_once(int p, std::vector<Node>& P, std::vector<double>& U, double t, std::size_t k) {
    const auto ps = static_cast<std::size_t>(p);
    std::vector<Node> Q(P.size() + 1);
    for (std::size_t i = 0; i + ps <= k; ++i) Q[i] = P[i];
    for (std::size_t i = k - ps + 1; i <= k; ++i) Q[i] = lerp(P[i - 1], P[i], (t - U[i]) / (U[i + ps] - U[i]));
    for (std::size_t i = k + 1; i < Q.size(); ++i) Q[i] = P[i - 1];
    P = std::move(Q);
    U.insert(U.begin() + static_cast<std::ptrdiff_t>(k + 1), t);
}

//! The Bézier points of span k of a degree-p curve: `local` holds P_{k-p..k}, `knots` points at U[k-p] (2p + 2 knots
//! U[k-p..k+p+1]). Raises U[k] and U[k+1] to multiplicity p among the knots the span's basis functions see; returns
//! the p + 1 Bézier points in `local`.
void span_to_bezier(int p, std::vector<Node>& local, const double* knots, std::vector<double>& L) {
    const auto ps = static_cast<std::size_t>(p);
    L.assign(knots, knots + 2 * ps + 2);
    const double a = L[ps], b = L[ps + 1];
    std::size_t span = ps;
    const auto have_a =
        static_cast<std::size_t>(std::count(L.begin() + 1, L.begin() + static_cast<std::ptrdiff_t>(ps + 1), a));
    for (std::size_t t = have_a; t < ps; ++t) insert_once(p, local, L, a, span++);
    const auto have_b = static_cast<std::size_t>(std::count(L.begin() + static_cast<std::ptrdiff_t>(span + 1),
                                                            L.begin() + static_cast<std::ptrdiff_t>(span + ps + 1), b));
    for (std::size_t t = have_b; t < ps; ++t) insert_once(p, local, L, b, span);
    local.erase(local.begin() + static_cast<std::ptrdiff_t>(span + 1), local.end());
    local.erase(local.begin(), local.begin() + static_cast<std::ptrdiff_t>(span - ps));
}

Status validate_knots(SurfaceDirection d, const std::vector<double>& U, int p, int n) {
    const char* name = knot_name(d);
    const auto ps = static_cast<std::size_t>(p), ns = static_cast<std::size_t>(n);
    for (std::size_t i = 0; i < U.size(); ++i) {
        if (!std::isfinite(U[i]))
            return element_error(ErrorCode::NonFinite, std::string(name) + "[" + std::to_string(i) + "] is not finite",
                                 ElementKind::None, static_cast<std::int64_t>(i));
        if (i > 0 && U[i] < U[i - 1])
            return element_error(ErrorCode::InvalidArgument,
                                 std::string(name) + "[" + std::to_string(i) + "] (" + num(U[i]) +
                                     ") is smaller than " + name + "[" + std::to_string(i - 1) + "] (" + num(U[i - 1]) +
                                     "): knots must be non-decreasing",
                                 ElementKind::None, static_cast<std::int64_t>(i));
    }
    for (std::size_t start = 0; start < U.size();) {
        std::size_t end = start;
        while (end < U.size() && U[end] == U[start]) ++end;
        const bool at_end = start == 0 || end == U.size();
        const std::size_t allowed = at_end ? ps + 1 : ps;
        if (end - start > allowed)
            return element_error(ErrorCode::InvalidArgument,
                                 std::string(name) + "[" + std::to_string(start + allowed) + "]: the value " +
                                     num(U[start]) + " is repeated " + std::to_string(end - start) + " times (from " +
                                     name + "[" + std::to_string(start) +
                                     "]); at most degree + 1 = " + std::to_string(ps + 1) +
                                     " for the first or last value, degree = " + std::to_string(ps) + " for any other",
                                 ElementKind::None, static_cast<std::int64_t>(start + allowed));
        start = end;
    }
    if (!(U[ps] < U[ns]))
        return element_error(ErrorCode::InvalidArgument,
                             std::string(name) + ": the domain [" + name + "[" + std::to_string(ps) + "], " + name +
                                 "[" + std::to_string(ns) + "]] = [" + num(U[ps]) + ", " + num(U[ns]) + "] is empty",
                             ElementKind::None, static_cast<std::int64_t>(ns));
    return Ok{};
}

//! Basis functions N_{k-p+r,p} (r = 0..p) and their derivatives up to order n <= p at u on span k (A2.3):
//! ders[d][r] = d-th derivative. Orders above p are left to the caller (zero).
void basis_derivatives(const double* U, int p, std::size_t k, double u, int n, double ders[3][kLocal]) {
    double ndu[kLocal][kLocal], left[kLocal], right[kLocal], a[2][kLocal];
    ndu[0][0] = 1.0;
    for (int j = 1; j <= p; ++j) {
        left[j] = u - U[k + 1 - static_cast<std::size_t>(j)];
        right[j] = U[k + static_cast<std::size_t>(j)] - u;
        double saved = 0.0;
        for (int r = 0; r < j; ++r) {
            ndu[j][r] = right[r + 1] + left[j - r];  // lower triangle: knot differences
            const double temp = ndu[r][j - 1] / ndu[j][r];
            ndu[r][j] = saved + right[r + 1] * temp;  // upper triangle: basis functions
            saved = left[j - r] * temp;
        }
        ndu[j][j] = saved;
    }
    for (int j = 0; j <= p; ++j) ders[0][j] = ndu[j][p];
    for (int r = 0; r <= p; ++r) {
        int s1 = 0, s2 = 1;
        a[0][0] = 1.0;
        for (int d = 1; d <= n; ++d) {
            double value = 0.0;
            const int rk = r - d, pk = p - d;
            if (r >= d) {
                a[s2][0] = a[s1][0] / ndu[pk + 1][rk];
                value = a[s2][0] * ndu[rk][pk];
            }
            const int j1 = rk >= -1 ? 1 : -rk;
            const int j2 = r - 1 <= pk ? d - 1 : p - r;
            for (int j = j1; j <= j2; ++j) {
                a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][rk + j];
                value += a[s2][j] * ndu[rk + j][pk];
            }
            if (r <= pk) {
                a[s2][d] = -a[s1][d - 1] / ndu[pk + 1][r];
                value += a[s2][d] * ndu[r][pk];
            }
            ders[d][r] = value;
            std::swap(s1, s2);
        }
    }
    double factor = p;
    for (int d = 1; d <= n; ++d) {
        for (int j = 0; j <= p; ++j) ders[d][j] *= factor;
        factor *= p - d;
    }
}

Status check_parameters(const BSplineSurface& s, double u, double v) {
    const auto [u0, u1] = domain_u(s);
    const auto [v0, v1] = domain_v(s);
    if (!(std::isfinite(u) && u >= u0 && u <= u1))
        return make_error(ErrorCode::InvalidArgument,
                          "u = " + num(u) + " is outside the domain [" + num(u0) + ", " + num(u1) + "]");
    if (!(std::isfinite(v) && v >= v0 && v <= v1))
        return make_error(ErrorCode::InvalidArgument,
                          "v = " + num(v) + " is outside the domain [" + num(v0) + ", " + num(v1) + "]");
    return Ok{};
}

//! Position and derivatives up to total order `order` (0 or 2) at (u, v) in the domain.
PatchDerivatives derivatives(const BSplineSurface& s, double u, double v, int order) {
    const int p = s.degree_u, q = s.degree_v;
    const std::size_t ku = find_span(s.knots_u, p, static_cast<std::size_t>(s.count_u), u);
    const std::size_t kv = find_span(s.knots_v, q, static_cast<std::size_t>(s.count_v), v);
    const int du = std::min(order, p), dv = std::min(order, q);
    double Nu[3][kLocal] = {}, Nv[3][kLocal] = {};
    basis_derivatives(s.knots_u.data(), p, ku, u, du, Nu);
    basis_derivatives(s.knots_v.data(), q, kv, v, dv, Nv);
    // A[k][l], W[k][l]: derivatives of the homogeneous numerator and of the weight (A3.6), zero above the degrees
    Vec3 A[3][3] = {};
    double W[3][3] = {};
    const int iu = static_cast<int>(ku) - p, jv = static_cast<int>(kv) - q;
    Vec3 temp[kLocal];
    double wtemp[kLocal];
    for (int k = 0; k <= du; ++k) {
        for (int sj = 0; sj <= q; ++sj) {
            temp[sj] = {};
            wtemp[sj] = 0;
            for (int r = 0; r <= p; ++r) {
                const double w = s.weight(iu + r, jv + sj);
                const double b = Nu[k][r] * w;
                temp[sj] += b * s.at(iu + r, jv + sj);
                wtemp[sj] += b;
            }
        }
        for (int l = 0; l <= std::min(order - k, dv); ++l) {
            for (int sj = 0; sj <= q; ++sj) {
                A[k][l] += Nv[l][sj] * temp[sj];
                W[k][l] += Nv[l][sj] * wtemp[sj];
            }
        }
    }
    Vec3 S[3][3] = {};
    if (!s.rational()) {
        for (int k = 0; k <= order; ++k)
            for (int l = 0; k + l <= order; ++l) S[k][l] = A[k][l];
    } else {
        // A4.4 (the binomials of orders <= 2 are 1, 1 and 1, 2, 1)
        constexpr double binomial[3][3] = {{1, 0, 0}, {1, 1, 0}, {1, 2, 1}};
        for (int k = 0; k <= order; ++k)
            for (int l = 0; k + l <= order; ++l) {
                Vec3 value = A[k][l];
                for (int j = 1; j <= l; ++j) value -= binomial[l][j] * W[0][j] * S[k][l - j];
                for (int i = 1; i <= k; ++i) {
                    value -= binomial[k][i] * W[i][0] * S[k - i][l];
                    for (int j = 1; j <= l; ++j) value -= binomial[k][i] * binomial[l][j] * W[i][j] * S[k - i][l - j];
                }
                S[k][l] = value * (1.0 / W[0][0]);
            }
    }
    PatchDerivatives out;
    out.position = S[0][0];
    out.du = S[1][0];
    out.dv = S[0][1];
    out.duu = S[2][0];
    out.duv = S[1][1];
    out.dvv = S[0][2];
    return out;
}

Vec3 normalized(const Vec3& v) {
    const double length = norm(v);
    return length > 0 ? v * (1.0 / length) : Vec3{};
}

//! Relative difference below which two seam edges count as one edge computed twice (by de Boor at the two ends of a
//! periodic knot vector, from different knot values): far above the rounding of the extraction, far below any
//! geometric feature.
constexpr double kSeamTolerance = 1e-12;

//! Where the first and the last patch column (u seam) or row (v seam) have edges that agree to within
//! kSeamTolerance -- the surface closes there, as a periodic (unclamped, wrapped) net does -- the last edge is made a
//! copy of the first, so that the tessellator welds the seam. Clamped closed nets already agree bit for bit.
void close_seams(SurfaceBezierPatches& out, const BSplineSurface& s) {
    double size = 0, wmax = 0;
    for (const Vec3& p : s.points) size = std::max(size, norm(p));
    for (double w : s.weights) wmax = std::max(wmax, w);
    const std::size_t nu = out.breaks_u.size() - 1, nv = out.breaks_v.size() - 1;
    const int p = s.degree_u, q = s.degree_v;
    // first and last patch of each row (u seam: columns 0 and p) or column (v seam: rows 0 and q)
    const auto close = [&](BezierPatch& first, BezierPatch& last, bool u_seam) {
        const int count = u_seam ? q : p;
        const auto index = [&](const BezierPatch& patch, int k, bool at_end) {
            const int i = u_seam ? (at_end ? p : 0) : k, j = u_seam ? k : (at_end ? q : 0);
            return static_cast<std::size_t>(j) * static_cast<std::size_t>(patch.degree_u + 1) +
                   static_cast<std::size_t>(i);
        };
        for (int k = 0; k <= count; ++k) {
            const std::size_t a = index(first, k, false), b = index(last, k, true);
            if (norm(first.points[a] - last.points[b]) > kSeamTolerance * size) return;
            if (s.rational() && std::fabs(first.weights[a] - last.weights[b]) > kSeamTolerance * wmax) return;
        }
        for (int k = 0; k <= count; ++k) {
            const std::size_t a = index(first, k, false), b = index(last, k, true);
            last.points[b] = first.points[a];
            if (s.rational()) last.weights[b] = first.weights[a];
        }
    };
    for (std::size_t b = 0; b < nv; ++b) close(out.patches[b * nu], out.patches[b * nu + nu - 1], true);
    for (std::size_t a = 0; a < nu; ++a) close(out.patches[a], out.patches[(nv - 1) * nu + a], false);
}

//! The average of nodes, keeping the Euclidean position exact when they all share it.
Node average(const Node* nodes, std::size_t count) {
    Node out{Vec3{}, 0.0, nodes[0].e};
    bool same = true;
    for (std::size_t k = 0; k < count; ++k) {
        out.hp += nodes[k].hp;
        out.w += nodes[k].w;
        same = same && nodes[k].e == nodes[0].e;
    }
    out.hp = out.hp * (1.0 / static_cast<double>(count));
    out.w /= static_cast<double>(count);
    if (!same) out.e = out.hp * (1.0 / out.w);
    return out;
}

//! The knot vector of a degree-(p+1) elevation of a degree-p spline with knots U and n points: the p + 1 knots left
//! of the domain (U[0..p]) and right of it (U[n..n+p]) each gain a copy of their outermost value, every distinct
//! value of U[p+1..n-1] one more copy.
std::vector<double> elevated_knots(const std::vector<double>& U, std::size_t p, std::size_t n) {
    std::vector<double> out;
    out.reserve(2 * U.size());
    out.push_back(U[0]);
    out.insert(out.end(), U.begin(), U.begin() + static_cast<std::ptrdiff_t>(p + 1));
    for (std::size_t k = p + 1; k < n; ++k) {
        out.push_back(U[k]);
        if (k + 1 == n || U[k + 1] != U[k]) out.push_back(U[k]);
    }
    out.insert(out.end(), U.begin() + static_cast<std::ptrdiff_t>(n), U.end());
    out.push_back(U.back());
    return out;
}

//! One degree elevation of the curve (P, U) of degree p (blossoming, see elevate_degree in the header); T is
//! elevated_knots(U). Returns the T.size() - p - 2 new points.
std::vector<Node> elevate_curve(int p, const std::vector<Node>& P, const std::vector<double>& U,
                                const std::vector<double>& T) {
    const auto ps = static_cast<std::size_t>(p), d = ps + 1;
    const std::size_t n = P.size(), m = T.size() - d - 1;  // new point count
    std::vector<Node> out(m);
    std::array<Node, kLocal + 1> terms;
    std::array<Node, kLocal> level;
    std::array<double, kLocal + 1> args;
    for (std::size_t i = 0; i < m; ++i) {
        // a non-empty span l of T inside the domain [T[d], T[m]] that point i's support covers (l in [i, i + d]),
        // else the nearest non-empty domain span (point i then does not act on the domain)
        const std::size_t lo = std::max(i, d), hi = std::min(i + d, m - 1);
        std::size_t l = m;
        for (std::size_t k = lo; k <= hi && l == m; ++k)
            if (T[k] < T[k + 1]) l = k;
        if (l == m) {
            const double target = T[std::clamp(i, d, m - 1)];
            for (std::size_t k = d; k < m; ++k)
                if (T[k] < T[k + 1] && (l == m || std::abs(T[k] - target) < std::abs(T[l] - target))) l = k;
        }
        // the same span in U (its left end is inside the domain and below its right end)
        const std::size_t span = find_span(U, p, n, T[l]);
        for (std::size_t k = 0; k <= ps; ++k) {
            std::size_t a = 0;
            for (std::size_t r = 0; r <= ps; ++r)
                if (r != k) args[a++] = T[i + 1 + r];
            // de Boor with argument args[r - 1] at level r: the blossom of the span's polynomial
            for (std::size_t r = 0; r <= ps; ++r) level[r] = P[span - ps + r];
            for (std::size_t r = 1; r <= ps; ++r)
                for (std::size_t j = ps; j >= r; --j) {
                    const std::size_t g = span - ps + j;  // global index of level[j]
                    const double alpha = (args[r - 1] - U[g]) / (U[g + ps + 1 - r] - U[g]);
                    level[j] = lerp(level[j - 1], level[j], alpha);
                }
            terms[k] = level[ps];
        }
        out[i] = average(terms.data(), ps + 1);
    }
    return out;
}

}  // namespace

Status validate(const BSplineSurface& s) {
    for (auto [name, degree] : {std::pair{"degree_u", s.degree_u}, std::pair{"degree_v", s.degree_v}})
        if (degree < 1 || degree > kMaxBSplineSurfaceDegree)
            return make_error(ErrorCode::InvalidArgument, std::string(name) + " " + std::to_string(degree) +
                                                              " is outside 1.." +
                                                              std::to_string(kMaxBSplineSurfaceDegree));
    for (auto [name, count, degree] : {std::tuple{"u", s.count_u, s.degree_u}, std::tuple{"v", s.count_v, s.degree_v}})
        if (count < degree + 1)
            return make_error(ErrorCode::InvalidArgument,
                              std::string("count_") + name + " is " + std::to_string(count) + "; degree " +
                                  std::to_string(degree) + " along " + name + " needs at least " +
                                  std::to_string(degree + 1) + " control points");
    for (auto [d, knots, count, degree] : {std::tuple{SurfaceDirection::U, &s.knots_u, s.count_u, s.degree_u},
                                           std::tuple{SurfaceDirection::V, &s.knots_v, s.count_v, s.degree_v}}) {
        const std::size_t need = static_cast<std::size_t>(count) + static_cast<std::size_t>(degree) + 1;
        const char* axis = d == SurfaceDirection::U ? "u" : "v";
        if (knots->size() != need)
            return make_error(ErrorCode::InvalidArgument,
                              std::string(knot_name(d)) + " has " + std::to_string(knots->size()) + " entries; " +
                                  std::to_string(count) + " control points along " + axis + " of degree " +
                                  std::to_string(degree) + " need " + std::to_string(need) + " (count_" + axis +
                                  " + degree_" + axis + " + 1)");
    }
    const std::size_t expected = static_cast<std::size_t>(s.count_u) * static_cast<std::size_t>(s.count_v);
    if (s.points.size() != expected)
        return make_error(ErrorCode::InvalidArgument, "points has " + std::to_string(s.points.size()) +
                                                          " entries; a net of " + std::to_string(s.count_u) + " x " +
                                                          std::to_string(s.count_v) + " (count_u x count_v) needs " +
                                                          std::to_string(expected));
    if (s.rational() && s.weights.size() != expected)
        return make_error(ErrorCode::InvalidArgument, "weights has " + std::to_string(s.weights.size()) +
                                                          " entries for " + std::to_string(expected) +
                                                          " control points");
    const auto where = [&](std::size_t k) {
        return std::to_string(k) + " (i " + std::to_string(k % static_cast<std::size_t>(s.count_u)) + ", j " +
               std::to_string(k / static_cast<std::size_t>(s.count_u)) + ")";
    };
    for (std::size_t k = 0; k < s.points.size(); ++k)
        if (!is_finite(s.points[k]))
            return element_error(ErrorCode::NonFinite, "control point " + where(k) + " is not finite",
                                 ElementKind::Vertex, static_cast<std::int64_t>(k));
    if (s.rational()) {
        double lo = s.weights[0], hi = s.weights[0];
        for (std::size_t k = 0; k < s.weights.size(); ++k) {
            const double w = s.weights[k];
            if (!(std::isfinite(w) && w > 0))
                return element_error(ErrorCode::InvalidArgument,
                                     "weight " + where(k) + " must be a finite number > 0 (got " + num(w) + ")",
                                     ElementKind::Vertex, static_cast<std::int64_t>(k));
            if (!is_finite(w * s.points[k]))
                return element_error(ErrorCode::InvalidArgument,
                                     "weight " + where(k) + " times its control point overflows", ElementKind::Vertex,
                                     static_cast<std::int64_t>(k));
            lo = std::min(lo, w);
            hi = std::max(hi, w);
        }
        if (hi > kMaxWeightRatio * lo)
            return make_error(
                ErrorCode::InvalidArgument,
                "the largest weight (" + num(hi) + ") is more than 1e12 times the smallest (" + num(lo) + ")");
    }
    if (auto ok = validate_knots(SurfaceDirection::U, s.knots_u, s.degree_u, s.count_u); !ok) return ok;
    if (auto ok = validate_knots(SurfaceDirection::V, s.knots_v, s.degree_v, s.count_v); !ok) return ok;
    return Ok{};
}

std::pair<double, double> domain_u(const BSplineSurface& s) {
    return {s.knots_u[static_cast<std::size_t>(s.degree_u)], s.knots_u[static_cast<std::size_t>(s.count_u)]};
}

std::pair<double, double> domain_v(const BSplineSurface& s) {
    return {s.knots_v[static_cast<std::size_t>(s.degree_v)], s.knots_v[static_cast<std::size_t>(s.count_v)]};
}

Result<Vec3> evaluate(const BSplineSurface& s, double u, double v) {
    if (auto ok = check_parameters(s, u, v); !ok) return ok.error();
    return derivatives(s, u, v, 0).position;
}

Result<PatchDerivatives> evaluate_derivatives(const BSplineSurface& s, double u, double v) {
    if (auto ok = check_parameters(s, u, v); !ok) return ok.error();
    return derivatives(s, u, v, 2);
}

Result<Vec3> unit_normal(const BSplineSurface& s, double u, double v) {
    if (auto ok = check_parameters(s, u, v); !ok) return ok.error();
    const PatchDerivatives d = derivatives(s, u, v, 2);
    const auto [u0, u1] = domain_u(s);
    const auto [v0, v1] = domain_v(s);
    // The floor of "vanishes" when both first derivatives vanish: the size of the local net times the degree over the
    // span length, per direction (the order of magnitude of a first derivative there), multiplied.
    const std::size_t ku = find_span(s.knots_u, s.degree_u, static_cast<std::size_t>(s.count_u), u);
    const std::size_t kv = find_span(s.knots_v, s.degree_v, static_cast<std::size_t>(s.count_v), v);
    Box3 box;
    for (int j = 0; j <= s.degree_v; ++j)
        for (int i = 0; i <= s.degree_u; ++i)
            box.add(s.at(static_cast<int>(ku) - s.degree_u + i, static_cast<int>(kv) - s.degree_v + j));
    const double size = box.diagonal();
    const double floor = (size * s.degree_u / (s.knots_u[ku + 1] - s.knots_u[ku])) *
                         (size * s.degree_v / (s.knots_v[kv + 1] - s.knots_v[kv]));
    const double scale = std::max(dot(d.du, d.du) + dot(d.dv, d.dv), floor);
    constexpr double kVanishing = 1e-12;
    const Vec3 n0 = cross(d.du, d.dv);
    if (norm(n0) > kVanishing * scale) return normalized(n0);

    // first-order expansion of S_u x S_v along (su, sv), pointing into the domain
    const double su = u < 0.5 * (u0 + u1) ? 1.0 : -1.0, sv = v < 0.5 * (v0 + v1) ? 1.0 : -1.0;
    const Vec3 n1 = su * (cross(d.duu, d.dv) + cross(d.du, d.duv)) + sv * (cross(d.duv, d.dv) + cross(d.du, d.dvv));
    const double second = norm(d.duu) + norm(d.duv) + norm(d.dvv);
    if (norm(n1) > kVanishing * (norm(d.du) + norm(d.dv) + std::sqrt(floor)) * second) return normalized(n1);

    for (double step : {1e-3, 1e-5, 1e-7}) {
        const double uu = std::clamp(u + su * step * (u1 - u0), u0, u1);
        const double vv = std::clamp(v + sv * step * (v1 - v0), v0, v1);
        const PatchDerivatives inside = derivatives(s, uu, vv, 1);
        const Vec3 n = cross(inside.du, inside.dv);
        if (norm(n) > kVanishing * floor * step * step) return normalized(n);
    }
    return Vec3{};
}

Result<BSplineSurface> insert_knot(const BSplineSurface& s, SurfaceDirection direction, double t, int times) {
    if (auto ok = validate(s); !ok) return ok.error();
    const bool along_u = direction == SurfaceDirection::U;
    const auto [lo, hi] = along_u ? domain_u(s) : domain_v(s);
    const std::string name = along_u ? "u" : "v";
    if (!(std::isfinite(t) && t >= lo && t <= hi))
        return make_error(ErrorCode::InvalidArgument, "the knot " + name + " = " + num(t) + " is outside the domain [" +
                                                          num(lo) + ", " + num(hi) + "]");
    if (times < 0)
        return make_error(ErrorCode::InvalidArgument, "times must be >= 0 (got " + std::to_string(times) + ")");
    const std::vector<double>& knots = along_u ? s.knots_u : s.knots_v;
    const int degree = along_u ? s.degree_u : s.degree_v;
    const auto have = static_cast<std::size_t>(std::count(knots.begin(), knots.end(), t));
    if (have + static_cast<std::size_t>(times) > static_cast<std::size_t>(degree))
        return make_error(ErrorCode::InvalidArgument,
                          "the knot " + name + " = " + num(t) + " already has multiplicity " + std::to_string(have) +
                              "; inserting it " + std::to_string(times) + " more times would exceed the degree " +
                              std::to_string(degree));
    const int length = along_u ? s.count_u : s.count_v;  // points per curve refined
    const int curves = along_u ? s.count_v : s.count_u;  // number of such curves
    const SpanSide side = t >= hi ? SpanSide::Left : SpanSide::Right;
    BSplineSurface out = s;
    (along_u ? out.count_u : out.count_v) += times;
    out.points.assign(static_cast<std::size_t>(out.count_u) * static_cast<std::size_t>(out.count_v), Vec3{});
    if (s.rational()) out.weights.assign(out.points.size(), 0.0);
    std::vector<Node> P;
    std::vector<double> U;
    for (int c = 0; c < curves; ++c) {
        P.clear();
        for (int k = 0; k < length; ++k) P.push_back(along_u ? node(s, k, c) : node(s, c, k));
        U = knots;
        for (int r = 0; r < times; ++r) insert_once(degree, P, U, t, find_span(U, degree, P.size(), t, side));
        for (std::size_t k = 0; k < P.size(); ++k) {
            const std::size_t at = along_u ? static_cast<std::size_t>(c) * static_cast<std::size_t>(out.count_u) + k
                                           : k * static_cast<std::size_t>(out.count_u) + static_cast<std::size_t>(c);
            out.points[at] = P[k].e;
            if (s.rational()) out.weights[at] = P[k].w;
        }
        if (c == 0) (along_u ? out.knots_u : out.knots_v) = U;
    }
    return out;
}

//! The surface with the knot vector of `direction` clamped: the domain's ends inserted up to multiplicity p (Boehm),
//! then the control points left of the start and right of the end dropped with their knots, the ends repeated
//! p + 1 times. The surface is unchanged on its domain; a clamped vector is returned as it is.
Result<BSplineSurface> clamp_direction(const BSplineSurface& s, SurfaceDirection direction) {
    const bool along_u = direction == SurfaceDirection::U;
    BSplineSurface out = s;
    for (bool left : {true, false}) {
        const std::vector<double>& U = along_u ? out.knots_u : out.knots_v;
        const int p = along_u ? out.degree_u : out.degree_v;
        const auto [a, b] = along_u ? domain_u(out) : domain_v(out);
        const double end = left ? a : b;
        const bool is_clamped =
            left ? U[static_cast<std::size_t>(p)] == U.front() && std::count(U.begin(), U.end(), U.front()) == p + 1
                 : U[U.size() - 1 - static_cast<std::size_t>(p)] == U.back() &&
                       std::count(U.begin(), U.end(), U.back()) == p + 1;
        if (is_clamped) continue;
        const auto have = static_cast<int>(std::count(U.begin(), U.end(), end));
        if (have < p) {
            auto inserted = insert_knot(out, direction, end, p - have);
            if (!inserted) return inserted.error();
            out = std::move(inserted.value());
        }
        const std::vector<double>& V = along_u ? out.knots_u : out.knots_v;
        const int n = along_u ? out.count_u : out.count_v;
        // keep points [first, last] and knots [first, last + p + 1] with the ends extended to p + 1 copies
        const auto first_of = static_cast<int>(std::find(V.begin(), V.end(), end) - V.begin());
        const auto last_of = static_cast<int>(V.rend() - std::find(V.rbegin(), V.rend(), end)) - 1;
        const int first = left ? first_of - 1 : 0, last = left ? n - 1 : last_of - p;
        std::vector<double> knots;
        if (left) knots.push_back(end);
        knots.insert(knots.end(), V.begin() + first + (left ? 1 : 0), V.begin() + last + p + 1 + (left ? 1 : 0));
        if (!left) knots.push_back(end);
        BSplineSurface cut = out;
        const int count = last - first + 1;
        (along_u ? cut.count_u : cut.count_v) = count;
        cut.points.clear();
        cut.weights.clear();
        for (int j = 0; j < cut.count_v; ++j)
            for (int i = 0; i < cut.count_u; ++i) {
                const int si = along_u ? i + first : i, sj = along_u ? j : j + first;
                cut.points.push_back(out.at(si, sj));
                if (out.rational()) cut.weights.push_back(out.weight(si, sj));
            }
        (along_u ? cut.knots_u : cut.knots_v) = std::move(knots);
        out = std::move(cut);
    }
    return out;
}

Result<BSplineSurface> elevate_degree(const BSplineSurface& s, SurfaceDirection direction, int times) {
    if (auto ok = validate(s); !ok) return ok.error();
    const bool along_u = direction == SurfaceDirection::U;
    const int degree = along_u ? s.degree_u : s.degree_v;
    if (times < 0)
        return make_error(ErrorCode::InvalidArgument, "times must be >= 0 (got " + std::to_string(times) + ")");
    if (times > kMaxBSplineSurfaceDegree - degree)
        return make_error(ErrorCode::InvalidArgument, std::string("elevating degree_") + (along_u ? "u" : "v") + " " +
                                                          std::to_string(degree) + " by " + std::to_string(times) +
                                                          " would exceed the largest degree " +
                                                          std::to_string(kMaxBSplineSurfaceDegree));
    if (times == 0) return s;
    // an unclamped knot vector is clamped first (the domain's ends inserted up to multiplicity p, the control points
    // outside dropped): the blossoms of the elevated points then stay inside the spans the points act on, and the
    // weights stay positive
    auto clamped = clamp_direction(s, direction);
    if (!clamped) return clamped.error();
    BSplineSurface out = std::move(clamped.value());
    std::vector<Node> P;
    for (int step = 0; step < times; ++step) {
        const BSplineSurface in = out;
        const int p = along_u ? in.degree_u : in.degree_v;
        const int length = along_u ? in.count_u : in.count_v;
        const int curves = along_u ? in.count_v : in.count_u;
        const std::vector<double>& U = along_u ? in.knots_u : in.knots_v;
        std::vector<double> T = elevated_knots(U, static_cast<std::size_t>(p), static_cast<std::size_t>(length));
        const int new_length = static_cast<int>(T.size()) - p - 2;
        (along_u ? out.degree_u : out.degree_v) = p + 1;
        (along_u ? out.count_u : out.count_v) = new_length;
        out.points.assign(static_cast<std::size_t>(out.count_u) * static_cast<std::size_t>(out.count_v), Vec3{});
        if (in.rational()) out.weights.assign(out.points.size(), 0.0);
        for (int c = 0; c < curves; ++c) {
            P.clear();
            for (int k = 0; k < length; ++k) P.push_back(along_u ? node(in, k, c) : node(in, c, k));
            const std::vector<Node> Q = elevate_curve(p, P, U, T);
            for (std::size_t k = 0; k < Q.size(); ++k) {
                const std::size_t at = along_u
                                           ? static_cast<std::size_t>(c) * static_cast<std::size_t>(out.count_u) + k
                                           : k * static_cast<std::size_t>(out.count_u) + static_cast<std::size_t>(c);
                out.points[at] = Q[k].e;
                if (in.rational()) out.weights[at] = Q[k].w;
            }
        }
        (along_u ? out.knots_u : out.knots_v) = std::move(T);
    }
    return out;
}

std::vector<double> bezier_breaks(const BSplineSurface& s, SurfaceDirection direction) {
    const bool along_u = direction == SurfaceDirection::U;
    const std::vector<double>& U = along_u ? s.knots_u : s.knots_v;
    const auto p = static_cast<std::size_t>(along_u ? s.degree_u : s.degree_v);
    const auto n = static_cast<std::size_t>(along_u ? s.count_u : s.count_v);
    std::vector<double> breaks;
    for (std::size_t k = p; k <= n; ++k)
        if (breaks.empty() || U[k] != breaks.back()) breaks.push_back(U[k]);
    return breaks;
}

std::size_t bezier_patch_count(const BSplineSurface& s) {
    return (bezier_breaks(s, SurfaceDirection::U).size() - 1) * (bezier_breaks(s, SurfaceDirection::V).size() - 1);
}

Result<SurfaceBezierPatches> to_bezier(const BSplineSurface& s, const Cancel& cancel) {
    if (auto ok = validate(s); !ok) return ok.error();
    const int p = s.degree_u, q = s.degree_v;
    const auto ps = static_cast<std::size_t>(p), qs = static_cast<std::size_t>(q);
    SurfaceBezierPatches out;
    out.breaks_u = bezier_breaks(s, SurfaceDirection::U);
    out.breaks_v = bezier_breaks(s, SurfaceDirection::V);
    const std::size_t patches_u = out.breaks_u.size() - 1, patches_v = out.breaks_v.size() - 1;
    out.patches.resize(patches_u * patches_v);
    const auto nv = static_cast<std::size_t>(s.count_v);

    std::vector<Node> local, previous_last(nv);
    std::vector<double> scratch;
    std::vector<std::vector<Node>> strip(nv);  // strip[j]: the p + 1 Bézier points of row j on the current u span
    std::size_t a = 0;
    for (std::size_t ku = ps; ku < static_cast<std::size_t>(s.count_u); ++ku) {
        if (!(s.knots_u[ku] < s.knots_u[ku + 1])) continue;
        if (cancel.requested()) return make_error(ErrorCode::Cancelled, "cancelled while converting to Bézier form");
        for (std::size_t j = 0; j < nv; ++j) {
            local.clear();
            for (std::size_t r = 0; r <= ps; ++r)
                local.push_back(node(s, static_cast<int>(ku - ps + r), static_cast<int>(j)));
            span_to_bezier(p, local, s.knots_u.data() + (ku - ps), scratch);
            if (a > 0) local.front() = previous_last[j];  // the shared column, bit for bit
            previous_last[j] = local.back();
            strip[j] = local;
        }
        // each column of the strip along v, one v span at a time
        std::size_t b = 0;
        std::vector<std::vector<Node>> column_last(ps + 1);
        for (std::size_t kv = qs; kv < nv; ++kv) {
            if (!(s.knots_v[kv] < s.knots_v[kv + 1])) continue;
            if (cancel.requested())
                return make_error(ErrorCode::Cancelled, "cancelled while converting to Bézier form");
            BezierPatch& patch = out.patches[b * patches_u + a];
            patch.degree_u = p;
            patch.degree_v = q;
            patch.points.resize((ps + 1) * (qs + 1));
            if (s.rational()) patch.weights.resize(patch.points.size());
            for (std::size_t i = 0; i <= ps; ++i) {
                local.clear();
                for (std::size_t r = 0; r <= qs; ++r) local.push_back(strip[kv - qs + r][i]);
                span_to_bezier(q, local, s.knots_v.data() + (kv - qs), scratch);
                if (b > 0) local.front() = column_last[i].back();  // the shared row, bit for bit
                column_last[i] = local;
                for (std::size_t r = 0; r <= qs; ++r) {
                    patch.points[r * (ps + 1) + i] = local[r].e;
                    if (s.rational()) patch.weights[r * (ps + 1) + i] = local[r].w;
                }
            }
            const double u0 = out.breaks_u[a], u1 = out.breaks_u[a + 1];
            const double v0 = out.breaks_v[b], v1 = out.breaks_v[b + 1];
            patch.corner_uvs = std::array<Vec2, 4>{Vec2{u0, v0}, Vec2{u1, v0}, Vec2{u0, v1}, Vec2{u1, v1}};
            ++b;
        }
        ++a;
    }
    close_seams(out, s);
    return out;
}

Result<PatchTessellation> tessellate(const BSplineSurface& s, const TessellationOptions& options) {
    auto patches = to_bezier(s, options.cancel);
    if (!patches) return patches.error();
    return tessellate_patches(patches->patches, options);
}

}  // namespace surfaced
