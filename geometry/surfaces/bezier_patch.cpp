// Tensor-product Bézier patches. Evaluation is separable de Casteljau (geometry/curves/de_casteljau.h): u on each
// row of the control net, then v on the column of row results; derivatives come from the rows' hodographs.
//
// Tolerance bound (why tessellation_error_bound is a guarantee). For a triangle of the parameter grid with legs
// h = 1/nu and k = 1/nv, a point x of it with barycentric weights l_i, and the linear interpolant L of S at the
// triangle's corners p_i: S(p_i) = S(x) + DS(x)(p_i - x) + R_i with |R_i| <= (1/2)(Muu du_i^2 + 2 Muv |du_i dv_i|
// + Mvv dv_i^2). Since sum l_i (p_i - x) = 0, |L(x) - S(x)| = |sum l_i R_i|. The weighted variance of the corners'
// u coordinates is at most h^2/4 (one corner off the others by h), of v at most k^2/4, and by Cauchy-Schwarz the
// weighted mean of |du dv| at most hk/4. Hence |L - S| <= (1/8)(Muu h^2 + 2 Muv h k + Mvv k^2). The second partial
// derivatives are Bernstein combinations (convex) of the net's scaled second differences, so
// Muu <= m(m-1) max|D2u b|, Mvv <= n(n-1) max|D2v b|, Muv <= m n max|DuDv b| (Filip, Magedson, Markot 1986).
//
// Rational patches. S = A / w with A = sum B_ij w_ij P_ij and w = sum B_ij w_ij, all w_ij > 0. The distance
// argument above needs only bounds on |S_uu|, |S_uv|, |S_vv|, so it carries over once those are bounded. S is
// translation-equivariant, so write it about a centre c (the control points' bounding-box centre): S - c = A' / w
// with A' = sum B_ij Q_ij, Q_ij = w_ij (P_ij - c). Differentiating w (S - c) = A':
//   S_u  = (A'_u - w_u (S - c)) / w
//   S_uu = (A'_uu - 2 w_u S_u - w_uu (S - c)) / w
//   S_uv = (A'_uv - w_u S_v - w_v S_u - w_uv (S - c)) / w          (and v alike).
// Bounds over the whole patch: w >= wmin = min w_ij (w is a convex combination of the weights); |S - c| <= R =
// max |P_ij - c| (positive weights: S is a convex combination of the P_ij); |A'_u| <= m max|Du Q|, |A'_uu| <=
// m(m-1) max|D2u Q|, |A'_uv| <= m n max|DuDv Q|, and the same for w's derivatives from its net of weights (the
// Bernstein-convexity argument above, applied to the homogeneous nets). Hence with Gu = (|A'_u| + |w_u| R) / wmin:
//   Muu <= (|A'_uu| + |w_uu| R + 2 |w_u| Gu) / wmin,  Muv <= (|A'_uv| + |w_uv| R + |w_u| Gv + |w_v| Gu) / wmin,
// a guaranteed (if pessimistic for strongly varying weights) bound; with all weights equal it is the polynomial one.
// Evaluation is de Casteljau on the homogeneous net (w P, w), divided at the end; derivatives by the quotient rule
// above (exact up to rounding).
//
// Distance bound of one triangle (triangle_distance_bound). The bound above is on |S(x) - T(x)| at equal parameters
// and so also counts the tangential drift of a non-uniform parameterisation, which does not move the mesh off the
// surface. Let B be the triangle's parameter box (H x K), x0 its centre, n0 the unit normal and c0 the point there.
// Bounds over B (the Taylor argument above needs the derivatives on the triangle only, which lies in B), each the
// maximum over 2 x 2 sub-boxes of B of the bound from that sub-box's own net (exact de Casteljau restriction; the
// Bernstein bounds converge quadratically under subdivision, and the one-net form over B is used alone when it is
// already small enough for the caller): M (full second derivatives, the single-net rational bound above) and, for a
// unit direction dir, bounds on |dir . S_u|, |dir . S_v|, |dir . S_uu|, |dir . S_uv|, |dir . S_vv| -- the quotient
// rule above dotted with dir: dir . S_uu = (dir . A'_uu - 2 w_u (dir . S_u) - w_uu dir . (S - c0)) / w, with
// A' = sum B_ij w_ij (P_ij - c0), the scalar net dir . w_ij (P_ij - c0) bounding dir . A' and its derivatives by
// Bernstein convexity, and |dir . (S - c0)| <= max |dir . (P_ij - c0)|. For x in the triangle split
// S(x) - T(x) = a n0 + t (t orthogonal to n0). The derivation at the top, applied to the scalar n0 . S (bounds N),
// gives |a| <= (1/8)(Nuu H^2 + 2 Nuv H K + Nvv K^2) =: e_n, and |t| <= |S(x) - T(x)| <= (1/8)(Muu H^2 + ...) =: e_f;
// also |t| <= e_t := |(e_1, e_2)|, e_i the same bound for t_i . S, t_1, t_2 an orthonormal basis of the plane
// orthogonal to n0 (so |S - T| <= |(e_n, e_t)|); and |P S_uu| <= min(Muu, |(t_1 . S_uu, t_2 . S_uu)| bounds) =: Puu
// (P the projection orthogonal to n0; Puv, Pvv alike).
// The move. Let E be B grown by half its size on each side, clipped to the patch, and R bounds over E (its own net).
// J(x) = P DS(x) maps parameter steps into the tangent plane of n0. Scale the parameters by alpha = |P S_u(x0)|,
// beta = |P S_v(x0)| (the scaled J(x0) has unit columns at an angle theta: smallest singular value
// sigma0 = sqrt(1 - |cos theta|)); over B each scaled column moves by at most (Puu H / 2 + Puv K / 2) / alpha (and
// (Puv H / 2 + Pvv K / 2) / beta), so by Weyl's inequality (Frobenius norm) the scaled J(x)'s smallest singular value
// is at least sigma = sigma0 - |(those)|. When sigma > 0 take d with J(x) d = -t: |d_u| <= (e_t / sigma) / alpha,
// |d_v| <= (e_t / sigma) / beta. If these are within B's margins inside E, x + d is in E, and with
// DS(x) d = -t + (n0 . DS(x) d) n0 and the remainder Q = S(x + d) - S(x) - DS(x) d,
// |Q| <= (1/2)(Ruu d_u^2 + 2 Ruv |d_u d_v| + Rvv d_v^2):
//   T(x) - S(x + d) = -(a + n0 . DS(x) d) n0 - Q,   so   dist(T(x), S) <= e_n + Gn_u |d_u| + Gn_v |d_v| + |Q|,
// a point of the patch, where |n0 . S_u(x)| <= Gn_u := |n0 . S_u(x0)| + Nuu H / 2 + Nuv K / 2 (x in B; the first term
// is zero up to rounding), or the bound over B if smaller. Where B touches a patch side (no margin across it) the step
// runs along the side only, direction k (u or v): with l0 = P S_k(x0) / |P S_k(x0)| and m0 = n0 x l0,
// l0 . S_k(x) >= |P S_k(x0)| - (change of P S_k over B) =: s_k > 0, d_k = -(l0 . t) / (l0 . S_k(x)),
// |d_k| <= e_t / s_k, and
//   T(x) - S(x + d_k) = -(a + d_k n0 . S_k) n0 - (m0 . (S(x) - T(x)) + d_k m0 . S_k) m0 - Q,
// where m0 . (S - T) is bounded like a (the scalar net along m0), |m0 . S_k(x)| like |n0 . S_k(x)| (m0 . S_k(x0) = 0),
// and |Q| <= (1/2) R_kk d_k^2. The triangle's bound is the smallest of e_f, |(e_n, e_t)| and these; the first two alone
// where du x dv vanishes, at a patch corner, or where the step exceeds the margin. e_n is second order in the normal
// curvature only (no tangential acceleration, no twist of a surface of revolution), and the correction is third order.
#include "geometry/surfaces/bezier_patch.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <numeric>
#include <optional>
#include <string>
#include <unordered_map>

#include "geometry/core/format_number.h"
#include "geometry/curves/de_casteljau.h"

namespace surfaced {
namespace {

std::span<const Vec3> row(const BezierPatch& patch, int j) {
    return {patch.points.data() + static_cast<std::size_t>(j * patch.row_size()),
            static_cast<std::size_t>(patch.row_size())};
}

//! Size of the control net, the scale against which "du x dv vanishes" is judged.
double net_scale(const BezierPatch& patch) {
    Box3 box;
    for (const Vec3& p : patch.points) box.add(p);
    return box.diagonal();
}

//! |du x dv| scales like (net size)^2; below kVanishing times that it is rounding noise, not a direction.
constexpr double kVanishing = 1e-12;

Vec3 normalized(const Vec3& v) {
    const double length = norm(v);
    return length > 0 ? v * (1.0 / length) : Vec3{};
}

struct NetBounds {
    double uu = 0, uv = 0, vv = 0;  //!< bounds on |S_uu|, |S_uv|, |S_vv| over the patch
    double u = 0, v = 0;            //!< bounds on |S_u|, |S_v| over the patch
};

NetBounds rational_second_derivative_bounds(const BezierPatch& patch);

NetBounds second_derivative_bounds(const BezierPatch& patch) {
    if (patch.rational()) return rational_second_derivative_bounds(patch);
    const int m = patch.degree_u, n = patch.degree_v;
    double d1u = 0, d1v = 0, d2u = 0, d2v = 0, duv = 0;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i < m; ++i) d1u = std::max(d1u, norm(patch.at(i + 1, j) - patch.at(i, j)));
    for (int j = 0; j < n; ++j)
        for (int i = 0; i <= m; ++i) d1v = std::max(d1v, norm(patch.at(i, j + 1) - patch.at(i, j)));
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i + 2 <= m; ++i)
            d2u = std::max(d2u, norm(patch.at(i + 2, j) - 2.0 * patch.at(i + 1, j) + patch.at(i, j)));
    for (int j = 0; j + 2 <= n; ++j)
        for (int i = 0; i <= m; ++i)
            d2v = std::max(d2v, norm(patch.at(i, j + 2) - 2.0 * patch.at(i, j + 1) + patch.at(i, j)));
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < m; ++i)
            duv =
                std::max(duv, norm(patch.at(i + 1, j + 1) - patch.at(i + 1, j) - patch.at(i, j + 1) + patch.at(i, j)));
    return {m * (m - 1) * d2u, m * n * duv, n * (n - 1) * d2v, m * d1u, n * d1v};
}

//! Bounds on the first and second partial derivatives of the polynomial patch with net `q` (u fastest).
template <class Net, class Norm>
std::array<double, 5> net_derivative_bounds(const Net& q, int m, int n, Norm size) {
    const auto at = [&](int i, int j) { return q[static_cast<std::size_t>(j * (m + 1) + i)]; };
    double du = 0, dv = 0, d2u = 0, d2v = 0, duv = 0;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i < m; ++i) du = std::max(du, size(at(i + 1, j) - at(i, j)));
    for (int j = 0; j < n; ++j)
        for (int i = 0; i <= m; ++i) dv = std::max(dv, size(at(i, j + 1) - at(i, j)));
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i + 2 <= m; ++i) d2u = std::max(d2u, size(at(i + 2, j) - 2.0 * at(i + 1, j) + at(i, j)));
    for (int j = 0; j + 2 <= n; ++j)
        for (int i = 0; i <= m; ++i) d2v = std::max(d2v, size(at(i, j + 2) - 2.0 * at(i, j + 1) + at(i, j)));
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < m; ++i)
            duv = std::max(duv, size(at(i + 1, j + 1) - at(i + 1, j) - at(i, j + 1) + at(i, j)));
    return {m * du, n * dv, m * (m - 1) * d2u, n * (n - 1) * d2v, m * n * duv};
}

// The rational bound derived at the top of this file, from one net.
NetBounds single_net_rational_bounds(const BezierPatch& patch) {
    const int m = patch.degree_u, n = patch.degree_v;
    Box3 box;
    for (const Vec3& p : patch.points) box.add(p);
    const Vec3 c = 0.5 * (box.min + box.max);
    double radius = 0, wmin = patch.weights[0];
    std::vector<Vec3> q(patch.points.size());
    for (std::size_t k = 0; k < q.size(); ++k) {
        radius = std::max(radius, norm(patch.points[k] - c));
        wmin = std::min(wmin, patch.weights[k]);
        q[k] = patch.weights[k] * (patch.points[k] - c);
    }
    const auto a = net_derivative_bounds(q, m, n, [](const Vec3& x) { return norm(x); });
    const auto w = net_derivative_bounds(patch.weights, m, n, [](double x) { return std::fabs(x); });
    const double gu = (a[0] + w[0] * radius) / wmin, gv = (a[1] + w[1] * radius) / wmin;
    NetBounds out;
    out.u = gu;
    out.v = gv;
    out.uu = (a[2] + w[2] * radius + 2 * w[0] * gu) / wmin;
    out.vv = (a[3] + w[3] * radius + 2 * w[1] * gv) / wmin;
    out.uv = (a[4] + w[4] * radius + w[0] * gv + w[1] * gu) / wmin;
    return out;
}

using Homogeneous = std::array<double, 4>;  //!< (w x, w y, w z, w)

//! Replaces the Bézier curve p[first + k stride], k = 0..degree, by its piece over [a, b] (de Casteljau splits at
//! b, then at a / b of the left part; exact up to rounding).
void restrict_curve(std::vector<Homogeneous>& net, std::size_t first, std::size_t stride, int degree, double a,
                    double b) {
    Homogeneous c[kMaxPatchDegree + 1];
    const auto n = static_cast<std::size_t>(degree);
    for (std::size_t k = 0; k <= n; ++k) c[k] = net[first + k * stride];
    const auto lerp = [](const Homogeneous& x, const Homogeneous& y, double t) {
        return Homogeneous{x[0] + t * (y[0] - x[0]), x[1] + t * (y[1] - x[1]), x[2] + t * (y[2] - x[2]),
                           x[3] + t * (y[3] - x[3])};
    };
    // left part [0, b]: the first points of each de Casteljau level, computed in place from the right
    if (b < 1)
        for (std::size_t level = 1; level <= n; ++level)
            for (std::size_t k = n; k >= level; --k) c[k] = lerp(c[k - 1], c[k], b);
    // right part [a / b, 1] of that: the last points of each level, in place from the left
    if (a > 0) {
        const double t = a / b;
        for (std::size_t level = 1; level <= n; ++level)
            for (std::size_t k = 0; k + level <= n; ++k) c[k] = lerp(c[k], c[k + 1], t);
    }
    for (std::size_t k = 0; k <= n; ++k) net[first + k * stride] = c[k];
}

//! Bounds for a rational patch, tightened by subdivision: the patch is cut into pieces x pieces sub-patches (exact
//! homogeneous de Casteljau subdivision); each piece's single-net bound on its own second derivatives, divided by
//! the squared piece size (T(s, t) = S(a + h s, c + h t) has T_ss = h^2 S_uu), bounds S's derivatives over that piece,
//! so the maximum over the pieces is again a guaranteed bound on the whole patch -- and a far tighter one, as the
//! weights and the radius R vary little over a small piece. The smaller of this and the single-net bound is kept.
NetBounds rational_second_derivative_bounds(const BezierPatch& patch) {
    NetBounds best = single_net_rational_bounds(patch);
    constexpr int pieces = 8;
    const int m = patch.degree_u, n = patch.degree_v;
    const auto row = static_cast<std::size_t>(m + 1);
    std::vector<Homogeneous> whole(patch.points.size());
    for (std::size_t k = 0; k < whole.size(); ++k) {
        const double w = patch.weights[k];
        whole[k] = {w * patch.points[k].x, w * patch.points[k].y, w * patch.points[k].z, w};
    }
    NetBounds sub_max;
    BezierPatch piece;
    piece.degree_u = m;
    piece.degree_v = n;
    piece.points.resize(whole.size());
    piece.weights.resize(whole.size());
    std::vector<Homogeneous> net;
    const double h = 1.0 / pieces;
    for (int pj = 0; pj < pieces; ++pj)
        for (int pi = 0; pi < pieces; ++pi) {
            net = whole;
            for (int j = 0; j <= n; ++j)
                restrict_curve(net, static_cast<std::size_t>(j) * row, 1, m, pi * h, (pi + 1) * h);
            for (int i = 0; i <= m; ++i) restrict_curve(net, static_cast<std::size_t>(i), row, n, pj * h, (pj + 1) * h);
            for (std::size_t k = 0; k < net.size(); ++k) {
                piece.weights[k] = net[k][3];
                piece.points[k] = Vec3{net[k][0], net[k][1], net[k][2]} * (1.0 / net[k][3]);
            }
            const NetBounds b = single_net_rational_bounds(piece);
            sub_max.uu = std::max(sub_max.uu, b.uu / (h * h));
            sub_max.uv = std::max(sub_max.uv, b.uv / (h * h));
            sub_max.vv = std::max(sub_max.vv, b.vv / (h * h));
            sub_max.u = std::max(sub_max.u, b.u / h);  // T_s = h S_u
            sub_max.v = std::max(sub_max.v, b.v / h);
        }
    best.uu = std::min(best.uu, sub_max.uu);
    best.uv = std::min(best.uv, sub_max.uv);
    best.vv = std::min(best.vv, sub_max.vv);
    best.u = std::min(best.u, sub_max.u);
    best.v = std::min(best.v, sub_max.v);
    return best;
}

// ---- local distance bound of one triangle ----------------------------------------------------------------------

constexpr int kPieces = 2;
constexpr double kGrow = 0.5;

//! The homogeneous net of `patch` restricted to [u0, u1] x [v0, v1] (exact de Casteljau subdivision; weights 1 for a
//! polynomial patch).
std::vector<Homogeneous> restricted_net(const BezierPatch& patch, double u0, double u1, double v0, double v1) {
    const int m = patch.degree_u, n = patch.degree_v;
    const auto row = static_cast<std::size_t>(m + 1);
    std::vector<Homogeneous> net(patch.points.size());
    for (std::size_t k = 0; k < net.size(); ++k) {
        const double w = patch.rational() ? patch.weights[k] : 1.0;
        net[k] = {w * patch.points[k].x, w * patch.points[k].y, w * patch.points[k].z, w};
    }
    for (int j = 0; j <= n; ++j) restrict_curve(net, static_cast<std::size_t>(j) * row, 1, m, u0, u1);
    for (int i = 0; i <= m; ++i) restrict_curve(net, static_cast<std::size_t>(i), row, n, v0, v1);
    return net;
}

}  // namespace

namespace {

//! The patch restricted to one parameter box (exact de Casteljau subdivision of the homogeneous net), with what the
//! bounds below need of it: its Euclidean points, its weights and bounds on their derivatives.
struct Region {
    double su = 1, sv = 1;  //!< the box's size in patch parameters (the restricted net's parameters are [0, 1]^2)
    BezierPatch piece;      //!< the restricted net, Euclidean points and weights
    double wmin = 1;
    std::array<double, 5> wa{};  //!< net_derivative_bounds of the weights

    Region(const BezierPatch& patch, double u0, double u1, double v0, double v1) : su(u1 - u0), sv(v1 - v0) {
        const std::vector<Homogeneous> net = restricted_net(patch, u0, u1, v0, v1);
        piece.degree_u = patch.degree_u;
        piece.degree_v = patch.degree_v;
        piece.points.resize(net.size());
        piece.weights.resize(net.size());
        wmin = net[0][3];
        for (std::size_t k = 0; k < net.size(); ++k) {
            piece.weights[k] = net[k][3];
            piece.points[k] = Vec3{net[k][0], net[k][1], net[k][2]} * (1.0 / net[k][3]);
            wmin = std::min(wmin, net[k][3]);
        }
        wa =
            net_derivative_bounds(piece.weights, piece.degree_u, piece.degree_v, [](double x) { return std::fabs(x); });
    }
    //! Bounds on |S_u|, |S_v|, |S_uu|, |S_uv|, |S_vv| over the box, in patch parameters.
    NetBounds full() const { return to_patch_parameters(single_net_rational_bounds(piece)); }
    //! The same for the scalar dir . S (dir a unit vector, c0 any point): the quotient rule of the top of this file
    //! dotted with dir, from the scalar net dir . w (P - c0), the weights and |dir . (S - c0)| <= max |dir . (P - c0)|.
    NetBounds along(const Vec3& dir, const Vec3& c0) const {
        std::array<double, (kMaxPatchDegree + 1) * (kMaxPatchDegree + 1)> q;  // the first |points| used
        double radius = 0;
        for (std::size_t i = 0; i < piece.points.size(); ++i) {
            const double x = dot(dir, piece.points[i] - c0);
            radius = std::max(radius, std::fabs(x));
            q[i] = piece.weights[i] * x;
        }
        const auto qa = net_derivative_bounds(q, piece.degree_u, piece.degree_v, [](double x) { return std::fabs(x); });
        NetBounds b;
        b.u = (qa[0] + wa[0] * radius) / wmin;
        b.v = (qa[1] + wa[1] * radius) / wmin;
        b.uu = (qa[2] + wa[2] * radius + 2 * wa[0] * b.u) / wmin;
        b.vv = (qa[3] + wa[3] * radius + 2 * wa[1] * b.v) / wmin;
        b.uv = (qa[4] + wa[4] * radius + wa[0] * b.v + wa[1] * b.u) / wmin;
        return to_patch_parameters(b);
    }
    //! Bounds in the box's own parameters (each in [0, 1]) as bounds in the patch's: d/du = (1 / su) d/ds.
    NetBounds to_patch_parameters(NetBounds b) const {
        b.u /= su;
        b.v /= sv;
        b.uu /= su * su;
        b.uv /= su * sv;
        b.vv /= sv * sv;
        return b;
    }
};

NetBounds max_bounds(const NetBounds& a, const NetBounds& b) {
    return {std::max(a.uu, b.uu), std::max(a.uv, b.uv), std::max(a.vv, b.vv), std::max(a.u, b.u), std::max(a.v, b.v)};
}

//! What the two forms of triangle_distance_bound share: the triangle's box B, the derivatives at its centre, and the
//! bounds over the grown box E (computed when first needed).
struct Shared {
    double u0, u1, v0, v1;
    PatchDerivatives d;  //!< position, du and dv at the centre (the second derivatives are not used)
    std::optional<NetBounds> grown;
};

//! S, S_u and S_v at (uc, vc) exactly (up to rounding), from the net restricted to [u0, uc] x [v0, vc]: its corner
//! (1, 1) is that point, where the value is the last control point and the derivatives are differences of the last
//! ones (for a rational net through the quotient rule S_s = (A_s - w_s S) / w).
PatchDerivatives corner_frame(const BezierPatch& patch, double u0, double uc, double v0, double vc) {
    const std::vector<Homogeneous> net = restricted_net(patch, u0, uc, v0, vc);
    const int m = patch.degree_u, n = patch.degree_v;
    const auto at = [&](int i, int j) { return net[static_cast<std::size_t>(j * (m + 1) + i)]; };
    const Homogeneous q = at(m, n), qu = at(m - 1, n), qv = at(m, n - 1);
    PatchDerivatives d;
    d.position = Vec3{q[0], q[1], q[2]} * (1.0 / q[3]);
    const auto derivative = [&](const Homogeneous& before, int degree, double span) {
        const Vec3 a{degree * (q[0] - before[0]), degree * (q[1] - before[1]), degree * (q[2] - before[2])};
        return (a - (degree * (q[3] - before[3])) * d.position) * (1.0 / (q[3] * span));
    };
    d.du = derivative(qu, m, uc - u0);
    d.dv = derivative(qv, n, vc - v0);
    return d;
}

//! triangle_distance_bound with B's bounds taken over pieces x pieces sub-boxes.
double distance_bound(const BezierPatch& patch, Shared& shared, int pieces_per_side) {
    // The method and its proof are in the comment at the top of this file ("Distance bound of one triangle").
    const double u0 = shared.u0, u1 = shared.u1, v0 = shared.v0, v1 = shared.v1;
    const double bu = u1 - u0, bv = v1 - v0;
    const auto quadratic = [&](const NetBounds& m) {
        return (m.uu * bu * bu + 2.0 * m.uv * bu * bv + m.vv * bv * bv) / 8.0;
    };
    // bounds over B, the triangle's box (the Taylor argument needs them on the triangle only): the maximum over
    // kPieces x kPieces sub-boxes, each from its own net (tighter than one net over B, the Bernstein bounds
    // converging quadratically under subdivision)
    const int np = pieces_per_side;
    std::vector<Region> pieces;
    pieces.reserve(static_cast<std::size_t>(np * np));
    for (int j = 0; j < np; ++j)
        for (int i = 0; i < np; ++i)
            pieces.emplace_back(patch, u0 + bu * i / np, u0 + bu * (i + 1) / np, v0 + bv * j / np,
                                v0 + bv * (j + 1) / np);
    const auto over_b = [&](auto&& bounds) {
        NetBounds out = bounds(pieces[0]);
        for (std::size_t k = 1; k < pieces.size(); ++k) out = max_bounds(out, bounds(pieces[k]));
        return out;
    };
    const NetBounds full = over_b([](const Region& r) { return r.full(); });
    const double e_full = quadratic(full);

    // the frame at B's centre x0: the normal n0, tangents t1, t2
    const PatchDerivatives& d = shared.d;
    const Vec3 n0 = normalized(cross(d.du, d.dv));
    if (!(norm(n0) > 0.5)) return e_full;
    const Vec3 c0 = d.position;
    const auto along = [&](const Vec3& dir) { return over_b([&](const Region& r) { return r.along(dir, c0); }); };
    const NetBounds normal = along(n0);
    const double e_n = quadratic(normal);
    // the tangential part t of S(x) - T(x) and bounds on the projected second derivatives |P S_uu|, ...
    double e_t = e_full;
    NetBounds projected = full;
    const Vec3 t1 = normalized(d.du - dot(n0, d.du) * n0);
    if (norm(t1) > 0.5) {
        const NetBounds b1 = along(t1), b2 = along(cross(n0, t1));
        e_t = std::min(e_t, std::hypot(quadratic(b1), quadratic(b2)));
        projected.uu = std::min(full.uu, std::hypot(b1.uu, b2.uu));
        projected.uv = std::min(full.uv, std::hypot(b1.uv, b2.uv));
        projected.vv = std::min(full.vv, std::hypot(b1.vv, b2.vv));
    }
    double best = std::min(e_full, std::hypot(e_n, e_t));

    // E: B grown by kGrow of its size on each side inside the patch; B's margins inside it (zero on a patch side)
    const double eu0 = std::max(0.0, u0 - kGrow * bu), eu1 = std::min(1.0, u1 + kGrow * bu);
    const double ev0 = std::max(0.0, v0 - kGrow * bv), ev1 = std::min(1.0, v1 + kGrow * bv);
    const double margin_u = std::min(u0 - eu0, eu1 - u1), margin_v = std::min(v0 - ev0, ev1 - v1);
    if (!(margin_u > 0) && !(margin_v > 0)) return best;
    if (!shared.grown) shared.grown = Region(patch, eu0, eu1, ev0, ev1).full();  // for the move's remainder, over E
    const NetBounds& grown = *shared.grown;
    // |n0 . S_u(x)| over B: n0 . S_u(x0) (zero up to rounding) plus the change over half of B
    const double gn_u = std::min(normal.u, std::fabs(dot(n0, d.du)) + 0.5 * (normal.uu * bu + normal.uv * bv));
    const double gn_v = std::min(normal.v, std::fabs(dot(n0, d.dv)) + 0.5 * (normal.uv * bu + normal.vv * bv));
    // the change of P S_u and P S_v from x0 over B
    const double change_u = 0.5 * (projected.uu * bu + projected.uv * bv);
    const double change_v = 0.5 * (projected.uv * bu + projected.vv * bv);
    const Vec3 ju = d.du - dot(n0, d.du) * n0, jv = d.dv - dot(n0, d.dv) * n0;
    const double alpha = norm(ju), beta = norm(jv);

    // a move in both directions, in parameters scaled by alpha and beta (the projected Jacobian's columns at x0 made
    // unit): sigma bounds the scaled Jacobian's smallest singular value over B from below
    if (alpha > 0 && beta > 0 && margin_u > 0 && margin_v > 0) {
        const double cosine = std::min(1.0, std::fabs(dot(ju, jv)) / (alpha * beta));
        const double sigma0 = norm(cross(ju, jv)) / (alpha * beta) / std::sqrt(1 + cosine);
        const double sigma = sigma0 * (1 - 1e-12) - std::hypot(change_u / alpha, change_v / beta);
        if (sigma > 0) {
            const double step = e_t / sigma, du = step / alpha, dv = step / beta;
            if (du <= margin_u && dv <= margin_v)
                best = std::min(best, e_n + gn_u * du + gn_v * dv +
                                          0.5 * (grown.uu * du * du + 2.0 * grown.uv * du * dv + grown.vv * dv * dv));
        }
    }
    // a move along one direction only (B on a patch side running that way): the drift across, along m0, stays
    for (int k = 0; k < 2; ++k) {
        const Vec3& j = k == 0 ? ju : jv;
        const double length = k == 0 ? alpha : beta, margin = k == 0 ? margin_u : margin_v;
        if (!(length > 0) || !(margin > 0)) continue;
        const double speed = length * (1 - 1e-12) - (k == 0 ? change_u : change_v);  // <= l0 . S_k over B
        if (!(speed > 0)) continue;
        const double step = e_t / speed;
        if (!(step <= margin)) continue;
        const Vec3 l0 = j * (1.0 / length), m0 = cross(n0, l0);
        const NetBounds across = along(m0);
        const Vec3& s_k = k == 0 ? d.du : d.dv;
        const double gm = k == 0
                              ? std::min(across.u, std::fabs(dot(m0, s_k)) + 0.5 * (across.uu * bu + across.uv * bv))
                              : std::min(across.v, std::fabs(dot(m0, s_k)) + 0.5 * (across.uv * bu + across.vv * bv));
        const double g = (k == 0 ? gn_u : gn_v) + gm;
        best = std::min(best, e_n + quadratic(across) + g * step + 0.5 * (k == 0 ? grown.uu : grown.vv) * step * step);
    }
    return best;
}

}  // namespace

double triangle_distance_bound(const BezierPatch& patch, Vec2 a, Vec2 b, Vec2 c, double enough) {
    Shared shared{std::min({a.x, b.x, c.x}),
                  std::max({a.x, b.x, c.x}),
                  std::min({a.y, b.y, c.y}),
                  std::max({a.y, b.y, c.y}),
                  {},
                  std::nullopt};
    const double bu = shared.u1 - shared.u0, bv = shared.v1 - shared.v0;
    if (!(bu > 0) || !(bv > 0)) {  // a segment or point: the whole patch's bound
        const NetBounds m = second_derivative_bounds(patch);
        return (m.uu * bu * bu + 2.0 * m.uv * bu * bv + m.vv * bv * bv) / 8.0;
    }
    shared.d = corner_frame(patch, shared.u0, 0.5 * (shared.u0 + shared.u1), shared.v0, 0.5 * (shared.v0 + shared.v1));
    const double coarse = distance_bound(patch, shared, 1);
    if (coarse <= enough) return coarse;
    return std::min(coarse, distance_bound(patch, shared, kPieces));
}

namespace {

// ---- shared edges ---------------------------------------------------------------------------------------------

//! Edges of a patch, in this order: v = 0 and v = 1 (running along u), u = 0 and u = 1 (running along v).
enum EdgeSide { kEdgeV0 = 0, kEdgeV1 = 1, kEdgeU0 = 2, kEdgeU1 = 3 };

bool runs_along_u(int side) { return side == kEdgeV0 || side == kEdgeV1; }

std::vector<Vec3> edge_points(const BezierPatch& patch, int side, std::vector<double>* weights = nullptr) {
    std::vector<Vec3> out;
    const auto add = [&](int i, int j) {
        out.push_back(patch.at(i, j));
        if (weights) weights->push_back(patch.weight(i, j));
    };
    if (runs_along_u(side)) {
        const int j = side == kEdgeV0 ? 0 : patch.degree_v;
        for (int i = 0; i <= patch.degree_u; ++i) add(i, j);
    } else {
        const int i = side == kEdgeU0 ? 0 : patch.degree_u;
        for (int j = 0; j <= patch.degree_v; ++j) add(i, j);
    }
    return out;
}

//! Bit pattern of a coordinate with -0 and +0 identified (adding +0.0 turns -0.0 into +0.0).
std::uint64_t coordinate_key(double x) {
    x += 0.0;
    std::uint64_t bits = 0;
    std::memcpy(&bits, &x, sizeof bits);
    return bits;
}

using PointKey = std::array<std::uint64_t, 3>;
PointKey point_key(const Vec3& p) { return {coordinate_key(p.x), coordinate_key(p.y), coordinate_key(p.z)}; }

struct PointKeyHash {
    std::size_t operator()(const PointKey& k) const {
        std::size_t h = 1469598103934665603ull;
        for (std::uint64_t w : k) h = (h ^ w) * 1099511628211ull;
        return h;
    }
};

//! A control point and its weight (1 for polynomial patches): edges match only when both agree.
using EdgePointKey = std::array<std::uint64_t, 4>;

//! An edge's control points in a direction both patches agree on (the lexicographically smaller of the two).
struct CanonicalEdge {
    std::vector<EdgePointKey> key;
    std::vector<Vec3> points;     //!< in canonical order
    std::vector<double> weights;  //!< in canonical order, empty for a polynomial edge
    bool reversed = false;        //!< the patch runs along the edge opposite to the canonical order
    bool collapsed = false;       //!< all control points equal: the edge is a single point
};

CanonicalEdge canonical_edge(const BezierPatch& patch, int side) {
    CanonicalEdge edge;
    edge.points = edge_points(patch, side, patch.rational() ? &edge.weights : nullptr);
    for (std::size_t k = 0; k < edge.points.size(); ++k) {
        const PointKey p = point_key(edge.points[k]);
        edge.key.push_back({p[0], p[1], p[2], coordinate_key(edge.weights.empty() ? 1.0 : edge.weights[k])});
    }
    std::vector<EdgePointKey> reversed_key(edge.key.rbegin(), edge.key.rend());
    if (reversed_key < edge.key) {
        edge.key = std::move(reversed_key);
        std::reverse(edge.points.begin(), edge.points.end());
        std::reverse(edge.weights.begin(), edge.weights.end());
        edge.reversed = true;
    }
    edge.collapsed = std::all_of(edge.points.begin(), edge.points.end(),
                                 [&](const Vec3& p) { return point_key(p) == point_key(edge.points[0]); });
    if (edge.collapsed)  // one point whatever the weights: identify it by position alone
        for (EdgePointKey& k : edge.key) k[3] = coordinate_key(1.0);
    return edge;
}

//! Points of an edge at parameters k/segments, k = 0..segments, in the patch's own direction. Computed from the
//! canonical control points at canonical parameters, so two patches sharing the edge get bit-identical points.
//! Rational edges are evaluated in homogeneous coordinates; their ends are the end control points exactly (so a
//! corner is bit-identical whichever edge, patch or weights it is computed from).
std::vector<Vec3> edge_samples(const CanonicalEdge& edge, int segments) {
    std::vector<Vec3> out(static_cast<std::size_t>(segments) + 1);
    std::vector<Vec3> homogeneous, weights;  // (w P) and (w, 0, 0)
    for (std::size_t i = 0; i < edge.weights.size(); ++i) {
        homogeneous.push_back(edge.weights[i] * edge.points[i]);
        weights.push_back({edge.weights[i], 0, 0});
    }
    for (int k = 0; k <= segments; ++k) {
        const double t = static_cast<double>(k) / segments;
        Vec3 p;
        if (edge.collapsed || k == 0)
            p = edge.points.front();
        else if (k == segments)
            p = edge.points.back();
        else if (edge.weights.empty())
            p = bezier::de_casteljau(edge.points, t);
        else
            p = bezier::de_casteljau(homogeneous, t) * (1.0 / bezier::de_casteljau(weights, t).x);
        out[static_cast<std::size_t>(edge.reversed ? segments - k : k)] = p;
    }
    return out;
}

struct UnionFind {
    std::vector<std::size_t> parent;
    explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), std::size_t{0}); }
    std::size_t find(std::size_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    }
    void unite(std::size_t a, std::size_t b) { parent[find(a)] = find(b); }
};

//! Direction classes: 2p = "along u of patch p", 2p + 1 = "along v of patch p". Two patches sharing an edge must
//! use the same segment count along it, so the classes of the edge's direction in both patches are merged.
std::size_t direction_class(std::size_t patch, int side) { return 2 * patch + (runs_along_u(side) ? 0 : 1); }

// ---- per-patch grid -------------------------------------------------------------------------------------------

//! Evaluates position and derivatives with the rows' hodographs computed once per patch (the tessellator's inner
//! loop; evaluate_derivatives() is the same arithmetic).
class NetEvaluator {
public:
    //! `points`: a (degree_u + 1) x (degree_v + 1) net, u fastest (must outlive the evaluator).
    NetEvaluator(const std::vector<Vec3>& points, int degree_u, int degree_v)
        : points_(points), degree_u_(degree_u), degree_v_(degree_v) {
        for (int j = 0; j <= degree_v; ++j) {
            d1_.push_back(bezier::hodograph(row(j), 1));
            d2_.push_back(bezier::hodograph(row(j), 2));
        }
    }

    PatchDerivatives operator()(double u, double v) const {
        const auto count = static_cast<std::size_t>(degree_v_ + 1);
        Vec3 c0[kMaxPatchDegree + 1], c1[kMaxPatchDegree + 1], c2[kMaxPatchDegree + 1];
        for (std::size_t j = 0; j < count; ++j) {
            c0[j] = bezier::de_casteljau(row(static_cast<int>(j)), u);
            c1[j] = d1_[j].empty() ? Vec3{} : bezier::de_casteljau(d1_[j], u);
            c2[j] = d2_[j].empty() ? Vec3{} : bezier::de_casteljau(d2_[j], u);
        }
        const std::span<const Vec3> s0(c0, count), s1(c1, count), s2(c2, count);
        PatchDerivatives d;
        d.position = bezier::de_casteljau(s0, v);
        d.dv = bezier::derivative(s0, v, 1);
        d.dvv = bezier::derivative(s0, v, 2);
        d.du = bezier::de_casteljau(s1, v);
        d.duv = bezier::derivative(s1, v, 1);
        d.duu = bezier::de_casteljau(s2, v);
        return d;
    }

private:
    std::span<const Vec3> row(int j) const {
        return {points_.data() + static_cast<std::size_t>(j * (degree_u_ + 1)),
                static_cast<std::size_t>(degree_u_ + 1)};
    }

    const std::vector<Vec3>& points_;
    int degree_u_, degree_v_;
    std::vector<std::vector<Vec3>> d1_, d2_;
};

//! The homogeneous nets of a rational patch: (w P) and (w, 0, 0).
struct HomogeneousNets {
    std::vector<Vec3> weighted, weights;
    explicit HomogeneousNets(const BezierPatch& patch) {
        if (!patch.rational()) return;
        for (std::size_t k = 0; k < patch.points.size(); ++k) {
            weighted.push_back(patch.weights[k] * patch.points[k]);
            weights.push_back({patch.weights[k], 0, 0});
        }
    }
};

//! Position and derivatives of a polynomial or rational patch (the quotient rule of the derivation at the top).
class PatchEvaluator {
public:
    explicit PatchEvaluator(const BezierPatch& patch)
        : nets_(patch), numerator_(patch.rational() ? nets_.weighted : patch.points, patch.degree_u, patch.degree_v) {
        if (patch.rational()) denominator_.emplace(nets_.weights, patch.degree_u, patch.degree_v);
    }

    PatchDerivatives operator()(double u, double v) const {
        const PatchDerivatives a = numerator_(u, v);
        if (!denominator_) return a;
        const PatchDerivatives w = (*denominator_)(u, v);
        const double inv = 1.0 / w.position.x;
        PatchDerivatives s;
        s.position = a.position * inv;
        s.du = (a.du - w.du.x * s.position) * inv;
        s.dv = (a.dv - w.dv.x * s.position) * inv;
        s.duu = (a.duu - 2.0 * w.du.x * s.du - w.duu.x * s.position) * inv;
        s.dvv = (a.dvv - 2.0 * w.dv.x * s.dv - w.dvv.x * s.position) * inv;
        s.duv = (a.duv - w.du.x * s.dv - w.dv.x * s.du - w.duv.x * s.position) * inv;
        return s;
    }

private:
    HomogeneousNets nets_;
    NetEvaluator numerator_;
    std::optional<NetEvaluator> denominator_;
};

struct Grid {
    std::vector<Vec3> positions;  //!< (nu + 1) x (nv + 1), u fastest
    std::vector<Vec3> normals;
};

Grid patch_grid(const BezierPatch& patch, int nu, int nv) {
    Grid grid;
    const auto stride = static_cast<std::size_t>(nu + 1);
    grid.positions.resize(stride * static_cast<std::size_t>(nv + 1));
    grid.normals.resize(grid.positions.size());
    const PatchEvaluator evaluator(patch);
    const double scale = net_scale(patch);
    const double vanishing = kVanishing * scale * scale;
    for (int j = 0; j <= nv; ++j) {
        const double v = static_cast<double>(j) / nv;
        for (int i = 0; i <= nu; ++i) {
            const double u = static_cast<double>(i) / nu;
            const std::size_t at = static_cast<std::size_t>(j) * stride + static_cast<std::size_t>(i);
            const PatchDerivatives d = evaluator(u, v);
            grid.positions[at] = d.position;
            // the common case directly; collapsed edges and parallel tangents take unit_normal's limit
            const Vec3 n = cross(d.du, d.dv);
            grid.normals[at] = norm(n) > vanishing ? normalized(n) : unit_normal(patch, u, v);
        }
    }
    // boundary positions from the canonical edges (overwrites the tensor evaluation there)
    for (int side = 0; side < 4; ++side) {
        const CanonicalEdge edge = canonical_edge(patch, side);
        const int segments = runs_along_u(side) ? nu : nv;
        const std::vector<Vec3> samples = edge_samples(edge, segments);
        for (int k = 0; k <= segments; ++k) {
            const int i = runs_along_u(side) ? k : (side == kEdgeU0 ? 0 : nu);
            const int j = runs_along_u(side) ? (side == kEdgeV0 ? 0 : nv) : k;
            grid.positions[static_cast<std::size_t>(j) * stride + static_cast<std::size_t>(i)] =
                samples[static_cast<std::size_t>(k)];
        }
    }
    return grid;
}

}  // namespace

Status validate(std::span<const BezierPatch> patches) {
    for (std::size_t p = 0; p < patches.size(); ++p) {
        const BezierPatch& patch = patches[p];
        const std::string name = "patch " + std::to_string(p);
        for (int degree : {patch.degree_u, patch.degree_v})
            if (degree < 1 || degree > kMaxPatchDegree) {
                GeoError error =
                    make_error(ErrorCode::InvalidArgument, name + ": degree " + std::to_string(degree) +
                                                               " is outside 1.." + std::to_string(kMaxPatchDegree));
                error.element = static_cast<std::int64_t>(p);
                return error;
            }
        const auto expected = static_cast<std::size_t>((patch.degree_u + 1) * (patch.degree_v + 1));
        if (patch.points.size() != expected) {
            GeoError error = make_error(ErrorCode::InvalidArgument,
                                        name + ": degree " + std::to_string(patch.degree_u) + "x" +
                                            std::to_string(patch.degree_v) + " needs " + std::to_string(expected) +
                                            " control points, got " + std::to_string(patch.points.size()));
            error.element = static_cast<std::int64_t>(p);
            return error;
        }
        for (std::size_t k = 0; k < patch.points.size(); ++k)
            if (!is_finite(patch.points[k])) {
                GeoError error =
                    make_error(ErrorCode::NonFinite, name + ": control point " + std::to_string(k) + " is not finite");
                error.element = static_cast<std::int64_t>(p);
                return error;
            }
        if (!patch.rational()) continue;
        const auto fail = [&](const std::string& what) {
            GeoError error = make_error(ErrorCode::InvalidArgument, name + ": " + what);
            error.element = static_cast<std::int64_t>(p);
            return error;
        };
        if (patch.weights.size() != expected)
            return fail("has " + std::to_string(patch.weights.size()) + " weights for " + std::to_string(expected) +
                        " control points");
        double lo = patch.weights[0], hi = patch.weights[0];
        for (std::size_t k = 0; k < patch.weights.size(); ++k) {
            const double w = patch.weights[k];
            if (!std::isfinite(w) || !(w > 0))
                return fail("weight " + std::to_string(k) + " must be a finite number > 0");
            if (!is_finite(w * patch.points[k]))
                return fail("weight " + std::to_string(k) + " times its control point overflows");
            lo = std::min(lo, w);
            hi = std::max(hi, w);
        }
        if (hi > kMaxWeightRatio * lo) return fail("the largest weight is more than 1e12 times the smallest");
    }
    return Ok{};
}

Vec3 evaluate(const BezierPatch& patch, double u, double v) {
    const auto count = static_cast<std::size_t>(patch.degree_v + 1);
    Vec3 column[kMaxPatchDegree + 1];
    if (!patch.rational()) {
        for (int j = 0; j <= patch.degree_v; ++j) column[j] = bezier::de_casteljau(row(patch, j), u);
        return bezier::de_casteljau(std::span<const Vec3>(column, count), v);
    }
    // homogeneous de Casteljau on (w P, w), then the division
    Vec3 weights[kMaxPatchDegree + 1], hrow[kMaxPatchDegree + 1], wrow[kMaxPatchDegree + 1];
    for (int j = 0; j <= patch.degree_v; ++j) {
        for (int i = 0; i <= patch.degree_u; ++i) {
            hrow[i] = patch.weight(i, j) * patch.at(i, j);
            wrow[i] = {patch.weight(i, j), 0, 0};
        }
        const std::span<const Vec3> h(hrow, static_cast<std::size_t>(patch.degree_u + 1));
        const std::span<const Vec3> w(wrow, static_cast<std::size_t>(patch.degree_u + 1));
        column[j] = bezier::de_casteljau(h, u);
        weights[j] = bezier::de_casteljau(w, u);
    }
    return bezier::de_casteljau(std::span<const Vec3>(column, count), v) *
           (1.0 / bezier::de_casteljau(std::span<const Vec3>(weights, count), v).x);
}

PatchDerivatives evaluate_derivatives(const BezierPatch& patch, double u, double v) {
    return PatchEvaluator(patch)(u, v);
}

Vec3 unit_normal(const BezierPatch& patch, double u, double v) {
    const double scale = net_scale(patch);
    if (scale == 0) return {};
    const double vanishing = kVanishing * scale * scale;
    const PatchDerivatives d = evaluate_derivatives(patch, u, v);
    const Vec3 n0 = cross(d.du, d.dv);
    if (norm(n0) > vanishing) return normalized(n0);

    // First-order expansion of du x dv along the direction (su, sv) pointing into the patch:
    // n(u + e su, v + e sv) = e [su (duu x dv + du x duv) + sv (duv x dv + du x dvv)] + O(e^2).
    // On a collapsed edge v = 0 (du = duu = 0) this is duv x dv, the normal of the fan around the apex.
    const double su = u < 0.5 ? 1.0 : -1.0, sv = v < 0.5 ? 1.0 : -1.0;
    const Vec3 n1 = su * (cross(d.duu, d.dv) + cross(d.du, d.duv)) + sv * (cross(d.duv, d.dv) + cross(d.du, d.dvv));
    if (norm(n1) > vanishing) return normalized(n1);

    // Higher-order degeneracy (rare): the normal a short way inside, moving closer while it stays defined.
    for (double step : {1e-3, 1e-5, 1e-7}) {
        const PatchDerivatives inside =
            evaluate_derivatives(patch, std::clamp(u + su * step, 0.0, 1.0), std::clamp(v + sv * step, 0.0, 1.0));
        const Vec3 n = cross(inside.du, inside.dv);
        if (norm(n) > vanishing * step * step) return normalized(n);
    }
    return {};
}

PatchDerivativeBounds derivative_bounds(const BezierPatch& patch) {
    const NetBounds m = second_derivative_bounds(patch);
    return {m.u, m.v, m.uu, m.uv, m.vv};
}

double tessellation_error_bound(const BezierPatch& patch, int nu, int nv) {
    const NetBounds m = second_derivative_bounds(patch);
    const double h = 1.0 / nu, k = 1.0 / nv;
    return (m.uu * h * h + 2.0 * m.uv * h * k + m.vv * k * k) / 8.0;
}

Result<TessellationPlan> plan_tessellation(std::span<const BezierPatch> patches, const TessellationOptions& options) {
    if (options.max_segments < 1) return make_error(ErrorCode::InvalidArgument, "max_segments must be >= 1");
    if (auto valid = validate(patches); !valid) return valid.error();
    TessellationPlan plan;
    plan.segments.resize(patches.size());

    // 1. what each patch needs on its own
    if (options.tolerance) {
        const double tolerance = *options.tolerance;
        if (!std::isfinite(tolerance) || tolerance <= 0)
            return make_error(ErrorCode::InvalidArgument, "tolerance must be a finite number > 0");
        for (std::size_t p = 0; p < patches.size(); ++p) {
            // (1/8)(A/nu^2 + 2B/(nu nv) + C/nv^2) <= (1/8)((A+B)/nu^2 + (B+C)/nv^2) (AM-GM on the middle term);
            // each half is <= tolerance/2 when nu >= sqrt((A+B)/(4 tol)) and nv >= sqrt((B+C)/(4 tol)).
            const NetBounds m = second_derivative_bounds(patches[p]);
            const double need_u = std::ceil(std::sqrt((m.uu + m.uv) / (4.0 * tolerance)));
            const double need_v = std::ceil(std::sqrt((m.uv + m.vv) / (4.0 * tolerance)));
            if (!(need_u <= options.max_segments) || !(need_v <= options.max_segments)) {
                GeoError error = make_error(
                    ErrorCode::BudgetExceeded,
                    "patch " + std::to_string(p) + ": tolerance " + shortest_text(tolerance) + " needs " +
                        std::to_string(static_cast<long long>(std::min(std::max(need_u, need_v), 1e15))) +
                        " segments along one direction; the limit is " + std::to_string(options.max_segments));
                error.element = static_cast<std::int64_t>(p);
                return error;
            }
            plan.segments[p] = {std::max(1, static_cast<int>(need_u)), std::max(1, static_cast<int>(need_v))};
        }
    } else {
        if (options.segments < 1 || options.segments > options.max_segments)
            return make_error(options.segments < 1 ? ErrorCode::InvalidArgument : ErrorCode::BudgetExceeded,
                              "segments must be between 1 and " + std::to_string(options.max_segments) + ", got " +
                                  std::to_string(options.segments));
        for (auto& s : plan.segments) s = {options.segments, options.segments};
    }

    // 2. equal counts along shared edges: merge direction classes of patches that share an edge
    UnionFind classes(2 * patches.size());
    std::map<std::vector<EdgePointKey>, std::size_t> first_owner;  // canonical edge -> direction class
    for (std::size_t p = 0; p < patches.size(); ++p)
        for (int side = 0; side < 4; ++side) {
            CanonicalEdge edge = canonical_edge(patches[p], side);
            if (edge.collapsed) continue;
            const std::size_t cls = direction_class(p, side);
            auto [it, inserted] = first_owner.emplace(std::move(edge.key), cls);
            if (!inserted) classes.unite(cls, it->second);
        }
    std::vector<int> class_segments(2 * patches.size(), 0);
    for (std::size_t p = 0; p < patches.size(); ++p) {
        int& su = class_segments[classes.find(2 * p)];
        int& sv = class_segments[classes.find(2 * p + 1)];
        su = std::max(su, plan.segments[p].nu);
        sv = std::max(sv, plan.segments[p].nv);
    }
    for (std::size_t p = 0; p < patches.size(); ++p) {
        PatchSegments& s = plan.segments[p];
        s = {class_segments[classes.find(2 * p)], class_segments[classes.find(2 * p + 1)]};
        plan.triangles += 2ull * static_cast<std::uint64_t>(s.nu) * static_cast<std::uint64_t>(s.nv);
        plan.vertices += static_cast<std::uint64_t>(s.nu + 1) * static_cast<std::uint64_t>(s.nv + 1);
        plan.error_bound = std::max(plan.error_bound, tessellation_error_bound(patches[p], s.nu, s.nv));
    }
    return plan;
}

Result<PatchTessellation> tessellate_patches(std::span<const BezierPatch> patches, const TessellationOptions& options) {
    auto planned = plan_tessellation(patches, options);
    if (!planned) return planned.error();
    PatchTessellation out;
    out.plan = std::move(planned.value());
    PolygonMesh& mesh = out.mesh;
    mesh.positions.reserve(out.plan.vertices);
    mesh.normals.reserve(out.plan.vertices);
    mesh.uvs.reserve(out.plan.vertices);
    mesh.face_offsets.reserve(out.plan.triangles + 1);
    mesh.face_indices.reserve(3 * out.plan.triangles);
    mesh.uv_indices.reserve(3 * out.plan.triangles);

    std::unordered_map<PointKey, Index, PointKeyHash> welded;
    std::vector<Vec3> normal_sums;
    std::vector<Index> vertex_of, uv_of;  // per grid vertex of the current patch
    for (std::size_t p = 0; p < patches.size(); ++p) {
        if (options.cancel.requested())
            return make_error(ErrorCode::Cancelled, "tessellation cancelled at patch " + std::to_string(p) + " of " +
                                                        std::to_string(patches.size()) + " (deadline or shutdown)");
        const auto [nu, nv] = out.plan.segments[p];
        const Grid grid = patch_grid(patches[p], nu, nv);
        const auto stride = static_cast<std::size_t>(nu + 1);

        // vertices (welded by exact position) and this patch's own uvs
        vertex_of.resize(grid.positions.size());
        uv_of.resize(grid.positions.size());
        for (std::size_t k = 0; k < grid.positions.size(); ++k) {
            const auto next = static_cast<Index>(mesh.positions.size());
            Index index = next;
            if (options.weld) index = welded.emplace(point_key(grid.positions[k]), next).first->second;
            if (index == next) {
                mesh.positions.push_back(grid.positions[k]);
                normal_sums.push_back(grid.normals[k]);
            } else {
                normal_sums[index] += grid.normals[k];
            }
            vertex_of[k] = index;
            uv_of[k] = static_cast<Index>(mesh.uvs.size());
            const double u = static_cast<double>(k % stride) / nu, v = static_cast<double>(k / stride) / nv;
            if (const auto& c = patches[p].corner_uvs) {  // bilinear in the corners' texture coordinates
                const double a = (1 - u) * (1 - v), b = u * (1 - v), d = (1 - u) * v, e = u * v;
                mesh.uvs.push_back({a * (*c)[0].x + b * (*c)[1].x + d * (*c)[2].x + e * (*c)[3].x,
                                    a * (*c)[0].y + b * (*c)[1].y + d * (*c)[2].y + e * (*c)[3].y});
            } else {
                mesh.uvs.push_back({u, v});
            }
        }

        // two triangles per grid cell, counter-clockwise in (u, v) so that they face du x dv
        for (int j = 0; j < nv; ++j)
            for (int i = 0; i < nu; ++i) {
                const std::size_t a = static_cast<std::size_t>(j) * stride + static_cast<std::size_t>(i);
                const std::size_t corners[2][3] = {{a, a + 1, a + 1 + stride}, {a, a + 1 + stride, a + stride}};
                for (const auto& tri : corners) {
                    const Index v0 = vertex_of[tri[0]], v1 = vertex_of[tri[1]], v2 = vertex_of[tri[2]];
                    if (v0 == v1 || v1 == v2 || v0 == v2) continue;  // next to a collapsed edge
                    mesh.add_face({v0, v1, v2});
                    out.face_patches.push_back(static_cast<Index>(p));
                    for (std::size_t c : tri) mesh.uv_indices.push_back(uv_of[c]);
                }
            }
    }

    // Welded vertices average the patches' normals (equal on G1 joins; on a collapsed edge, the fan's limits).
    mesh.normals.resize(mesh.positions.size());
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        const Vec3 n = normalized(normal_sums[v]);
        mesh.normals[v] = norm(n) > 0 ? n : Vec3{0, 0, 1};
    }
    return out;
}

}  // namespace surfaced
