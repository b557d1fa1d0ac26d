#include "geometry/subdivision/tessellation_grading.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <tuple>

#include "geometry/core/format_number.h"
#include "geometry/subdivision/tessellation_strips.h"

namespace surfaced::tessellation_detail {
namespace {

//! The ratio (bound / tolerance) a graded grid's coarsening aims its cells at.
constexpr double kCoarsenTarget = 0.97;

//! How many times a graded grid within the tolerance is coarsened.
constexpr int kCoarsenRounds = 6;
//! Staggered grids are used from this many segments each way (on smaller ones, the vertex removal that follows
//! does better from the plain grid).
constexpr int kStaggerFrom = 4;
//! How many single-line trims a graded grid within the tolerance tries after its coarsenings.
constexpr int kTrimTrials = 4;

//! How much to shrink a failing triangle of parameter extents (hs, ht) whose bound is `ratio` times the tolerance:
//! per direction, by the share of the bound that direction carries (the bound is a quadratic form in the extents).
std::pair<double, double> shrink(const Bounds& m, double hs, double ht, double ratio) {
    const double cu = std::max(0.0, m.uu * hs * hs + m.uv * hs * ht),
                 cv = std::max(0.0, m.vv * ht * ht + m.uv * hs * ht);
    double fs = 1.05, ft = 1.05;
    if (cu + cv > 0) {
        fs = std::max(1.0, std::sqrt(2.0 * ratio * cu / (cu + cv)));
        ft = std::max(1.0, std::sqrt(2.0 * ratio * cv / (cu + cv)));
    }
    if (std::max(fs, ft) < 1.05) fs = ft = 1.05;
    return {std::min(fs, 8.0), std::min(ft, 8.0)};
}

}  // namespace

Status check_budget(std::uint64_t triangles, const LimitTessellationOptions& options) {
    if (options.max_triangles > 0 && triangles > options.max_triangles)
        return make_error(ErrorCode::BudgetExceeded, "tolerance " + shortest_text(options.tolerance) + " needs " +
                                                         std::to_string(triangles) + " triangles; the limit is " +
                                                         std::to_string(options.max_triangles));
    return Ok{};
}

GeoError too_many_segments(double needed, const LimitTessellationOptions& options, std::size_t face) {
    return element_error(ErrorCode::BudgetExceeded,
                         "tolerance " + shortest_text(options.tolerance) + " needs " +
                             std::to_string(static_cast<long long>(needed)) + " segments on face " +
                             std::to_string(face) + "; max_segments is " + std::to_string(options.max_segments),
                         ElementKind::Face, static_cast<std::int64_t>(face));
}

std::pair<int, std::vector<double>> grid_lines(const Density& rho) {
    double total = 0;
    for (double r : rho) total += r / kBins;
    const int n = std::max(1, int(std::ceil(total * (1.0 - 1e-12))));
    if (n == 1 || std::all_of(rho.begin(), rho.end(), [&](double r) { return r == rho[0]; })) return {n, {}};
    std::vector<double> lines(std::size_t(n) + 1, 0.0);
    lines[std::size_t(n)] = 1.0;
    int bin = 0;
    double before = 0;  // the integral of rho up to the start of `bin`
    for (int i = 1; i < n; ++i) {
        const double target = total * i / n;
        while (bin < kBins - 1 && before + rho[std::size_t(bin)] / kBins < target) {
            before += rho[std::size_t(bin)] / kBins;
            ++bin;
        }
        lines[std::size_t(i)] =
            std::clamp(double(bin) / kBins + (target - before) / rho[std::size_t(bin)], lines[std::size_t(i - 1)], 1.0);
    }
    return {n, lines};
}

void raise(Density& density, double lo, double hi, double rho) {
    const int b0 = std::clamp(int(std::floor(lo * kBins)), 0, kBins - 1);
    const int b1 = std::clamp(int(std::ceil(hi * kBins)), b0 + 1, kBins);
    for (int b = b0; b < b1; ++b) density[std::size_t(b)] = std::max(density[std::size_t(b)], rho);
}

Status regrade(Graded& g, const LimitTessellationOptions& options, std::size_t face) {
    std::tie(g.nu, g.s_lines) = grid_lines(g.rs);
    std::tie(g.nv, g.t_lines) = grid_lines(g.rt);
    if (std::max(g.nu, g.nv) > options.max_segments) return too_many_segments(std::max(g.nu, g.nv), options, face);
    return Ok{};
}

void apply(const Graded& g, LimitTessellationPlan::Domain& d) {
    d.s_lines = g.s_lines;
    d.t_lines = g.t_lines;
    d.nu = g.nu;
    d.nv = g.nv;
    d.staggered = g.staggered;
    fix_inner(d);
}

namespace {

//! Triangles of a graded grid whose sides carry its lines.
std::uint64_t grid_triangles(const Graded& g) {
    const auto cells = 2 * std::uint64_t(g.nu) * std::uint64_t(g.nv);
    return staggered(g.staggered, g.nu, g.nv) ? cells + 2 * std::uint64_t(g.nv / 2) : cells;
}

//! graded_demand's checks, coarsenings and trims from the first densities in `g`, for its layout.
Result<Graded> refine(const FaceData& fd, std::size_t face, int subface, const LimitTessellationOptions& options,
                      Graded g) {
    const double tol = options.tolerance;
    const std::size_t root = domain_root(fd, subface);
    std::optional<Graded> best;  // the smallest grid within the tolerance so far
    int coarsenings = 0;
    // last, one line fewer along s (trim 0), then along t (trim 1), as long as the grid passes: a trial that fails
    // is dropped, not refined
    int trim = -1, trials = 0;
    const auto next_trial = [&]() {
        for (; trim <= 1; ++trim) {
            const int n = trim == 0 ? best->nu : best->nv;
            if (n <= 1 || trials >= kTrimTrials) continue;
            ++trials;
            g = *best;
            for (double& r : trim == 0 ? g.rs : g.rt) r *= double(n - 1) / n;
            return true;
        }
        return false;
    };
    for (int iteration = 0;; ++iteration) {
        if (auto status = regrade(g, options, face); !status) return status.error();
        if (iteration > 40 && trim < 0) break;
        const int nu = g.nu, nv = g.nv;
        const auto t_at = [&](int j) { return g.t_lines.empty() ? double(j) / nv : g.t_lines[std::size_t(j)]; };
        // the output has at least this domain's grid: refuse before evaluating more than the budget allows
        if (auto status = check_budget(2 * std::uint64_t(nu) * std::uint64_t(nv), options); !status)
            return status.error();
        // the domain's layout as triangulate() makes it for a grid whose sides carry its lines: rows of points
        // (staggered ones at the midpoints), S at each for the triangles' planes, and the bands' triangles
        std::vector<P2> points;
        std::vector<OffsetPoint> grid;
        std::vector<std::array<std::uint32_t, 3>> triangles;
        {
            std::vector<std::uint32_t> lower, upper;
            std::vector<double> lower_s, upper_s;
            for (int j = 0; j <= nv; ++j) {
                upper_s = row_s(g.s_lines, nu, nv, j, staggered(g.staggered, nu, nv));
                upper.clear();
                for (double x : upper_s) {
                    upper.push_back(std::uint32_t(points.size()));
                    points.push_back({x, t_at(j)});
                    auto p = corner_at(fd, subface, points.back());
                    if (!p) return p.error();
                    grid.push_back(*p);
                }
                if (j > 0) {
                    if (staggered(g.staggered, nu, nv)) {
                        zigzag(lower, lower_s, upper, upper_s, triangles);
                    } else {
                        cells(lower, upper, triangles);
                    }
                }
                std::swap(lower, upper);
                std::swap(lower_s, upper_s);
            }
        }
        Density next_s = g.rs, next_t = g.rt;
        Density worst_s{}, worst_t{};  // per bin, the largest ratio (bound / tolerance) of the triangles over it
        bool fail = false;
        for (const auto& tri : triangles) {
            const P2 &a = points[tri[0]], &b = points[tri[1]], &c = points[tri[2]];
            const P2 lo{std::min({a.s, b.s, c.s}), std::min({a.t, b.t, c.t})};
            const P2 hi{std::max({a.s, b.s, c.s}), std::max({a.t, b.t, c.t})};
            const double hs = hi.s - lo.s, ht = hi.t - lo.t;
            Overlap o;
            query(fd, root, 0.0, 0.0, 1.0, lo, hi, o);
            const std::optional<Vec3> n =
                unit_normal(grid[tri[0]].position, grid[tri[1]].position, grid[tri[2]].position);
            const std::array<Vec3, 3> offsets{grid[tri[0]].offset, grid[tri[1]].offset, grid[tri[2]].offset};
            Bounds larger_side;  // the bounds of the triangle's larger side, for shrink
            const double ratio = offset_bound(plane_bounds(fd, o, n, a, b, c), a, b, c, n, offsets, &larger_side) / tol;
            double fs = 1, ft = 1, cell_ratio = ratio;
            if (ratio > 1) {
                // a patch that fails on its own (a narrow band of high curvature inside a coarse triangle) refines
                // the grid around itself, by as much as the triangle would need; the whole triangle only when none
                // does
                bool local = false;
                for (const auto& piece : o.patches) {
                    Overlap one;
                    one.m.include(fd.patches[piece.patch].m, 1.0 / (piece.w * piece.w));
                    one.patches = {piece};
                    Bounds m;
                    const double r = offset_bound(plane_bounds(fd, one, n, a, b, c), a, b, c, n, offsets, &m) / tol;
                    if (r <= 1) continue;
                    local = true;
                    const auto [ps, pt] = shrink(m, hs, ht, r);
                    const double ws = 0.5 * hs / ps, wt = 0.5 * ht / pt;
                    raise(next_s, std::max(lo.s, piece.s0 - ws), std::min(hi.s, piece.s0 + piece.w + ws), ps / hs);
                    raise(next_t, std::max(lo.t, piece.t0 - wt), std::min(hi.t, piece.t0 + piece.w + wt), pt / ht);
                    fail = true;
                }
                if (!local) std::tie(fs, ft) = shrink(larger_side, hs, ht, ratio);
            }
            if (o.uncovered) {  // the parts no patch bounds (deep at irregular vertices) are sampled
                auto sampled = sampled_error(fd, subface, a, b, c, {grid[tri[0]], grid[tri[1]], grid[tri[2]]});
                if (!sampled) return sampled.error();
                const double sampled_ratio = sampled->check / tol;
                cell_ratio = std::max(cell_ratio, sampled_ratio);
                if (sampled_ratio > 1) {
                    // the triangles next to the uncovered parts shrink by f: the density rises over a triangle's
                    // width around them, not over the whole triangle (a coarse one that reaches an irregular vertex
                    // would otherwise refine everything it spans)
                    const double f = std::min(4.0, std::max(1.1, std::sqrt(sampled_ratio)));
                    const double ws = 0.5 * hs / f, wt = 0.5 * ht / f;
                    fail = true;
                    raise(next_s, std::max(lo.s, o.uncovered_lo.s - ws), std::min(hi.s, o.uncovered_hi.s + ws), f / hs);
                    raise(next_t, std::max(lo.t, o.uncovered_lo.t - wt), std::min(hi.t, o.uncovered_hi.t + wt), f / ht);
                }
            }
            if (fs > 1 || ft > 1) {
                fail = true;
                raise(next_s, lo.s, hi.s, fs / hs);
                raise(next_t, lo.t, hi.t, ft / ht);
            }
            raise(worst_s, lo.s, hi.s, cell_ratio);
            raise(worst_t, lo.t, hi.t, cell_ratio);
        }
        if (trim >= 0) {
            if (fail) {
                ++trim;
            } else if (std::uint64_t(nu) * std::uint64_t(nv) < std::uint64_t(best->nu) * std::uint64_t(best->nv)) {
                best = g;
            }
            if (!next_trial()) break;
            continue;
        }
        if (!fail) {
            // the raises overshoot (a factor at least 1.05, lines rounded up): once every cell is within the
            // tolerance, the densities fall where the cells over a bin all have room (the bounds go with the
            // squares of the cells' sizes); the refinement above then repairs what that breaks, and the smallest
            // grid that passed is kept
            if (!best || std::uint64_t(nu) * std::uint64_t(nv) < std::uint64_t(best->nu) * std::uint64_t(best->nv))
                best = g;
            if (coarsenings == kCoarsenRounds) {
                trim = 0;
                if (!next_trial()) break;
                continue;
            }
            ++coarsenings;
            bool lower = false;
            for (int b = 0; b < kBins; ++b)
                for (auto [rho, worst] : {std::pair{&g.rs, &worst_s}, std::pair{&g.rt, &worst_t}}) {
                    const double f = std::sqrt(std::max((*worst)[std::size_t(b)], 0.0625) / kCoarsenTarget);
                    if (f >= 1) continue;
                    (*rho)[std::size_t(b)] = std::max(1.0, (*rho)[std::size_t(b)] * f);
                    lower = true;
                }
            if (!lower) {
                trim = 0;
                if (!next_trial()) break;
            }
            continue;
        }
        g.rs = next_s;
        g.rt = next_t;
        if (options.cancel.requested()) return make_error(ErrorCode::Cancelled, "tessellation cancelled");
    }
    if (best) return *best;
    return g;
}

}  // namespace

Result<Graded> graded_demand(const FaceData& fd, std::size_t face, int subface,
                             const LimitTessellationOptions& options) {
    const double tol = options.tolerance;
    const std::size_t root = domain_root(fd, subface);
    Graded g;
    g.rs.fill(1.0);
    g.rt.fill(1.0);
    {
        std::vector<std::tuple<std::size_t, double, double, double>> stack{{root, 0.0, 0.0, 1.0}};
        while (!stack.empty()) {
            const auto [node, s0, t0, w] = stack.back();
            stack.pop_back();
            if (w < kBoundedWidth) continue;
            const auto& n = fd.surface->nodes()[node];
            if (n.patch >= 0) {
                // a first guess, not a bound: the second derivatives along the patch's mean normal (the checks
                // below bound every cell with its triangles' own planes and raise the densities where needed)
                const PatchData& pd = fd.patches[std::size_t(n.patch)];
                Bounds m;
                m.include(norm(pd.n0) > 0 ? along_in_box(pd, pd.n0, 0, 1, 0, 1) : pd.plane, 1.0 / (w * w));
                const auto [ru, rv] = rates_for(m, tol);
                raise(g.rs, s0, s0 + w, ru);
                raise(g.rt, t0, t0 + w, rv);
            } else if (n.first_child >= 0) {
                const double h = 0.5 * w;
                const auto c = std::size_t(n.first_child);
                stack.emplace_back(c, s0, t0, h);
                stack.emplace_back(c + 1, s0 + h, t0, h);
                stack.emplace_back(c + 2, s0 + h, t0 + h, h);
                stack.emplace_back(c + 3, s0, t0 + h, h);
            }
        }
    }
    Graded stagger = g;
    stagger.staggered = true;
    auto plain = refine(fd, face, subface, options, std::move(g));
    // a staggered grid needs fewer lines than the plain one, so below kStaggerFrom each way it would not be kept
    if (!plain || !options.stagger || std::min(plain->nu, plain->nv) < kStaggerFrom) return plain;
    auto staggered_grid = refine(fd, face, subface, options, std::move(stagger));
    // a staggered grid that would exceed the budget where the plain one does not is not needed
    if (!staggered_grid && staggered_grid.error().code == ErrorCode::BudgetExceeded) return *plain;
    if (!staggered_grid) return staggered_grid.error();
    const bool large = std::min(staggered_grid->nu, staggered_grid->nv) >= kStaggerFrom;
    return large && grid_triangles(*staggered_grid) < grid_triangles(*plain) ? *staggered_grid : *plain;
}

Result<std::pair<int, int>> domain_demand(const FaceData& fd, std::size_t face, int subface,
                                          const LimitTessellationOptions& options) {
    const double tol = options.tolerance;
    const std::size_t root = domain_root(fd, subface);
    const bool bounded = options.guaranteed;
    // start from the patches down to two levels (their normal cones' plane bounds), then check every cell's two
    // triangles against the patches they overlap
    Overlap coarse;
    {
        std::vector<std::pair<std::size_t, double>> stack{{root, 1.0}};
        int depth = 0;
        while (!stack.empty() && depth <= 2) {
            std::vector<std::pair<std::size_t, double>> next;
            for (const auto& [node, w] : stack) {
                const auto& n = fd.surface->nodes()[node];
                if (n.patch >= 0) coarse.m.include(fd.patches[std::size_t(n.patch)].plane, 1.0 / (w * w));
                if (n.first_child >= 0)
                    for (int c = 0; c < 4; ++c) next.emplace_back(std::size_t(n.first_child + c), 0.5 * w);
            }
            stack = std::move(next);
            ++depth;
        }
    }
    auto [fu, fv] = rates_for(coarse.m, tol);
    int nu = int(fu), nv = int(fv);
    if (!bounded) {  // the bound overestimates: start below it and let the measurements decide
        nu = std::max(1, nu / 4);
        nv = std::max(1, nv / 4);
    }
    for (int iteration = 0;; ++iteration) {
        if (std::max(nu, nv) > options.max_segments) return too_many_segments(std::max(nu, nv), options, face);
        if (iteration > 40) break;
        double worst_ratio = 0;  // largest bound / tolerance
        bool bounded_fail = false, sampled_fail = false;
        std::vector<OffsetPoint> grid;  // the vertices at the grid points, for the triangles' planes
        if (bounded) {
            grid.reserve(std::size_t(nu + 1) * std::size_t(nv + 1));
            for (int j = 0; j <= nv; ++j)
                for (int i = 0; i <= nu; ++i) {
                    auto p = corner_at(fd, subface, {double(i) / nu, double(j) / nv});
                    if (!p) return p.error();
                    grid.push_back(*p);
                }
        }
        const auto at = [&](int i, int j) { return grid[std::size_t(j) * std::size_t(nu + 1) + std::size_t(i)]; };
        for (int j = 0; j < nv; ++j)
            for (int i = 0; i < nu; ++i) {
                const P2 lo{double(i) / nu, double(j) / nv}, hi{double(i + 1) / nu, double(j + 1) / nv};
                Overlap o;
                query(fd, root, 0.0, 0.0, 1.0, lo, hi, o);
                // the patches a cell overlaps bound it; the parts no patch bounds (deep at irregular vertices) are
                // sampled as well
                if (bounded) {
                    const P2 c01{lo.s, hi.t}, c10{hi.s, lo.t};
                    const auto bound = [&](const OffsetPoint& x, const OffsetPoint& y, const OffsetPoint& z,
                                           const P2& px, const P2& py, const P2& pz) {
                        const auto n = unit_normal(x.position, y.position, z.position);
                        return offset_bound(plane_bounds(fd, o, n, px, py, pz), px, py, pz, n,
                                            {x.offset, y.offset, z.offset});
                    };
                    worst_ratio =
                        std::max({worst_ratio, bound(at(i, j), at(i + 1, j), at(i + 1, j + 1), lo, c10, hi) / tol,
                                  bound(at(i, j), at(i + 1, j + 1), at(i, j + 1), lo, hi, c01) / tol});
                }
                if ((o.uncovered || !bounded) && !sampled_fail) {
                    const P2 c01{lo.s, hi.t}, c10{hi.s, lo.t};
                    for (const auto& [p, q] : {std::pair{c10, hi}, std::pair{hi, c01}}) {
                        // the grid's vertices where it has them, else (measured rates) evaluated for these
                        const auto grid_at = [&](const P2& x) {
                            return at(x.s == lo.s ? i : i + 1, x.t == lo.t ? j : j + 1);
                        };
                        auto e = bounded ? sampled_error(fd, subface, lo, p, q, {grid_at(lo), grid_at(p), grid_at(q)})
                                         : sampled_error(fd, subface, lo, p, q);
                        if (!e) return e.error();
                        if (e->check > tol) sampled_fail = true;
                    }
                }
            }
        bounded_fail = worst_ratio > 1;
        if (!bounded_fail && !sampled_fail) break;
        int next_u = nu, next_v = nv;
        if (bounded_fail) {  // the bounds fall with the square of the cell size
            const double scale = std::min(1e3, std::sqrt(worst_ratio));
            next_u = std::max(nu, int(std::ceil(nu * scale)));
            next_v = std::max(nv, int(std::ceil(nv * scale)));
        }
        if (sampled_fail || (next_u == nu && next_v == nv)) {
            next_u = std::max(next_u, nu + std::max(1, nu / 4));
            next_v = std::max(next_v, nv + std::max(1, nv / 4));
        }
        nu = next_u;
        nv = next_v;
        if (options.cancel.requested()) return make_error(ErrorCode::Cancelled, "tessellation cancelled");
    }
    return std::pair<int, int>{nu, nv};
}

}  // namespace surfaced::tessellation_detail
