// The one de Casteljau core shared by Bézier curves and tensor-product patches: evaluation of a
// polynomial Bézier control polygon and of its derivatives (through the hodograph, i.e. forward differences of the
// control points). Header-only and allocation-free for degrees up to kMaxInlineDegree.
//
// Exactness that callers rely on: at t = 0 the result is bit-exactly points[0], at t = 1 bit-exactly points.back()
// ((1 - 0) * a + 0 * b == a and 0 * a + 1 * b == b in IEEE arithmetic, for finite a and b). A constant control
// polygon, however, does not necessarily evaluate bit-exactly to that constant inside (0, 1).
#pragma once

#include <cassert>
#include <cstddef>
#include <span>
#include <vector>

#include "geometry/core/types.h"

namespace surfaced::bezier {

inline constexpr int kMaxInlineDegree = 31;

//! Point of the Bézier curve with control points `points` (degree = size - 1, size >= 1) at parameter t.
inline Vec3 de_casteljau(std::span<const Vec3> points, double t) {
    assert(!points.empty());
    const std::size_t n = points.size();
    Vec3 inline_buffer[kMaxInlineDegree + 1];
    std::vector<Vec3> heap;
    Vec3* b = inline_buffer;
    if (n > kMaxInlineDegree + 1) {
        heap.assign(points.begin(), points.end());
        b = heap.data();
    } else {
        for (std::size_t i = 0; i < n; ++i) b[i] = points[i];
    }
    const double s = 1.0 - t;
    for (std::size_t level = n - 1; level > 0; --level)
        for (std::size_t i = 0; i < level; ++i) b[i] = s * b[i] + t * b[i + 1];
    return b[0];
}

//! Control points of the k-th derivative (the k-th hodograph): n!/(n-k)! * forward differences of order k.
//! Empty when k > degree (the derivative is identically zero).
inline std::vector<Vec3> hodograph(std::span<const Vec3> points, int k) {
    assert(k >= 0);
    std::vector<Vec3> d(points.begin(), points.end());
    for (int order = 0; order < k; ++order) {
        if (d.size() <= 1) return {};
        const double degree = static_cast<double>(d.size() - 1);
        for (std::size_t i = 0; i + 1 < d.size(); ++i) d[i] = degree * (d[i + 1] - d[i]);
        d.pop_back();
    }
    return d;
}

//! k-th derivative with respect to t of the Bézier curve at t (k = 0 is the point itself).
inline Vec3 derivative(std::span<const Vec3> points, double t, int k) {
    if (k == 0) return de_casteljau(points, t);
    const std::vector<Vec3> d = hodograph(points, k);
    if (d.empty()) return {};
    return de_casteljau(d, t);
}

//! Bernstein polynomial B_{i,n}(t) = C(n, i) t^i (1 - t)^(n - i), for the Bernstein-form evaluation that tests
//! compare de Casteljau against.
inline double bernstein(int n, int i, double t) {
    if (i < 0 || i > n) return 0.0;
    double binomial = 1.0;
    for (int k = 1; k <= i; ++k) binomial = binomial * (n - i + k) / k;
    double value = binomial;
    for (int k = 0; k < i; ++k) value *= t;
    for (int k = 0; k < n - i; ++k) value *= 1.0 - t;
    return value;
}

}  // namespace surfaced::bezier
