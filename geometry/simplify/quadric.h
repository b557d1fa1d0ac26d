// Quadric value type of the Garland-Heckbert error metric. Private to geometry/simplify (pmp made its Quadric private
// for the same reason: it is an implementation detail of decimation, not an API).
//
// Reference: M. Garland, P. Heckbert, "Surface Simplification Using Quadric Error Metrics", SIGGRAPH 1997, sec. 5.
//
// Q(p) = p^T A p + 2 b.p + c, the weighted sum of squared distances from p to a set of planes n.p + d = 0 (unit n).
// `weight` is the sum of the plane weights, so Q(p) / weight is a weighted mean squared distance.
#pragma once

#include <cmath>

#include "geometry/core/types.h"

namespace surfaced::simplify_detail {

struct Quadric {
    // symmetric A: a00 a01 a02 a11 a12 a22
    double a00 = 0, a01 = 0, a02 = 0, a11 = 0, a12 = 0, a22 = 0;
    double b0 = 0, b1 = 0, b2 = 0;
    double c = 0;
    double weight = 0;

    //! The plane n.p + d = 0 (n unit length) with weight w.
    static Quadric from_plane(const Vec3& n, double d, double w) {
        Quadric q;
        q.a00 = w * n.x * n.x;
        q.a01 = w * n.x * n.y;
        q.a02 = w * n.x * n.z;
        q.a11 = w * n.y * n.y;
        q.a12 = w * n.y * n.z;
        q.a22 = w * n.z * n.z;
        q.b0 = w * d * n.x;
        q.b1 = w * d * n.y;
        q.b2 = w * d * n.z;
        q.c = w * d * d;
        q.weight = w;
        return q;
    }

    Quadric& operator+=(const Quadric& o) {
        a00 += o.a00;
        a01 += o.a01;
        a02 += o.a02;
        a11 += o.a11;
        a12 += o.a12;
        a22 += o.a22;
        b0 += o.b0;
        b1 += o.b1;
        b2 += o.b2;
        c += o.c;
        weight += o.weight;
        return *this;
    }

    Vec3 apply_a(const Vec3& p) const {
        return {a00 * p.x + a01 * p.y + a02 * p.z, a01 * p.x + a11 * p.y + a12 * p.z,
                a02 * p.x + a12 * p.y + a22 * p.z};
    }

    //! Q(p); clamped at 0 (rounding can make it slightly negative).
    double error(const Vec3& p) const {
        const double e = dot(p, apply_a(p)) + 2 * (b0 * p.x + b1 * p.y + b2 * p.z) + c;
        return e > 0 ? e : 0;
    }

    //! |det A| <= kSingularDet trace(A)^3 counts as singular. Small on purpose: on a finely tessellated smooth surface
    //! the tangential eigenvalues are (edge length x curvature)^2 of the normal one, det / trace^3 about 1e-10..1e-7,
    //! and the exact minimiser there is what keeps vertices on the surface rather than on chords (the caller rejects
    //! placements far from the edge, which is what an ill-conditioned solve would produce).
    static constexpr double kSingularDet = 1e-15;

    //! Solves A x = -b: the point where Q is least. Returns false when A is (nearly) singular: flat or cylindrical
    //! regions, where the minimum is a plane or a line and the caller must pick a point on it.
    bool minimizer(Vec3& out) const { return solve({-b0, -b1, -b2}, out); }

    //! Solves A x = rhs by Cramer's rule; false when A is (nearly) singular (see kSingularDet).
    bool solve(const Vec3& rhs, Vec3& out) const {
        const double c00 = a11 * a22 - a12 * a12;
        const double c01 = a02 * a12 - a01 * a22;
        const double c02 = a01 * a12 - a02 * a11;
        const double det = a00 * c00 + a01 * c01 + a02 * c02;
        // Relative test: det scales with the cube of the matrix entries. The largest eigenvalue is <= trace, so
        // |det| <= kSingularDet trace^3 means the smallest eigenvalue is tiny compared to the largest.
        const double trace = a00 + a11 + a22;
        if (!(trace > 0) || std::fabs(det) <= kSingularDet * trace * trace * trace) return false;
        const double c11 = a00 * a22 - a02 * a02;
        const double c12 = a01 * a02 - a00 * a12;
        const double c22 = a00 * a11 - a01 * a01;
        const double inv = 1.0 / det;
        out = {inv * (c00 * rhs.x + c01 * rhs.y + c02 * rhs.z), inv * (c01 * rhs.x + c11 * rhs.y + c12 * rhs.z),
               inv * (c02 * rhs.x + c12 * rhs.y + c22 * rhs.z)};
        return is_finite(out);
    }
};

}  // namespace surfaced::simplify_detail
