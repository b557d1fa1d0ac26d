// Mesh -> narrow-band signed distance grid (see distance_grid.h): per-triangle distance scatter, crossing marks,
// signs by connected components and winding numbers.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <unordered_map>
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
//! Open meshes: a run whose two ends have winding numbers at least this far from 1/2, on one side, takes that side.
constexpr double kConfident = 0.25;
//! Bit of the per-node marks (beside the three crossing bits): within the band of a boundary edge.
constexpr std::uint8_t kNearBoundary = 8;

struct Grid {
    std::size_t n[3];
    std::size_t stride[3];
    Vec3 origin;
    double h;
    std::size_t nodes;

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

//! Squared distance from (qu, qv) to the 2D triangle (pu[k], pv[k]): 0 inside, else to the nearest edge.
inline double triangle_distance2_2d(double qu, double qv, const double* pu, const double* pv) {
    double e[3], best = kInf;
    for (int k = 0; k < 3; ++k) {
        const int l = k == 2 ? 0 : k + 1;
        const double eu = pu[l] - pu[k], ev = pv[l] - pv[k], wu = qu - pu[k], wv = qv - pv[k];
        e[k] = eu * wv - ev * wu;
        const double len2 = eu * eu + ev * ev;
        const double s = len2 > 0 ? std::clamp((eu * wu + ev * wv) / len2, 0.0, 1.0) : 0.0;
        const double du = wu - s * eu, dv = wv - s * ev;
        best = std::min(best, du * du + dv * dv);
    }
    if ((e[0] >= 0 && e[1] >= 0 && e[2] >= 0) || (e[0] <= 0 && e[1] <= 0 && e[2] <= 0)) return 0;
    return best;
}

//! Keeps, per node, the minimum squared distance to the triangle over the nodes within `radius` of it: the nodes of
//! its box grown by radius, and along the axis its normal is closest to only those within radius of its plane.
void scatter_triangle(const Grid& g, const BvhTriangle& t, double radius, double* d2) {
    Box3 box;
    for (const Vec3& p : t.p) box.add(p);
    const double r2 = radius * radius;
    std::size_t lo[3], hi[3];
    for (int a = 0; a < 3; ++a)
        if (!g.range(a, box.min[a] - radius, box.max[a] + radius, lo[a], hi[a])) return;
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
    const Vec3 centre = (box.min + box.max) * 0.5;
    const double sphere = std::max({norm(t.p[0] - centre), norm(t.p[1] - centre), norm(t.p[2] - centre)});
    // widened by a little so that rounding in the interval never drops a node the box test would keep
    const double reach = (radius + 1e-9 * (radius + box.diagonal())) / (slab ? std::abs(n[m]) : 1.0);
    // the triangle projected along m: a column farther than radius from it (projection never lengthens a
    // distance) has no node within radius; the test is widened like `reach`
    const double pu[3] = {t.p[0][u], t.p[1][u], t.p[2][u]}, pv[3] = {t.p[0][v], t.p[1][v], t.p[2][v]};
    const double column_reach2 = r2 * (1 + 1e-9) + 1e-18 * box.diagonal() * box.diagonal();
    for (std::size_t b = lo[v]; b <= hi[v]; ++b) {
        for (std::size_t c = lo[u]; c <= hi[u]; ++c) {
            std::size_t first = lo[m], last = hi[m];
            Vec3 p;
            p[u] = g.origin[u] + static_cast<double>(c) * g.h;
            p[v] = g.origin[v] + static_cast<double>(b) * g.h;
            if (triangle_distance2_2d(p[u], p[v], pu, pv) > column_reach2) continue;
            if (slab) {
                // n . p = plane +- radius solved for p[m]
                const double middle = (plane - n[u] * p[u] - n[v] * p[v]) / n[m];
                std::size_t l, h;
                if (!g.range(m, middle - reach, middle + reach, l, h)) continue;
                first = std::max(first, l);
                last = std::min(last, h);
                if (first > last) continue;
            }
            std::size_t index = c * g.stride[u] + b * g.stride[v] + first * g.stride[m];
            for (std::size_t a = first; a <= last; ++a, index += g.stride[m]) {
                p[m] = g.origin[m] + static_cast<double>(a) * g.h;
                const double best = std::min(d2[index], r2);
                // lower bounds first: the distance to the plane, then to the triangle's bounding sphere (scaled
                // down a little so that rounding never skips a node the exact distance would lower)
                if (slab) {
                    const double plane_distance = dot(n, p) - plane;
                    if (plane_distance * plane_distance * (1 - 1e-9) > best) continue;
                }
                const double centre_distance = norm(p - centre) - sphere;
                if (centre_distance > 0 && centre_distance * centre_distance * (1 - 1e-9) > best) continue;
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
//! positions counting as one). None for a closed surface, whose winding number is constant off it on each region.
std::vector<std::array<Vec3, 2>> boundary_edges(const std::vector<BvhTriangle>& triangles) {
    struct PositionHash {
        std::size_t operator()(const Vec3& p) const {
            const std::hash<double> h;
            return h(p.x) ^ (h(p.y) * 0x9e3779b97f4a7c15ULL) ^ (h(p.z) * 0xc2b2ae3d27d4eb4fULL);
        }
    };
    std::unordered_map<Vec3, std::uint32_t, PositionHash> ids;
    std::vector<Vec3> positions;
    ids.reserve(triangles.size());
    auto id = [&](const Vec3& p) {
        const Vec3 key{p.x + 0.0, p.y + 0.0, p.z + 0.0};  // -0 and 0 as one
        const auto [it, added] = ids.try_emplace(key, static_cast<std::uint32_t>(ids.size()));
        if (added) positions.push_back(key);
        return it->second;
    };
    // balance per undirected edge: +1 for (lo -> hi), -1 for (hi -> lo)
    std::unordered_map<std::uint64_t, int> balance;
    balance.reserve(triangles.size() * 2);
    for (const BvhTriangle& t : triangles) {
        const std::uint32_t v[3] = {id(t.p[0]), id(t.p[1]), id(t.p[2])};
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = v[k], b = v[(k + 1) % 3];
            if (a == b) continue;
            const std::uint64_t key = (std::uint64_t{std::min(a, b)} << 32) | std::max(a, b);
            balance[key] += a < b ? 1 : -1;
        }
    }
    std::vector<std::array<Vec3, 2>> out;
    for (const auto& [key, count] : balance)
        if (count != 0) out.push_back({positions[key >> 32], positions[key & 0xffffffffu]});
    return out;
}

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
        bvh_options.cancel = options.cancel;
        auto built = build_bvh(mesh, bvh_options);
        if (!built) return built.error();
        bvh = std::move(built.value());
        tree = build_winding_tree(*bvh);
        return Ok{};
    };
    if (options.cancel.requested()) return cancelled();

    Grid g{{lay.dims[0], lay.dims[1], lay.dims[2]},
           {1, lay.dims[0], lay.dims[0] * lay.dims[1]},
           lay.origin,
           lay.spacing,
           static_cast<std::size_t>(lay.nodes)};
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
    // The first few winding numbers (a closed mesh needs about two) are exact sums over the triangles; past
    // kDirectQueries the hierarchy is built and used as options.winding says.
    auto winding_at = [&](std::size_t node) -> Result<double> {
        const std::size_t i = node % g.n[0], j = (node / g.n[0]) % g.n[1], k = node / (g.n[0] * g.n[1]);
        const Vec3 p = g.position(i, j, k);
        ++queries;
        if (!bvh && (queries <= kDirectQueries || options.winding.exact)) {
            double sum = 0;
            for (const BvhTriangle& t : triangles) sum += triangle_solid_angle(p, t.p[0], t.p[1], t.p[2]);
            return sum / (4 * std::numbers::pi);
        }
        if (!bvh)
            if (auto built = build_hierarchy(); !built) return built.error();
        auto w = winding_number(*bvh, tree, p, options.winding);
        if (!w) return w.error();
        return w->value;
    };
    auto inside_at = [&](std::size_t node) -> Result<bool> {
        auto w = winding_at(node);
        if (!w) return w.error();
        return w.value() >= 0.5;
    };
    const std::vector<std::array<Vec3, 2>> boundary = boundary_edges(triangles);
    const bool closed = boundary.empty();
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
        // Rows split into runs at the x-edges that cross a triangle: no run crosses the surface, and the winding
        // number varies smoothly along it. A run's two ends are asked; where both are on one side of 1/2 by at
        // least kConfident and no node between is within the band of a boundary edge (where w turns fast around
        // the edge), the nodes between take that side; otherwise the middle is asked and each half is treated the
        // same way, down to neighbouring nodes.
        struct Span {
            std::size_t lo, hi;
            double wlo, whi;
        };
        const auto side = [](double w) { return w >= 0.5 ? std::int8_t{-1} : std::int8_t{1}; };
        const auto confident = [&](const Span& span) {
            return side(span.wlo) == side(span.whi) && std::abs(span.wlo - 0.5) >= kConfident &&
                   std::abs(span.whi - 0.5) >= kConfident;
        };
        std::vector<Span> pending;
        for (std::size_t row = 0; row < g.n[1] * g.n[2]; ++row) {
            if (row % g.n[1] == 0 && options.cancel.requested()) return cancelled();
            const std::size_t base = row * g.n[0];
            for (std::size_t i = 0; i < g.n[0];) {
                std::size_t end = i;
                while (end + 1 < g.n[0] && !(blocked[base + end] & 1u)) ++end;
                ++components;
                auto first = winding_at(base + i);
                if (!first) return first.error();
                sign[base + i] = side(first.value());
                if (end > i) {
                    auto last = winding_at(base + end);
                    if (!last) return last.error();
                    sign[base + end] = side(last.value());
                    pending.push_back({base + i, base + end, first.value(), last.value()});
                }
                while (!pending.empty()) {
                    const Span span = pending.back();
                    pending.pop_back();
                    if (span.hi - span.lo < 2) continue;
                    if (confident(span) && std::none_of(blocked.begin() + static_cast<std::ptrdiff_t>(span.lo + 1),
                                                        blocked.begin() + static_cast<std::ptrdiff_t>(span.hi),
                                                        [](std::uint8_t m) { return (m & kNearBoundary) != 0; })) {
                        std::fill(sign.begin() + static_cast<std::ptrdiff_t>(span.lo + 1),
                                  sign.begin() + static_cast<std::ptrdiff_t>(span.hi), side(span.wlo));
                        continue;
                    }
                    const std::size_t mid = span.lo + (span.hi - span.lo) / 2;
                    auto w = winding_at(mid);
                    if (!w) return w.error();
                    sign[mid] = side(w.value());
                    pending.push_back({span.lo, mid, span.wlo, w.value()});
                    pending.push_back({mid, span.hi, w.value(), span.whi});
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
