#include "geometry/spatial/closest_point.h"

#include <cmath>
#include <cstdint>

#include "geometry/spatial/traversal_stack.h"

namespace surfaced {

namespace {

//! Closest point of segment [a, b] to p as the parameter along it (0 for a point-like segment).
double segment_parameter(const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 ab = b - a;
    const double len2 = dot(ab, ab);
    if (!(len2 > 0)) return 0.0;
    const double t = dot(p - a, ab) / len2;
    return t < 0 ? 0.0 : (t > 1 ? 1.0 : t);
}

//! Nearest of the three edges: what is left of a triangle without area.
TrianglePoint degenerate_closest(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const std::array<const Vec3*, 3> v{&a, &b, &c};
    TrianglePoint best;
    double best_d2 = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < 3; ++i) {
        const std::size_t j = (i + 1) % 3;
        const double t = segment_parameter(p, *v[i], *v[j]);
        const Vec3 q = *v[i] + (*v[j] - *v[i]) * t;
        const Vec3 d = p - q;
        if (dot(d, d) < best_d2) {
            best_d2 = dot(d, d);
            best.point = q;
            best.barycentric = {0, 0, 0};
            best.barycentric[i] = 1 - t;
            best.barycentric[j] = t;
        }
    }
    return best;
}

struct StackEntry {
    Index node;
    double d2;
};

}  // namespace

TrianglePoint triangle_closest_point(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    // The region of p is found from the signs of dot products with the edge vectors; each edge's denominator is its
    // squared length, so a zero-length edge or a zero-area triangle goes to degenerate_closest instead of dividing
    // by zero.
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return {a, {1, 0, 0}};
    const Vec3 bp = p - b;
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return {b, {0, 1, 0}};
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        if (!(d1 - d3 > 0)) return degenerate_closest(p, a, b, c);
        const double v = d1 / (d1 - d3);
        return {a + ab * v, {1 - v, v, 0}};
    }
    const Vec3 cp = p - c;
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return {c, {0, 0, 1}};
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        if (!(d2 - d6 > 0)) return degenerate_closest(p, a, b, c);
        const double w = d2 / (d2 - d6);
        return {a + ac * w, {1 - w, 0, w}};
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
        const double den = (d4 - d3) + (d5 - d6);
        if (!(den > 0)) return degenerate_closest(p, a, b, c);
        const double w = (d4 - d3) / den;
        return {b + (c - b) * w, {0, 1 - w, w}};
    }
    // va + vb + vc = |ab x ac|^2; when it is lost in the rounding of its terms (corners collinear to about 1e-6
    // radians) the division below is meaningless, and the nearest edge is within the triangle's width of the answer
    const double sum = va + vb + vc;
    if (!(sum > 1e-12 * dot(ab, ab) * dot(ac, ac)) || !std::isfinite(sum)) return degenerate_closest(p, a, b, c);
    const double v = vb / sum, w = vc / sum;
    return {a + ab * v + ac * w, {1 - v - w, v, w}};
}

std::optional<SurfacePoint> closest_point(const TriangleBvh& bvh, const Vec3& query,
                                          const ClosestPointOptions& options) {
    if (bvh.empty() || !is_finite(query) || std::isnan(options.max_distance) || options.max_distance < 0)
        return std::nullopt;
    double best_d2 = options.max_distance * options.max_distance;
    std::size_t best = SIZE_MAX;
    TrianglePoint best_point;

    spatial_detail::TraversalStack<StackEntry> stack;
    stack.push({0, squared_distance(bvh.nodes[0].bounds, query)});
    while (!stack.empty()) {
        StackEntry entry = stack.pop();
        if (entry.d2 > best_d2) continue;
        for (;;) {
            const BvhNode& node = bvh.nodes[entry.node];
            if (node.is_leaf()) {
                for (Index i = node.index; i < node.index + node.count; ++i) {
                    const BvhTriangle& t = bvh.triangles[i];
                    const TrianglePoint tp = triangle_closest_point(query, t.p[0], t.p[1], t.p[2]);
                    const Vec3 d = tp.point - query;
                    const double d2 = dot(d, d);
                    if (d2 < best_d2 || (best == SIZE_MAX && d2 <= best_d2)) {
                        best_d2 = d2;
                        best = i;
                        best_point = tp;
                    }
                }
                break;
            }
            const Index left = entry.node + 1, right = node.index;
            const double dl = squared_distance(bvh.nodes[left].bounds, query);
            const double dr = squared_distance(bvh.nodes[right].bounds, query);
            const bool left_first = dl <= dr;
            const Index near = left_first ? left : right, far = left_first ? right : left;
            const double dn = left_first ? dl : dr, df = left_first ? dr : dl;
            if (df <= best_d2) stack.push({far, df});
            if (dn > best_d2) break;
            entry = {near, dn};
        }
    }
    if (best == SIZE_MAX) return std::nullopt;
    const BvhTriangle& t = bvh.triangles[best];
    SurfacePoint out;
    out.point = best_point.point;
    out.distance = std::sqrt(best_d2);
    out.face = t.face;
    out.vertices = t.vertices;
    out.barycentric = best_point.barycentric;
    return out;
}

}  // namespace surfaced
