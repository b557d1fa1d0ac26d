// Bézier curves on the shared de Casteljau core. Rational curves work on homogeneous points (w b, w) throughout:
// split and elevation are the polynomial algorithms in 4D, evaluation divides at the end.
#include "geometry/curves/bezier_curve.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "geometry/core/format_number.h"
#include "geometry/curves/de_casteljau.h"

namespace surfaced {
namespace {

//! Homogeneous control point: (w x, w y, w z, w).
struct Hom {
    Vec3 p;
    double w = 1;
};

std::vector<Hom> homogeneous(const BezierCurve& curve) {
    std::vector<Hom> out(curve.points.size());
    for (std::size_t i = 0; i < out.size(); ++i) {
        const double w = curve.is_rational() ? curve.weights[i] : 1.0;
        out[i] = {curve.points[i] * w, w};
    }
    return out;
}

BezierCurve from_homogeneous(const std::vector<Hom>& h, bool rational) {
    BezierCurve curve;
    curve.points.reserve(h.size());
    for (const Hom& q : h) curve.points.push_back(rational ? q.p * (1.0 / q.w) : q.p);
    if (rational)
        for (const Hom& q : h) curve.weights.push_back(q.w);
    return curve;
}

//! The homogeneous numerator A = sum w_i b_i B_i as a polynomial curve, and the weight polynomial's coefficients.
void split_numerator(const BezierCurve& curve, std::vector<Vec3>& numerator, std::vector<Vec3>& weight) {
    numerator.resize(curve.points.size());
    weight.resize(curve.points.size());
    for (std::size_t i = 0; i < curve.points.size(); ++i) {
        const double w = curve.is_rational() ? curve.weights[i] : 1.0;
        numerator[i] = curve.points[i] * w;
        weight[i] = {w, 0, 0};
    }
}

double binomial(int n, int k) {
    double value = 1;
    for (int i = 1; i <= k; ++i) value = value * (n - k + i) / i;
    return value;
}

double polygon_length(const BezierCurve& curve) {
    double length = 0;
    for (std::size_t i = 1; i < curve.points.size(); ++i) length += norm(curve.points[i] - curve.points[i - 1]);
    return length;
}

double distance_to_box(const Box3& box, const Vec3& q) {
    Vec3 d;
    for (int c = 0; c < 3; ++c) d[c] = std::max({box.min[c] - q[c], 0.0, q[c] - box.max[c]});
    return norm(d);
}

double distance_to_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 ab = b - a;
    const double len2 = dot(ab, ab);
    const double s = len2 > 0 ? std::clamp(dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    return norm(p - (a + ab * s));
}

//! n (n-1) max |D2 b|: bounds |C''| of a polynomial curve.
double second_derivative_bound(const BezierCurve& curve) {
    const int n = curve.degree();
    if (n < 2) return 0;
    double m = 0;
    for (std::size_t i = 0; i + 2 < curve.points.size(); ++i)
        m = std::max(m, norm(curve.points[i + 2] - 2.0 * curve.points[i + 1] + curve.points[i]));
    return n * (n - 1) * m;
}

//! Wang's formula: uniform segments that keep a polynomial curve within tol of its polyline (|C - L| <= h^2 M / 8).
std::size_t wang_segments(const BezierCurve& curve, double tolerance) {
    const double m = second_derivative_bound(curve);
    if (m == 0) return 1;
    const double need = std::ceil(std::sqrt(m / (8.0 * tolerance)));
    if (!(need < 1e15)) return std::numeric_limits<std::size_t>::max() / 4;
    return std::max<std::size_t>(1, static_cast<std::size_t>(need));
}

//! Distance of every control point from the chord: bounds the whole piece's distance from it (convex hull, and
//! distance to a segment is a convex function).
double hull_distance_to_chord(const BezierCurve& curve) {
    double d = 0;
    for (const Vec3& p : curve.points)
        d = std::max(d, distance_to_segment(p, curve.points.front(), curve.points.back()));
    return d;
}

struct Piece {
    BezierCurve curve;
    double t0 = 0, t1 = 1;
};

}  // namespace

Status validate(const BezierCurve& curve) {
    if (curve.points.empty()) return make_error(ErrorCode::InvalidArgument, "a curve needs at least one control point");
    if (curve.is_rational() && curve.weights.size() != curve.points.size())
        return make_error(ErrorCode::InvalidArgument, "weights has " + std::to_string(curve.weights.size()) +
                                                          " entries for " + std::to_string(curve.points.size()) +
                                                          " control points");
    for (std::size_t i = 0; i < curve.points.size(); ++i) {
        if (!is_finite(curve.points[i]))
            return element_error(ErrorCode::NonFinite, "control point " + std::to_string(i) + " is not finite",
                                 ElementKind::Vertex, static_cast<std::int64_t>(i));
        if (curve.is_rational() && !(std::isfinite(curve.weights[i]) && curve.weights[i] > 0))
            return element_error(ErrorCode::InvalidArgument,
                                 "weight " + std::to_string(i) + " must be a finite number > 0", ElementKind::Vertex,
                                 static_cast<std::int64_t>(i));
    }
    return Ok{};
}

Vec3 evaluate(const BezierCurve& curve, double t) {
    if (!curve.is_rational()) return bezier::de_casteljau(curve.points, t);
    std::vector<Vec3> numerator, weight;
    split_numerator(curve, numerator, weight);
    return bezier::de_casteljau(numerator, t) * (1.0 / bezier::de_casteljau(weight, t).x);
}

Vec3 evaluate_bernstein(const BezierCurve& curve, double t) {
    const int n = curve.degree();
    Vec3 sum;
    double weight = 0;
    for (int i = 0; i <= n; ++i) {
        const double b =
            bezier::bernstein(n, i, t) * (curve.is_rational() ? curve.weights[static_cast<std::size_t>(i)] : 1.0);
        sum += b * curve.points[static_cast<std::size_t>(i)];
        weight += b;
    }
    return sum * (1.0 / weight);
}

Vec3 derivative(const BezierCurve& curve, double t, int order) {
    if (!curve.is_rational()) return bezier::derivative(curve.points, t, order);
    std::vector<Vec3> numerator, weight;
    split_numerator(curve, numerator, weight);
    const double w = bezier::de_casteljau(weight, t).x;
    std::vector<Vec3> c(static_cast<std::size_t>(order) + 1);
    for (int k = 0; k <= order; ++k) {
        Vec3 value = bezier::derivative(numerator, t, k);
        for (int j = 1; j <= k; ++j)
            value -= binomial(k, j) * bezier::derivative(weight, t, j).x * c[static_cast<std::size_t>(k - j)];
        c[static_cast<std::size_t>(k)] = value * (1.0 / w);
    }
    return c.back();
}

std::pair<BezierCurve, BezierCurve> split(const BezierCurve& curve, double t) {
    std::vector<Hom> b = homogeneous(curve);
    const std::size_t n = b.size();
    std::vector<Hom> left(n), right(n);
    const double s = 1.0 - t;
    for (std::size_t level = 0; level < n; ++level) {
        left[level] = b[0];
        right[n - 1 - level] = b[n - 1 - level];
        for (std::size_t i = 0; i + 1 < n - level; ++i)
            b[i] = {s * b[i].p + t * b[i + 1].p, s * b[i].w + t * b[i + 1].w};
    }
    return {from_homogeneous(left, curve.is_rational()), from_homogeneous(right, curve.is_rational())};
}

BezierCurve elevate_degree(const BezierCurve& curve, int times) {
    std::vector<Hom> b = homogeneous(curve);
    for (int k = 0; k < times; ++k) {
        const std::size_t n = b.size() - 1;  // current degree
        std::vector<Hom> e(n + 2);
        e[0] = b[0];
        e[n + 1] = b[n];
        for (std::size_t i = 1; i <= n; ++i) {
            const double a = static_cast<double>(i) / static_cast<double>(n + 1);
            e[i] = {a * b[i - 1].p + (1 - a) * b[i].p, a * b[i - 1].w + (1 - a) * b[i].w};
        }
        b = std::move(e);
    }
    return from_homogeneous(b, curve.is_rational());
}

Box3 bounding_box(const BezierCurve& curve) {
    Box3 box;
    for (const Vec3& p : curve.points) box.add(p);
    return box;
}

double curvature(const BezierCurve& curve, double t) {
    const Vec3 d1 = derivative(curve, t, 1), d2 = derivative(curve, t, 2);
    const double speed = norm(d1);
    if (speed == 0) return 0;
    return norm(cross(d1, d2)) / (speed * speed * speed);
}

ArcLength arc_length(const BezierCurve& curve, double tolerance, int max_depth) {
    ArcLength result;
    if (curve.points.size() < 2) return result;
    const double n = curve.degree();
    // Each piece at depth d may contribute tolerance / 2^d: the total stays within tolerance (a piece is split
    // only into two halves with half the allowance each).
    struct Item {
        BezierCurve piece;
        double allowance;
        int depth;
    };
    std::vector<Item> stack{{curve, tolerance, 0}};
    while (!stack.empty()) {
        Item item = std::move(stack.back());
        stack.pop_back();
        const double chord = norm(item.piece.points.back() - item.piece.points.front());
        const double polygon = polygon_length(item.piece);
        if (polygon - chord <= item.allowance || item.depth >= max_depth) {
            const double estimate = (2 * chord + (n - 1) * polygon) / (n + 1);  // Gravesen
            result.length += estimate;
            result.error_bound += std::max(estimate - chord, polygon - estimate);
            continue;
        }
        auto [left, right] = split(item.piece, 0.5);
        stack.push_back({std::move(left), item.allowance / 2, item.depth + 1});
        stack.push_back({std::move(right), item.allowance / 2, item.depth + 1});
    }
    return result;
}

ClosestPoint closest_point(const BezierCurve& curve, const Vec3& query) {
    ClosestPoint best;
    best.t = 0;
    best.point = curve.points.front();
    best.distance = norm(best.point - query);
    const auto consider = [&](double t) {
        t = std::clamp(t, 0.0, 1.0);
        const Vec3 p = evaluate(curve, t);
        const double d = norm(p - query);
        if (d < best.distance) best = {t, p, d};
    };
    consider(1.0);

    // 1. branch and bound: keep pieces whose control box could hold a closer point; record leaf candidates
    std::vector<Piece> stack{{curve, 0.0, 1.0}};
    std::vector<std::pair<double, double>> leaves;  // parameter intervals that survived to the finest level
    constexpr double kLeafWidth = 1.0 / 256;
    while (!stack.empty()) {
        Piece piece = std::move(stack.back());
        stack.pop_back();
        if (distance_to_box(bounding_box(piece.curve), query) > best.distance) continue;
        const double mid = 0.5 * (piece.t0 + piece.t1);
        consider(mid);
        if (piece.t1 - piece.t0 <= kLeafWidth) {
            leaves.emplace_back(piece.t0, piece.t1);
            continue;
        }
        auto [left, right] = split(piece.curve, 0.5);
        stack.push_back({std::move(left), piece.t0, mid});
        stack.push_back({std::move(right), mid, piece.t1});
    }

    // 2. Newton on f(t) = (C(t) - q) . C'(t) from the middle of every surviving leaf
    for (const auto& [t0, t1] : leaves) {
        double t = 0.5 * (t0 + t1);
        for (int iteration = 0; iteration < 30; ++iteration) {
            const Vec3 c = evaluate(curve, t) - query;
            const Vec3 d1 = derivative(curve, t, 1), d2 = derivative(curve, t, 2);
            const double f = dot(c, d1), df = dot(d1, d1) + dot(c, d2);
            if (df <= 0) break;
            const double next = std::clamp(t - f / df, 0.0, 1.0);
            if (std::abs(next - t) < 1e-15) {
                t = next;
                break;
            }
            t = next;
        }
        consider(t);
    }
    return best;
}

Result<CurveTessellation> tessellate(const BezierCurve& curve, double tolerance, std::size_t max_segments) {
    if (auto valid = validate(curve); !valid) return valid.error();
    if (!(std::isfinite(tolerance) && tolerance > 0))
        return make_error(ErrorCode::InvalidArgument, "tolerance must be a finite number > 0");
    CurveTessellation out;

    // 1. pieces, each tessellated uniformly with `count` segments
    struct Planned {
        Piece piece;
        std::size_t count;
    };
    std::vector<Planned> planned;
    std::vector<Piece> stack{{curve, 0.0, 1.0}};
    std::size_t total = 0;
    while (!stack.empty()) {
        Piece piece = std::move(stack.back());
        stack.pop_back();
        if (total > max_segments)
            return make_error(ErrorCode::BudgetExceeded, "tolerance " + shortest_text(tolerance) + " needs more than " +
                                                             std::to_string(max_segments) + " segments");
        const double width = piece.t1 - piece.t0;
        if (!curve.is_rational()) {
            const std::size_t whole = wang_segments(piece.curve, tolerance);
            auto halves = split(piece.curve, 0.5);
            const std::size_t parts = wang_segments(halves.first, tolerance) + wang_segments(halves.second, tolerance);
            // Split only while it saves segments (Wang's bound is loose where the second difference varies).
            if (whole > 1 && parts < whole && width > 1e-9) {
                const double mid = piece.t0 + 0.5 * width;
                stack.push_back({std::move(halves.second), mid, piece.t1});
                stack.push_back({std::move(halves.first), piece.t0, mid});
                continue;
            }
            if (whole > max_segments)
                return make_error(ErrorCode::BudgetExceeded, "tolerance " + shortest_text(tolerance) +
                                                                 " needs more than " + std::to_string(max_segments) +
                                                                 " segments");
            total += whole;
            planned.push_back({std::move(piece), whole});
        } else {
            if (hull_distance_to_chord(piece.curve) <= tolerance || width <= 1e-9) {
                total += 1;
                planned.push_back({std::move(piece), 1});
                continue;
            }
            auto halves = split(piece.curve, 0.5);
            const double mid = piece.t0 + 0.5 * width;
            stack.push_back({std::move(halves.second), mid, piece.t1});
            stack.push_back({std::move(halves.first), piece.t0, mid});
        }
    }
    if (total > max_segments)
        return make_error(ErrorCode::BudgetExceeded, "tolerance " + shortest_text(tolerance) + " needs more than " +
                                                         std::to_string(max_segments) + " segments");

    // 2. the polyline, in parameter order (pieces were pushed so that they pop left to right)
    out.points.push_back(curve.points.front());
    out.params.push_back(0.0);
    for (const Planned& p : planned) {
        for (std::size_t k = 1; k <= p.count; ++k) {
            const double s = static_cast<double>(k) / static_cast<double>(p.count);
            out.points.push_back(k == p.count ? p.piece.curve.points.back() : evaluate(p.piece.curve, s));
            out.params.push_back(k == p.count ? p.piece.t1 : p.piece.t0 + s * (p.piece.t1 - p.piece.t0));
        }
        const double h = 1.0 / static_cast<double>(p.count);
        out.bound = std::max(out.bound, curve.is_rational() ? hull_distance_to_chord(p.piece.curve)
                                                            : second_derivative_bound(p.piece.curve) * h * h / 8.0);
    }
    out.segments = out.points.size() - 1;

    // 3. measured deviation: the curve sampled inside every segment, against the segment's chord
    for (std::size_t k = 0; k + 1 < out.points.size(); ++k)
        for (int j = 1; j < 16; ++j) {
            const double t = out.params[k] + (out.params[k + 1] - out.params[k]) * j / 16.0;
            out.max_deviation =
                std::max(out.max_deviation, distance_to_segment(evaluate(curve, t), out.points[k], out.points[k + 1]));
        }
    return out;
}

}  // namespace surfaced
