// The limit surface as a conforming set of bicubic Bézier patches at one isolation level (see the header).
#include "geometry/subdivision/limit_patches.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <string>
#include <utility>

namespace surfaced {

namespace {

using Grid = std::array<Vec3, 16>;  // 4 x 4 control points, u varying fastest

//! Uniform cubic B-spline control points -> the Bézier control points of the same cubic on [0, 1], along one line.
void bspline_to_bezier_1d(const Vec3 (&b)[4], Vec3 (&out)[4]) {
    out[0] = (b[0] + 4.0 * b[1] + b[2]) * (1.0 / 6.0);
    out[1] = (2.0 * b[1] + b[2]) * (1.0 / 3.0);
    out[2] = (b[1] + 2.0 * b[2]) * (1.0 / 3.0);
    out[3] = (b[1] + 4.0 * b[2] + b[3]) * (1.0 / 6.0);
}

//! The blossom of the cubic with Bézier control points `p` at (x1, x2, x3): de Casteljau with one parameter per step.
Vec3 blossom(const Vec3 (&p)[4], double x1, double x2, double x3) {
    Vec3 a[3];
    for (int i = 0; i < 3; ++i) a[i] = (1 - x1) * p[i] + x1 * p[i + 1];
    Vec3 b[2];
    for (int i = 0; i < 2; ++i) b[i] = (1 - x2) * a[i] + x2 * a[i + 1];
    return (1 - x3) * b[0] + x3 * b[1];
}

//! The cubic restricted to [t0, t1], as Bézier control points over [0, 1].
void restrict_1d(const Vec3 (&p)[4], double t0, double t1, Vec3 (&out)[4]) {
    out[0] = blossom(p, t0, t0, t0);
    out[1] = blossom(p, t0, t0, t1);
    out[2] = blossom(p, t0, t1, t1);
    out[3] = blossom(p, t1, t1, t1);
}

//! Applies a 1D map to every row (along u), then every column (along v).
template <class Map>
Grid separable(const Grid& in, Map&& map) {
    Grid rows{};
    for (int j = 0; j < 4; ++j) {
        const Vec3 line[4] = {in[4 * j], in[4 * j + 1], in[4 * j + 2], in[4 * j + 3]};
        Vec3 out[4];
        map(line, out, 0);
        for (int i = 0; i < 4; ++i) rows[4 * j + i] = out[i];
    }
    Grid result{};
    for (int i = 0; i < 4; ++i) {
        const Vec3 line[4] = {rows[i], rows[4 + i], rows[8 + i], rows[12 + i]};
        Vec3 out[4];
        map(line, out, 1);
        for (int j = 0; j < 4; ++j) result[4 * j + i] = out[j];
    }
    return result;
}

//! The cubic through p0..p3 at parameters 0, 1/3, 2/3, 1, as Bézier control points.
void interpolate_1d(const Vec3 (&p)[4], Vec3 (&out)[4]) {
    out[0] = p[0];
    out[1] = (-5.0 * p[0] + 18.0 * p[1] - 9.0 * p[2] + 2.0 * p[3]) * (1.0 / 6.0);
    out[2] = (2.0 * p[0] - 9.0 * p[1] + 18.0 * p[2] - 5.0 * p[3]) * (1.0 / 6.0);
    out[3] = p[3];
}

BezierPatch to_patch(const Grid& grid) {
    BezierPatch patch;
    patch.degree_u = patch.degree_v = 3;
    patch.points.assign(grid.begin(), grid.end());
    return patch;
}

//! Levels prepared below the layout's for bounding the approximated squares (and sampling them): the leaves left
//! without a patch there, next to irregular vertices, are 2^-10 of the square's side, and their hull (shrinking by
//! the subdominant eigenvalue per level) a small part of the bound.
constexpr int kBoundLevels = 10;

//! Every leaf of every face prepared to `levels`, with the patches it needs, for one level.
struct Layout {
    std::vector<LimitFaceSurface> surfaces;  //!< per face (holes: none)
    std::vector<std::uint32_t> surface_face;
    struct Square {
        std::size_t surface;
        LimitFaceSurface::Leaf leaf;  //!< the square itself when it is not a patch leaf's part
        Grid bezier;
        bool exact;
    };
    std::vector<Square> approximate;  //!< the squares without a B-spline patch, approximated
    double max_error = 0;             //!< bounded (bound_error)
};

Result<Grid> approximate_square(const LimitFaceSurface& surface, const LimitFaceSurface::Leaf& leaf) {
    Grid samples{};
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
            // the square's corners and thirds, computed so that a shared edge gives the same parameters from both
            const double u = i == 3 ? leaf.u0 + leaf.size : leaf.u0 + leaf.size * (i / 3.0);
            const double v = j == 3 ? leaf.v0 + leaf.size : leaf.v0 + leaf.size * (j / 3.0);
            auto sample = surface.evaluate(u, v);
            if (!sample) return sample.error();
            samples[4 * j + i] = sample->position;
        }
    return separable(samples, [](const Vec3(&line)[4], Vec3(&out)[4], int) { interpolate_1d(line, out); });
}

//! The largest norm of the bicubic Bézier patch `d` (a difference of two patches) over its square, bounded from
//! above: its largest control point, on quarters of the square (de Casteljau halves) where that exceeds both
//! `floor` (a value already reached elsewhere) and the largest corner (a value it takes) by more than 1%, up to
//! `depth` times.
double bounded_norm(const Grid& d, int depth, double floor) {
    double coefficients = 0;
    for (const Vec3& p : d) coefficients = std::max(coefficients, norm(p));
    const double corners = std::max(std::max(norm(d[0]), norm(d[3])), std::max(norm(d[12]), norm(d[15])));
    if (coefficients <= floor || coefficients <= 1.01 * corners || depth == 0) return coefficients;
    double worst = std::max(floor, corners);
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
            const Grid quarter = separable(d, [&](const Vec3(&line)[4], Vec3(&out)[4], int direction) {
                const double a = 0.5 * (direction == 0 ? i : j);
                restrict_1d(line, a, a + 0.5, out);
            });
            worst = std::max(worst, bounded_norm(quarter, depth - 1, worst));
        }
    return worst;
}

//! The largest distance between the approximating patch `grid` over `square` and the limit surface, bounded: over
//! each deeper leaf inside the square that is a B-spline patch, the difference of the two as Bézier patches of the
//! leaf (the approximation cut to the leaf, the leaf's B-spline converted), whose largest control point bounds it
//! (the Bernstein basis is a partition of unity); over a leaf without a patch, the farthest control point of the
//! cut approximation from a centre plus the farthest point of the hull holding the limit surface there.
//! `deep`: the face's leaves at the prepared levels. `floor`: a bound already reached elsewhere; the result is the
//! larger of it and this square's bound (parts that stay below it are not refined).
double bound_error(const LimitFaceSurface& surface, const LimitFaceSurface::Leaf& square, const Grid& grid,
                   const std::vector<LimitFaceSurface::Leaf>& deep, double floor) {
    double worst = floor;
    for (const LimitFaceSurface::Leaf& leaf : deep) {
        const double s0 = (leaf.u0 - square.u0) / square.size, t0 = (leaf.v0 - square.v0) / square.size;
        if (s0 < 0 || t0 < 0 || s0 >= 1 || t0 >= 1) continue;  // another square's
        const double width = leaf.size / square.size;
        const Grid cut = separable(grid, [&](const Vec3(&line)[4], Vec3(&out)[4], int direction) {
            const double a = direction == 0 ? s0 : t0;
            restrict_1d(line, a, a + width, out);
        });
        if (leaf.bspline) {
            const Grid exact = separable(
                *leaf.bspline, [](const Vec3(&line)[4], Vec3(&out)[4], int) { bspline_to_bezier_1d(line, out); });
            Grid difference;
            for (int i = 0; i < 16; ++i) difference[i] = cut[i] - exact[i];
            worst = std::max(worst, bounded_norm(difference, 4, worst));
            continue;
        }
        const std::vector<Vec3> hull = surface.hull_points(leaf);
        // |B(x) - S(x)| <= |B(x) - c| + |c - S(x)|, with c the middle of the hull's bounding box
        Box3 box;
        for (const Vec3& p : hull) box.add(p);
        const Vec3 centre = 0.5 * (box.min + box.max);
        double to_patch = 0, to_hull = 0;
        for (const Vec3& p : cut) to_patch = std::max(to_patch, norm(p - centre));
        for (const Vec3& p : hull) to_hull = std::max(to_hull, norm(p - centre));
        worst = std::max(worst, to_patch + to_hull);
    }
    return worst;
}

Result<Layout> prepare(const LimitSurfaceEvaluator& evaluator, const PolygonMesh& mesh, int levels,
                       const Cancel& cancel) {
    Layout layout;
    layout.surfaces.reserve(mesh.face_count());
    const int bound_levels = std::min(levels + kBoundLevels, evaluator.max_level());
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        if (cancel.requested()) return make_error(ErrorCode::Cancelled, "cancelled while isolating the limit patches");
        if (evaluator.is_hole(f)) continue;  // no limit surface, no patches
        // prepared deeper than the layout, for the bound, and so that sampling near an irregular vertex is a
        // patch evaluation rather than a descent from the base face
        auto surface = evaluator.face_surface(f, bound_levels);
        if (!surface) return surface.error();
        const std::size_t index = layout.surfaces.size();
        layout.surfaces.push_back(std::move(surface.value()));
        layout.surface_face.push_back(static_cast<std::uint32_t>(f));
        std::vector<LimitFaceSurface::Leaf> deep;
        for (const LimitFaceSurface::Leaf& leaf : layout.surfaces.back().leaves(levels)) {
            if (leaf.bspline) continue;
            auto grid = approximate_square(layout.surfaces[index], leaf);
            if (!grid) return grid.error();
            if (deep.empty()) deep = layout.surfaces[index].leaves(bound_levels);
            layout.max_error = std::max(
                layout.max_error, bound_error(layout.surfaces[index], leaf, grid.value(), deep, layout.max_error));
            layout.approximate.push_back({index, leaf, grid.value(), false});
        }
    }
    return layout;
}

//! Bounding-box diagonal of the patches' control points.
double diagonal(const std::vector<BezierPatch>& patches) {
    Box3 box;
    for (const BezierPatch& patch : patches)
        for (const Vec3& p : patch.points) box.add(p);
    return box.diagonal();
}

bool close(const Vec3& a, const Vec3& b, double tolerance) {
    return std::abs(a[0] - b[0]) <= tolerance && std::abs(a[1] - b[1]) <= tolerance &&
           std::abs(a[2] - b[2]) <= tolerance;
}

std::size_t find_root(std::vector<std::size_t>& parent, std::size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
}

//! Makes positions that differ only by rounding bit-identical: corners, then the inner points of shared edges.
void make_shared_edges_identical(std::vector<BezierPatch>& patches) {
    const double tolerance = 1e-9 * diagonal(patches);
    static constexpr int kCorner[4] = {0, 3, 15, 12};
    // corners: clusters of points within the tolerance (a sweep along x, then union-find)
    const std::size_t count = patches.size() * 4;
    std::vector<std::size_t> order(count);
    std::iota(order.begin(), order.end(), std::size_t{0});
    const auto corner = [&](std::size_t ref) -> Vec3& { return patches[ref / 4].points[kCorner[ref % 4]]; };
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return corner(a)[0] < corner(b)[0] || (corner(a)[0] == corner(b)[0] && a < b);
    });
    std::vector<std::size_t> parent(count);
    std::iota(parent.begin(), parent.end(), std::size_t{0});
    for (std::size_t a = 0; a < count; ++a)
        for (std::size_t b = a + 1; b < count && corner(order[b])[0] - corner(order[a])[0] <= tolerance; ++b)
            if (close(corner(order[a]), corner(order[b]), tolerance)) {
                const std::size_t ra = find_root(parent, order[a]), rb = find_root(parent, order[b]);
                if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
            }
    std::vector<std::size_t> cluster(count);
    for (std::size_t ref = 0; ref < count; ++ref) cluster[ref] = find_root(parent, ref);
    for (std::size_t ref = 0; ref < count; ++ref) corner(ref) = corner(cluster[ref]);

    // edges: the two inner points of every edge between the same two corner clusters, in one direction
    struct EdgeRef {
        std::size_t patch;
        int side;
        bool reversed;
    };
    // side k runs from corner k to corner k + 1 (counter-clockwise in (u, v)) through these inner points
    static constexpr int kInner[4][2] = {{1, 2}, {7, 11}, {14, 13}, {8, 4}};
    std::map<std::pair<std::size_t, std::size_t>, EdgeRef> first;
    for (std::size_t p = 0; p < patches.size(); ++p)
        for (int side = 0; side < 4; ++side) {
            const std::size_t a = cluster[4 * p + side], b = cluster[4 * p + (side + 1) % 4];
            if (a == b) continue;
            const bool reversed = b < a;
            const auto key = reversed ? std::make_pair(b, a) : std::make_pair(a, b);
            const auto [it, inserted] = first.emplace(key, EdgeRef{p, side, reversed});
            if (inserted) continue;
            const EdgeRef& ref = it->second;
            Vec3 inner[2] = {patches[ref.patch].points[kInner[ref.side][0]],
                             patches[ref.patch].points[kInner[ref.side][1]]};
            if (ref.reversed != reversed) std::swap(inner[0], inner[1]);
            Vec3& p0 = patches[p].points[kInner[side][0]];
            Vec3& p1 = patches[p].points[kInner[side][1]];
            if (close(p0, inner[0], tolerance) && close(p1, inner[1], tolerance)) {
                p0 = inner[0];
                p1 = inner[1];
            }
        }
}

}  // namespace

std::uint64_t limit_patch_count(const PolygonMesh& mesh, int levels) {
    std::uint64_t count = 0;
    const std::uint64_t per_quad = std::uint64_t{1} << (2 * levels);
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const std::size_t n = mesh.face_size(f);
        count += n == 4 ? per_quad : n * (per_quad / 4);
    }
    return count;
}

int min_limit_patch_level(const PolygonMesh& mesh) {
    for (std::size_t f = 0; f < mesh.face_count(); ++f)
        if (mesh.face_size(f) != 4) return 1;
    return 0;
}

Result<LimitPatchSet> limit_patches(const LimitSurfaceEvaluator& evaluator, const PolygonMesh& mesh,
                                    const LimitPatchOptions& options) {
    if (evaluator.scheme() != SubdivisionScheme::CatmullClark)
        return make_error(ErrorCode::Unsupported, "limit patches are bicubic: Catmull-Clark surfaces only");
    if (options.max_levels < 0 || options.max_levels > 10)
        return make_error(ErrorCode::InvalidArgument,
                          "max_levels must be in [0, 10], got " + std::to_string(options.max_levels));
    const int lowest = min_limit_patch_level(mesh);
    if (options.levels && (*options.levels < lowest || *options.levels > options.max_levels))
        return make_error(ErrorCode::InvalidArgument,
                          "levels must be in [" + std::to_string(lowest) + ", " + std::to_string(options.max_levels) +
                              "], got " + std::to_string(*options.levels) +
                              (lowest == 1 ? " (the mesh has faces that are not quads)" : ""));
    if (!options.levels && !(std::isfinite(options.tolerance) && options.tolerance > 0))
        return make_error(ErrorCode::InvalidArgument, "tolerance must be finite and > 0");
    if (lowest > options.max_levels)
        return make_error(ErrorCode::InvalidArgument, "the mesh has faces that are not quads: max_levels must be >= 1");

    const int first_level = options.levels ? *options.levels : lowest;
    const int last_level = options.levels ? *options.levels : options.max_levels;
    std::optional<Layout> layout;
    int level = first_level;
    for (;; ++level) {
        const std::uint64_t count = limit_patch_count(mesh, level);
        if (count > options.max_patches)
            return make_error(ErrorCode::BudgetExceeded,
                              "isolation level " + std::to_string(level) + " makes " + std::to_string(count) +
                                  " patches, more than the limit of " + std::to_string(options.max_patches) +
                                  (options.levels ? "" : " (raise the tolerance)"));
        auto prepared = prepare(evaluator, mesh, level, options.cancel);
        if (!prepared) return prepared.error();
        layout = std::move(prepared.value());
        if (options.levels || layout->max_error <= options.tolerance) break;
        if (level == last_level)
            return make_error(ErrorCode::BudgetExceeded,
                              "no isolation level up to " + std::to_string(last_level) +
                                  " approximates the irregular regions within the tolerance (level " +
                                  std::to_string(level) + " is off by " + std::to_string(layout->max_error) + ")");
    }

    LimitPatchSet out;
    out.levels = level;
    out.max_error = layout->max_error;
    out.patches.reserve(limit_patch_count(mesh, level));
    std::size_t next_approximate = 0;
    for (std::size_t s = 0; s < layout->surfaces.size(); ++s) {
        if (options.cancel.requested()) return make_error(ErrorCode::Cancelled, "cancelled while exporting patches");
        for (const LimitFaceSurface::Leaf& leaf : layout->surfaces[s].leaves(level)) {
            const auto emit = [&](const Grid& grid, double u0, double v0, double size, bool exact) {
                out.patches.push_back(to_patch(grid));
                out.faces.push_back(layout->surface_face[s]);
                out.squares.push_back({u0, v0, size});
                out.exact.push_back(exact);
            };
            if (!leaf.bspline) {
                // leaves() lists them in the order prepare() met them
                const Layout::Square& square = layout->approximate[next_approximate++];
                emit(square.bezier, leaf.u0, leaf.v0, leaf.size, false);
                ++out.approximate_count;
                continue;
            }
            const Grid bezier = separable(
                *leaf.bspline, [](const Vec3(&line)[4], Vec3(&result)[4], int) { bspline_to_bezier_1d(line, result); });
            const int cuts = 1 << (level - leaf.level);
            const double step = 1.0 / cuts;
            for (int j = 0; j < cuts; ++j)
                for (int i = 0; i < cuts; ++i) {
                    const Grid piece =
                        cuts == 1 ? bezier
                                  : separable(bezier, [&](const Vec3(&line)[4], Vec3(&result)[4], int direction) {
                                        const int k = direction == 0 ? i : j;
                                        restrict_1d(line, k * step, k + 1 == cuts ? 1.0 : (k + 1) * step, result);
                                    });
                    emit(piece, leaf.u0 + leaf.size * i * step, leaf.v0 + leaf.size * j * step, leaf.size * step, true);
                }
        }
    }
    make_shared_edges_identical(out.patches);
    return out;
}

}  // namespace surfaced
