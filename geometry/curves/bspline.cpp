// B-spline and NURBS curves. NURBS work on homogeneous points (w P, w) throughout: de Boor, the derivative control
// points and knot insertion are the polynomial algorithms in 4D; evaluation divides at the end. Everything local to
// one knot span touches only its p + 1 control points and 2p knots, so evaluation is O(p^2) whatever n is.
#include "geometry/curves/bspline.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <string>

namespace surfaced {
namespace {

//! Homogeneous control point: (w x, w y, w z, w).
struct Hom {
    Vec3 p;
    double w = 1;
};

Hom lerp(const Hom& a, const Hom& b, double alpha) {
    return {(1.0 - alpha) * a.p + alpha * b.p, (1.0 - alpha) * a.w + alpha * b.w};
}

Hom homogeneous(const BSplineCurve& curve, std::size_t i) {
    const double w = curve.is_rational() ? curve.weights[i] : 1.0;
    return {curve.points[i] * w, w};
}

//! A knot or parameter value for a message: shortest form that tells neighbouring values apart.
std::string num(double v) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.15g", v);
    return buffer;
}

double binomial(int n, int k) {
    double value = 1;
    for (int i = 1; i <= k; ++i) value = value * (n - k + i) / i;
    return value;
}

//! de Boor's triangle on d[0..q] = the local points Q_{k-q..k} of a degree-q spline whose knots are U (already offset
//! for a derivative curve), on span k. Overwrites d; returns the point.
Hom de_boor(Hom* d, int q, std::size_t k, const double* U, double u) {
    const std::size_t qs = static_cast<std::size_t>(q);
    for (std::size_t r = 1; r <= qs; ++r)
        for (std::size_t j = qs; j >= r; --j) {
            const std::size_t i = k - qs + j;
            const double alpha = (u - U[i]) / (U[i + qs - r + 1] - U[i]);
            d[j] = lerp(d[j - 1], d[j], alpha);
        }
    return d[qs];
}

//! Homogeneous derivatives A^(j), w^(j) (packed in Hom) for j = 0..order at u on span k (derivatives above the
//! degree are zero).
std::vector<Hom> homogeneous_derivatives(const BSplineCurve& curve, double u, std::size_t k, int order) {
    const int p = curve.degree;
    const std::size_t ps = static_cast<std::size_t>(p);
    const double* U = curve.knots.data();
    std::vector<Hom> out(static_cast<std::size_t>(order) + 1, Hom{{}, 0.0});
    // q[t] = Q^(j)_{k-p+t}, t = 0..p-j: control points of the j-th derivative curve local to span k
    std::vector<Hom> q(ps + 1), d(ps + 1);
    for (std::size_t t = 0; t <= ps; ++t) q[t] = homogeneous(curve, k - ps + t);
    for (int j = 0; j <= std::min(order, p); ++j) {
        const std::size_t js = static_cast<std::size_t>(j);
        if (j > 0) {
            // Q^(j)_i = (p - j + 1) (Q^(j-1)_{i+1} - Q^(j-1)_i) / (u_{i+p+1} - u_{i+j}); the span is non-empty, so
            // for i in [k-p, k-j] the denominator is >= u_{k+1} - u_k > 0.
            for (std::size_t t = 0; t + js <= ps; ++t) {
                const std::size_t i = k - ps + t;
                const double f = static_cast<double>(p - j + 1) / (U[i + ps + 1] - U[i + js]);
                q[t] = {(q[t + 1].p - q[t].p) * f, (q[t + 1].w - q[t].w) * f};
            }
        }
        // the j-th derivative curve has degree p - j and knots U + j; span k becomes k - j
        std::copy(q.begin(), q.begin() + static_cast<std::ptrdiff_t>(ps - js + 1), d.begin());
        out[js] = de_boor(d.data(), p - j, k - js, U + js, u);
    }
    return out;
}

//! One Boehm insertion of u into span k (u_k <= u <= u_{k+1}, u_k < u_{k+1}) of a degree-p spline.
void insert_once(int p, std::vector<Hom>& P, std::vector<double>& U, double u, std::size_t k) {
    const std::size_t ps = static_cast<std::size_t>(p);
    std::vector<Hom> Q(P.size() + 1);
    for (std::size_t i = 0; i + ps <= k; ++i) Q[i] = P[i];
    for (std::size_t i = k - ps + 1; i <= k; ++i) {
        const double alpha = (u - U[i]) / (U[i + ps] - U[i]);
        Q[i] = lerp(P[i - 1], P[i], alpha);
    }
    for (std::size_t i = k + 1; i < Q.size(); ++i) Q[i] = P[i - 1];
    P = std::move(Q);
    U.insert(U.begin() + static_cast<std::ptrdiff_t>(k + 1), u);
}

std::vector<Hom> homogeneous_points(const BSplineCurve& curve) {
    std::vector<Hom> h(curve.points.size());
    for (std::size_t i = 0; i < h.size(); ++i) h[i] = homogeneous(curve, i);
    return h;
}

void store_points(const std::vector<Hom>& h, bool rational, std::vector<Vec3>& points, std::vector<double>& weights) {
    points.clear();
    weights.clear();
    points.reserve(h.size());
    for (const Hom& q : h) points.push_back(rational ? q.p * (1.0 / q.w) : q.p);
    if (rational)
        for (const Hom& q : h) weights.push_back(q.w);
}

double clamp_to_domain(const BSplineCurve& curve, double u) {
    const auto [lo, hi] = domain(curve);
    if (!(u > lo)) return lo;  // also NaN
    return u > hi ? hi : u;
}

//! Knot errors carry the knot index with ElementKind::None (GeoError has no knot kind); see bspline.h.
GeoError knot_error(ErrorCode code, std::string message, std::size_t index) {
    return element_error(code, std::move(message), ElementKind::None, static_cast<std::int64_t>(index));
}

}  // namespace

Status validate(const BSplineCurve& curve) {
    const int p = curve.degree;
    if (p < 1) return make_error(ErrorCode::InvalidArgument, "degree must be >= 1 (got " + std::to_string(p) + ")");
    const std::size_t n = curve.points.size(), ps = static_cast<std::size_t>(p);
    if (n < ps + 1)
        return make_error(ErrorCode::InvalidArgument, "a curve of degree " + std::to_string(p) + " needs at least " +
                                                          std::to_string(ps + 1) + " control points (got " +
                                                          std::to_string(n) + ")");
    if (curve.knots.size() != n + ps + 1)
        return make_error(ErrorCode::InvalidArgument, "knots has " + std::to_string(curve.knots.size()) + " entries; " +
                                                          std::to_string(n) + " control points of degree " +
                                                          std::to_string(p) + " need " + std::to_string(n + ps + 1) +
                                                          " (points + degree + 1)");
    if (curve.is_rational() && curve.weights.size() != n)
        return make_error(ErrorCode::InvalidArgument, "weights has " + std::to_string(curve.weights.size()) +
                                                          " entries for " + std::to_string(n) + " control points");
    for (std::size_t i = 0; i < n; ++i) {
        if (!is_finite(curve.points[i]))
            return element_error(ErrorCode::NonFinite, "control point " + std::to_string(i) + " is not finite",
                                 ElementKind::Vertex, static_cast<std::int64_t>(i));
        if (curve.is_rational() && !(std::isfinite(curve.weights[i]) && curve.weights[i] > 0))
            return element_error(ErrorCode::InvalidArgument,
                                 "weight " + std::to_string(i) + " must be a finite number > 0", ElementKind::Vertex,
                                 static_cast<std::int64_t>(i));
    }
    const std::vector<double>& U = curve.knots;
    for (std::size_t i = 0; i < U.size(); ++i) {
        if (!std::isfinite(U[i]))
            return knot_error(ErrorCode::NonFinite, "knot " + std::to_string(i) + " is not finite", i);
        if (i > 0 && U[i] < U[i - 1])
            return knot_error(ErrorCode::InvalidArgument,
                              "knot " + std::to_string(i) + " (" + num(U[i]) + ") is smaller than knot " +
                                  std::to_string(i - 1) + " (" + num(U[i - 1]) + "): knots must be non-decreasing",
                              i);
    }
    for (std::size_t start = 0; start < U.size();) {
        std::size_t end = start;
        while (end < U.size() && U[end] == U[start]) ++end;
        const bool at_end = start == 0 || end == U.size();
        const std::size_t allowed = at_end ? ps + 1 : ps;
        if (end - start > allowed)
            return knot_error(ErrorCode::InvalidArgument,
                              "knot " + std::to_string(start + allowed) + ": the value " + num(U[start]) +
                                  " is repeated " + std::to_string(end - start) + " times (from knot " +
                                  std::to_string(start) + "); at most degree + 1 = " + std::to_string(ps + 1) +
                                  " for the first or last value, degree = " + std::to_string(ps) + " for any other",
                              start + allowed);
        start = end;
    }
    if (!(U[ps] < U[n]))
        return knot_error(ErrorCode::InvalidArgument,
                          "knot " + std::to_string(n) + ": the domain [knots[" + std::to_string(ps) + "], knots[" +
                              std::to_string(n) + "]] = [" + num(U[ps]) + ", " + num(U[n]) + "] is empty",
                          n);
    return Ok{};
}

namespace {

Status check_knot_arguments(std::size_t point_count, int degree, double u0, double u1) {
    if (degree < 1)
        return make_error(ErrorCode::InvalidArgument, "degree must be >= 1 (got " + std::to_string(degree) + ")");
    if (point_count < static_cast<std::size_t>(degree) + 1)
        return make_error(ErrorCode::InvalidArgument, "a curve of degree " + std::to_string(degree) +
                                                          " needs at least " + std::to_string(degree + 1) +
                                                          " control points (got " + std::to_string(point_count) + ")");
    if (!(std::isfinite(u0) && std::isfinite(u1) && u0 < u1))
        return make_error(ErrorCode::InvalidArgument,
                          "the domain [" + num(u0) + ", " + num(u1) + "] must be finite with start < end");
    return Ok{};
}

}  // namespace

Result<std::vector<double>> clamped_uniform_knots(std::size_t point_count, int degree, double u0, double u1) {
    if (auto ok = check_knot_arguments(point_count, degree, u0, u1); !ok) return ok.error();
    const std::size_t p = static_cast<std::size_t>(degree), spans = point_count - p;
    std::vector<double> knots(point_count + p + 1);
    for (std::size_t i = 0; i <= p; ++i) {
        knots[i] = u0;
        knots[point_count + i] = u1;
    }
    for (std::size_t j = 1; j < spans; ++j)
        knots[p + j] = u0 + (u1 - u0) * static_cast<double>(j) / static_cast<double>(spans);
    return knots;
}

Result<std::vector<double>> uniform_knots(std::size_t point_count, int degree, double u0, double u1) {
    if (auto ok = check_knot_arguments(point_count, degree, u0, u1); !ok) return ok.error();
    const std::size_t p = static_cast<std::size_t>(degree), spans = point_count - p;
    const double h = (u1 - u0) / static_cast<double>(spans);
    std::vector<double> knots(point_count + p + 1);
    for (std::size_t i = 0; i < knots.size(); ++i) {
        const double j = static_cast<double>(i) - static_cast<double>(p);
        knots[i] = u0 + h * j;
    }
    knots[p] = u0;  // exact domain ends
    knots[point_count] = u1;
    return knots;
}

Result<BSplineCurve> closed_uniform(std::span<const Vec3> points, int degree, std::span<const double> weights) {
    if (degree < 1)
        return make_error(ErrorCode::InvalidArgument, "degree must be >= 1 (got " + std::to_string(degree) + ")");
    if (points.size() < 3)
        return make_error(ErrorCode::InvalidArgument,
                          "a closed curve needs at least 3 control points (got " + std::to_string(points.size()) + ")");
    if (!weights.empty() && weights.size() != points.size())
        return make_error(ErrorCode::InvalidArgument, "weights has " + std::to_string(weights.size()) +
                                                          " entries for " + std::to_string(points.size()) +
                                                          " control points");
    BSplineCurve curve;
    curve.degree = degree;
    const std::size_t p = static_cast<std::size_t>(degree);
    curve.points.reserve(points.size() + p);
    for (std::size_t i = 0; i < points.size() + p; ++i) {
        curve.points.push_back(points[i % points.size()]);
        if (!weights.empty()) curve.weights.push_back(weights[i % points.size()]);
    }
    auto knots = uniform_knots(curve.points.size(), degree);
    if (!knots) return knots.error();
    curve.knots = std::move(*knots);
    if (auto ok = validate(curve); !ok) return ok.error();
    return curve;
}

std::pair<double, double> domain(const BSplineCurve& curve) {
    assert(curve.degree >= 0 && curve.knots.size() == curve.points.size() + static_cast<std::size_t>(curve.degree) + 1);
    return {curve.knots[static_cast<std::size_t>(curve.degree)], curve.knots[curve.points.size()]};
}

std::size_t find_span(std::span<const double> knots, int degree, std::size_t point_count, double u, SpanSide side) {
    const std::size_t p = static_cast<std::size_t>(degree), n = point_count;
    assert(knots.size() == n + p + 1 && n > p && knots[p] < knots[n]);
    const double lo = knots[p], hi = knots[n];
    if (!(u > lo)) {
        u = lo;  // also NaN
        side = SpanSide::Right;
    } else if (u >= hi) {
        u = hi;
        side = SpanSide::Left;
    }
    const auto first = knots.begin() + static_cast<std::ptrdiff_t>(p),
               last = knots.begin() + static_cast<std::ptrdiff_t>(n) + 1;
    // Right: the last k with u_k <= u (u < u_n, so k <= n - 1). Left: the first k + 1 with u <= u_{k+1} (u > u_p).
    const auto it = side == SpanSide::Right ? std::upper_bound(first, last, u) : std::lower_bound(first, last, u);
    const std::size_t k = static_cast<std::size_t>(it - knots.begin()) - 1;
    assert(k >= p && k < n);
    return k;
}

double basis_function(std::span<const double> knots, int degree, std::size_t i, double u, SpanSide side) {
    const std::size_t p = static_cast<std::size_t>(degree);
    assert(i + p + 1 < knots.size());
    // N[j] = N_{i+j, level}, built up from level 0 (Cox-de Boor)
    std::vector<double> N(p + 1);
    for (std::size_t j = 0; j <= p; ++j) {
        const double a = knots[i + j], b = knots[i + j + 1];
        N[j] = (side == SpanSide::Right ? (a <= u && u < b) : (a < u && u <= b)) ? 1.0 : 0.0;
    }
    for (std::size_t level = 1; level <= p; ++level)
        for (std::size_t j = 0; j + level <= p; ++j) {
            const std::size_t r = i + j;
            double value = 0;
            const double left = knots[r + level] - knots[r];
            if (left > 0) value += (u - knots[r]) / left * N[j];
            const double right = knots[r + level + 1] - knots[r + 1];
            if (right > 0) value += (knots[r + level + 1] - u) / right * N[j + 1];
            N[j] = value;
        }
    return N[0];
}

Vec3 evaluate(const BSplineCurve& curve, double u) {
    u = clamp_to_domain(curve, u);
    const std::size_t k = find_span(curve.knots, curve.degree, curve.points.size(), u);
    const std::size_t p = static_cast<std::size_t>(curve.degree);
    // no allocation for the usual degrees: evaluation is the hot path of sampling
    constexpr std::size_t kInline = 32;
    Hom inline_buffer[kInline];
    std::vector<Hom> heap;
    Hom* d = inline_buffer;
    if (p + 1 > kInline) {
        heap.resize(p + 1);
        d = heap.data();
    }
    for (std::size_t j = 0; j <= p; ++j) d[j] = homogeneous(curve, k - p + j);
    const Hom h = de_boor(d, curve.degree, k, curve.knots.data(), u);
    return curve.is_rational() ? h.p * (1.0 / h.w) : h.p;
}

Vec3 evaluate_basis(const BSplineCurve& curve, double u) {
    u = clamp_to_domain(curve, u);
    const SpanSide side = u >= domain(curve).second ? SpanSide::Left : SpanSide::Right;
    Vec3 sum;
    double weight = 0;
    for (std::size_t i = 0; i < curve.points.size(); ++i) {
        const double b =
            basis_function(curve.knots, curve.degree, i, u, side) * (curve.is_rational() ? curve.weights[i] : 1.0);
        sum += b * curve.points[i];
        weight += b;
    }
    return sum * (1.0 / weight);
}

Vec3 derivative(const BSplineCurve& curve, double u, int order, SpanSide side) {
    assert(order >= 0);
    if (!curve.is_rational() && order > curve.degree) return {};
    u = clamp_to_domain(curve, u);
    const std::size_t k = find_span(curve.knots, curve.degree, curve.points.size(), u, side);
    const std::vector<Hom> h = homogeneous_derivatives(curve, u, k, order);
    if (!curve.is_rational()) return h.back().p;
    std::vector<Vec3> c(h.size());
    for (std::size_t j = 0; j < h.size(); ++j) {
        Vec3 value = h[j].p;
        for (std::size_t i = 1; i <= j; ++i)
            value -= binomial(static_cast<int>(j), static_cast<int>(i)) * h[i].w * c[j - i];
        c[j] = value * (1.0 / h[0].w);
    }
    return c.back();
}

Result<BSplineCurve> derivative_curve(const BSplineCurve& curve) {
    if (auto ok = validate(curve); !ok) return ok.error();
    if (curve.is_rational())
        return make_error(ErrorCode::Unsupported, "the derivative of a NURBS curve is not a B-spline curve");
    const std::size_t p = static_cast<std::size_t>(curve.degree), n = curve.points.size();
    BSplineCurve out;
    out.degree = curve.degree - 1;
    out.knots.assign(curve.knots.begin() + 1, curve.knots.end() - 1);
    out.points.resize(n - 1);
    for (std::size_t i = 0; i + 1 < n; ++i) {
        const double span = curve.knots[i + p + 1] - curve.knots[i + 1];
        out.points[i] = span > 0 ? (curve.points[i + 1] - curve.points[i]) * (static_cast<double>(p) / span) : Vec3{};
    }
    return out;
}

Box3 bounding_box(const BSplineCurve& curve) {
    Box3 box;
    for (const Vec3& p : curve.points) box.add(p);
    return box;
}

Result<BSplineCurve> insert_knot(const BSplineCurve& curve, double u, int times) {
    if (auto ok = validate(curve); !ok) return ok.error();
    const auto [lo, hi] = domain(curve);
    if (!(std::isfinite(u) && u >= lo && u <= hi))
        return make_error(ErrorCode::InvalidArgument,
                          "the knot " + num(u) + " is outside the domain [" + num(lo) + ", " + num(hi) + "]");
    if (times < 0)
        return make_error(ErrorCode::InvalidArgument, "times must be >= 0 (got " + std::to_string(times) + ")");
    const std::size_t s = static_cast<std::size_t>(std::count(curve.knots.begin(), curve.knots.end(), u));
    const std::size_t p = static_cast<std::size_t>(curve.degree);
    if (s + static_cast<std::size_t>(times) > p)
        return make_error(ErrorCode::InvalidArgument,
                          "the knot " + num(u) + " already has multiplicity " + std::to_string(s) + "; inserting it " +
                              std::to_string(times) + " more times would exceed the degree " + std::to_string(p));
    std::vector<Hom> P = homogeneous_points(curve);
    std::vector<double> U = curve.knots;
    const SpanSide side = u >= hi ? SpanSide::Left : SpanSide::Right;
    for (int t = 0; t < times; ++t) insert_once(curve.degree, P, U, u, find_span(U, curve.degree, P.size(), u, side));
    BSplineCurve out;
    out.degree = curve.degree;
    out.knots = std::move(U);
    store_points(P, curve.is_rational(), out.points, out.weights);
    return out;
}

std::vector<double> bezier_breaks(const BSplineCurve& curve) {
    const std::size_t p = static_cast<std::size_t>(curve.degree), n = curve.points.size();
    std::vector<double> breaks;
    for (std::size_t k = p; k <= n; ++k)
        if (breaks.empty() || curve.knots[k] != breaks.back()) breaks.push_back(curve.knots[k]);
    return breaks;
}

Result<BezierChain> to_bezier(const BSplineCurve& curve, const Cancel& cancel) {
    if (auto ok = validate(curve); !ok) return ok.error();
    const std::size_t p = static_cast<std::size_t>(curve.degree), n = curve.points.size();
    const std::vector<double>& U = curve.knots;
    BezierChain chain;
    std::vector<Hom> P;
    std::vector<double> L;
    for (std::size_t k = p; k < n; ++k) {
        if (!(U[k] < U[k + 1])) continue;  // empty span
        if (cancel.requested()) return make_error(ErrorCode::Cancelled, "cancelled while converting to Bézier form");
        // The span alone: points P_{k-p..k} and knots u_{k-p..k+p+1}, whose only non-empty span is [a, b] at local
        // index p. Raise a and b to multiplicity p among the knots that the span's basis functions see; the p + 1
        // points of the span are then its Bézier points.
        const double a = U[k], b = U[k + 1];
        P.assign(p + 1, Hom{});
        for (std::size_t j = 0; j <= p; ++j) P[j] = homogeneous(curve, k - p + j);
        L.assign(U.begin() + static_cast<std::ptrdiff_t>(k - p), U.begin() + static_cast<std::ptrdiff_t>(k + p + 2));
        std::size_t span = p;
        const std::size_t have_a =
            static_cast<std::size_t>(std::count(L.begin() + 1, L.begin() + static_cast<std::ptrdiff_t>(p + 1), a));
        for (std::size_t t = have_a; t < p; ++t) insert_once(curve.degree, P, L, a, span++);
        const std::size_t have_b =
            static_cast<std::size_t>(std::count(L.begin() + static_cast<std::ptrdiff_t>(span + 1),
                                                L.begin() + static_cast<std::ptrdiff_t>(span + p + 1), b));
        for (std::size_t t = have_b; t < p; ++t) insert_once(curve.degree, P, L, b, span);
        BezierCurve piece;
        const std::vector<Hom> local(P.begin() + static_cast<std::ptrdiff_t>(span - p),
                                     P.begin() + static_cast<std::ptrdiff_t>(span + 1));
        store_points(local, curve.is_rational(), piece.points, piece.weights);
        if (!chain.pieces.empty()) {  // the shared end point, bit-for-bit
            piece.points.front() = chain.pieces.back().points.back();
            if (curve.is_rational()) piece.weights.front() = chain.pieces.back().weights.back();
        }
        chain.pieces.push_back(std::move(piece));
    }
    return chain;
}

Result<CurveTessellation> tessellate(const BSplineCurve& curve, const BSplineTessellationOptions& options) {
    if (auto ok = validate(curve); !ok) return ok.error();
    if (!(std::isfinite(options.tolerance) && options.tolerance > 0))
        return make_error(ErrorCode::InvalidArgument, "tolerance must be a finite number > 0");
    auto chain = to_bezier(curve, options.cancel);
    if (!chain) return chain.error();
    const std::vector<double> breaks = bezier_breaks(curve);
    assert(breaks.size() == chain->pieces.size() + 1);
    CurveTessellation out;
    for (std::size_t j = 0; j < chain->pieces.size(); ++j) {
        if (options.cancel.requested()) return make_error(ErrorCode::Cancelled, "cancelled while tessellating");
        if (out.segments >= options.max_segments)
            return make_error(ErrorCode::BudgetExceeded, "tolerance " + num(options.tolerance) + " needs more than " +
                                                             std::to_string(options.max_segments) + " segments");
        auto piece = tessellate(chain->pieces[j], options.tolerance, options.max_segments - out.segments);
        if (!piece) {
            if (piece.error().code == ErrorCode::BudgetExceeded)
                return make_error(ErrorCode::BudgetExceeded, "tolerance " + num(options.tolerance) +
                                                                 " needs more than " +
                                                                 std::to_string(options.max_segments) + " segments");
            return piece.error();
        }
        const double a = breaks[j], b = breaks[j + 1];
        for (std::size_t i = out.points.empty() ? 0 : 1; i < piece->points.size(); ++i) {
            out.points.push_back(piece->points[i]);
            const double t = piece->params[i];
            out.params.push_back(t == 1.0 ? b : a + t * (b - a));
        }
        out.segments += piece->segments;
        out.bound = std::max(out.bound, piece->bound);
        out.max_deviation = std::max(out.max_deviation, piece->max_deviation);
    }
    return out;
}

}  // namespace surfaced
