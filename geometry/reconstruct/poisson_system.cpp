#include "geometry/reconstruct/poisson_system.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <utility>

#include "geometry/core/two_parts.h"

namespace surfaced::reconstruct {
namespace {

// 1-D integrals of hats of one level (spacing h) at offsets -1, 0, +1, divided by the power of h they scale with:
// mass    integral phi_u phi_w      = h * kMass
// stiff   integral phi_u' phi_w'    = kStiff / h
// mixed   integral phi_u' phi_w     = kMixed           (w = u + 1: phi_u falls where phi_w rises: -1/2)
constexpr double kMass[3] = {1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0};
constexpr double kStiff[3] = {-1.0, 2.0, -1.0};
constexpr double kMixed[3] = {0.5, 0.0, -0.5};

//! The 3-D stiffness stencil integral grad phi_u . grad phi_{u+o} / h, o = (a-1, b-1, c-1).
struct StiffnessStencil {
    double w[27];
    StiffnessStencil() {
        for (int c = 0; c < 3; ++c)
            for (int b = 0; b < 3; ++b)
                for (int a = 0; a < 3; ++a)
                    w[a + 3 * b + 9 * c] = kStiff[a] * kMass[b] * kMass[c] + kMass[a] * kStiff[b] * kMass[c] +
                                           kMass[a] * kMass[b] * kStiff[c];
    }
};
const StiffnessStencil kStiffness;

bool on_boundary(std::uint64_t key, std::uint32_t n) {
    const std::uint32_t i = key_i(key), j = key_j(key), k = key_k(key);
    return i == 0 || j == 0 || k == 0 || i == n || j == n || k == n;
}

//! Whether key + (di, dj, dk) stays in [0, n]^3.
bool offset_inside(std::uint64_t key, int di, int dj, int dk, std::uint32_t n) {
    const std::int64_t i = static_cast<std::int64_t>(key_i(key)) + di;
    const std::int64_t j = static_cast<std::int64_t>(key_j(key)) + dj;
    const std::int64_t k = static_cast<std::int64_t>(key_k(key)) + dk;
    const std::int64_t m = n;
    return i >= 0 && j >= 0 && k >= 0 && i <= m && j <= m && k <= m;
}

std::uint64_t corner_key(std::uint64_t cell, int c) {
    return pack_key(key_i(cell) + static_cast<std::uint32_t>(c & 1),
                    key_j(cell) + static_cast<std::uint32_t>((c >> 1) & 1),
                    key_k(cell) + static_cast<std::uint32_t>(c >> 2));
}

// A plane crosses a cell of side h over h^2 / 1.5 on average, and sample_density counts about that many samples' worth
// (sigma h^2 / 1.5 at sigma samples per unit area): the samples a square of side h of the surface holds are 1.5 times
// it. samples_per_node counts those (as the trimming's density value and the area estimate do).
constexpr double kSquarePerCell = 1.5;

// A level whose cells hold at least this many samples each on average screens through per-cell matrices (64 values
// a cell against 8 weights and 8 indices a sample).
constexpr std::size_t kSamplesPerScreeningCell = 16;

// Levels with fewer dofs than this are assembled on one thread (a second one would cost more than it saves).
constexpr std::size_t kThreadedSize = 1 << 16;

//! Runs body(begin, end) on the halves of [0, n), concurrently when `threaded` (and n is large enough). Every pass
//! below writes only the rows of its own range and sums each row in a fixed order, so the result is the same either
//! way.
template <class F>
void halves(std::size_t n, bool threaded, F&& body) {
    const std::size_t middle = n / 2;
    run_two_parts(threaded && n >= kThreadedSize, [&](int part) {
        if (part == 0)
            body(std::size_t{0}, middle);
        else
            body(middle, n);
    });
}

//! sum_o stencil[o] * values[neighbour o of dof v] over the neighbours inside the grid, in the order of o; values
//! has rows.padded_size() entries (zero in the padding).
inline double stencil_sum(const StencilRows& rows, std::size_t v, const double* values, const double* stencil) {
    const std::uint32_t r = rows.run[v];
    const std::uint32_t* base = &rows.rows[9 * std::size_t{r}];
    const double* x = values + (v - rows.first[r]);
    double sum = 0;
    if (rows.on_edge[v] == 0) {
        for (int q = 0; q < 9; ++q) {
            const double* at = x + base[q] - 1;
            sum += stencil[3 * q] * at[0];
            sum += stencil[3 * q + 1] * at[1];
            sum += stencil[3 * q + 2] * at[2];
        }
        return sum;
    }
    const int from = rows.on_edge[v] == 1 ? 1 : 0, to = rows.on_edge[v] == 2 ? 1 : 2;
    for (int q = 0; q < 9; ++q)
        for (int a = from; a <= to; ++a) sum += stencil[3 * q + a] * (x + base[q])[a - 1];
    return sum;
}

//! The same for a vector field against a vector stencil (dot products).
inline double stencil_dot(const StencilRows& rows, std::size_t v, const Vec3* values, const Vec3* stencil) {
    const std::uint32_t r = rows.run[v];
    const std::uint32_t* base = &rows.rows[9 * std::size_t{r}];
    const Vec3* x = values + (v - rows.first[r]);
    double sum = 0;
    const int from = rows.on_edge[v] == 1 ? 1 : 0, to = rows.on_edge[v] == 2 ? 1 : 2;
    for (int q = 0; q < 9; ++q)
        for (int a = from; a <= to; ++a) sum += dot((x + base[q])[a - 1], stencil[3 * q + a]);
    return sum;
}

}  // namespace

StencilRows StencilRows::build(const OctreeLevel& level, bool threaded) {
    StencilRows out;
    const std::size_t dofs = level.dofs.size();
    const std::vector<std::uint64_t>& keys = level.dofs.keys;
    out.support = level.support_vertices.size();
    const std::uint32_t n = std::uint32_t{1} << level.depth;
    out.run.resize(dofs);
    out.on_edge.resize(dofs);
    for (std::size_t v = 0; v < dofs; ++v) {
        if (v == 0 || keys[v] != keys[v - 1] + 1) {  // (i + 1, j, k) follows (i, j, k) within a row
            if (!out.first.empty()) out.longest = std::max<std::size_t>(out.longest, v - out.first.back());
            out.first.push_back(static_cast<std::uint32_t>(v));
        }
        out.run[v] = static_cast<std::uint32_t>(out.first.size() - 1);
        const std::uint32_t i = key_i(keys[v]);
        out.on_edge[v] = i == 0 ? 1 : i == n ? 2 : 0;
    }
    if (!out.first.empty()) out.longest = std::max<std::size_t>(out.longest, dofs - out.first.back());
    const auto padding = static_cast<std::uint32_t>(out.support + 1);  // reads padding - 1 .. padding + longest
    const std::size_t runs = out.first.size();
    out.rows.resize(runs * 9);
    halves(runs, threaded, [&](std::size_t begin, std::size_t end) {
        for (int q = 0; q < 9; ++q) {
            const int b = q % 3 - 1, c = q / 3 - 1;
            const std::uint64_t delta = offset_delta(0, b, c);
            SortedCursor cursor(level.support_vertices.keys);
            for (std::size_t r = begin; r < end; ++r) {
                const std::uint64_t key = keys[out.first[r]];
                std::uint32_t position = padding;
                if (offset_inside(key, 0, b, c, n)) {
                    position = cursor.seek(key + delta);
                    assert(position != SortedCursor::kNone);
                }
                out.rows[r * 9 + static_cast<std::size_t>(q)] = position;
            }
        }
    });
    return out;
}

void corner_weights(const Vec3& p, int depth, std::uint64_t cell, double weights[8]) {
    const double n = std::ldexp(1.0, depth);
    const double tx = std::clamp(p.x * n - key_i(cell), 0.0, 1.0);
    const double ty = std::clamp(p.y * n - key_j(cell), 0.0, 1.0);
    const double tz = std::clamp(p.z * n - key_k(cell), 0.0, 1.0);
    for (int c = 0; c < 8; ++c)
        weights[c] = ((c & 1) ? tx : 1 - tx) * ((c & 2) ? ty : 1 - ty) * ((c & 4) ? tz : 1 - tz);
}

std::vector<double> sample_density(const OrientedSamples& samples, int depth) {
    const std::size_t n = samples.positions.size();
    std::vector<std::uint64_t> cells(n);
    KeyCollector collector;
    for (std::size_t i = 0; i < n; ++i) {
        cells[i] = cell_key(samples.positions[i], depth);
        for (int c = 0; c < 8; ++c) collector.insert(corner_key(cells[i], c));
    }
    const std::vector<std::uint64_t> keys = collector.take();
    KeyMap index;
    index.assign(keys);
    std::vector<std::uint32_t> corners(n * 8);
    std::vector<double> weights(n * 8);
    std::vector<double> counts(keys.size(), 0.0);
    for (std::size_t i = 0; i < n; ++i) {
        corner_weights(samples.positions[i], depth, cells[i], &weights[i * 8]);
        for (int c = 0; c < 8; ++c) {
            const std::size_t slot = i * 8 + static_cast<std::size_t>(c);
            corners[slot] = index.find(corner_key(cells[i], c));
            counts[corners[slot]] += weights[slot];
        }
    }
    std::vector<double> density(n, 0.0);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t slot = i * 8; slot < i * 8 + 8; ++slot) density[i] += weights[slot] * counts[corners[slot]];
    return density;  // each >= the sample's own contribution sum_c w_c^2 >= 1/8 > 0
}

void assign_splat_depths(OrientedSamples& samples, const std::vector<double>& density, int density_depth, int min_depth,
                         int max_depth, double samples_per_node) {
    const std::size_t n = samples.positions.size();
    samples.splat_depths.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const double depth = density_depth + 0.5 * std::log2(kSquarePerCell * density[i] / samples_per_node);
        samples.splat_depths[i] = std::clamp(depth, static_cast<double>(min_depth), static_cast<double>(max_depth));
    }
}

void assign_area_shares(OrientedSamples& samples, const std::vector<double>& density) {
    const std::size_t n = samples.positions.size();
    samples.area_shares.resize(n);
    double sum = 0;
    for (std::size_t i = 0; i < n; ++i) {
        samples.area_shares[i] = samples.weights[i] / density[i];
        sum += samples.area_shares[i];
    }
    for (double& a : samples.area_shares) a *= samples.area / sum;
}

void assign_area_shares(OrientedSamples& samples, int depth) {
    assign_area_shares(samples, sample_density(samples, depth));
}

namespace {

//! The gradient stencil integral grad phi_v phi_w / h^2 for w = v + o, o = (a-1, b-1, c-1).
Vec3 gradient_stencil(int a, int b, int c) {
    return {kMixed[a] * kMass[b] * kMass[c], kMass[a] * kMixed[b] * kMass[c], kMass[a] * kMass[b] * kMixed[c]};
}

//! The gradient stencil of every offset o = a + 3 b + 9 c.
struct GradientStencil {
    Vec3 w[27];
    GradientStencil() {
        for (int o = 0; o < 27; ++o) w[o] = gradient_stencil(o % 3, (o / 3) % 3, o / 9);
    }
};

//! out[v] += integral grad phi_v . V for V = sum_u field_u phi_u / h^3, the field given at the level's support
//! vertices (padded, StencilRows), gathered at every dof from its 27 neighbours.
void add_support_field(const OctreeLevel& level, const StencilRows& rows, const std::vector<Vec3>& padded_field,
                       std::vector<double>& out, bool threaded) {
    static const GradientStencil stencil;
    const double h = std::ldexp(1.0, -level.depth);
    halves(level.dofs.size(), threaded, [&](std::size_t begin, std::size_t end) {
        for (std::size_t v = begin; v < end; ++v) out[v] += stencil_dot(rows, v, padded_field.data(), stencil.w) / h;
    });
}

//! out[v] += integral grad phi_v . V_l for V_l = sum_w splat_w phi_w / h^3 (splats given at the level's dofs).
//! `spread`: a scratch buffer, all zero (and left so), of at least the level's padded size.
void add_own_splats(const OctreeLevel& level, const StencilRows& rows, const std::vector<Vec3>& splat,
                    std::vector<double>& out, std::vector<Vec3>& spread, bool threaded) {
    halves(splat.size(), threaded, [&](std::size_t begin, std::size_t end) {
        for (std::size_t v = begin; v < end; ++v) spread[rows.position(v, 4)] = splat[v];
    });
    add_support_field(level, rows, spread, out, threaded);
    halves(splat.size(), threaded, [&](std::size_t begin, std::size_t end) {
        for (std::size_t v = begin; v < end; ++v) spread[rows.position(v, 4)] = Vec3{};
    });
}

}  // namespace

std::vector<std::vector<double>> divergence_rhs(const PoissonOctree& tree, const OrientedSamples& samples,
                                                const std::vector<StencilRows>& rows, bool threaded) {
    const std::size_t levels = tree.levels.size();

    // splat: n_{d,w} = sum_i a_i N_i phi_{d,w}(p_i), each sample's share split between the two levels around its
    // splatting depth
    std::vector<std::vector<Vec3>> splat(levels);
    for (std::size_t l = 0; l < levels; ++l) splat[l].assign(tree.levels[l].dofs.size(), Vec3{});
    std::vector<char> used(levels, 0);
    // per level, the last cell looked up and its corners' dofs (samples in space order: runs share their cell)
    std::vector<std::uint64_t> last_cell(levels, ~std::uint64_t{0});
    std::vector<std::uint32_t> cell_dofs(levels * 8, 0);
    // the even levels on one part, the odd ones on the other: each level is written by one part, in sample order,
    // so the sums do not depend on whether the parts run concurrently
    run_two_parts(threaded && samples.positions.size() >= kThreadedSize, [&](int parity) {
        for (std::size_t i = 0; i < samples.positions.size(); ++i) {
            const double depth = samples.splat_depths.empty() ? tree.max_depth : samples.splat_depths[i];
            const int lower = std::min(static_cast<int>(std::floor(depth)), tree.max_depth);
            const double t = depth - lower;  // the share of level lower + 1
            const double a = samples.area_shares.empty() ? samples.area * samples.weights[i] / samples.weight_sum
                                                         : samples.area_shares[i];
            for (int part = 0; part < 2; ++part) {
                const double share = part == 0 ? 1 - t : t;
                if (share <= 0) continue;
                const int d = lower + part;
                if (d % 2 != parity) continue;
                const auto l = static_cast<std::size_t>(d - tree.min_depth);
                const OctreeLevel& level = tree.levels[l];
                const std::uint64_t cell = cell_key(samples.positions[i], d);
                double w[8];
                corner_weights(samples.positions[i], d, cell, w);
                std::uint32_t* dofs = &cell_dofs[l * 8];
                if (cell != last_cell[l]) {
                    for (int c = 0; c < 8; ++c) {
                        dofs[c] = level.dofs.find(corner_key(cell, c));
                        assert(dofs[c] != RowIndex::kNone);
                    }
                    last_cell[l] = cell;
                }
                for (int c = 0; c < 8; ++c) splat[l][dofs[c]] += samples.normals[i] * (a * share * w[c]);
                used[l] = 1;
            }
        }
    });

    // splats of the level and finer ones: integrated on their level, restricted to coarser hats (a coarse hat is
    // sum 2^-(odd offsets) of the fine hats around its centre)
    std::vector<std::vector<double>> rhs(levels);
    // scratch fields over the support vertices, allocated once at the finest level's size and reused level by level
    std::size_t largest = 0;
    for (const StencilRows& r : rows) largest = std::max(largest, r.padded_size());
    std::vector<Vec3> scratch(largest, Vec3{}), carried;
    for (std::size_t li = levels; li-- > 0;) {
        const OctreeLevel& to = tree.levels[li];
        std::vector<double>& coarse = rhs[li];
        coarse.assign(to.dofs.size(), 0.0);
        if (used[li]) add_own_splats(to, rows[li], splat[li], coarse, scratch, threaded);
        if (li + 1 == levels) continue;
        const OctreeLevel& from = tree.levels[li + 1];
        const std::vector<double>& f = rhs[li + 1];
        // gathered: coarse hat v is the fine hats 2v + o, o in {-1, 0, 1}^3, weighted 2^-(non-zero offsets); one
        // sorted pass per row offset (b, c), the three offsets along i being consecutive targets of one cursor
        const std::uint32_t fine_n = std::uint32_t{1} << from.depth;
        halves(to.dofs.size(), threaded, [&](std::size_t begin, std::size_t end) {
            for (int q = 0; q < 9; ++q) {
                const int b = q % 3 - 1, c = q / 3 - 1;
                const double row_weight = (b ? 0.5 : 1.0) * (c ? 0.5 : 1.0);
                SortedCursor cursor(from.dofs.keys);
                for (std::size_t v = begin; v < end; ++v) {
                    const std::uint64_t doubled = 2 * to.dofs.keys[v];
                    if (!offset_inside(doubled, 0, b, c, fine_n)) continue;
                    const std::uint64_t centre = doubled + offset_delta(0, b, c);
                    double sum = 0;
                    for (int a = -1; a <= 1; ++a) {
                        if (!offset_inside(doubled, a, b, c, fine_n)) continue;
                        const std::uint32_t u = cursor.seek(centre + offset_delta(a, 0, 0));
                        if (u != SortedCursor::kNone) sum += (a ? 0.5 : 1.0) * f[u];
                    }
                    coarse[v] += row_weight * sum;
                }
            }
        });
    }

    // splats of coarser levels: V_{<d} carried down as values at each level's support vertices, in the level's own
    // normalisation (V = sum field_u phi_u / h^3, so a coarser level's values shrink by 8 per level)
    carried.reserve(largest);
    carried.assign(tree.levels[0].support_vertices.size(), Vec3{});
    bool any = false;
    for (std::size_t li = 0; li + 1 < levels; ++li) {
        const OctreeLevel& level = tree.levels[li];
        const OctreeLevel& next = tree.levels[li + 1];
        if (used[li]) {
            any = true;
            for (std::size_t w = 0; w < level.dofs.size(); ++w) {
                const Vec3 nw = splat[li][w];
                if (nw.x == 0 && nw.y == 0 && nw.z == 0) continue;
                carried[level.support_vertices.find(level.dofs.keys[w])] += nw;
            }
        }
        if (!any) {
            carried.assign(next.support_vertices.size(), Vec3{});
            continue;
        }
        interpolate_to_finer(level, carried, next, scratch, threaded);
        std::swap(carried, scratch);
        for (Vec3& v : carried) v *= 0.125;
        carried.resize(rows[li + 1].padded_size(), Vec3{});  // the padding read through StencilRows
        add_support_field(next, rows[li + 1], carried, rhs[li + 1], threaded);
        carried.resize(next.support_vertices.size());
    }
    return rhs;
}

LevelSystem::LevelSystem(const PoissonOctree& tree, int depth, const OrientedSamples& samples, double alpha,
                         bool dirichlet, StencilRows rows, bool threaded)
    : tree_(tree), level_(tree.level(depth)), samples_(samples), rows_(std::move(rows)) {
    h_ = std::ldexp(1.0, -depth);
    beta_ = samples.weight_sum > 0 ? alpha * std::ldexp(1.0, depth) * samples.area / samples.weight_sum : 0.0;
    const std::uint32_t n = std::uint32_t{1} << depth;
    const std::size_t dofs = level_.dofs.size();

    fixed_.assign(dofs, 0);
    if (dirichlet)
        for (std::size_t v = 0; v < dofs; ++v) {
            fixed_[v] = on_boundary(level_.dofs.keys[v], n) ? 1 : 0;
            any_fixed_ = any_fixed_ || fixed_[v];
        }

    spread_.assign(rows_.padded_size(), 0.0);
    threaded_ = threaded;

    diagonal_.assign(dofs, kStiffness.w[13] * h_);
    const std::size_t count = samples.positions.size();
    sample_dofs_.resize(count * 8);
    sample_cells_.resize(count);
    sample_weights_.resize(count * 8);
    screening_.assign(count, 0.0);
    // each sample's cell, corner weights and corner dofs, on two threads for a large cloud (each half keeps its own
    // last cell); then the diagonal, summed in sample order
    halves(count, threaded, [&](std::size_t begin, std::size_t end) {
        std::uint64_t last_cell = ~std::uint64_t{0};
        std::uint32_t cell_dofs[8] = {};
        for (std::size_t i = begin; i < end; ++i) {
            const std::uint64_t cell = cell_key(samples.positions[i], depth);
            sample_cells_[i] = cell;
            // a sample screens the levels down to its splatting level only: on finer ones, around a sample too
            // isolated for their cells, pulling chi to the iso-value would raise a bubble around it (with a
            // fractional depth D + t, level D + 1 screens with weight t, as it gets a share t of the normal)
            const double share =
                samples.splat_depths.empty() ? 1.0 : std::clamp(samples.splat_depths[i] - depth + 1, 0.0, 1.0);
            screening_[i] = beta_ * samples.weights[i] * share;
            corner_weights(samples.positions[i], depth, cell, &sample_weights_[i * 8]);
            if (cell != last_cell) {  // samples come in space order (poisson.cpp): runs share their cell
                for (int c = 0; c < 8; ++c) {
                    cell_dofs[c] = level_.dofs.find(corner_key(cell, c));
                    assert(cell_dofs[c] != RowIndex::kNone);
                }
                last_cell = cell;
            }
            for (int c = 0; c < 8; ++c) sample_dofs_[i * 8 + static_cast<std::size_t>(c)] = cell_dofs[c];
        }
    });
    for (std::size_t i = 0; i < count; ++i) {
        if (screening_[i] == 0) continue;
        for (std::size_t c = 0; c < 8; ++c) {
            const double w = sample_weights_[i * 8 + c];
            diagonal_[sample_dofs_[i * 8 + c]] += screening_[i] * w * w;
        }
    }
    // on a level whose cells hold many samples each, the screening is summed per cell once, as the 8 x 8 matrix
    // sum_i beta w_i phi_c(p_i) phi_c'(p_i) of the cell's corners, so that each product costs a cell, not its samples
    // (the samples of a cell are consecutive: Morton order on the finest level is Morton order on every level)
    std::size_t runs = 0;
    for (std::size_t i = 0; i < count; ++i) runs += i == 0 || sample_cells_[i] != sample_cells_[i - 1] ? 1 : 0;
    if (runs * kSamplesPerScreeningCell > count && threaded && count >= kThreadedSize) {
        // otherwise, for products on two threads: the screening's scatter turned into a gather per dof, each dof's
        // terms in sample order (as the scatter adds them), found through the slots (sample, corner) sorted by dof
        std::vector<std::uint32_t> first(dofs + 1, 0);
        for (std::size_t slot = 0; slot < count * 8; ++slot)
            if (screening_[slot / 8] != 0) ++first[sample_dofs_[slot] + 1];
        for (std::size_t v = 0; v < dofs; ++v) first[v + 1] += first[v];
        screen_slots_.resize(first[dofs]);
        std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
        for (std::size_t slot = 0; slot < count * 8; ++slot)
            if (screening_[slot / 8] != 0) screen_slots_[fill[sample_dofs_[slot]]++] = static_cast<std::uint32_t>(slot);
        for (std::size_t v = 0; v < dofs; ++v)
            if (first[v + 1] > first[v]) {
                screen_dofs_.push_back(static_cast<std::uint32_t>(v));
                screen_offsets_.push_back(first[v]);
            }
        screen_offsets_.push_back(first[dofs]);
        sample_values_.assign(count, 0.0);
    }
    if (runs * kSamplesPerScreeningCell <= count) {
        cell_dofs_.reserve(runs * 8);
        cell_screening_.reserve(runs * 64);
        for (std::size_t i = 0; i < count; ++i) {
            if (i == 0 || sample_cells_[i] != sample_cells_[i - 1]) {
                cell_dofs_.insert(cell_dofs_.end(), &sample_dofs_[i * 8], &sample_dofs_[i * 8] + 8);
                cell_screening_.resize(cell_screening_.size() + 64, 0.0);
            }
            if (screening_[i] == 0) continue;
            double* m = &cell_screening_[cell_screening_.size() - 64];
            const double* w = &sample_weights_[i * 8];
            for (int r = 0; r < 8; ++r)
                for (int c = 0; c < 8; ++c) m[r * 8 + c] += screening_[i] * w[r] * w[c];
        }
    }
    (void)tree_;
}

void LevelSystem::apply(const std::vector<double>& x, std::vector<double>& y, bool threaded) const {
    const std::size_t dofs = fixed_.size();
    y.resize(dofs);  // every entry is written below (no clearing pass over the level first)
    const std::size_t middle = dofs / 2;
    run_two_parts(threaded, [&](int part) {
        const std::size_t begin = part == 0 ? 0 : middle, end = part == 0 ? middle : dofs;
        for (std::size_t v = begin; v < end; ++v) spread_[rows_.position(v, 4)] = fixed_[v] ? 0.0 : x[v];
    });
    run_two_parts(threaded, [&](int part) {
        const std::size_t begin = part == 0 ? 0 : middle, end = part == 0 ? middle : dofs;
        for (std::size_t v = begin; v < end; ++v)
            y[v] = fixed_[v] ? 0.0 : stencil_sum(rows_, v, spread_.data(), kStiffness.w) * h_;
    });
    if (!cell_dofs_.empty()) {
        for (std::size_t cell = 0; cell < cell_dofs_.size() / 8; ++cell) {
            const std::uint32_t* d = &cell_dofs_[cell * 8];
            const double* m = &cell_screening_[cell * 64];
            double xs[8];
            for (int c = 0; c < 8; ++c) xs[c] = any_fixed_ && fixed_[d[c]] ? 0.0 : x[d[c]];
            for (int r = 0; r < 8; ++r) {
                if (any_fixed_ && fixed_[d[r]]) continue;
                double sum = 0;
                for (int c = 0; c < 8; ++c) sum += m[r * 8 + c] * xs[c];
                y[d[r]] += sum;
            }
        }
        return;
    }
    if (!screen_dofs_.empty()) {
        halves(sample_cells_.size(), threaded, [&](std::size_t begin, std::size_t end) {
            for (std::size_t i = begin; i < end; ++i) {
                if (screening_[i] == 0) continue;
                const double* w = &sample_weights_[i * 8];
                const std::uint32_t* d = &sample_dofs_[i * 8];
                double value = 0;
                for (int c = 0; c < 8; ++c)
                    if (!any_fixed_ || !fixed_[d[c]]) value += w[c] * x[d[c]];
                sample_values_[i] = value * screening_[i];
            }
        });
        halves(screen_dofs_.size(), threaded, [&](std::size_t begin, std::size_t end) {
            for (std::size_t t = begin; t < end; ++t) {
                const std::uint32_t v = screen_dofs_[t];
                if (any_fixed_ && fixed_[v]) continue;
                double sum = y[v];
                for (std::uint32_t q = screen_offsets_[t]; q < screen_offsets_[t + 1]; ++q) {
                    const std::uint32_t slot = screen_slots_[q];
                    sum += sample_weights_[slot] * sample_values_[slot / 8];
                }
                y[v] = sum;
            }
        });
        return;
    }
    for (std::size_t i = 0; i < sample_cells_.size(); ++i) {
        if (screening_[i] == 0) continue;
        const double* w = &sample_weights_[i * 8];
        const std::uint32_t* d = &sample_dofs_[i * 8];
        double value = 0;
        if (any_fixed_) {
            for (int c = 0; c < 8; ++c)
                if (!fixed_[d[c]]) value += w[c] * x[d[c]];
            value *= screening_[i];
            for (int c = 0; c < 8; ++c)
                if (!fixed_[d[c]]) y[d[c]] += w[c] * value;
            continue;
        }
        for (int c = 0; c < 8; ++c) value += w[c] * x[d[c]];
        value *= screening_[i];
        for (int c = 0; c < 8; ++c) y[d[c]] += w[c] * value;
    }
}

void LevelSystem::subtract_stiffness(const std::vector<double>& support_values, std::vector<double>& out) const {
    const std::size_t dofs = fixed_.size();
    std::copy(support_values.begin(), support_values.end(), spread_.begin());
    halves(dofs, threaded_, [&](std::size_t begin, std::size_t end) {
        for (std::size_t v = begin; v < end; ++v) out[v] -= stencil_sum(rows_, v, spread_.data(), kStiffness.w) * h_;
    });
    std::fill(spread_.begin(), spread_.end(), 0.0);
}

void LevelSystem::subtract_screening(const std::vector<double>& sample_values, std::vector<double>& out) const {
    for (std::size_t i = 0; i < sample_cells_.size(); ++i) {
        if (screening_[i] == 0) continue;
        const double* w = &sample_weights_[i * 8];
        const double value = screening_[i] * sample_values[i];
        for (int c = 0; c < 8; ++c) out[sample_dofs_[i * 8 + static_cast<std::size_t>(c)]] -= w[c] * value;
    }
}

void LevelSystem::evaluate_at_samples(const std::vector<double>& x, std::vector<double>& out) const {
    out.assign(sample_cells_.size(), 0.0);
    for (std::size_t i = 0; i < sample_cells_.size(); ++i) {
        const double* w = &sample_weights_[i * 8];
        double value = 0;
        for (int c = 0; c < 8; ++c) value += w[c] * x[sample_dofs_[i * 8 + static_cast<std::size_t>(c)]];
        out[i] = value;
    }
}

std::size_t LevelSystem::memory_bytes() const {
    return rows_.memory_bytes() + spread_.capacity() * 8 + sample_dofs_.capacity() * 4 + cell_dofs_.capacity() * 4 +
           cell_screening_.capacity() * 8 + screen_dofs_.capacity() * 4 + screen_offsets_.capacity() * 4 +
           screen_slots_.capacity() * 4 + sample_values_.capacity() * 8 + sample_cells_.capacity() * 8 +
           sample_weights_.capacity() * 8 + screening_.capacity() * 8 + fixed_.capacity() + diagonal_.capacity() * 8;
}

}  // namespace surfaced::reconstruct
