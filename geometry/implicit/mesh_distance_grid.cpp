// Mesh -> narrow-band signed distance grid (see distance_grid.h): per-triangle distance scatter, crossing marks,
// signs by connected components and winding numbers.
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "geometry/implicit/distance_grid.h"
#include "geometry/spatial/bvh.h"
#include "geometry/mesh/triangulate.h"
#include "geometry/spatial/closest_point.h"

namespace surfaced::implicit {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
//! Triangles scattered between two looks at the Cancel.
constexpr std::size_t kTriangleBatch = 256;
//! Nodes popped by the flood fill between two looks at the Cancel.
constexpr std::size_t kFillBatch = std::size_t{1} << 16;
//! Winding numbers summed directly over the triangles before the hierarchy is built for the rest.
constexpr std::uint64_t kDirectQueries = 16;
//! Open meshes: allowance for the hierarchy's error in a winding number (about 5e-3 at most at accuracy 2) when a
//! bound on how far w can drift along a run is compared with its distance from 1/2.
constexpr double kWindingMargin = 0.02;
//! Open meshes: a run whose two ends have winding numbers at least this far from 1/2, on one side, takes that side.
constexpr double kConfident = 0.25;
//! Bit of the per-node marks (beside the three crossing bits): within the band of a boundary edge.
constexpr std::uint8_t kNearBoundary = 8;
//! Boundary edges per cluster of the drift bound.
constexpr std::size_t kClusterEdges = 8;

struct Grid {
    std::size_t n[3];
    std::size_t stride[3];
    Vec3 origin;
    double h;
    std::size_t nodes;
    double inv_h;

    Vec3 position(std::size_t i, std::size_t j, std::size_t k) const {
        return {origin.x + static_cast<double>(i) * h, origin.y + static_cast<double>(j) * h,
                origin.z + static_cast<double>(k) * h};
    }
    //! Node index range [lo, hi] along axis a covering coordinates [from, to]; false when empty.
    bool range(int a, double from, double to, std::size_t& lo, std::size_t& hi) const {
        const double last = static_cast<double>(n[a] - 1);
        const double l = std::max(0.0, std::ceil((from - origin[a]) / h));
        const double u = std::min(last, std::floor((to - origin[a]) / h));
        if (!(l <= u)) return false;
        lo = static_cast<std::size_t>(l);
        hi = static_cast<std::size_t>(u);
        return true;
    }
    //! Narrows [lo, hi] to the nodes along axis a at coordinates in [from, to]; false when none is left. A
    //! multiplication for the division, and conversions for ceil and floor: callers widen [from, to] by far more than
    //! the difference.
    bool clip(int a, double from, double to, std::size_t& lo, std::size_t& hi) const {
        const double f = (from - origin[a]) * inv_h, t = (to - origin[a]) * inv_h;
        if (!(f <= t)) return false;
        if (f > static_cast<double>(lo)) {
            if (f > static_cast<double>(hi)) return false;
            auto i = static_cast<std::size_t>(f);
            lo = static_cast<double>(i) < f ? i + 1 : i;
        }
        if (t < static_cast<double>(hi)) {
            if (t < static_cast<double>(lo)) return false;
            hi = static_cast<std::size_t>(t);
        }
        return lo <= hi;
    }
};

//! Squared distance from p to triangle t: triangle_closest_point's regions (Ericson) inlined, with its fallback for
//! the degenerate cases, so that the values equal its answers.
inline double triangle_distance2(const Vec3& p, const BvhTriangle& t) {
    const Vec3 &a = t.p[0], &b = t.p[1], &c = t.p[2];
    const auto general = [&] {
        const Vec3 q = triangle_closest_point(p, a, b, c).point - p;
        return dot(q, q);
    };
    const auto d2 = [&](const Vec3& q) { return dot(q - p, q - p); };
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = dot(ab, ap), e2 = dot(ac, ap);
    if (d1 <= 0 && e2 <= 0) return d2(a);
    const Vec3 bp = p - b;
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return d2(b);
    const double vc = d1 * d4 - d3 * e2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        if (!(d1 - d3 > 0)) return general();
        return d2(a + ab * (d1 / (d1 - d3)));
    }
    const Vec3 cp = p - c;
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return d2(c);
    const double vb = d5 * e2 - d1 * d6;
    if (vb <= 0 && e2 >= 0 && d6 <= 0) {
        if (!(e2 - d6 > 0)) return general();
        return d2(a + ac * (e2 / (e2 - d6)));
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
        const double den = (d4 - d3) + (d5 - d6);
        if (!(den > 0)) return general();
        return d2(b + (c - b) * ((d4 - d3) / den));
    }
    const double sum = va + vb + vc;
    if (!(sum > 1e-12 * dot(ab, ab) * dot(ac, ac)) || !std::isfinite(sum)) return general();
    return d2(a + ab * (vb / sum) + ac * (vc / sum));
}

//! The triangle projected along one axis, as 2D points (u, v), set up for many distance queries.
struct Triangle2d {
    double pu[3], pv[3], eu[3], ev[3], inv_len2[3];
    Triangle2d(const BvhTriangle& t, int u, int v) {
        for (int k = 0; k < 3; ++k) {
            pu[k] = t.p[k][u];
            pv[k] = t.p[k][v];
        }
        for (int k = 0; k < 3; ++k) {
            const int l = k == 2 ? 0 : k + 1;
            eu[k] = pu[l] - pu[k];
            ev[k] = pv[l] - pv[k];
            const double len2 = eu[k] * eu[k] + ev[k] * ev[k];
            inv_len2[k] = len2 > 0 ? 1.0 / len2 : 0.0;
        }
    }
    //! Squared distance from (qu, qv): 0 inside, else to the nearest edge.
    double distance2(double qu, double qv) const {
        double e[3], best = kInf;
        for (int k = 0; k < 3; ++k) {
            const double wu = qu - pu[k], wv = qv - pv[k];
            e[k] = eu[k] * wv - ev[k] * wu;
            const double s = std::clamp((eu[k] * wu + ev[k] * wv) * inv_len2[k], 0.0, 1.0);
            const double du = wu - s * eu[k], dv = wv - s * ev[k];
            best = std::min(best, du * du + dv * dv);
        }
        if ((e[0] >= 0 && e[1] >= 0 && e[2] >= 0) || (e[0] <= 0 && e[1] <= 0 && e[2] <= 0)) return 0;
        return best;
    }
};

//! Keeps, per node, the minimum squared distance to the triangle over the nodes within `radius` of it: the nodes of
//! its box grown by radius, and along the axis m its normal is closest to only those within radius of its plane.
//! A node is sent to the exact distance only when two lower bounds do not already put it beyond its best: the
//! distance to the triangle's plane, and the prism bound. The prism bound: with q the triangle's point nearest to p,
//! |p - q|^2 = |(p - q) across m|^2 + (p_m - q_m)^2, where the first is at least the squared distance `column2`
//! from p's column to the triangle projected along m (one value per column) and the second at least the squared
//! distance from p_m to the triangle's extent along m (for a triangle no wider than a voxel, `column2` is taken from
//! the projection's box, which is cheaper and nearly as tight). It also bounds which rows, columns and nodes of a
//! column are visited at all.
//! Both bounds are compared with a relative and an absolute allowance that cover their rounding, so a node is
//! skipped only when the exact distance would not lower its value: the result is the minimum over all triangles.
void scatter_triangle(const Grid& g, const BvhTriangle& t, double radius, double* d2) {
    Box3 box;
    for (const Vec3& p : t.p) box.add(p);
    const double r2 = radius * radius;
    std::size_t lo[3], hi[3];
    const double diagonal = box.diagonal();
    // widened by a little so that rounding in the intervals never drops a node within radius
    const double widen = 1e-9 * (radius + diagonal);
    for (int a = 0; a < 3; ++a) {
        lo[a] = 0;
        hi[a] = g.n[a] - 1;
        if (!g.clip(a, box.min[a] - radius - widen, box.max[a] + radius + widen, lo[a], hi[a])) return;
    }
    const Vec3 normal = cross(t.p[1] - t.p[0], t.p[2] - t.p[0]);
    const double length = norm(normal);
    // m: the innermost axis, restricted to the plane's slab when the triangle has a usable normal
    int m = 0;
    for (int a = 1; a < 3; ++a)
        if (std::abs(normal[a]) > std::abs(normal[m])) m = a;
    const int u = (m + 1) % 3, v = (m + 2) % 3;
    const bool slab = length > 0 && std::isfinite(length) && std::abs(normal[m]) > 1e-3 * length;
    const Vec3 n = slab ? normal * (1.0 / length) : Vec3{};
    const double plane = dot(n, t.p[0]);
    const double inv_nm = slab ? 1.0 / n[m] : 0.0;
    const double reach = (radius + widen) / (slab ? std::abs(n[m]) : 1.0);
    // rounding allowance of the squared lower bounds: relative, and absolute for values near 0 (scale: the largest
    // coordinate magnitude involved)
    double scale = radius;
    for (int a = 0; a < 3; ++a)
        scale = std::max({scale, std::abs(box.min[a]) + radius, std::abs(box.max[a]) + radius, std::abs(g.origin[a])});
    const double absolute = 1e-20 * scale * scale;
    const auto beyond = [&](double bound2, double best) { return bound2 * (1 - 1e-9) - absolute > best; };
    // the triangle projected along m: a column farther than radius from it (projection never lengthens a
    // distance) has no node within radius. Its distance from a column is at least that from the projection's box
    // (the rows and columns are bounded by that first), and is computed exactly only for a triangle wider than a
    // voxel, where it is much the larger.
    const Triangle2d projected(t, u, v);
    const bool wide = std::max(box.max[u] - box.min[u], box.max[v] - box.min[v]) > g.h;
    const double column_reach2 = r2 * (1 + 1e-9) + 1e-18 * diagonal * diagonal + absolute;
    const double mmin = box.min[m], mmax = box.max[m];
    const auto outside = [](double x, double from, double to) { return std::max({from - x, x - to, 0.0}); };
    Vec3 p;
    for (std::size_t b = lo[v]; b <= hi[v]; ++b) {
        p[v] = g.origin[v] + static_cast<double>(b) * g.h;
        const double dv = outside(p[v], box.min[v], box.max[v]), dv2 = dv * dv;
        if (dv2 > column_reach2) continue;
        const double across = std::sqrt(column_reach2 - dv2) + widen;
        std::size_t clo = lo[u], chi = hi[u];
        if (!g.clip(u, box.min[u] - across, box.max[u] + across, clo, chi)) continue;
        for (std::size_t c = clo; c <= chi; ++c) {
            p[u] = g.origin[u] + static_cast<double>(c) * g.h;
            const double du = outside(p[u], box.min[u], box.max[u]);
            double column2 = dv2 + du * du;
            if (wide) column2 = std::max(column2, projected.distance2(p[u], p[v]));
            if (column2 > column_reach2) continue;
            // the prism bound within radius: p_m within `along` of [mmin, mmax]; and the plane's slab
            const double along = std::sqrt(column_reach2 - column2) + widen;
            double from = mmin - along, to = mmax + along;
            if (slab) {
                // n . p = plane +- radius solved for p[m]
                const double middle = (plane - n[u] * p[u] - n[v] * p[v]) * inv_nm;
                from = std::max(from, middle - reach);
                to = std::min(to, middle + reach);
            }
            std::size_t first = lo[m], last = hi[m];
            if (!g.clip(m, from, to, first, last)) continue;
            std::size_t index = c * g.stride[u] + b * g.stride[v] + first * g.stride[m];
            for (std::size_t a = first; a <= last; ++a, index += g.stride[m]) {
                p[m] = g.origin[m] + static_cast<double>(a) * g.h;
                const double best = std::min(d2[index], r2);
                const double dm = outside(p[m], mmin, mmax);
                if (beyond(column2 + dm * dm, best)) continue;
                if (slab) {
                    const double plane_distance = dot(n, p) - plane;
                    if (beyond(plane_distance * plane_distance, best)) continue;
                }
                const double dist2 = triangle_distance2(p, t);
                if (dist2 <= r2 && dist2 < d2[index]) d2[index] = dist2;
            }
        }
    }
}

//! Marks, in bit a of blocked[node], the grid edges from node to node + 1 along a that the triangle crosses. The
//! test is inclusive with a tolerance, and a crossing within rounding of an edge's end blocks the edges on both
//! sides of that node, so a crossing is never missed (blocking more edges only makes more components).
void mark_crossings(const Grid& g, const BvhTriangle& t, std::uint8_t* blocked) {
    const Vec3 normal = cross(t.p[1] - t.p[0], t.p[2] - t.p[0]);
    const double plane = dot(normal, t.p[0]);
    for (int a = 0; a < 3; ++a) {
        const int u = (a + 1) % 3, v = (a + 2) % 3;
        if (normal[a] == 0) continue;  // parallel to the lines along a: its neighbours' crossings close it
        // the triangle projected along a, as 2D points (u, v), counter-clockwise or not
        double pu[3], pv[3], umin = kInf, umax = -kInf, vmin = kInf, vmax = -kInf, scale = 0;
        for (int k = 0; k < 3; ++k) {
            pu[k] = t.p[k][u];
            pv[k] = t.p[k][v];
            umin = std::min(umin, pu[k]);
            umax = std::max(umax, pu[k]);
            vmin = std::min(vmin, pv[k]);
            vmax = std::max(vmax, pv[k]);
        }
        scale = std::max(umax - umin, vmax - vmin);
        const double tolerance = 1e-9 * scale;
        std::size_t ulo, uhi, vlo, vhi;
        if (!g.range(u, umin - tolerance, umax + tolerance, ulo, uhi)) continue;
        if (!g.range(v, vmin - tolerance, vmax + tolerance, vlo, vhi)) continue;
        const double area_tolerance = 1e-9 * scale * scale;
        for (std::size_t jv = vlo; jv <= vhi; ++jv) {
            const double qv = g.origin[v] + static_cast<double>(jv) * g.h;
            for (std::size_t ju = ulo; ju <= uhi; ++ju) {
                const double qu = g.origin[u] + static_cast<double>(ju) * g.h;
                double e[3];
                for (int k = 0; k < 3; ++k) {
                    const int l = (k + 1) % 3;
                    e[k] = (pu[l] - pu[k]) * (qv - pv[k]) - (pv[l] - pv[k]) * (qu - pu[k]);
                }
                const bool inside = (e[0] >= -area_tolerance && e[1] >= -area_tolerance && e[2] >= -area_tolerance) ||
                                    (e[0] <= area_tolerance && e[1] <= area_tolerance && e[2] <= area_tolerance);
                if (!inside) continue;
                // where the line meets the plane, in node units along a
                const double at = (plane - normal[u] * qu - normal[v] * qv) / normal[a];
                const double s = (at - g.origin[a]) / g.h;
                const double last = static_cast<double>(g.n[a] - 1);
                constexpr double kEnd = 1e-7;  // node units: a crossing this close to a node touches both its edges
                if (!(s >= -kEnd && s <= last + kEnd)) continue;
                const std::size_t base = ju * g.stride[u] + jv * g.stride[v];
                const double cell = std::clamp(std::floor(s), 0.0, last);
                const auto i = static_cast<std::size_t>(cell);
                const auto bit = static_cast<std::uint8_t>(1u << a);
                if (i + 1 < g.n[a]) blocked[base + i * g.stride[a]] |= bit;
                const double frac = s - cell;
                if (frac < kEnd && i > 0) blocked[base + (i - 1) * g.stride[a]] |= bit;
                if (frac > 1 - kEnd && i + 2 < g.n[a]) blocked[base + (i + 1) * g.stride[a]] |= bit;
            }
        }
    }
}

//! The edges where the surface has a boundary: those not matched by their reverse as often (vertices at equal
//! positions counting as one), each as many times as it is unmatched. None for a closed surface, whose winding
//! number is constant off it on each region.
std::vector<std::array<Vec3, 2>> boundary_edges(const std::vector<BvhTriangle>& triangles) {
    // open addressing, linear probing: tables of at least twice the corners, so probes stay short
    std::size_t size = 16;
    while (size < 6 * triangles.size()) size *= 2;
    const int shift = 64 - std::countr_zero(size);
    const auto slot = [&](std::uint64_t key) {
        return static_cast<std::size_t>((key * 0x9e3779b97f4a7c15ULL) >> shift);
    };
    constexpr Index kEmpty = kInvalidIndex;
    // vertex ids: equal positions (-0 and 0 as one) get one id
    std::vector<Vec3> positions;
    positions.reserve(triangles.size());
    std::vector<Index> vertex_table(size, kEmpty);
    const auto id = [&](const Vec3& p) {
        const Vec3 key{p.x + 0.0, p.y + 0.0, p.z + 0.0};
        std::uint64_t bits[3];
        std::memcpy(bits, &key.x, 8);
        std::memcpy(bits + 1, &key.y, 8);
        std::memcpy(bits + 2, &key.z, 8);
        std::size_t at = slot(bits[0] ^ (bits[1] * 0xc2b2ae3d27d4eb4fULL) ^ (bits[2] * 0x165667b19e3779f9ULL));
        for (;; at = (at + 1) & (size - 1)) {
            const Index v = vertex_table[at];
            if (v == kEmpty) {
                vertex_table[at] = static_cast<Index>(positions.size());
                positions.push_back(key);
                return vertex_table[at];
            }
            const Vec3& q = positions[v];
            if (q.x == key.x && q.y == key.y && q.z == key.z) return v;
        }
    };
    // balance per undirected edge: +1 for (lo -> hi), -1 for (hi -> lo); edges in the order first seen
    std::vector<std::pair<std::uint64_t, int>> edges;
    edges.reserve(3 * triangles.size() / 2 + 1);
    std::vector<Index> edge_table(size, kEmpty);
    for (const BvhTriangle& t : triangles) {
        const Index v[3] = {id(t.p[0]), id(t.p[1]), id(t.p[2])};
        for (int k = 0; k < 3; ++k) {
            const Index a = v[k], b = v[(k + 1) % 3];
            if (a == b) continue;
            const std::uint64_t key = (std::uint64_t{std::min(a, b)} << 32) | std::max(a, b);
            std::size_t at = slot(key);
            while (edge_table[at] != kEmpty && edges[edge_table[at]].first != key) at = (at + 1) & (size - 1);
            if (edge_table[at] == kEmpty) {
                edge_table[at] = static_cast<Index>(edges.size());
                edges.push_back({key, 0});
            }
            edges[edge_table[at]].second += a < b ? 1 : -1;
        }
    }
    std::vector<std::array<Vec3, 2>> out;
    for (const auto& [key, count] : edges)
        for (int c = std::abs(count); c > 0; --c) out.push_back({positions[key >> 32], positions[key & 0xffffffffu]});
    return out;
}

//! Bounds how much the winding number can change along a segment that crosses no triangle. Off the surface the
//! gradient of a triangle's solid angle is the Biot-Savart integral over its edges, and over the whole surface the
//! edges matched by their reverse cancel, so |grad w(p)| <= 1/(4 pi) * sum over boundary edges e of
//! length(e) / distance(p, e)^2. Along a segment of length L, w changes by at most L times the largest of that.
//! The edges are kept in clusters (a ball holding them and their total length) so that far ones cost one test.
class DriftBound {
public:
    explicit DriftBound(std::vector<std::array<Vec3, 2>> edges) : edges_(std::move(edges)) {
        // clusters of spatially close edges: sorted along the longest axis of their box, recursively halved
        std::vector<std::size_t> order(edges_.size());
        for (std::size_t e = 0; e < order.size(); ++e) order[e] = e;
        split(order, 0, order.size());
        std::vector<std::array<Vec3, 2>> sorted(edges_.size());
        for (std::size_t e = 0; e < order.size(); ++e) sorted[e] = edges_[order[e]];
        edges_ = std::move(sorted);
        for (std::size_t first = 0; first < edges_.size(); first += kClusterEdges) {
            const std::size_t last = std::min(edges_.size(), first + kClusterEdges);
            Box3 box;
            Cluster c{{}, 0, 0, first, last};
            for (std::size_t e = first; e < last; ++e) {
                box.add(edges_[e][0]);
                box.add(edges_[e][1]);
                c.length += norm(edges_[e][1] - edges_[e][0]);
            }
            c.centre = (box.min + box.max) * 0.5;
            for (std::size_t e = first; e < last; ++e)
                c.radius = std::max({c.radius, norm(edges_[e][0] - c.centre), norm(edges_[e][1] - c.centre)});
            clusters_.push_back(c);
        }
    }

    //! An upper bound on |w(x) - w(y)| for x, y on the segment [p, q], given that it crosses no triangle; stops adding
    //! once past `limit` (then any value above it).
    double along(const Vec3& p, const Vec3& q, double limit) const {
        const Vec3 pq = q - p;
        const double length2 = dot(pq, pq), length = std::sqrt(length2);
        if (length == 0) return 0;
        const auto distance_to_segment = [&](const Vec3& c) {
            const double s = std::clamp(dot(c - p, pq) / length2, 0.0, 1.0);
            return norm(c - (p + pq * s));
        };
        double sum = 0;
        limit *= 4 * std::numbers::pi / length;
        for (const Cluster& c : clusters_) {
            const double gap = distance_to_segment(c.centre) - c.radius;
            if (gap > c.radius) {
                sum += c.length / (gap * gap);
            } else {
                for (std::size_t e = c.first; e < c.last; ++e) {
                    const Vec3 &a = edges_[e][0], &b = edges_[e][1];
                    const Vec3 middle = (a + b) * 0.5;
                    const double half = 0.5 * norm(b - a);
                    const double edge_gap = distance_to_segment(middle) - half;
                    if (!(edge_gap > 0)) return kInf;
                    sum += 2 * half / (edge_gap * edge_gap);
                }
            }
            if (sum > limit) break;
        }
        // widened a little for rounding
        return sum * length / (4 * std::numbers::pi) * (1 + 1e-9);
    }

    //! An upper bound on |grad w| over the box (the same sum with the distances to the box); stops adding once past
    //! `limit` (then any value above it).
    double gradient(const Box3& box, double limit) const {
        const auto distance_to_box = [&](const Vec3& c) {
            const Vec3 d{c.x - std::clamp(c.x, box.min.x, box.max.x), c.y - std::clamp(c.y, box.min.y, box.max.y),
                         c.z - std::clamp(c.z, box.min.z, box.max.z)};
            return norm(d);
        };
        double sum = 0;
        limit *= 4 * std::numbers::pi;
        for (const Cluster& c : clusters_) {
            const double gap = distance_to_box(c.centre) - c.radius;
            if (gap > c.radius) {
                sum += c.length / (gap * gap);
            } else {
                for (std::size_t e = c.first; e < c.last; ++e) {
                    const Vec3 &a = edges_[e][0], &b = edges_[e][1];
                    const Vec3 middle = (a + b) * 0.5;
                    const double half = 0.5 * norm(b - a);
                    const double edge_gap = distance_to_box(middle) - half;
                    if (!(edge_gap > 0)) return kInf;
                    sum += 2 * half / (edge_gap * edge_gap);
                }
            }
            if (sum > limit) break;
        }
        return sum / (4 * std::numbers::pi) * (1 + 1e-9);
    }

private:
    struct Cluster {
        Vec3 centre;
        double radius, length;
        std::size_t first, last;
    };

    void split(std::vector<std::size_t>& order, std::size_t first, std::size_t last) {
        if (last - first <= kClusterEdges) return;
        Box3 box;
        for (std::size_t e = first; e < last; ++e) box.add((edges_[order[e]][0] + edges_[order[e]][1]) * 0.5);
        const Vec3 extent = box.max - box.min;
        const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
        // halves on a multiple of the cluster size, so that every cluster but the last is full
        const std::size_t half = first + ((last - first) / 2 + kClusterEdges - 1) / kClusterEdges * kClusterEdges;
        const auto key = [&](std::size_t e) { return edges_[e][0][axis] + edges_[e][1][axis]; };
        std::nth_element(order.begin() + static_cast<std::ptrdiff_t>(first),
                         order.begin() + static_cast<std::ptrdiff_t>(half),
                         order.begin() + static_cast<std::ptrdiff_t>(last),
                         [&](std::size_t l, std::size_t r) { return key(l) < key(r); });
        split(order, first, half);
        split(order, half, last);
    }

    std::vector<std::array<Vec3, 2>> edges_;
    std::vector<Cluster> clusters_;
};

//! Sets bit 3 of flags[node] for the nodes within `radius` of segment [a, b].
void mark_near_segment(const Grid& g, const Vec3& a, const Vec3& b, double radius, std::uint8_t* flags) {
    Box3 box;
    box.add(a);
    box.add(b);
    std::size_t lo[3], hi[3];
    for (int k = 0; k < 3; ++k)
        if (!g.range(k, box.min[k] - radius, box.max[k] + radius, lo[k], hi[k])) return;
    const Vec3 ab = b - a;
    const double len2 = dot(ab, ab), r2 = radius * radius * (1 + 1e-9);
    for (std::size_t k = lo[2]; k <= hi[2]; ++k)
        for (std::size_t j = lo[1]; j <= hi[1]; ++j)
            for (std::size_t i = lo[0]; i <= hi[0]; ++i) {
                const Vec3 p = g.position(i, j, k);
                const double s = len2 > 0 ? std::clamp(dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
                const Vec3 d = p - (a + ab * s);
                if (dot(d, d) <= r2) flags[i * g.stride[0] + j * g.stride[1] + k * g.stride[2]] |= kNearBoundary;
            }
}

//! The winding numbers' hierarchy: the SAH hierarchy (bvh.h) with every subtree of at most kWindingLeaf triangles
//! made one leaf (when its triangles are consecutive, as build_bvh lays them out). The SAH splits small triangles
//! down to leaves of one or two, and for a winding number a node is an expansion to build and evaluate; a few more
//! solid angles in a leaf cost less than the nodes above them.
constexpr std::size_t kWindingLeaf = 8;

void collapse_small_subtrees(TriangleBvh& bvh) {
    const std::size_t n = bvh.nodes.size();
    if (n == 0) return;
    // triangles below each node, and the range of triangle indices they span (children follow their parent)
    std::vector<Index> count(n), first(n), end(n);
    for (std::size_t k = n; k-- > 0;) {
        const BvhNode& node = bvh.nodes[k];
        if (node.is_leaf()) {
            count[k] = node.count;
            first[k] = node.index;
            end[k] = node.index + node.count;
        } else {
            count[k] = count[k + 1] + count[node.index];
            first[k] = std::min(first[k + 1], first[node.index]);
            end[k] = std::max(end[k + 1], end[node.index]);
        }
    }
    // depth first again: a node, its left subtree, then its right child, whose index the node gets
    std::vector<BvhNode> out;
    out.reserve(n);
    struct Visit {
        std::size_t node, parent;  // parent: the copied node whose right child this is, or SIZE_MAX
    };
    std::vector<Visit> stack{{0, SIZE_MAX}};
    while (!stack.empty()) {
        const Visit visit = stack.back();
        stack.pop_back();
        const std::size_t at = out.size();
        if (visit.parent != SIZE_MAX) out[visit.parent].index = static_cast<Index>(at);
        const BvhNode& node = bvh.nodes[visit.node];
        out.push_back(node);
        if (node.is_leaf()) continue;
        if (count[visit.node] <= kWindingLeaf && end[visit.node] - first[visit.node] == count[visit.node]) {
            out[at].index = first[visit.node];
            out[at].count = count[visit.node];
            continue;
        }
        stack.push_back({node.index, at});
        stack.push_back({visit.node + 1, SIZE_MAX});
    }
    bvh.nodes = std::move(out);
}

GeoError cancelled() { return GeoError{ErrorCode::Cancelled, "cancelled while building the distance grid"}; }

}  // namespace

Result<LevelSetGrid> mesh_distance_grid(const PolygonMesh& mesh, const DistanceGridOptions& options,
                                        DistanceGridStats* stats) {
    if (options.band < 1 || options.band > kMaxDistanceBand)
        return GeoError{ErrorCode::InvalidArgument,
                        "band must be in 1.." + std::to_string(kMaxDistanceBand) + " voxels"};
    if (!(options.voxel_size > 0) || !std::isfinite(options.voxel_size))
        return GeoError{ErrorCode::InvalidArgument, "voxel_size must be a positive finite number"};
    if (mesh.face_count() == 0)
        return GeoError{ErrorCode::InvalidArgument, "a mesh without faces has no surface to measure distances to"};
    const Box3 bounds = options.bounds ? *options.bounds
                                       : default_distance_grid_bounds(mesh.bounds(), options.voxel_size, options.band);
    auto layout = distance_grid_layout(bounds, options.voxel_size, options.max_nodes);
    if (!layout) return layout.error();
    const DistanceGridLayout& lay = layout.value();

    // the triangles (polygons triangulated); the hierarchy only when many winding numbers are asked
    std::vector<BvhTriangle> triangles;
    {
        const PolygonMesh triangulated = mesh.is_triangle_mesh() ? PolygonMesh{} : triangulate(mesh);
        const PolygonMesh& tm = mesh.is_triangle_mesh() ? mesh : triangulated;
        triangles.resize(tm.face_count());
        for (std::size_t f = 0; f < tm.face_count(); ++f) {
            const auto face = tm.face(f);
            for (int k = 0; k < 3; ++k) triangles[f].p[static_cast<std::size_t>(k)] = tm.positions[face[k]];
        }
    }
    std::optional<TriangleBvh> bvh;
    WindingTree tree;
    auto build_hierarchy = [&]() -> Status {
        BvhOptions bvh_options;
        bvh_options.ray_nodes = false;  // winding numbers walk the binary nodes only
        bvh_options.cancel = options.cancel;
        auto built = build_bvh(mesh, bvh_options);
        if (!built) return built.error();
        bvh = std::move(built.value());
        collapse_small_subtrees(*bvh);
        tree = build_winding_tree(*bvh);
        return Ok{};
    };
    if (options.cancel.requested()) return cancelled();

    Grid g{{lay.dims[0], lay.dims[1], lay.dims[2]},
           {1, lay.dims[0], lay.dims[0] * lay.dims[1]},
           lay.origin,
           lay.spacing,
           static_cast<std::size_t>(lay.nodes),
           1.0 / lay.spacing};
    const double radius = options.band * g.h, radius2 = radius * radius;

    // 1. unsigned squared distances within the band (kInf beyond it)
    LevelSetGrid out;
    out.dims = lay.dims;
    out.origin = lay.origin;
    out.spacing = {g.h, g.h, g.h};
    out.values.assign(g.nodes, kInf);
    double* d2 = out.values.data();
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        if (t % kTriangleBatch == 0 && options.cancel.requested()) return cancelled();
        scatter_triangle(g, triangles[t], radius, d2);
    }

    // 2. signs: +1 / -1 per node (0 not known yet)
    std::vector<std::int8_t> sign(g.nodes, 0);
    std::uint64_t queries = 0, components = 0;
    // The first few winding numbers of a closed mesh (it needs about two) are exact sums over the triangles; past
    // kDirectQueries, and from the first on an open mesh (which asks thousands), the hierarchy is built and used as
    // options.winding says.
    std::uint64_t direct_queries = kDirectQueries;
    auto winding_at = [&](std::size_t node) -> Result<double> {
        const std::size_t i = node % g.n[0], j = (node / g.n[0]) % g.n[1], k = node / (g.n[0] * g.n[1]);
        const Vec3 p = g.position(i, j, k);
        ++queries;
        if (!bvh && (queries <= direct_queries || options.winding.exact)) {
            double sum = 0;
            for (const BvhTriangle& t : triangles) sum += triangle_solid_angle(p, t.p[0], t.p[1], t.p[2]);
            return sum / (4 * std::numbers::pi);
        }
        if (!bvh)
            if (auto built = build_hierarchy(); !built) return built.error();
        return winding_number_value(*bvh, tree, p, options.winding);
    };
    auto inside_at = [&](std::size_t node) -> Result<bool> {
        auto w = winding_at(node);
        if (!w) return w.error();
        return w.value() >= 0.5;
    };
    std::vector<std::array<Vec3, 2>> boundary = boundary_edges(triangles);
    const bool closed = boundary.empty();
    if (!closed) direct_queries = 0;
    std::vector<std::uint8_t> blocked(g.nodes, 0);
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        if (t % kTriangleBatch == 0 && options.cancel.requested()) return cancelled();
        mark_crossings(g, triangles[t], blocked.data());
    }
    for (const auto& [a, b] : boundary) mark_near_segment(g, a, b, radius, blocked.data());
    if (closed) {
        // Scanline flood fill over unblocked edges: runs of nodes joined along x, grown into the neighbouring rows
        // (y and z) through unblocked edges. Each component is signed by one query at its node farthest from the
        // surface.
        struct Run {
            std::size_t row, x0, x1;  // row = j + ny k; nodes row * nx + x0 .. row * nx + x1
        };
        const std::size_t nx = g.n[0];
        std::vector<Run> members, stack;
        // marks the run of unvisited nodes through (row, x) joined along unblocked x-edges, and queues it
        auto open_run = [&](std::size_t row, std::size_t x) {
            const std::size_t base = row * nx;
            std::size_t x0 = x, x1 = x;
            while (x0 > 0 && sign[base + x0 - 1] == 0 && !(blocked[base + x0 - 1] & 1u)) --x0;
            while (x1 + 1 < nx && sign[base + x1 + 1] == 0 && !(blocked[base + x1] & 1u)) ++x1;
            std::fill(sign.begin() + static_cast<std::ptrdiff_t>(base + x0),
                      sign.begin() + static_cast<std::ptrdiff_t>(base + x1 + 1), std::int8_t{2});
            stack.push_back({row, x0, x1});
        };
        std::size_t popped = 0;
        for (std::size_t seed = 0; seed < g.nodes; ++seed) {
            if (sign[seed] != 0) continue;
            members.clear();
            stack.clear();
            open_run(seed / nx, seed % nx);
            std::size_t best = seed;
            while (!stack.empty()) {
                if (++popped % kFillBatch == 0 && options.cancel.requested()) return cancelled();
                const Run run = stack.back();
                stack.pop_back();
                members.push_back(run);
                const std::size_t base = run.row * nx;
                for (std::size_t x = run.x0; x <= run.x1; ++x)
                    if (d2[base + x] > d2[best]) best = base + x;
                const std::size_t j = run.row % g.n[1], k = run.row / g.n[1];
                // the four neighbouring rows: its index, the axis bit of the edges to it, whether it exists, and
                // whether those edges' bits are this row's (towards +y, +z) or the other's
                const struct {
                    std::size_t row;
                    std::uint8_t bit;
                    bool exists, forward;
                } next[4] = {{run.row + 1, 2, j + 1 < g.n[1], true},
                             {run.row - 1, 2, j > 0, false},
                             {run.row + g.n[1], 4, k + 1 < g.n[2], true},
                             {run.row - g.n[1], 4, k > 0, false}};
                for (const auto& n : next) {
                    if (!n.exists) continue;
                    const std::size_t other = n.row * nx;
                    for (std::size_t x = run.x0; x <= run.x1; ++x) {
                        if (sign[other + x] != 0) continue;
                        const std::uint8_t edge = n.forward ? blocked[base + x] : blocked[other + x];
                        if (!(edge & n.bit)) open_run(n.row, x);
                    }
                }
            }
            auto inside = inside_at(best);
            if (!inside) return inside.error();
            ++components;
            const std::int8_t s = inside.value() ? -1 : 1;
            for (const Run& run : members)
                std::fill(sign.begin() + static_cast<std::ptrdiff_t>(run.row * nx + run.x0),
                          sign.begin() + static_cast<std::ptrdiff_t>(run.row * nx + run.x1 + 1), s);
        }
    } else {
        // Rows split into runs at the x-edges that cross a triangle: no run crosses the surface, so along it w
        // changes by no more than the drift bound. Row by row, each node first inherits what is proven of w at its
        // neighbours before it along y and z and along its run (an interval grown by one step of the gradient
        // bound); a node whose interval lies on one side of 1/2 takes that side. Each stretch of the others is
        // asked at its ends (or bounded by the proven nodes beside it) and halved at asked nodes until each part
        // is on one side: proven by the drift bound, or both ends at least kConfident from 1/2 on one side with
        // no node between within the band of a boundary edge (where w turns fast), down to neighbouring nodes.
        const DriftBound drift(std::move(boundary));
        struct Span {
            std::size_t lo, hi;
            double wlo, whi;
            double slo, shi;  // w at lo and hi within these of wlo and whi
        };
        const auto side = [](double w) { return w >= 0.5 ? std::int8_t{-1} : std::int8_t{1}; };
        const auto at = [&](std::size_t node) {
            return g.position(node % g.n[0], (node / g.n[0]) % g.n[1], node / (g.n[0] * g.n[1]));
        };
        // whether w (known within `slack` of w at node `from`) provably stays on its side of 1/2 up to node `to`
        const auto holds = [&](std::size_t from, double w, double slack, std::size_t to) {
            const double room = std::abs(w - 0.5) - slack;
            if (!(room > 0)) return false;
            return drift.along(at(from), at(to), room) < room;
        };
        const auto confident = [&](const Span& span) {
            return side(span.wlo) == side(span.whi) && std::abs(span.wlo - 0.5) >= kConfident &&
                   std::abs(span.whi - 0.5) >= kConfident;
        };
        const auto fill = [&](std::size_t lo, std::size_t hi, std::int8_t s) {
            std::fill(sign.begin() + static_cast<std::ptrdiff_t>(lo),
                      sign.begin() + static_cast<std::ptrdiff_t>(hi + 1), s);
        };
        // What is known of w at the nodes of the last ny rows (the rows before along y and z), by row modulo ny:
        // w is on the side of 1/2 that `w` is on, at least `room` from it (-inf: nothing known). Queried nodes get
        // the hierarchy's margin. Rounding to float moves room by far less than the 1e-6 each step subtracts, and
        // a stored room is rounded down by as much.
        struct Known {
            float w, room;
        };
        constexpr float kUnknown = -std::numeric_limits<float>::infinity();
        const std::size_t nx = g.n[0];
        std::vector<Known> known(nx * g.n[1], Known{0.5f, kUnknown}), candidate(nx);
        const auto remember = [&](std::size_t node, double w, double slack) {
            known[(node / nx) % g.n[1] * nx + node % nx] = {static_cast<float>(w),
                                                            static_cast<float>(std::abs(w - 0.5) - slack - 1e-7)};
        };
        // the slack of what c says of w: w within it of c.w
        const auto slack_of = [](const Known& c) { return std::abs(double{c.w} - 0.5) - double{c.room}; };
        // c, or what `from` proves one step away when that leaves more room (an unknown `from` never replaces c)
        const auto better = [](Known& c, const Known& from, float step) {
            const float next = from.room - step;
            if (next > c.room) c = {from.w, next};
        };
        std::vector<Span> pending;
        for (std::size_t row = 0; row < g.n[1] * g.n[2]; ++row) {
            if (row % g.n[1] == 0 && options.cancel.requested()) return cancelled();
            const std::size_t base = row * nx;
            const std::size_t j = row % g.n[1], k = row / g.n[1];
            Known* line = known.data() + j * nx;
            for (std::size_t i = 0; i < nx;) {
                std::size_t end = i;
                while (end + 1 < nx && !(blocked[base + end] & 1u)) ++end;
                ++components;
                // one step of the gradient bound over the run and the nodes before it along y and z
                Box3 box;
                box.add(at(base + i));
                box.add(at(base + end) - Vec3{0, j > 0 ? g.h : 0, k > 0 ? g.h : 0});
                const double step = g.h * drift.gradient(box, 0.5 / g.h);
                const auto fstep = static_cast<float>(step + 1e-6);
                // what the nodes before along y and z, and along the run both ways, prove of each node's w (the
                // row before along z is the one this row replaces in `known`, so it is read before any write)
                for (std::size_t x = i; x <= end; ++x) {
                    Known c{0.5f, kUnknown};
                    if (step < 0.5) {
                        if (j > 0 && !(blocked[base - nx + x] & 2u)) better(c, known[(j - 1) * nx + x], fstep);
                        if (k > 0 && !(blocked[base - nx * g.n[1] + x] & 4u)) better(c, line[x], fstep);
                        if (x > i) better(c, candidate[x - 1], fstep);
                    }
                    candidate[x] = c;
                }
                if (step < 0.5)
                    for (std::size_t x = end; x > i; --x) better(candidate[x - 1], candidate[x], fstep);
                std::copy(candidate.begin() + static_cast<std::ptrdiff_t>(i),
                          candidate.begin() + static_cast<std::ptrdiff_t>(end + 1),
                          line + static_cast<std::ptrdiff_t>(i));
                const std::uint64_t asked_before = queries;
                // the nodes so proven take their side; each stretch of the others is asked at its ends and halved
                for (std::size_t a = i; a <= end;) {
                    if (line[a].room > 0) {
                        sign[base + a] = side(line[a].w);
                        ++a;
                        continue;
                    }
                    std::size_t b = a;
                    while (b < end && !(line[b + 1].room > 0)) ++b;
                    // the stretch's ends: the proven nodes beside it, else its own end nodes asked
                    Span stretch{a, b, 0, 0, kWindingMargin, kWindingMargin};
                    if (a > i) {
                        stretch = {a - 1, b, line[a - 1].w, 0, slack_of(line[a - 1]), kWindingMargin};
                    } else {
                        auto w = winding_at(base + a);
                        if (!w) return w.error();
                        sign[base + a] = side(w.value());
                        remember(base + a, w.value(), kWindingMargin);
                        stretch.wlo = w.value();
                    }
                    stretch.lo += base;
                    if (b < end) {
                        stretch.hi = base + b + 1;
                        stretch.whi = line[b + 1].w;
                        stretch.shi = slack_of(line[b + 1]);
                    } else if (stretch.lo != base + b) {
                        stretch.hi = base + b;
                        if (holds(stretch.lo, stretch.wlo, stretch.slo, stretch.hi)) {
                            fill(stretch.lo + 1, stretch.hi, side(stretch.wlo));
                            a = b + 1;
                            continue;
                        }
                        auto w = winding_at(base + b);
                        if (!w) return w.error();
                        sign[base + b] = side(w.value());
                        remember(base + b, w.value(), kWindingMargin);
                        stretch.whi = w.value();
                    } else {
                        stretch.hi = stretch.lo;
                    }
                    pending.push_back(stretch);
                    while (!pending.empty()) {
                        const Span span = pending.back();
                        pending.pop_back();
                        if (span.hi - span.lo < 2) continue;
                        if (confident(span) && std::none_of(blocked.begin() + static_cast<std::ptrdiff_t>(span.lo + 1),
                                                            blocked.begin() + static_cast<std::ptrdiff_t>(span.hi),
                                                            [](std::uint8_t m) { return (m & kNearBoundary) != 0; })) {
                            fill(span.lo + 1, span.hi - 1, side(span.wlo));
                            continue;
                        }
                        if (holds(span.lo, span.wlo, span.slo, span.hi)) {
                            fill(span.lo + 1, span.hi - 1, side(span.wlo));
                            continue;
                        }
                        if (holds(span.hi, span.whi, span.shi, span.lo)) {
                            fill(span.lo + 1, span.hi - 1, side(span.whi));
                            continue;
                        }
                        // Neither end holds over the whole span; but when the nodes the low end provably holds
                        // to (the farthest found by bisection on holds) and those the high end holds to meet, each
                        // node is proven by one of them and no query is needed.
                        std::size_t from_lo = span.lo;
                        for (std::size_t l = span.lo + 1, h = span.hi - 1; l <= h;) {
                            const std::size_t x = l + (h - l) / 2;
                            if (holds(span.lo, span.wlo, span.slo, x)) {
                                from_lo = x;
                                l = x + 1;
                            } else {
                                h = x - 1;
                            }
                        }
                        if (from_lo + 1 == span.hi || holds(span.hi, span.whi, span.shi, from_lo + 1)) {
                            if (from_lo > span.lo) fill(span.lo + 1, from_lo, side(span.wlo));
                            if (from_lo + 1 < span.hi) fill(from_lo + 1, span.hi - 1, side(span.whi));
                            continue;
                        }
                        const std::size_t mid = span.lo + (span.hi - span.lo) / 2;
                        auto w = winding_at(mid);
                        if (!w) return w.error();
                        sign[mid] = side(w.value());
                        remember(mid, w.value(), kWindingMargin);
                        pending.push_back({span.lo, mid, span.wlo, w.value(), span.slo, kWindingMargin});
                        pending.push_back({mid, span.hi, w.value(), span.whi, kWindingMargin, span.shi});
                    }
                    a = b + 1;
                }
                // what the queries prove along the run, for the rows after (and over the kConfident guesses)
                if (step < 0.5 && queries != asked_before) {
                    for (std::size_t x = i + 1; x <= end; ++x) better(line[x], line[x - 1], fstep);
                    for (std::size_t x = end; x > i; --x) better(line[x - 1], line[x], fstep);
                    for (std::size_t x = i; x <= end; ++x)
                        if (line[x].room > 0) sign[base + x] = side(line[x].w);
                }
                i = end + 1;
            }
        }
    }

    // 3. values: signed distance in the band, +-radius beyond it
    std::uint64_t band_nodes = 0;
    for (std::size_t node = 0; node < g.nodes; ++node) {
        const bool in_band = d2[node] <= radius2;
        band_nodes += in_band;
        const double d = in_band ? std::sqrt(d2[node]) : radius;
        d2[node] = sign[node] < 0 ? -d : d;
    }
    if (stats) {
        *stats = DistanceGridStats{};
        stats->layout = lay;
        stats->band_nodes = band_nodes;
        stats->winding_queries = queries;
        stats->components = components;
        stats->closed = closed;
    }
    return out;
}

}  // namespace surfaced::implicit
