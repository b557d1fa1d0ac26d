// Rays are transformed once so that the triangle test is 2D: the axis the direction is largest along becomes z, and
// a shear maps the direction to (0, 0, 1). Each vertex is then transformed the same way in every triangle it belongs
// to, and the edge functions U, V, W of two triangles sharing an edge are exact negatives of each other, so a ray
// through the edge is inside (or on) one of them. An edge function that comes out exactly zero is recomputed in long
// double, which decides between "on the edge" and "just outside" when double rounding cannot (Woop et al. fall back
// from float to double the same way). The fallback is per edge, not per triangle, so that both triangles of an edge
// always use the same precision for it.
//
// The box test is the slab test with the far distance enlarged by 2 gamma(3) relative (Ize 2013), so that rounding
// in the slab distances never culls a box the ray touches; an axis the ray is parallel to is a containment test.
#include "geometry/spatial/ray_cast.h"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <cmath>
#include <cstring>

#include "geometry/spatial/traversal_stack.h"

namespace surfaced {

namespace {

//! The ray in the form the watertight test needs (Woop et al. sec. 3), plus what the slab test needs.
struct PreparedRay {
    Vec3 origin;
    Vec3 direction;
    int kx = 0, ky = 1, kz = 2;
    double sx = 0, sy = 0, sz = 0;
    Vec3 inv;                                  //!< 1 / direction (0 where the direction is 0)
    bool parallel[3] = {false, false, false};  //!< direction component exactly 0
    bool negative[3] = {false, false, false};  //!< direction component < 0: the box's max plane is met first
    double t_min = 0, t_max = 0;
};

double component(const Vec3& v, int k) { return k == 0 ? v.x : (k == 1 ? v.y : v.z); }

bool prepare(const Ray& ray, PreparedRay& out) {
    if (!is_finite(ray.origin) || !is_finite(ray.direction)) return false;
    if (std::isnan(ray.t_min) || std::isnan(ray.t_max) || ray.t_min > ray.t_max) return false;
    const Vec3& d = ray.direction;
    const double ax = std::fabs(d.x), ay = std::fabs(d.y), az = std::fabs(d.z);
    if (!(ax > 0 || ay > 0 || az > 0)) return false;
    out.origin = ray.origin;
    out.direction = d;
    out.kz = ax >= ay ? (ax >= az ? 0 : 2) : (ay >= az ? 1 : 2);
    out.kx = (out.kz + 1) % 3;
    out.ky = (out.kx + 1) % 3;
    // keep the triangles' orientation: swap the 2D axes when the direction points down the new z
    if (component(d, out.kz) < 0) std::swap(out.kx, out.ky);
    const double dz = component(d, out.kz);
    out.sx = component(d, out.kx) / dz;
    out.sy = component(d, out.ky) / dz;
    out.sz = 1.0 / dz;
    for (int k = 0; k < 3; ++k) {
        const double c = component(d, k);
        out.parallel[k] = c == 0;
        out.negative[k] = c < 0;
        (k == 0 ? out.inv.x : (k == 1 ? out.inv.y : out.inv.z)) = c == 0 ? 0.0 : 1.0 / c;
    }
    out.t_min = ray.t_min;
    out.t_max = ray.t_max;
    return true;
}

//! One slab of the box test: narrows [lo, hi] to where the ray is between the two planes (near and far chosen once
//! per ray by the direction's sign). An axis the ray is parallel to is all or nothing (a division would make
//! 0 * inf = NaN when the origin is on a plane).
inline bool slab(double box_min, double box_max, double origin, double inv, bool negative, bool parallel, double& lo,
                 double& hi) {
    constexpr double kEps = std::numeric_limits<double>::epsilon() * 0.5;
    constexpr double kGrow = 1.0 + 2.0 * (3 * kEps) / (1 - 3 * kEps);  // Ize's 1 + 2 gamma(3)
    if (parallel) return origin >= box_min && origin <= box_max;
    const double t0 = ((negative ? box_max : box_min) - origin) * inv;
    const double t1 = ((negative ? box_min : box_max) - origin) * inv;
    // t1 < 0 means the box is behind: growing it towards 0 would only be less conservative, and it is culled anyway
    const double far = t1 * kGrow;
    lo = t0 > lo ? t0 : lo;
    hi = far < hi ? far : hi;
    return true;
}

//! Entry distance of the ray into the box, or +infinity when it misses it within [t_min, t_max].
inline double box_entry(const Box3& b, const PreparedRay& r, double t_max) {
    double lo = r.t_min, hi = t_max;
    if (!slab(b.min.x, b.max.x, r.origin.x, r.inv.x, r.negative[0], r.parallel[0], lo, hi) ||
        !slab(b.min.y, b.max.y, r.origin.y, r.inv.y, r.negative[1], r.parallel[1], lo, hi) ||
        !slab(b.min.z, b.max.z, r.origin.z, r.inv.z, r.negative[2], r.parallel[2], lo, hi))
        return std::numeric_limits<double>::infinity();
    return lo <= hi ? lo : std::numeric_limits<double>::infinity();
}

//! The edge function of the 2D edge (p, q) at the origin; a zero is recomputed in long double. The value depends only
//! on the edge's two transformed vertices and is negated exactly when they are swapped, so two triangles sharing the
//! edge always see opposite signs (or both zero).
inline double edge_function(double px, double py, double qx, double qy) {
    const double e = px * qy - py * qx;
    if (e != 0) return e;
    using L = long double;
    return static_cast<double>(L(px) * L(qy) - L(py) * L(qx));
}

//! The watertight test; t in [t_min, t_max].
inline bool intersect(const PreparedRay& r, const Vec3& a, const Vec3& b, const Vec3& c, double t_max,
                      RayTriangleHit& hit) {
    // vertices relative to the origin as arrays, so the per-ray axis permutation is an index (memcpy: Vec3 is three
    // doubles, and this is the defined way to view it as an array)
    double A[3], B[3], C[3];
    const Vec3 da = a - r.origin, db = b - r.origin, dc = c - r.origin;
    static_assert(sizeof(Vec3) == sizeof A);
    std::memcpy(A, &da, sizeof A);
    std::memcpy(B, &db, sizeof B);
    std::memcpy(C, &dc, sizeof C);
    const double az = A[r.kz], bz = B[r.kz], cz = C[r.kz];
    const double ax = A[r.kx] - r.sx * az, ay = A[r.ky] - r.sy * az;
    const double bx = B[r.kx] - r.sx * bz, by = B[r.ky] - r.sy * bz;
    const double cx = C[r.kx] - r.sx * cz, cy = C[r.ky] - r.sy * cz;
    const double u = edge_function(cx, cy, bx, by);  // edge b-c, weight of a
    const double v = edge_function(ax, ay, cx, cy);  // edge c-a, weight of b
    if ((u < 0 && v > 0) || (u > 0 && v < 0)) return false;
    const double w = edge_function(bx, by, ax, ay);  // edge a-b, weight of c
    if ((u < 0 || v < 0 || w < 0) && (u > 0 || v > 0 || w > 0)) return false;
    const double det = u + v + w;
    if (det == 0) return false;
    const double t = (u * r.sz * az + v * r.sz * bz + w * r.sz * cz) / det;
    if (!(t >= r.t_min && t <= t_max)) return false;
    hit.t = t;
    hit.barycentric = {u / det, v / det, w / det};
    return true;
}

RayHit make_hit(const PreparedRay& r, const BvhTriangle& tri, const RayTriangleHit& h) {
    RayHit out;
    out.t = h.t;
    out.point = r.origin + r.direction * h.t;
    const Vec3 n = cross(tri.p[1] - tri.p[0], tri.p[2] - tri.p[0]);
    const double len = norm(n);
    out.normal = len > 0 ? n * (1.0 / len) : Vec3{};
    out.face = tri.face;
    out.vertices = tri.vertices;
    out.barycentric = h.barycentric;
    return out;
}

struct StackEntry {
    Index node;
    double t;
};

}  // namespace

std::optional<RayTriangleHit> ray_triangle(const Ray& ray, const Vec3& a, const Vec3& b, const Vec3& c) {
    PreparedRay r;
    if (!prepare(ray, r)) return std::nullopt;
    RayTriangleHit hit;
    if (!intersect(r, a, b, c, r.t_max, hit)) return std::nullopt;
    return hit;
}

std::optional<RayHit> ray_first_hit(const TriangleBvh& bvh, const Ray& ray) {
    PreparedRay r;
    if (bvh.empty() || !prepare(ray, r)) return std::nullopt;
    double best_t = r.t_max;
    std::size_t best = SIZE_MAX;
    RayTriangleHit best_hit;

    spatial_detail::TraversalStack<StackEntry> stack;
    const double root_t = box_entry(bvh.nodes[0].bounds, r, best_t);
    if (root_t == std::numeric_limits<double>::infinity()) return std::nullopt;
    stack.push({0, root_t});
    while (!stack.empty()) {
        StackEntry entry = stack.pop();
        if (entry.t > best_t) continue;
        for (;;) {
            const BvhNode& node = bvh.nodes[entry.node];
            if (node.is_leaf()) {
                for (Index i = node.index; i < node.index + node.count; ++i) {
                    const BvhTriangle& tri = bvh.triangles[i];
                    RayTriangleHit hit;
                    if (intersect(r, tri.p[0], tri.p[1], tri.p[2], best_t, hit) &&
                        (best == SIZE_MAX || hit.t < best_t)) {
                        best_t = hit.t;
                        best = i;
                        best_hit = hit;
                    }
                }
                break;
            }
            const Index left = entry.node + 1, right = node.index;
            const double tl = box_entry(bvh.nodes[left].bounds, r, best_t);
            const double tr = box_entry(bvh.nodes[right].bounds, r, best_t);
            constexpr double kMiss = std::numeric_limits<double>::infinity();
            if (tl == kMiss && tr == kMiss) break;
            if (tl == kMiss || tr == kMiss) {
                entry = {tl == kMiss ? right : left, std::min(tl, tr)};
                continue;
            }
            const bool left_first = tl <= tr;
            stack.push({left_first ? right : left, left_first ? tr : tl});
            entry = {left_first ? left : right, left_first ? tl : tr};
        }
    }
    if (best == SIZE_MAX) return std::nullopt;
    return make_hit(r, bvh.triangles[best], best_hit);
}

std::vector<RayHit> ray_all_hits(const TriangleBvh& bvh, const Ray& ray) {
    std::vector<RayHit> hits;
    PreparedRay r;
    if (bvh.empty() || !prepare(ray, r)) return hits;
    constexpr double kMiss = std::numeric_limits<double>::infinity();
    spatial_detail::TraversalStack<Index> stack;
    if (box_entry(bvh.nodes[0].bounds, r, r.t_max) == kMiss) return hits;
    stack.push(0);
    while (!stack.empty()) {
        const BvhNode& node = bvh.nodes[stack.pop()];
        if (node.is_leaf()) {
            for (Index i = node.index; i < node.index + node.count; ++i) {
                const BvhTriangle& tri = bvh.triangles[i];
                RayTriangleHit hit;
                if (intersect(r, tri.p[0], tri.p[1], tri.p[2], r.t_max, hit)) hits.push_back(make_hit(r, tri, hit));
            }
            continue;
        }
        const Index self = static_cast<Index>(&node - bvh.nodes.data());
        if (box_entry(bvh.nodes[self + 1].bounds, r, r.t_max) != kMiss) stack.push(self + 1);
        if (box_entry(bvh.nodes[node.index].bounds, r, r.t_max) != kMiss) stack.push(node.index);
    }
    std::sort(hits.begin(), hits.end(),
              [](const RayHit& x, const RayHit& y) { return x.t < y.t || (x.t == y.t && x.face < y.face); });
    return hits;
}

}  // namespace surfaced
