// Trimmed-surface tessellation: the method and its guarantees are in trimmed_surface.h. Steps, in order: Bézier patches
// and their grid plan; the derivative bound G and the trim flatness; trim polygons split at patch sides; per patch a
// constrained Delaunay triangulation of grid and trim points, refined; vertices evaluated on the surface and welded.
#include "geometry/surfaces/trimmed_surface.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <string>
#include <tuple>
#include <map>
#include <set>
#include <unordered_map>

#include "geometry/surfaces/bezier_patch.h"
#include "geometry/surfaces/constrained_triangulation.h"

namespace surfaced {
namespace {

using detail::ConstrainedTriangulation;

//! Grid points closer to a trim than this many grid spacings are left out (no sliver between trim and grid line).
constexpr double kExclusion = 0.4;
constexpr double kPi = 3.14159265358979323846;
//! Ratio of the largest to the smallest stretch of the map from the scaled plane to the surface over one triangle up
//! to which the refinement keeps asking for its surface angle alone. Beyond it (near a pole, where the length along u
//! shrinks to nothing while the plane keeps it), a triangle already well shaped in the plane is left as it is: its
//! thinness on the surface comes from the map, which circumcentres inserted in the plane do not change (every new
//! triangle there is as thin), so asking for it only inserts points until the budget runs out.
constexpr double kMildDistortion = 2;

std::uint64_t bits(double x) {
    x += 0.0;  // -0 as +0
    std::uint64_t out = 0;
    std::memcpy(&out, &x, sizeof out);
    return out;
}

//! Width of a grid's first and last interval relative to the others. Cells on a patch side get the weaker bound of
//! triangle_distance_bound (the correcting move may not leave the patch), so they are made narrower.
constexpr double kSideInterval = 0.6;

//! Grid line i of n across a patch, as a fraction of its side: intervals r s, s, ..., s, r s (r = kSideInterval) for
//! n >= 3, uniform below. A function of (i, n) alone, so patches sharing a side agree on its points.
double grid_fraction(int i, int n) {
    if (i <= 0) return 0;
    if (i >= n) return 1;
    if (n < 3) return static_cast<double>(i) / n;
    const double s = 1.0 / (n - 2 + 2 * kSideInterval);
    return (kSideInterval + (i - 1)) * s;
}

struct PatchInfo {
    double u0 = 0, u1 = 1, v0 = 0, v1 = 1;  //!< the patch's parameter rectangle
    int nu = 1, nv = 1;                     //!< grid segments
    PatchDerivativeBounds d;                //!< in patch units
    double lx = 1, ly = 1;                  //!< scaled size: about the surface's length along u and v
    //! Sides v = v0, v = v1, u = u0, u = u1 whose control points coincide: the side is one surface point (a pole)
    std::array<bool, 4> collapsed{};

    double x(double u) const { return (u - u0) * (lx / (u1 - u0)); }
    double y(double v) const { return (v - v0) * (ly / (v1 - v0)); }
    Vec2 scaled(Vec2 p) const { return {x(p.x), y(p.y)}; }
    Vec2 unscaled(Vec2 s) const { return {u0 + s.x * ((u1 - u0) / lx), v0 + s.y * ((v1 - v0) / ly)}; }
    double grid_u(int i) const { return i == 0 ? u0 : i == nu ? u1 : u0 + (u1 - u0) * grid_fraction(i, nu); }
    double grid_v(int j) const { return j == 0 ? v0 : j == nv ? v1 : v0 + (v1 - v0) * grid_fraction(j, nv); }
    double spacing() const { return std::min(lx / nu, ly / nv); }
    const BezierPatch* bezier = nullptr;  //!< the patch itself

    //! The interior bound of a triangle with these parameter corners (trimmed_surface.h): the smaller of the whole
    //! patch's equal-parameter bound and triangle_distance_bound (both guarantees). `enough`: a value at or below it
    //! is as good as any for the caller (triangle_distance_bound then skips its finer form).
    double bound(Vec2 a, Vec2 b, Vec2 c, double enough) const {
        const double h = (std::max({a.x, b.x, c.x}) - std::min({a.x, b.x, c.x})) / (u1 - u0);
        const double k = (std::max({a.y, b.y, c.y}) - std::min({a.y, b.y, c.y})) / (v1 - v0);
        const double whole = (d.uu * h * h + 2 * d.uv * h * k + d.vv * k * k) / 8;
        if (whole <= enough) return whole;
        const auto local = [&](Vec2 p) {
            return Vec2{std::clamp((p.x - u0) / (u1 - u0), 0.0, 1.0), std::clamp((p.y - v0) / (v1 - v0), 0.0, 1.0)};
        };
        // memoised by the parameter box, on which the bound depends alone (the refinement passes ask again, and
        // both triangles of a grid cell share their box); a value above the `enough` it was computed for is the finer
        // form's, final
        const std::array<std::uint64_t, 4> key{bits(std::min({a.x, b.x, c.x})), bits(std::max({a.x, b.x, c.x})),
                                               bits(std::min({a.y, b.y, c.y})), bits(std::max({a.y, b.y, c.y}))};
        const auto [it, inserted] = memo.emplace(key, Memo{});
        if (inserted || (it->second.value > enough && it->second.value <= it->second.enough)) {
            it->second.value = std::min(whole, triangle_distance_bound(*bezier, local(a), local(b), local(c), enough));
            it->second.enough = enough;
        }
        return it->second.value;
    }
    struct KeyHash {
        std::size_t operator()(const std::array<std::uint64_t, 4>& k) const {
            std::size_t h = 1469598103934665603ull;
            for (std::uint64_t w : k) h = (h ^ w) * 1099511628211ull;
            return h;
        }
    };
    struct Memo {
        double value = 0, enough = 0;
    };
    mutable std::unordered_map<std::array<std::uint64_t, 4>, Memo, KeyHash> memo;
    //! Grid cell (i, j) of the cu x cv grid: its corners counter-clockwise from (u_i, v_j).
    //! The same values as grid_u and grid_v (the patch's own sides exact), so vertices are shared by exact (u, v).
    std::array<Vec2, 4> cell(int i, int j, int cu, int cv) const {
        const auto line = [](int k, int n, double lo, double hi) {
            return k == 0 ? lo : k == n ? hi : lo + (hi - lo) * grid_fraction(k, n);
        };
        const double a = line(i, cu, u0, u1), b = line(i + 1, cu, u0, u1);
        const double c = line(j, cv, v0, v1), f = line(j + 1, cv, v0, v1);
        return {Vec2{a, c}, Vec2{b, c}, Vec2{b, f}, Vec2{a, f}};
    }
    //! Whether the cell's two triangles are within e (they share its box, on which the bound depends alone).
    bool cell_fits(const std::array<Vec2, 4>& q, double e) const { return bound(q[0], q[1], q[2], e) <= e; }
    //! Whether the fan of four triangles about the cell's centre is within e (each has half the cell's box in one
    //! direction: where a cell is too large by little, this costs two triangles instead of a finer grid everywhere).
    bool fan_fits(const std::array<Vec2, 4>& q, double e) const {
        const Vec2 m{0.5 * (q[0].x + q[2].x), 0.5 * (q[0].y + q[2].y)};
        for (int k = 0; k < 4; ++k)
            if (bound(q[static_cast<std::size_t>(k)], q[static_cast<std::size_t>((k + 1) % 4)], m, e) > e) return false;
        return true;
    }
    //! Triangles of the cu x cv grid within e (2 per cell, 4 per cell that needs its fan), or -1 when a cell fits
    //! neither way.
    long grid_cost(int cu, int cv, double e) const {
        long triangles = 0;
        for (int j = 0; j < cv; ++j)
            for (int i = 0; i < cu; ++i) {
                const auto q = cell(i, j, cu, cv);
                if (cell_fits(q, e))
                    triangles += 2;
                else if (fan_fits(q, e))
                    triangles += 4;
                else
                    return -1;
            }
        return triangles;
    }
};

struct UvKey {
    std::uint64_t u, v;
    bool operator==(const UvKey& o) const { return u == o.u && v == o.v; }
};
struct UvKeyHash {
    std::size_t operator()(const UvKey& k) const { return (k.u * 0x9E3779B97F4A7C15ull) ^ (k.v + (k.u >> 17)); }
};

//! Indices i of the intervals [breaks[i], breaks[i + 1]] holding x (one, or two when x is an interior break).
std::pair<std::size_t, std::size_t> intervals(const std::vector<double>& breaks, double x) {
    const std::size_t last = breaks.size() - 2;
    auto hi = static_cast<std::size_t>(std::upper_bound(breaks.begin(), breaks.end(), x) - breaks.begin());
    hi = hi == 0 ? 0 : std::min(hi - 1, last);
    const std::size_t lo = hi > 0 && x == breaks[hi] ? hi - 1 : hi;
    return {lo, hi};
}

//! The ring with a vertex added wherever a chord crosses an interior patch side.
std::vector<Vec2> split_at_sides(const std::vector<Vec2>& ring, const std::vector<double>& bu,
                                 const std::vector<double>& bv) {
    std::vector<Vec2> out;
    struct Cut {
        double t;
        Vec2 p;
        int axis;  //!< 0: on a u side, 1: on a v side
    };
    std::vector<Cut> cuts;
    for (std::size_t i = 0; i < ring.size(); ++i) {
        const Vec2 a = ring[i], b = ring[(i + 1) % ring.size()];
        out.push_back(a);
        cuts.clear();
        for (std::size_t k = 1; k + 1 < bu.size(); ++k) {
            const double u = bu[k];
            if ((a.x < u && u < b.x) || (b.x < u && u < a.x)) {
                const double t = (u - a.x) / (b.x - a.x);
                const double v = std::clamp(a.y + t * (b.y - a.y), std::min(a.y, b.y), std::max(a.y, b.y));
                cuts.push_back({t, {u, v}, 0});
            }
        }
        for (std::size_t k = 1; k + 1 < bv.size(); ++k) {
            const double v = bv[k];
            if ((a.y < v && v < b.y) || (b.y < v && v < a.y)) {
                const double t = (v - a.y) / (b.y - a.y);
                const double u = std::clamp(a.x + t * (b.x - a.x), std::min(a.x, b.x), std::max(a.x, b.x));
                cuts.push_back({t, {u, v}, 1});
            }
        }
        std::sort(cuts.begin(), cuts.end(), [](const Cut& p, const Cut& q) { return p.t < q.t; });
        for (std::size_t c = 0; c < cuts.size(); ++c) {
            Vec2 p = cuts[c].p;
            // through a patch corner (up to rounding): one vertex at the corner
            if (c + 1 < cuts.size() && cuts[c + 1].axis != cuts[c].axis && cuts[c + 1].t - cuts[c].t < 1e-12) {
                p = cuts[c].axis == 0 ? Vec2{cuts[c].p.x, cuts[c + 1].p.y} : Vec2{cuts[c + 1].p.x, cuts[c].p.y};
                ++c;
            }
            out.push_back(p);
        }
    }
    return out;
}

double distance_to_segment(Vec2 p, Vec2 a, Vec2 b) {
    const double dx = b.x - a.x, dy = b.y - a.y, len2 = dx * dx + dy * dy;
    const double t = len2 > 0 ? std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / len2, 0.0, 1.0) : 0.0;
    return std::hypot(a.x + t * dx - p.x, a.y + t * dy - p.y);
}

Vec2 circumcenter(Vec2 a, Vec2 b, Vec2 c) {
    const double bx = b.x - a.x, by = b.y - a.y, cx = c.x - a.x, cy = c.y - a.y;
    const double d = 2 * (bx * cy - by * cx);
    const double b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
    return {a.x + (cy * b2 - by * c2) / d, a.y + (bx * c2 - cx * b2) / d};
}

//! Output under construction: parameter vertices shared by exact (u, v), triangles over them.
struct ParamMesh {
    std::vector<Vec2> uvs;
    std::vector<Index> triangles;
    std::unordered_map<UvKey, Index, UvKeyHash> index;
    double interior_bound = 0;
    double trim_triangle_bound = 0;  //!< over the triangles with a trim vertex

    Index vertex(Vec2 uv) {
        const auto [it, inserted] = index.emplace(UvKey{bits(uv.x), bits(uv.y)}, static_cast<Index>(uvs.size()));
        if (inserted) uvs.push_back(uv);
        return it->second;
    }
    void add(const PatchInfo& patch, Vec2 a, Vec2 b, Vec2 c, bool at_trim, double tolerance) {
        triangles.push_back(vertex(a));
        triangles.push_back(vertex(b));
        triangles.push_back(vertex(c));
        const double bound = patch.bound(a, b, c, at_trim ? tolerance / 2 : tolerance);
        interior_bound = std::max(interior_bound, bound);
        if (at_trim) trim_triangle_bound = std::max(trim_triangle_bound, bound);
    }
};

//! Points added on patch sides by refinement (Ruppert's boundary splits), per line: (0, u) for a line u = const, (1, v)
//! for v = const; the coordinates along it. Both patches sharing a side take its points, so the sides still match.
using SidePoints = std::map<std::pair<int, double>, std::set<double>>;

struct PatchTrims {
    std::vector<std::pair<std::size_t, std::size_t>> vertices;  //!< (ring, index) in the closed rectangle
    std::vector<std::pair<std::size_t, std::size_t>> chords;    //!< (ring, first index) crossing the interior
};

//! Steps 3-4 of trimmed_surface.h for one patch with trims.
Status triangulate_patch(const BSplineSurface& surface, const PatchInfo& patch, const PatchTrims& trims,
                         const std::vector<std::vector<Vec2>>& rings, const PreparedTrims& polygons,
                         const SidePoints& side_points, double tolerance, double min_angle,
                         std::size_t max_refinement_points, ParamMesh& out, std::size_t& refinement_points,
                         std::vector<Vec2>& side_requests, bool last_round) {
    ConstrainedTriangulation cdt({0, 0}, {patch.x(patch.u1), patch.y(patch.v1)});
    std::vector<Vec2> uv{{patch.u0, patch.v0}, {patch.u1, patch.v0}, {patch.u1, patch.v1}, {patch.u0, patch.v1}};
    enum Kind : char { kGrid, kTrim, kInserted };
    std::vector<char> kind{kGrid, kGrid, kGrid, kGrid};
    const auto add = [&](Vec2 p, Kind k) {
        const int id = cdt.insert(patch.scaled(p));
        if (id == static_cast<int>(uv.size())) {
            uv.push_back(p);
            kind.push_back(k);
        } else if (id >= 0 && k == kTrim) {
            kind[static_cast<std::size_t>(id)] = kTrim;
        }
        return id;
    };
    const auto ring_point = [&](const std::pair<std::size_t, std::size_t>& at) { return rings[at.first][at.second]; };

    // the sides: corners, grid points not near a trim vertex on the same side, trim vertices on them
    for (int side = 0; side < 4; ++side) {
        const bool along_u = side < 2;
        const double fixed = side == 0 ? patch.v0 : side == 1 ? patch.v1 : side == 2 ? patch.u0 : patch.u1;
        const int count = along_u ? patch.nu : patch.nv;
        const double gap = kExclusion * (along_u ? patch.u1 - patch.u0 : patch.v1 - patch.v0) / count;
        std::vector<double> on_side;
        for (const auto& at : trims.vertices) {
            const Vec2 p = ring_point(at);
            if ((along_u ? p.y : p.x) == fixed) on_side.push_back(along_u ? p.x : p.y);
        }
        for (int i = 1; i < count; ++i) {
            const double t = along_u ? patch.grid_u(i) : patch.grid_v(i);
            if (std::any_of(on_side.begin(), on_side.end(), [&](double s) { return std::fabs(s - t) < gap; })) continue;
            if (add(along_u ? Vec2{t, fixed} : Vec2{fixed, t}, kGrid) < 0)
                return make_error(ErrorCode::Internal, "a grid point fell outside its patch");
        }
        const auto extra = side_points.find({along_u ? 1 : 0, fixed});
        if (extra == side_points.end()) continue;
        const double lo = along_u ? patch.u0 : patch.v0, hi = along_u ? patch.u1 : patch.v1;
        for (auto it = extra->second.upper_bound(lo); it != extra->second.end() && *it < hi; ++it)
            if (add(along_u ? Vec2{*it, fixed} : Vec2{fixed, *it}, kInserted) < 0)
                return make_error(ErrorCode::Internal, "a side point fell outside its patch");
    }
    std::vector<int> ids(trims.vertices.size(), -1);
    for (std::size_t k = 0; k < trims.vertices.size(); ++k) {
        const Vec2 p = ring_point(trims.vertices[k]);
        if (p.x == patch.u0 || p.x == patch.u1 || p.y == patch.v0 || p.y == patch.v1) ids[k] = add(p, kTrim);
    }
    // interior grid points away from the trims
    const int nu = patch.nu, nv = patch.nv;
    const double hx = patch.lx / nu, hy = patch.ly / nv, reach = kExclusion * patch.spacing();
    std::vector<char> excluded(static_cast<std::size_t>((nu + 1) * (nv + 1)), 0);
    for (const auto& [ring, k] : trims.chords) {
        const Vec2 a = patch.scaled(rings[ring][k]), b = patch.scaled(rings[ring][(k + 1) % rings[ring].size()]);
        // index ranges of a uniform grid, widened by one: grid_fraction is within one interval of i / n
        const int i0 = std::max(1, static_cast<int>(std::ceil((std::min(a.x, b.x) - reach) / hx)) - 1);
        const int i1 = std::min(nu - 1, static_cast<int>(std::floor((std::max(a.x, b.x) + reach) / hx)) + 1);
        const int j0 = std::max(1, static_cast<int>(std::ceil((std::min(a.y, b.y) - reach) / hy)) - 1);
        const int j1 = std::min(nv - 1, static_cast<int>(std::floor((std::max(a.y, b.y) + reach) / hy)) + 1);
        for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i)
                if (distance_to_segment(patch.scaled({patch.grid_u(i), patch.grid_v(j)}), a, b) < reach)
                    excluded[static_cast<std::size_t>(j * (nu + 1) + i)] = 1;
    }
    for (int j = 1; j < nv; ++j)
        for (int i = 1; i < nu; ++i)
            if (!excluded[static_cast<std::size_t>(j * (nu + 1) + i)])
                if (add({patch.grid_u(i), patch.grid_v(j)}, kGrid) < 0)
                    return make_error(ErrorCode::Internal, "a grid point fell outside its patch");
    for (std::size_t k = 0; k < trims.vertices.size(); ++k)
        if (ids[k] < 0) ids[k] = add(ring_point(trims.vertices[k]), kTrim);
    // the chords as constraints
    std::unordered_map<std::uint64_t, int> id_of;
    for (std::size_t k = 0; k < trims.vertices.size(); ++k)
        id_of[trims.vertices[k].first << 32 | trims.vertices[k].second] = ids[k];
    for (const auto& [ring, k] : trims.chords) {
        const auto a = id_of.find(ring << 32 | k), b = id_of.find(ring << 32 | ((k + 1) % rings[ring].size()));
        if (a == id_of.end() || b == id_of.end() || a->second < 0 || b->second < 0 ||
            !cdt.constrain(a->second, b->second))
            return make_error(ErrorCode::Internal, "trim chords cross after flattening (rounding): loops too close");
    }
    // The cells whose two triangles are over e get the fan about their centre that the grid fit found within e, as in a
    // patch without trims: its spokes and sides constrained, so the Delaunay flips cannot trade it for triangles across
    // two cells (larger boxes, over e). Only cells clear of the trims (no trim point within their circumcircle plus the
    // exclusion distance, so their corners are all grid points); the others are left to the refinement.
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            const auto q = patch.cell(i, j, nu, nv);
            if (patch.cell_fits(q, tolerance)) continue;
            const Vec2 m{0.5 * (q[0].x + q[2].x), 0.5 * (q[0].y + q[2].y)}, sm = patch.scaled(m);
            const Vec2 s0 = patch.scaled(q[0]);
            const double clear = std::hypot(sm.x - s0.x, sm.y - s0.y) + reach;
            const bool near = std::any_of(trims.chords.begin(), trims.chords.end(),
                                          [&](const auto& chord) {
                                              const auto& ring = rings[chord.first];
                                              return distance_to_segment(
                                                         sm, patch.scaled(ring[chord.second]),
                                                         patch.scaled(ring[(chord.second + 1) % ring.size()])) < clear;
                                          }) ||
                              std::any_of(trims.vertices.begin(), trims.vertices.end(), [&](const auto& at) {
                                  const Vec2 t = patch.scaled(ring_point(at));  // also those on the patch sides
                                  return std::hypot(t.x - sm.x, t.y - sm.y) < clear;
                              });
            if (near) continue;
            const int centre = add(m, kGrid);
            std::array<int, 4> corners{};
            for (std::size_t k = 0; k < 4; ++k) corners[k] = add(q[k], kGrid);  // already there: its index
            // (a constraint that cannot be made leaves the cell to the refinement, like one near a trim)
            for (std::size_t k = 0; k < 4 && centre >= 0 && corners[k] >= 0; ++k)
                if (!cdt.constrain(centre, corners[k]) || !cdt.constrain(corners[k], corners[(k + 1) % 4])) break;
        }
    cdt.restore_delaunay();

    // classification and refinement
    std::vector<int> label;
    std::vector<signed char> component_inside;
    const auto classify = [&] {
        const int count = cdt.components(label);
        component_inside.assign(static_cast<std::size_t>(count), -1);
        const auto& tris = cdt.triangles();
        const auto& pts = cdt.points();
        for (std::size_t t = 0; t < tris.size(); ++t) {
            signed char& inside = component_inside[static_cast<std::size_t>(label[t])];
            if (inside >= 0) continue;
            const Vec2 a = pts[static_cast<std::size_t>(tris[t].v[0])], b = pts[static_cast<std::size_t>(tris[t].v[1])],
                       c = pts[static_cast<std::size_t>(tris[t].v[2])];
            inside =
                inside_trimmed_domain(polygons, patch.unscaled({(a.x + b.x + c.x) / 3, (a.y + b.y + c.y) / 3})) ? 1 : 0;
        }
    };
    // the smallest angle of a triangle on the surface (its corners evaluated once), which the refinement improves
    std::vector<Vec3> corner_points;
    const auto evaluate_corners = [&] {
        while (corner_points.size() < uv.size()) {
            const Vec2 q = uv[corner_points.size()];
            auto point = evaluate(surface, q.x, q.y);
            corner_points.push_back(point ? *point : Vec3{});
        }
    };
    const auto surface_angle = [&](const std::array<int, 3>& v) {
        evaluate_corners();
        const auto at = [&](int i) { return corner_points[static_cast<std::size_t>(v[static_cast<std::size_t>(i)])]; };
        double smallest = 180;
        for (int i = 0; i < 3; ++i) {
            const Vec3 p = at((i + 1) % 3) - at(i), q = at((i + 2) % 3) - at(i);
            smallest = std::min(smallest, std::atan2(norm(cross(p, q)), dot(p, q)) * 180.0 / kPi);
        }
        return smallest;
    };
    // the smallest angle of a triangle in the scaled plane, where the circumcentre insertion works
    const auto plane_angle = [&](const std::array<int, 3>& v) {
        const auto& pts = cdt.points();
        const auto at = [&](int i) { return pts[static_cast<std::size_t>(v[static_cast<std::size_t>(i)])]; };
        double smallest = 180;
        for (int i = 0; i < 3; ++i) {
            const Vec2 o = at(i), p{at((i + 1) % 3).x - o.x, at((i + 1) % 3).y - o.y},
                       q{at((i + 2) % 3).x - o.x, at((i + 2) % 3).y - o.y};
            smallest =
                std::min(smallest, std::atan2(std::fabs(p.x * q.y - p.y * q.x), p.x * q.x + p.y * q.y) * 180.0 / kPi);
        }
        return smallest;
    };
    // the ratio of the largest to the smallest singular value of the affine map taking the triangle in the scaled
    // plane to its triangle on the surface (kMildDistortion)
    const auto distortion = [&](const std::array<int, 3>& v) {
        evaluate_corners();
        const auto& pts = cdt.points();
        const auto p = [&](int i) { return pts[static_cast<std::size_t>(v[static_cast<std::size_t>(i)])]; };
        const auto x = [&](int i) { return corner_points[static_cast<std::size_t>(v[static_cast<std::size_t>(i)])]; };
        // the affine map from the plane triangle to the surface triangle: A = X P^-1 (X: 3 x 2 edges, P: 2 x 2)
        const double p11 = p(1).x - p(0).x, p21 = p(1).y - p(0).y, p12 = p(2).x - p(0).x, p22 = p(2).y - p(0).y;
        const double det = p11 * p22 - p12 * p21;
        if (!(std::fabs(det) > 0)) return 1e300;
        const Vec3 x1 = x(1) - x(0), x2 = x(2) - x(0);
        const Vec3 a1 = (p22 * x1 - p21 * x2) * (1 / det), a2 = (p11 * x2 - p12 * x1) * (1 / det);
        const double g11 = dot(a1, a1), g12 = dot(a1, a2), g22 = dot(a2, a2);
        const double mean = 0.5 * (g11 + g22), radius = std::hypot(0.5 * (g11 - g22), g12);
        const double low = mean - radius;
        return low > 0 ? std::sqrt((mean + radius) / low) : 1e300;
    };
    const std::size_t budget = max_refinement_points > 0 ? max_refinement_points : 16 * uv.size() + 4096;
    std::set<std::pair<int, int>> requested;  //!< sides whose split this round asked for
    std::size_t inserted = 0;
    for (int pass = 0; pass < 400 && inserted < budget; ++pass) {
        classify();
        struct Bad {
            int t;
            std::array<int, 3> v;
            bool size;
        };
        std::vector<Bad> bad;
        const auto& tris = cdt.triangles();
        for (std::size_t t = 0; t < tris.size(); ++t) {
            if (!component_inside[static_cast<std::size_t>(label[t])]) continue;
            const auto& v = tris[t].v;
            const auto at = [&](int i) { return uv[static_cast<std::size_t>(v[static_cast<std::size_t>(i)])]; };
            const auto is = [&](int i, Kind k) {
                return kind[static_cast<std::size_t>(v[static_cast<std::size_t>(i)])] == k;
            };
            // triangles at a trim get half the tolerance: the trim bound adds the flattening's share (header)
            const bool at_trim = is(0, kTrim) || is(1, kTrim) || is(2, kTrim);
            const double limit = at_trim ? tolerance / 2 : tolerance;
            const bool size = patch.bound(at(0), at(1), at(2), limit) > limit;
            const bool near_trim = !is(0, kGrid) || !is(1, kGrid) || !is(2, kGrid);
            if (size || (near_trim && surface_angle(v) < min_angle &&
                         (plane_angle(v) < min_angle || distortion(v) <= kMildDistortion)))
                bad.push_back({static_cast<int>(t), v, size});
        }
        if (bad.empty()) break;
        bool progress = false;
        for (const Bad& b : bad) {
            if (inserted >= budget) break;
            const auto& now = cdt.triangles()[static_cast<std::size_t>(b.t)];
            if (now.v != b.v) continue;  // changed by an earlier insertion of this pass
            const auto& pts = cdt.points();
            const Vec2 a = pts[static_cast<std::size_t>(b.v[0])], p = pts[static_cast<std::size_t>(b.v[1])],
                       c = pts[static_cast<std::size_t>(b.v[2])];
            int id = cdt.insert_free(circumcenter(a, p, c), b.t);
            if (id < 0 && cdt.refused_side().first >= 0 && !last_round) {
                // Split that side (in the next round, in both patches), and leave the triangle until then. For an
                // angle, not when the side is already no longer than twice the triangle's shortest edge: the bad
                // angle then comes from the input (a trim meeting the side at a small angle), and halving the side
                // again would only cascade towards that corner.
                const auto [first, second] = cdt.refused_side();
                const std::pair<int, int> side{std::min(first, second), std::max(first, second)};
                if (requested.count(side)) continue;
                // Never a collapsed side (a pole): its points are all one surface point, so splitting it adds
                // nothing there but more triangles whose circumcentres fall beyond it again.
                const Vec2 u0 = uv[static_cast<std::size_t>(first)], u1 = uv[static_cast<std::size_t>(second)];
                const bool pole = (u0.y == u1.y && patch.collapsed[u0.y == patch.v0 ? 0 : 1]) ||
                                  (u0.x == u1.x && patch.collapsed[u0.x == patch.u0 ? 2 : 3]);
                const Vec2 s0 = pts[static_cast<std::size_t>(first)], s1 = pts[static_cast<std::size_t>(second)];
                const auto length = [](Vec2 x, Vec2 y) { return std::hypot(x.x - y.x, x.y - y.y); };
                if (!pole && (b.size || length(s0, s1) > 2 * std::min({length(a, p), length(p, c), length(c, a)}))) {
                    side_requests.push_back({0.5 * (u0.x + u1.x), 0.5 * (u0.y + u1.y)});
                    requested.insert(side);
                    continue;
                }
            }
            if (id < 0 && b.size) id = cdt.insert_free({(a.x + p.x + c.x) / 3, (a.y + p.y + c.y) / 3}, b.t, false);
            if (id < 0 || id != static_cast<int>(uv.size())) continue;
            uv.push_back(patch.unscaled(cdt.points()[static_cast<std::size_t>(id)]));
            kind.push_back(kInserted);
            ++inserted;
            progress = true;
        }
        if (!progress) break;
    }
    refinement_points += inserted;
    classify();
    const auto& tris = cdt.triangles();
    for (std::size_t t = 0; t < tris.size(); ++t) {
        if (!component_inside[static_cast<std::size_t>(label[t])]) continue;
        const auto& v = tris[t].v;
        const bool at_trim = kind[static_cast<std::size_t>(v[0])] == kTrim ||
                             kind[static_cast<std::size_t>(v[1])] == kTrim ||
                             kind[static_cast<std::size_t>(v[2])] == kTrim;
        out.add(patch, uv[static_cast<std::size_t>(v[0])], uv[static_cast<std::size_t>(v[1])],
                uv[static_cast<std::size_t>(v[2])], at_trim, tolerance);
    }
    return Ok{};
}

}  // namespace

Result<TrimmedTessellation> tessellate(const TrimmedSurface& trimmed, const TrimmedTessellationOptions& options) {
    const double e = options.tolerance;
    if (!(std::isfinite(e) && e > 0))
        return make_error(ErrorCode::InvalidArgument, "tolerance must be a finite number > 0");
    if (!(options.min_angle_degrees > 0 && options.min_angle_degrees <= 30))
        return make_error(ErrorCode::InvalidArgument, "min_angle_degrees must be in (0, 30]");
    if (!(std::isfinite(options.closure_tolerance) && options.closure_tolerance >= 0))
        return make_error(ErrorCode::InvalidArgument, "closure_tolerance must be a finite number >= 0");
    const BSplineSurface& surface = trimmed.surface;

    // 1. Bézier patches and their grids for e
    auto bezier = to_bezier(surface, options.cancel);
    if (!bezier) return bezier.error();
    const std::vector<double>& bu = bezier->breaks_u;
    const std::vector<double>& bv = bezier->breaks_v;
    const std::size_t columns = bu.size() - 1, rows = bv.size() - 1;
    TessellationOptions grid_options;
    grid_options.tolerance = e;
    grid_options.max_segments = options.max_segments;
    auto plan = plan_tessellation(bezier->patches, grid_options);
    if (!plan) return plan.error();
    if (plan->triangles > options.max_triangles)
        return make_error(ErrorCode::BudgetExceeded, "the tessellation needs at least " +
                                                         std::to_string(plan->triangles) + " triangles; the limit is " +
                                                         std::to_string(options.max_triangles));
    std::vector<PatchInfo> patches(bezier->patches.size());
    double g = 0;
    for (std::size_t b = 0; b < rows; ++b)
        for (std::size_t a = 0; a < columns; ++a) {
            const std::size_t p = b * columns + a;
            const BezierPatch& bp = bezier->patches[p];
            PatchInfo& info = patches[p];
            info.u0 = bu[a];
            info.u1 = bu[a + 1];
            info.v0 = bv[b];
            info.v1 = bv[b + 1];
            info.nu = plan->segments[p].nu;
            info.nv = plan->segments[p].nv;
            info.d = derivative_bounds(bp);
            info.bezier = &bp;
            // mean lengths of the net's rows and columns: the scale that makes the parameter plane about isometric
            double lx = 0, ly = 0;
            for (int j = 0; j <= bp.degree_v; ++j)
                for (int i = 0; i < bp.degree_u; ++i) lx += norm(bp.at(i + 1, j) - bp.at(i, j));
            for (int i = 0; i <= bp.degree_u; ++i)
                for (int j = 0; j < bp.degree_v; ++j) ly += norm(bp.at(i, j + 1) - bp.at(i, j));
            lx /= bp.degree_v + 1;
            ly /= bp.degree_u + 1;
            const double fallback = std::max({lx, ly, 1e-300});
            info.lx = lx > 1e-9 * fallback ? lx : fallback;
            info.ly = ly > 1e-9 * fallback ? ly : fallback;
            const auto same = [&](int i0, int j0, int di, int dj, int count) {
                for (int k = 1; k <= count; ++k)
                    if (!(bp.at(i0 + k * di, j0 + k * dj) == bp.at(i0, j0))) return false;
                return true;
            };
            info.collapsed = {same(0, 0, 1, 0, bp.degree_u), same(0, bp.degree_v, 1, 0, bp.degree_u),
                              same(0, 0, 0, 1, bp.degree_v), same(bp.degree_u, 0, 0, 1, bp.degree_v)};
            g = std::max(g, std::hypot(info.d.u / (info.u1 - info.u0), info.d.v / (info.v1 - info.v0)));
        }
    // Grid counts: the plan's, scaled by one common factor f (so counts stay equal along shared sides), the smallest
    // found (bisection, 10 steps) for which every grid cell of every patch is within e by its local bound.
    {
        const auto counts = [&](const PatchInfo& info, double f) {
            return std::pair{std::max(1, static_cast<int>(std::ceil(f * info.nu))),
                             std::max(1, static_cast<int>(std::ceil(f * info.nv)))};
        };
        const auto cost = [&](double f) {  // triangles of all grids, or -1 when a cell fits neither way
            long total = 0;
            for (const PatchInfo& info : patches) {
                const auto [cu, cv] = counts(info, f);
                const long c = info.grid_cost(cu, cv, e);
                if (c < 0) return -1L;
                total += c;
            }
            return total;
        };
        const auto fits = [&](double f) { return cost(f) >= 0; };
        double pass = 1.0, fail = 0.25;
        while (!fits(pass)) {  // the narrower side intervals widen the others a little
            fail = pass;
            pass *= 1.25;
            for (const PatchInfo& info : patches)
                if (std::max(counts(info, pass).first, counts(info, pass).second) > options.max_segments)
                    return make_error(ErrorCode::BudgetExceeded, "tolerance " + std::to_string(e) +
                                                                     " needs more than " +
                                                                     std::to_string(options.max_segments) +
                                                                     " grid segments along one direction of a patch");
        }
        if (fail == 0.25 && fits(fail)) pass = fail;
        for (int step = 0; step < 10 && pass > fail; ++step) {
            const double mid = 0.5 * (pass + fail);
            (fits(mid) ? pass : fail) = mid;
        }
        // the smallest grid that fits may need many fans: a slightly finer one can have fewer triangles
        long best = cost(pass);
        const double smallest = pass;
        for (int k = 1; k <= 8; ++k) {
            const double f = smallest * (1 + 0.04 * k);
            long cells = 0;  // 2 triangles per cell at least: no need to bound a grid that cannot do better
            for (const PatchInfo& info : patches)
                cells += static_cast<long>(counts(info, f).first) * counts(info, f).second;
            if (2 * cells >= best) continue;
            const long c = cost(f);
            if (c >= 0 && c < best) {
                best = c;
                pass = f;
            }
        }
        for (PatchInfo& info : patches) std::tie(info.nu, info.nv) = counts(info, pass);
    }
    const auto patch_at = [&](Vec2 p) -> const PatchInfo& {
        return patches[intervals(bv, p.y).second * columns + intervals(bu, p.x).second];
    };

    // 2. trims flattened to d, chords no longer than their patch's grid spacing
    const auto [du0, du1] = domain_u(surface);
    const auto [dv0, dv1] = domain_v(surface);
    const double flatness = g > 0 ? 0.9 * e / (2 * g) : 1e-4 * std::hypot(du1 - du0, dv1 - dv0);
    const auto refine = [&](Vec2 a, Vec2 b) {
        const PatchInfo& patch = patch_at({(a.x + b.x) / 2, (a.y + b.y) / 2});
        const Vec2 sa = patch.scaled(a), sb = patch.scaled(b);
        // about sqrt(1/2) of the grid spacing: triangles at a trim are held to half the tolerance
        return std::hypot(sb.x - sa.x, sb.y - sa.y) > 0.7 * patch.spacing();
    };
    const std::vector<double> cut_u(bu.begin() + 1, bu.end() - 1), cut_v(bv.begin() + 1, bv.end() - 1);
    TrimValidation prepared =
        prepare_trims(trimmed, flatness, options.closure_tolerance, options.max_trim_segments, refine, cut_u, cut_v);
    if (!prepared.ok()) return to_geo_error(*prepared.error);
    TrimmedTessellation out;
    out.derivative_bound = g;
    out.trim_flatness = flatness;
    out.max_gap = prepared.trims.max_gap;
    out.loops = prepared.trims.loops;

    // 3. polygons cut at patch sides, their vertices and chords handed to the patches
    std::vector<std::vector<Vec2>> rings;
    PreparedTrims split = prepared.trims;
    for (TrimPolygon& loop : split.loops) {
        loop.points = split_at_sides(loop.points, bu, bv);
        rings.push_back(loop.points);
    }
    std::vector<PatchTrims> patch_trims(patches.size());
    for (std::size_t r = 0; r < rings.size(); ++r)
        for (std::size_t k = 0; k < rings[r].size(); ++k) {
            const Vec2 p = rings[r][k];
            const auto [a0, a1] = intervals(bu, p.x);
            const auto [b0, b1] = intervals(bv, p.y);
            for (std::size_t b = b0; b <= b1; ++b)
                for (std::size_t a = a0; a <= a1; ++a) patch_trims[b * columns + a].vertices.push_back({r, k});
            const Vec2 q = rings[r][(k + 1) % rings[r].size()];
            const bool along_side = (p.x == q.x && std::binary_search(bu.begin(), bu.end(), p.x)) ||
                                    (p.y == q.y && std::binary_search(bv.begin(), bv.end(), p.y));
            if (along_side) continue;  // on a patch side: an edge of both patches' triangulations already
            const Vec2 m{(p.x + q.x) / 2, (p.y + q.y) / 2};
            patch_trims[intervals(bv, m.y).second * columns + intervals(bu, m.x).second].chords.push_back({r, k});
        }

    // 4. per patch: the plain grid where no trim enters, else the refined constrained triangulation; rounds until
    // no patch asks for a side to be split (or kRounds)
    constexpr int kRounds = 6;
    SidePoints side_points;
    std::vector<Vec2> side_requests;
    ParamMesh param;
    const auto has_side_points = [&](const PatchInfo& patch) {
        for (const auto& [line, fixed, lo, hi] :
             {std::tuple{1, patch.v0, patch.u0, patch.u1}, std::tuple{1, patch.v1, patch.u0, patch.u1},
              std::tuple{0, patch.u0, patch.v0, patch.v1}, std::tuple{0, patch.u1, patch.v0, patch.v1}}) {
            const auto it = side_points.find({line, fixed});
            if (it != side_points.end()) {
                const auto next = it->second.upper_bound(lo);
                if (next != it->second.end() && *next < hi) return true;
            }
        }
        return false;
    };
    for (int round = 0; round < kRounds; ++round) {
        param = ParamMesh{};
        out.refinement_points = 0;
        side_requests.clear();
        for (std::size_t p = 0; p < patches.size(); ++p) {
            if (options.cancel.requested())
                return make_error(ErrorCode::Cancelled, "tessellation cancelled at patch " + std::to_string(p) +
                                                            " of " + std::to_string(patches.size()) +
                                                            " (deadline or shutdown)");
            const PatchInfo& patch = patches[p];
            if (patch_trims[p].vertices.empty() && !has_side_points(patch)) {
                if (!inside_trimmed_domain(split, {(patch.u0 + patch.u1) / 2, (patch.v0 + patch.v1) / 2})) continue;
                for (int j = 0; j < patch.nv; ++j)
                    for (int i = 0; i < patch.nu; ++i) {
                        const auto q = patch.cell(i, j, patch.nu, patch.nv);
                        if (patch.cell_fits(q, e)) {
                            param.add(patch, q[0], q[1], q[2], false, e);
                            param.add(patch, q[0], q[2], q[3], false, e);
                        } else {  // the grid fit found its fan within e
                            const Vec2 m{0.5 * (q[0].x + q[2].x), 0.5 * (q[0].y + q[2].y)};
                            for (std::size_t k = 0; k < 4; ++k) param.add(patch, q[k], q[(k + 1) % 4], m, false, e);
                        }
                    }
            } else if (auto ok = triangulate_patch(surface, patch, patch_trims[p], rings, split, side_points, e,
                                                   options.min_angle_degrees, options.max_refinement_points, param,
                                                   out.refinement_points, side_requests, round + 1 == kRounds);
                       !ok) {
                return ok.error();
            }
            if (param.triangles.size() / 3 > options.max_triangles)
                return make_error(ErrorCode::BudgetExceeded, "the tessellation needs more than " +
                                                                 std::to_string(options.max_triangles) + " triangles");
        }
        if (side_requests.empty()) break;
        for (const Vec2& q : side_requests) {
            // on a line u = const (a break value) or v = const
            if (std::binary_search(bu.begin(), bu.end(), q.x)) side_points[{0, q.x}].insert(q.y);
            if (std::binary_search(bv.begin(), bv.end(), q.y)) side_points[{1, q.y}].insert(q.x);
        }
    }

    // 5. evaluation on the surface, 3D weld (seams, poles), collapsed triangles dropped
    std::vector<Vec3> positions(param.uvs.size()), normals(param.uvs.size());
    Box3 box;
    for (std::size_t k = 0; k < param.uvs.size(); ++k) {
        auto point = evaluate(surface, param.uvs[k].x, param.uvs[k].y);
        auto normal = unit_normal(surface, param.uvs[k].x, param.uvs[k].y);
        if (!point || !normal) return make_error(ErrorCode::Internal, "a mesh vertex fell outside the domain");
        positions[k] = *point;
        normals[k] = *normal;
        box.add(positions[k]);
    }
    const double weld = 1e-10 * std::max(box.diagonal(), 1e-300);
    std::unordered_map<UvKey, std::vector<Index>, UvKeyHash> cells;  // (x, y) cell -> welded vertices (z checked)
    std::vector<Index> welded(positions.size());
    PolygonMesh& mesh = out.mesh;
    std::vector<Vec3> normal_sums;
    for (std::size_t k = 0; k < positions.size(); ++k) {
        const Vec3& q = positions[k];
        const auto cx = static_cast<std::int64_t>(std::floor(q.x / weld)),
                   cy = static_cast<std::int64_t>(std::floor(q.y / weld));
        Index found = kInvalidIndex;
        for (std::int64_t y = cy - 1; y <= cy + 1 && found == kInvalidIndex; ++y)
            for (std::int64_t x = cx - 1; x <= cx + 1 && found == kInvalidIndex; ++x) {
                const auto it = cells.find({static_cast<std::uint64_t>(x), static_cast<std::uint64_t>(y)});
                if (it == cells.end()) continue;
                for (Index w : it->second)
                    if (norm(mesh.positions[w] - q) <= weld) {
                        found = w;
                        break;
                    }
            }
        if (found == kInvalidIndex) {
            found = static_cast<Index>(mesh.positions.size());
            mesh.positions.push_back(q);
            normal_sums.push_back(normals[k]);
            cells[{static_cast<std::uint64_t>(cx), static_cast<std::uint64_t>(cy)}].push_back(found);
        } else {
            normal_sums[found] += normals[k];
        }
        welded[k] = found;
    }
    mesh.uvs = param.uvs;
    for (std::size_t t = 0; t + 2 < param.triangles.size(); t += 3) {
        const Index a = welded[param.triangles[t]], b = welded[param.triangles[t + 1]],
                    c = welded[param.triangles[t + 2]];
        if (a == b || b == c || a == c) continue;
        mesh.add_face({a, b, c});
        for (int i = 0; i < 3; ++i) mesh.uv_indices.push_back(param.triangles[t + static_cast<std::size_t>(i)]);
    }
    mesh.normals.resize(mesh.positions.size());
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        const double length = norm(normal_sums[v]);
        mesh.normals[v] = length > 0 ? normal_sums[v] * (1.0 / length) : Vec3{0, 0, 1};
    }
    out.interior_bound = param.interior_bound;
    out.trim_bound = g * (flatness + out.max_gap) + param.trim_triangle_bound;
    out.bound = std::max(out.interior_bound, out.trim_bound);
    return out;
}

}  // namespace surfaced
