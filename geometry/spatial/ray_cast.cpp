// Rays are transformed once so that the triangle test is 2D: the axis the direction is largest along becomes z, and
// a shear maps the direction to (0, 0, 1). Each vertex is then transformed the same way in every triangle it belongs
// to, and the edge functions U, V, W of two triangles sharing an edge are exact negatives of each other, so a ray
// through the edge is inside (or on) one of them. An edge function that comes out exactly zero is recomputed in long
// double, which decides between "on the edge" and "just outside" when double rounding cannot (Woop et al. fall back
// from float to double the same way). The fallback is per edge, not per triangle, so that both triangles of an edge
// always use the same precision for it.
//
// Rays walk the 8-wide float ray nodes (TriangleBvh::ray_nodes) nearest child first, their boxes tested together
// (AVX when the processor has it, SSE otherwise) with margins that cover every rounding, and each leaf's triangles
// first go through a float filter that discards only triangles the exact test would reject; the exact test then
// decides, so hits, t and barycentrics are the same as without the layout (see the comments at enter_children and
// filter_triangles). Without the layout, and for rays outside the float layout's range (an origin beyond 2^100, a
// direction whose largest component is outside [2^-100, 2^100]), rays walk the binary double-precision nodes.
//
// The double box test is the slab test with the far distance enlarged by 2 gamma(3) relative (Ize 2013), so that
// rounding in the slab distances never culls a box the ray touches; an axis the ray is parallel to is a containment
// test.
#include "geometry/spatial/ray_cast.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "geometry/spatial/ray_dispatch.h"
#include "geometry/spatial/traversal_stack.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#define SURFACED_RAY_SIMD 1
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define SURFACED_RAY_AVX 1  // an AVX box test, chosen at run time when the processor has it
#endif
#endif

namespace surfaced {

std::atomic<bool> spatial_detail::ray_avx_disabled{false};

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

bool prepare(const Ray& ray, PreparedRay& out) {
    if (!is_finite(ray.origin) || !is_finite(ray.direction)) return false;
    if (std::isnan(ray.t_min) || std::isnan(ray.t_max) || ray.t_min > ray.t_max) return false;
    const Vec3& d = ray.direction;
    const double ax = std::fabs(d.x), ay = std::fabs(d.y), az = std::fabs(d.z);
    if (!(ax > 0 || ay > 0 || az > 0)) return false;
    out.origin = ray.origin;
    out.direction = d;
    // selects rather than branches: the direction's signs and largest axis are random from one ray to the next
    const double dv[3] = {d.x, d.y, d.z};
    const int kz = ax >= ay ? (ax >= az ? 0 : 2) : (ay >= az ? 1 : 2);
    const int kx = kz == 2 ? 0 : kz + 1, ky = kx == 2 ? 0 : kx + 1;
    // keep the triangles' orientation: swap the 2D axes when the direction points down the new z
    const bool flip = dv[kz] < 0;
    out.kz = kz;
    out.kx = flip ? ky : kx;
    out.ky = flip ? kx : ky;
    const double dz = dv[kz];
    out.sx = dv[out.kx] / dz;
    out.sy = dv[out.ky] / dz;
    out.sz = 1.0 / dz;
    for (int k = 0; k < 3; ++k) {
        const double c = dv[k];
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

//! Every hit through the binary double-precision nodes (rays the float layout does not take, or no layout).
void binary_all_hits(const TriangleBvh& bvh, const PreparedRay& r, std::vector<RayHit>& hits) {
    constexpr double kMiss = std::numeric_limits<double>::infinity();
    spatial_detail::TraversalStack<Index> stack;
    if (box_entry(bvh.nodes[0].bounds, r, r.t_max) == kMiss) return;
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
}

#if SURFACED_RAY_SIMD
// ---- the 8-wide float layout (TriangleBvh::ray_nodes) ----------------------------------------------------------
//
// The eight child boxes of a node are tested at once (one AVX register, or two SSE halves), in float. Each slab
// distance is computed as (plane - origin) * (1 / d): the planes were rounded outward when the nodes were built, the
// origin is rounded towards the far side of each plane (up for a near plane, down for a far plane, swapped when
// d < 0), and the three roundings that remain (the subtraction, 1 / d to float, the product) are relative, at most
// 3 u (u = 2^-24) in all. So each computed distance is within a factor 1 +- 3u of the distance to the rounded box
// (or of the same sign and larger when it overflows to infinity). After taking the largest entry and the smallest exit over the three axes and the ray's [t_min, t_max],
// the entry is moved down and the exit up by 2^-21 relative (8u, which covers the product's own rounding) and 2^-100
// absolute (products that fall into the subnormal range): the computed [entry, exit] then contains the true one, and
// a box the ray touches is never culled. An axis the ray is parallel to (d = +-0, 1 / d = +-inf) gives +-inf, or NaN
// (0 * inf) when the origin is on a plane: a NaN is dropped by taking max(t, acc) and min(t, acc) in that order
// (SSE returns the second operand when either is NaN), which is the containment test the double path does.
// Unused child slots have min = +inf and max = -inf: their entry is +inf and their exit -inf, never a hit.
//
// A leaf's triangles go through filter_triangles, four at a time, and those it keeps through the exact
// double-precision test above, on the copies of their BvhTriangles stored beside the float blocks (the same doubles,
// read from the memory the filter just read), so hits, t and barycentrics are those of the binary path.

//! Rays whose origin or direction is outside these magnitudes take the double path (no float overflow of the
//! origin, 1 / d within float range for the largest component).
constexpr double kWideOriginLimit = 0x1p100;
constexpr double kWideDirectionMin = 0x1p-100, kWideDirectionMax = 0x1p100;

//! The next float above (below) a finite f, by its bits: no library call on the hot path.
inline float float_up(float f) {
    if (f == 0) return std::numeric_limits<float>::denorm_min();
    const auto bits = std::bit_cast<std::uint32_t>(f);
    return std::bit_cast<float>(f > 0 ? bits + 1 : bits - 1);
}
//! The float at or below x (at or above for round_up).
inline float round_down(double x) {
    const float f = static_cast<float>(x);
    return static_cast<double>(f) > x ? -float_up(-f) : f;
}
inline float round_up(double x) {
    const float f = static_cast<float>(x);
    return static_cast<double>(f) < x ? float_up(f) : f;
}
//! A float at or above a finite x within the float range, without a branch (the per-ray constants, whose rounding
//! direction is random, would mispredict): adding |f| 2^-23 + 2^-126 to the nearest float f moves it at least one
//! float up, so the sum is at or above x.
inline float bound_up(double x) {
    const float f = static_cast<float>(x);
    return f + (std::fabs(f) * 0x1p-23f + 0x1p-126f);
}

//! What the float traversal reads of a ray, as scalars that the box and triangle tests broadcast.
struct WideRay {
    float origin_near[3], origin_far[3], inv[3];
    int near_plane[3], far_plane[3];  //!< rows of RayNode::box met first and last along each axis
    float t_lo = 0;                   //!< t_min rounded down
    // the triangle filter: the origin relative to TriangleBvh::ray_centre in the order kx, ky, kz, the shear, and the
    // constants of the error bound
    int axis[3];
    float origin[3], sx, sy, bound_linear, eps;
};
constexpr float kBoundSquare = static_cast<float>(4.5 * 0x1p-24), kBoundFloor = 0x1p-120f;

//! Both forms of the ray at once, for a ray the float layout takes: the fields of PreparedRay that the exact test and
//! the hit read (computed as prepare computes them, so the exact test gives the same answers), and the WideRay.
//! False for rays outside the float range, or that prepare would refuse (non-finite, NaN or reversed [t_min, t_max],
//! zero direction): those take prepare and the binary nodes. One pass without branches on the direction's signs or
//! largest axis, which are random from one ray to the next.
inline bool prepare_wide(const Ray& ray, const Vec3& bvh_centre, double bvh_extent, PreparedRay& r, WideRay& w) {
    const double o[3] = {ray.origin.x, ray.origin.y, ray.origin.z};
    const double d[3] = {ray.direction.x, ray.direction.y, ray.direction.z};
    const double ax = std::fabs(d[0]), ay = std::fabs(d[1]), az = std::fabs(d[2]);
    // comparisons false for NaN: every component is checked on its own
    const bool in_range = (ax <= kWideDirectionMax) & (ay <= kWideDirectionMax) & (az <= kWideDirectionMax) &
                          (std::max(ax, std::max(ay, az)) >= kWideDirectionMin) &
                          (std::fabs(o[0]) <= kWideOriginLimit) & (std::fabs(o[1]) <= kWideOriginLimit) &
                          (std::fabs(o[2]) <= kWideOriginLimit) & (ray.t_min <= ray.t_max);
    if (!in_range) return false;

    // the exact test's ray, as prepare computes it, in arithmetic rather than branches
    const int x_ge_y = ax >= ay, x_ge_z = ax >= az, y_ge_z = ay >= az;
    const int kz = 2 - 2 * (x_ge_y & x_ge_z) - ((1 - x_ge_y) & y_ge_z);
    constexpr int kNext[3] = {1, 2, 0};
    const int kx = kNext[kz], ky = kNext[kx];
    const int flip = -static_cast<int>(d[kz] < 0);  // all ones when the direction points down the new z
    r.origin = ray.origin;
    r.direction = ray.direction;
    r.kz = kz;
    r.kx = kx ^ ((kx ^ ky) & flip);
    r.ky = ky ^ ((kx ^ ky) & flip);
    constexpr double kInf = std::numeric_limits<double>::infinity();
    double inv[3];
    for (int k = 0; k < 3; ++k) inv[k] = d[k] == 0 ? std::copysign(kInf, d[k]) : 1.0 / d[k];
    const double dz = d[kz];
    r.sx = d[r.kx] / dz;
    r.sy = d[r.ky] / dz;
    r.sz = inv[kz];  // 1 / dz
    r.t_min = ray.t_min;
    r.t_max = ray.t_max;

    // the box test: the origin rounded towards the far side of each plane (f + delta is bound_up; rounding to nearest
    // is symmetric, so f - delta is its mirror, a float at or below the origin)
    for (int k = 0; k < 3; ++k) {
        const int negative = std::signbit(d[k]) ? 1 : 0;
        const float f = static_cast<float>(o[k]);
        const float delta = std::fabs(f) * 0x1p-23f + 0x1p-126f;
        const float bound[2] = {f + delta, f - delta};  // indices rather than branches on the sign
        w.near_plane[k] = k + 3 * negative;
        w.far_plane[k] = k + 3 - 3 * negative;
        w.origin_near[k] = bound[negative];
        w.origin_far[k] = bound[1 - negative];
        w.inv[k] = static_cast<float>(inv[k]);
    }
    w.t_lo = round_down(ray.t_min);

    // the triangle filter
    const double rel[3] = {o[0] - bvh_centre.x, o[1] - bvh_centre.y, o[2] - bvh_centre.z};
    const double origin_extent = std::max({std::fabs(rel[0]), std::fabs(rel[1]), std::fabs(rel[2])});
    w.axis[0] = r.kx;
    w.axis[1] = r.ky;
    w.axis[2] = r.kz;
    for (int k = 0; k < 3; ++k) w.origin[k] = static_cast<float>(rel[w.axis[k]]);
    w.sx = static_cast<float>(r.sx);
    w.sy = static_cast<float>(r.sy);
    // absolute error of each sheared float coordinate (see filter_triangles), and the bound's constants
    constexpr double u = 0x1p-24;
    w.eps = bound_up(8.5 * u * (bvh_extent + origin_extent) + 0x1p-140);
    w.bound_linear = bound_up(4.5 * static_cast<double>(w.eps));
    return true;
}

//! The lanes of a block of four triangles that the exact test might hit: a bit per lane.
//!
//! The edge functions U, V, W are computed as the exact test computes them, in float from the float corners (relative
//! to ray_centre) and the float origin. Each sheared coordinate is then within eps = 8.5 u D of the exact one (u =
//! 2^-24, D = ray_extent + the origin's largest |coordinate - ray_centre|: the corners' and the origin's roundings,
//! two relative to D; the subtraction, the shear's rounding, the product and the difference, about 6 more), and the
//! double computation is within 8.5 2^-53 D of it. With m' the largest |sheared coordinate| of the triangle plus eps,
//! an edge function from either computation is within 4 m' eps + 4 u m'^2 of the exact one (two products of
//! coordinates each off by eps, and three roundings), so each is within E = 4.5 m' eps + 4.5 u m'^2 (+ 2^-120 for
//! subnormal products) of the other. A lane is discarded only when one edge function is below -E and another above
//! E: the exact test's values then have those signs too, and it rejects the triangle. Infinite or NaN values (meshes
//! beyond the float range) fail both comparisons, so the lane is kept.
inline int filter_triangles(const RayTriangles& block, const WideRay& w) {
    __m128 x[3], y[3];
    __m128 m = _mm_setzero_ps();
    const __m128 abs_mask = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
    for (int c = 0; c < 3; ++c) {
        const __m128 az = _mm_sub_ps(_mm_load_ps(block.p[3 * c + w.axis[2]]), _mm_set1_ps(w.origin[2]));
        const __m128 ax = _mm_sub_ps(_mm_load_ps(block.p[3 * c + w.axis[0]]), _mm_set1_ps(w.origin[0]));
        const __m128 ay = _mm_sub_ps(_mm_load_ps(block.p[3 * c + w.axis[1]]), _mm_set1_ps(w.origin[1]));
        x[c] = _mm_sub_ps(ax, _mm_mul_ps(_mm_set1_ps(w.sx), az));
        y[c] = _mm_sub_ps(ay, _mm_mul_ps(_mm_set1_ps(w.sy), az));
        m = _mm_max_ps(m, _mm_max_ps(_mm_and_ps(x[c], abs_mask), _mm_and_ps(y[c], abs_mask)));
    }
    const __m128 u = _mm_sub_ps(_mm_mul_ps(x[2], y[1]), _mm_mul_ps(y[2], x[1]));
    const __m128 v = _mm_sub_ps(_mm_mul_ps(x[0], y[2]), _mm_mul_ps(y[0], x[2]));
    const __m128 t = _mm_sub_ps(_mm_mul_ps(x[1], y[0]), _mm_mul_ps(y[1], x[0]));
    m = _mm_add_ps(m, _mm_set1_ps(w.eps));
    const __m128 e =
        _mm_add_ps(_mm_mul_ps(m, _mm_add_ps(_mm_set1_ps(w.bound_linear), _mm_mul_ps(_mm_set1_ps(kBoundSquare), m))),
                   _mm_set1_ps(kBoundFloor));
    const __m128 ne = _mm_sub_ps(_mm_setzero_ps(), e);
    const __m128 below = _mm_or_ps(_mm_or_ps(_mm_cmplt_ps(u, ne), _mm_cmplt_ps(v, ne)), _mm_cmplt_ps(t, ne));
    const __m128 above = _mm_or_ps(_mm_or_ps(_mm_cmpgt_ps(u, e), _mm_cmpgt_ps(v, e)), _mm_cmpgt_ps(t, e));
    return _mm_movemask_ps(_mm_andnot_ps(_mm_and_ps(below, above), _mm_castsi128_ps(_mm_set1_epi32(-1))));
}

//! The children of `node` the ray enters within [t_lo, t_hi]: a bit per child, and each child's entry distance (a
//! lower bound) in `entry`.
inline int enter_children(const RayNode& node, const WideRay& w, float t_hi, float entry[kRayNodeWidth]) {
    int mask = 0;
    const __m128 down = _mm_set1_ps(1.0f - 0x1p-21f), up = _mm_set1_ps(1.0f + 0x1p-21f), tiny = _mm_set1_ps(0x1p-100f);
    for (int h = 0; h < kRayNodeWidth; h += 4) {
        __m128 lo = _mm_set1_ps(w.t_lo), hi = _mm_set1_ps(t_hi);
        for (int k = 0; k < 3; ++k) {
            const __m128 tn =
                _mm_mul_ps(_mm_sub_ps(_mm_load_ps(node.box[w.near_plane[k]] + h), _mm_set1_ps(w.origin_near[k])),
                           _mm_set1_ps(w.inv[k]));
            const __m128 tf =
                _mm_mul_ps(_mm_sub_ps(_mm_load_ps(node.box[w.far_plane[k]] + h), _mm_set1_ps(w.origin_far[k])),
                           _mm_set1_ps(w.inv[k]));
            lo = _mm_max_ps(tn, lo);  // NaN in tn: lo
            hi = _mm_min_ps(tf, hi);
        }
        lo = _mm_sub_ps(_mm_min_ps(_mm_mul_ps(lo, down), _mm_mul_ps(lo, up)), tiny);
        hi = _mm_add_ps(_mm_max_ps(_mm_mul_ps(hi, down), _mm_mul_ps(hi, up)), tiny);
        _mm_storeu_ps(entry + h, lo);
        mask |= _mm_movemask_ps(_mm_cmple_ps(lo, hi)) << h;
    }
    return mask;
}

struct WideEntry {
    Index child;
    Index count;  //!< 0: a ray node; otherwise a leaf of `count` triangles from `child`
    float t;      //!< entry distance, a lower bound
};

//! Starts loading what an entered child will read (a node; for a leaf, its whole blocks: the float parts the filter
//! reads and the copies of the triangles the exact test reads), while its parent's other children are sorted and
//! pushed, or the nearer ones walked. Always inlined: GCC finds a function that only prefetches free of side effects
//! and drops the calls to it.
[[gnu::always_inline]] inline void prefetch(const TriangleBvh& bvh, const WideEntry& e) {
    if (e.count == 0) {
        const char* p = reinterpret_cast<const char*>(&bvh.ray_nodes[e.child]);
        for (std::size_t offset = 0; offset < sizeof(RayNode); offset += 64) _mm_prefetch(p + offset, _MM_HINT_T0);
        return;
    }
    for (Index b = e.child / 4; b <= (e.child + e.count - 1) / 4; ++b) {
        const char* p = reinterpret_cast<const char*>(&bvh.ray_triangles[b]);
        for (std::size_t offset = 0; offset < sizeof(RayTriangles); offset += 64) _mm_prefetch(p + offset, _MM_HINT_T0);
    }
}

//! Calls hit(i) for each triangle i of the leaf (triangles first .. first + count) that the filter keeps, i naming
//! ray_triangles[i / 4].triangle[i % 4] (whose copies prefetch requested with the float parts).
template <class Hit>
inline void for_leaf_candidates(const TriangleBvh& bvh, const WideRay& w, Index first, Index count, Hit&& hit) {
    const Index end = first + count;
    for (Index t = first; t < end;) {
        const Index block = t / 4, lane = t % 4, lanes_end = std::min<Index>(4, lane + (end - t));
        int lanes = filter_triangles(bvh.ray_triangles[block], w) & ((1 << lanes_end) - (1 << lane));
        while (lanes != 0) {
            hit(4 * block + static_cast<Index>(__builtin_ctz(static_cast<unsigned>(lanes))));
            lanes &= lanes - 1;
        }
        t = 4 * block + 4;
    }
}

//! The SSE box test, as a parameter of the traversals.
struct EnterSse {
    int operator()(const RayNode& node, const WideRay& w, float t_hi, float entry[kRayNodeWidth]) const {
        return enter_children(node, w, t_hi, entry);
    }
};

#if SURFACED_RAY_AVX
//! enter_children with the eight children in one AVX register: the same operations in the same order, so the same
//! bounds.
struct EnterAvx {
    __attribute__((target("avx"))) int operator()(const RayNode& node, const WideRay& w, float t_hi,
                                                  float entry[kRayNodeWidth]) const {
        static_assert(kRayNodeWidth == 8);
        __m256 lo = _mm256_set1_ps(w.t_lo), hi = _mm256_set1_ps(t_hi);
        for (int k = 0; k < 3; ++k) {
            const __m256 tn = _mm256_mul_ps(
                _mm256_sub_ps(_mm256_load_ps(node.box[w.near_plane[k]]), _mm256_broadcast_ss(&w.origin_near[k])),
                _mm256_broadcast_ss(&w.inv[k]));
            const __m256 tf = _mm256_mul_ps(
                _mm256_sub_ps(_mm256_load_ps(node.box[w.far_plane[k]]), _mm256_broadcast_ss(&w.origin_far[k])),
                _mm256_broadcast_ss(&w.inv[k]));
            lo = _mm256_max_ps(tn, lo);  // NaN in tn: lo
            hi = _mm256_min_ps(tf, hi);
        }
        const __m256 down = _mm256_set1_ps(1.0f - 0x1p-21f), up = _mm256_set1_ps(1.0f + 0x1p-21f),
                     tiny = _mm256_set1_ps(0x1p-100f);
        lo = _mm256_sub_ps(_mm256_min_ps(_mm256_mul_ps(lo, down), _mm256_mul_ps(lo, up)), tiny);
        hi = _mm256_add_ps(_mm256_max_ps(_mm256_mul_ps(hi, down), _mm256_mul_ps(hi, up)), tiny);
        _mm256_storeu_ps(entry, lo);
        return _mm256_movemask_ps(_mm256_cmp_ps(lo, hi, _CMP_LE_OQ));
    }
};
#endif

template <class Enter>
std::optional<RayHit> wide_first_hit(const TriangleBvh& bvh, const PreparedRay& r, const WideRay& w, Enter enter) {
    double best_t = r.t_max;
    float best_f = round_up(best_t);
    std::size_t best = SIZE_MAX;
    RayTriangleHit best_hit;
    spatial_detail::TraversalStack<WideEntry> stack;
    stack.push({0, 0, -std::numeric_limits<float>::infinity()});
    while (!stack.empty()) {
        WideEntry entry = stack.pop();
        if (entry.t > best_f) continue;
        for (;;) {
            if (entry.count != 0) {
                for_leaf_candidates(bvh, w, entry.child, entry.count, [&](Index i) {
                    const BvhTriangle& tri = bvh.ray_triangles[i / 4].triangle[i % 4];
                    RayTriangleHit hit;
                    if (intersect(r, tri.p[0], tri.p[1], tri.p[2], best_t, hit) &&
                        (best == SIZE_MAX || hit.t < best_t)) {
                        best_t = hit.t;
                        best = i;
                        best_hit = hit;
                        best_f = round_up(best_t);
                    }
                });
                break;
            }
            const RayNode& node = bvh.ray_nodes[entry.child];
            float t[kRayNodeWidth];
            int mask = enter(node, w, best_f, t);
            if (mask == 0) break;
            // the entered children nearest first: the nearest is walked now, the others pushed farthest first
            WideEntry hits[kRayNodeWidth];
            int size = 0;
            while (mask != 0) {
                const int k = __builtin_ctz(static_cast<unsigned>(mask));
                mask &= mask - 1;
                WideEntry e{node.child[k], node.count[k], t[k]};
                prefetch(bvh, e);
                int j = size++;
                for (; j > 0 && hits[j - 1].t < e.t; --j) hits[j] = hits[j - 1];
                hits[j] = e;
            }
            for (int j = 0; j < size - 1; ++j) stack.push(hits[j]);
            entry = hits[size - 1];
        }
    }
    if (best == SIZE_MAX) return std::nullopt;
    return make_hit(r, bvh.ray_triangles[best / 4].triangle[best % 4], best_hit);
}

template <class Enter>
void wide_all_hits(const TriangleBvh& bvh, const PreparedRay& r, const WideRay& w, Enter enter,
                   std::vector<RayHit>& hits) {
    const float t_hi = round_up(r.t_max);
    spatial_detail::TraversalStack<WideEntry> stack;
    stack.push({0, 0, 0});
    while (!stack.empty()) {
        const WideEntry entry = stack.pop();
        if (entry.count != 0) {
            for_leaf_candidates(bvh, w, entry.child, entry.count, [&](Index i) {
                const BvhTriangle& tri = bvh.ray_triangles[i / 4].triangle[i % 4];
                RayTriangleHit hit;
                if (intersect(r, tri.p[0], tri.p[1], tri.p[2], r.t_max, hit)) hits.push_back(make_hit(r, tri, hit));
            });
            continue;
        }
        const RayNode& node = bvh.ray_nodes[entry.child];
        float t[kRayNodeWidth];
        int mask = enter(node, w, t_hi, t);
        while (mask != 0) {
            const int k = __builtin_ctz(static_cast<unsigned>(mask));
            mask &= mask - 1;
            stack.push({node.child[k], node.count[k], t[k]});
        }
    }
}

#if SURFACED_RAY_AVX
// The traversals compiled for AVX (flatten inlines them and the box test into these bodies), and the choice.
__attribute__((target("avx"), flatten)) std::optional<RayHit> wide_first_hit_avx(const TriangleBvh& bvh,
                                                                                 const PreparedRay& r,
                                                                                 const WideRay& w) {
    return wide_first_hit(bvh, r, w, EnterAvx{});
}
__attribute__((target("avx"), flatten)) void wide_all_hits_avx(const TriangleBvh& bvh, const PreparedRay& r,
                                                               const WideRay& w, std::vector<RayHit>& hits) {
    wide_all_hits(bvh, r, w, EnterAvx{}, hits);
}
bool has_avx() {
    static const bool avx = __builtin_cpu_supports("avx");
    return avx && !spatial_detail::ray_avx_disabled.load(std::memory_order_relaxed);
}
#endif

std::optional<RayHit> wide_first_hit(const TriangleBvh& bvh, const PreparedRay& r, const WideRay& w) {
#if SURFACED_RAY_AVX
    if (has_avx()) return wide_first_hit_avx(bvh, r, w);
#endif
    return wide_first_hit(bvh, r, w, EnterSse{});
}
void wide_all_hits(const TriangleBvh& bvh, const PreparedRay& r, const WideRay& w, std::vector<RayHit>& hits) {
#if SURFACED_RAY_AVX
    if (has_avx()) return wide_all_hits_avx(bvh, r, w, hits);
#endif
    wide_all_hits(bvh, r, w, EnterSse{}, hits);
}
#endif

}  // namespace

std::optional<RayTriangleHit> ray_triangle(const Ray& ray, const Vec3& a, const Vec3& b, const Vec3& c) {
    PreparedRay r;
    if (!prepare(ray, r)) return std::nullopt;
    RayTriangleHit hit;
    if (!intersect(r, a, b, c, r.t_max, hit)) return std::nullopt;
    return hit;
}

std::optional<RayHit> ray_first_hit(const TriangleBvh& bvh, const Ray& ray) {
    if (bvh.empty()) return std::nullopt;
    PreparedRay r;
#if SURFACED_RAY_SIMD
    if (WideRay w; !bvh.ray_nodes.empty() && prepare_wide(ray, bvh.ray_centre, bvh.ray_extent, r, w))
        return wide_first_hit(bvh, r, w);
#endif
    if (!prepare(ray, r)) return std::nullopt;
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
    if (bvh.empty()) return hits;
    PreparedRay r;
#if SURFACED_RAY_SIMD
    if (WideRay w; !bvh.ray_nodes.empty() && prepare_wide(ray, bvh.ray_centre, bvh.ray_extent, r, w))
        wide_all_hits(bvh, r, w, hits);
    else if (prepare(ray, r))
        binary_all_hits(bvh, r, hits);
#else
    if (prepare(ray, r)) binary_all_hits(bvh, r, hits);
#endif
    std::sort(hits.begin(), hits.end(),
              [](const RayHit& x, const RayHit& y) { return x.t < y.t || (x.t == y.t && x.face < y.face); });
    return hits;
}

}  // namespace surfaced
