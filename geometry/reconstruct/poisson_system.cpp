#include "geometry/reconstruct/poisson_system.h"

#include <algorithm>
#include <cassert>
#include <cmath>

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

std::uint64_t offset_key(std::uint64_t key, int di, int dj, int dk) {
    return pack_key(static_cast<std::uint32_t>(static_cast<std::int64_t>(key_i(key)) + di),
                    static_cast<std::uint32_t>(static_cast<std::int64_t>(key_j(key)) + dj),
                    static_cast<std::uint32_t>(static_cast<std::int64_t>(key_k(key)) + dk));
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

}  // namespace

void corner_weights(const Vec3& p, int depth, std::uint64_t cell, double weights[8]) {
    const double n = std::ldexp(1.0, depth);
    const double tx = std::clamp(p.x * n - key_i(cell), 0.0, 1.0);
    const double ty = std::clamp(p.y * n - key_j(cell), 0.0, 1.0);
    const double tz = std::clamp(p.z * n - key_k(cell), 0.0, 1.0);
    for (int c = 0; c < 8; ++c)
        weights[c] = ((c & 1) ? tx : 1 - tx) * ((c & 2) ? ty : 1 - ty) * ((c & 4) ? tz : 1 - tz);
}

std::vector<std::vector<double>> divergence_rhs(const PoissonOctree& tree, const OrientedSamples& samples) {
    const int finest = tree.max_depth;
    const OctreeLevel& fine = tree.level(finest);
    const double h = std::ldexp(1.0, -finest);
    const std::uint32_t n = std::uint32_t{1} << finest;

    // splat: n_w = sum_i a_i N_i phi_w(p_i) on the finest dofs
    std::vector<Vec3> splat(fine.dofs.size());
    for (std::size_t i = 0; i < samples.positions.size(); ++i) {
        const std::uint64_t cell = cell_key(samples.positions[i], finest);
        double w[8];
        corner_weights(samples.positions[i], finest, cell, w);
        const double a = samples.area * samples.weights[i] / samples.weight_sum;
        for (int c = 0; c < 8; ++c) {
            const std::uint32_t dof = fine.dofs.find(corner_key(cell, c));
            assert(dof != KeyMap::kNone);
            splat[dof] += samples.normals[i] * (a * w[c]);
        }
    }

    std::vector<std::vector<double>> rhs(tree.levels.size());
    std::vector<double>& b = rhs.back();
    b.assign(fine.dofs.size(), 0.0);
    // b_u = sum_w n_w . integral grad phi_u phi_w / h^3, scattered from each w with a non-zero splat
    for (std::size_t w = 0; w < splat.size(); ++w) {
        const Vec3 nw = splat[w];
        if (nw.x == 0 && nw.y == 0 && nw.z == 0) continue;
        const std::uint64_t key = fine.dofs.keys[w];
        for (int c = 0; c < 3; ++c)
            for (int bb = 0; bb < 3; ++bb)
                for (int a = 0; a < 3; ++a) {
                    // u = w - o with o = (a-1, bb-1, c-1)
                    if (!offset_inside(key, 1 - a, 1 - bb, 1 - c, n)) continue;
                    const std::uint32_t u = fine.dofs.find(offset_key(key, 1 - a, 1 - bb, 1 - c));
                    assert(u != KeyMap::kNone);
                    const double gx = kMixed[a] * kMass[bb] * kMass[c];
                    const double gy = kMass[a] * kMixed[bb] * kMass[c];
                    const double gz = kMass[a] * kMass[bb] * kMixed[c];
                    b[u] += (nw.x * gx + nw.y * gy + nw.z * gz) / h;
                }
    }

    // restriction: a coarse hat is sum 2^-(odd offsets) of the fine hats around its centre
    for (std::size_t li = tree.levels.size() - 1; li > 0; --li) {
        const OctreeLevel& from = tree.levels[li];
        const OctreeLevel& to = tree.levels[li - 1];
        std::vector<double>& coarse = rhs[li - 1];
        coarse.assign(to.dofs.size(), 0.0);
        const std::vector<double>& f = rhs[li];
        for (std::size_t u = 0; u < f.size(); ++u) {
            if (f[u] == 0) continue;
            const std::uint64_t key = from.dofs.keys[u];
            const std::uint32_t idx[3] = {key_i(key), key_j(key), key_k(key)};
            std::uint32_t lo[3], hi[3];
            for (int a = 0; a < 3; ++a) {
                lo[a] = idx[a] / 2;
                hi[a] = (idx[a] % 2) ? lo[a] + 1 : lo[a];
            }
            const double weight = ((idx[0] % 2) ? 0.5 : 1.0) * ((idx[1] % 2) ? 0.5 : 1.0) * ((idx[2] % 2) ? 0.5 : 1.0);
            for (std::uint32_t k = lo[2]; k <= hi[2]; ++k)
                for (std::uint32_t j = lo[1]; j <= hi[1]; ++j)
                    for (std::uint32_t i = lo[0]; i <= hi[0]; ++i) {
                        const std::uint32_t v = to.dofs.find(pack_key(i, j, k));
                        assert(v != KeyMap::kNone);
                        coarse[v] += weight * f[u];
                    }
        }
    }
    return rhs;
}

LevelSystem::LevelSystem(const PoissonOctree& tree, int depth, const OrientedSamples& samples, double alpha,
                         bool dirichlet)
    : tree_(tree), level_(tree.level(depth)), samples_(samples) {
    h_ = std::ldexp(1.0, -depth);
    beta_ = samples.weight_sum > 0 ? alpha * std::ldexp(1.0, depth) * samples.area / samples.weight_sum : 0.0;
    const std::uint32_t n = std::uint32_t{1} << depth;
    const std::size_t dofs = level_.dofs.size();

    fixed_.assign(dofs, 0);
    if (dirichlet)
        for (std::size_t v = 0; v < dofs; ++v) fixed_[v] = on_boundary(level_.dofs.keys[v], n) ? 1 : 0;

    neighbours_.assign(dofs * 27, KeyMap::kNone);
    for (std::size_t v = 0; v < dofs; ++v) {
        const std::uint64_t key = level_.dofs.keys[v];
        for (int c = 0; c < 3; ++c)
            for (int b = 0; b < 3; ++b)
                for (int a = 0; a < 3; ++a) {
                    if (!offset_inside(key, a - 1, b - 1, c - 1, n)) continue;
                    neighbours_[v * 27 + static_cast<std::size_t>(a + 3 * b + 9 * c)] =
                        level_.dofs.find(offset_key(key, a - 1, b - 1, c - 1));
                }
    }

    diagonal_.assign(dofs, kStiffness.w[13] * h_);
    const std::size_t count = samples.positions.size();
    sample_dofs_.resize(count * 8);
    sample_cells_.resize(count);
    for (std::size_t i = 0; i < count; ++i) {
        const std::uint64_t cell = cell_key(samples.positions[i], depth);
        sample_cells_[i] = cell;
        double w[8];
        corner_weights(samples.positions[i], depth, cell, w);
        for (int c = 0; c < 8; ++c) {
            const std::uint32_t dof = level_.dofs.find(corner_key(cell, c));
            assert(dof != KeyMap::kNone);
            sample_dofs_[i * 8 + static_cast<std::size_t>(c)] = dof;
            diagonal_[dof] += beta_ * samples.weights[i] * w[c] * w[c];
        }
    }
    (void)tree_;
}

void LevelSystem::apply(const std::vector<double>& x, std::vector<double>& y) const {
    const std::size_t dofs = fixed_.size();
    y.assign(dofs, 0.0);
    for (std::size_t v = 0; v < dofs; ++v) {
        if (fixed_[v]) continue;
        const std::uint32_t* nb = &neighbours_[v * 27];
        double sum = 0;
        for (int o = 0; o < 27; ++o) {
            const std::uint32_t w = nb[o];
            if (w != KeyMap::kNone && !fixed_[w]) sum += kStiffness.w[o] * x[w];
        }
        y[v] = sum * h_;
    }
    const int depth = level_.depth;
    for (std::size_t i = 0; i < sample_cells_.size(); ++i) {
        double w[8];
        corner_weights(samples_.positions[i], depth, sample_cells_[i], w);
        const std::uint32_t* d = &sample_dofs_[i * 8];
        double value = 0;
        for (int c = 0; c < 8; ++c)
            if (!fixed_[d[c]]) value += w[c] * x[d[c]];
        value *= beta_ * samples_.weights[i];
        for (int c = 0; c < 8; ++c)
            if (!fixed_[d[c]]) y[d[c]] += w[c] * value;
    }
}

void LevelSystem::subtract_stiffness(const std::vector<double>& support_values, std::vector<double>& out) const {
    const std::uint32_t n = std::uint32_t{1} << level_.depth;
    for (std::size_t v = 0; v < fixed_.size(); ++v) {
        const std::uint64_t key = level_.dofs.keys[v];
        double sum = 0;
        for (int c = 0; c < 3; ++c)
            for (int b = 0; b < 3; ++b)
                for (int a = 0; a < 3; ++a) {
                    if (!offset_inside(key, a - 1, b - 1, c - 1, n)) continue;
                    const std::uint32_t s = level_.support_vertices.find(offset_key(key, a - 1, b - 1, c - 1));
                    assert(s != KeyMap::kNone);
                    sum += kStiffness.w[a + 3 * b + 9 * c] * support_values[s];
                }
        out[v] -= sum * h_;
    }
}

void LevelSystem::subtract_screening(const std::vector<double>& sample_values, std::vector<double>& out) const {
    const int depth = level_.depth;
    for (std::size_t i = 0; i < sample_cells_.size(); ++i) {
        double w[8];
        corner_weights(samples_.positions[i], depth, sample_cells_[i], w);
        const double value = beta_ * samples_.weights[i] * sample_values[i];
        for (int c = 0; c < 8; ++c) out[sample_dofs_[i * 8 + static_cast<std::size_t>(c)]] -= w[c] * value;
    }
}

void LevelSystem::evaluate_at_samples(const std::vector<double>& x, std::vector<double>& out) const {
    const int depth = level_.depth;
    out.assign(sample_cells_.size(), 0.0);
    for (std::size_t i = 0; i < sample_cells_.size(); ++i) {
        double w[8];
        corner_weights(samples_.positions[i], depth, sample_cells_[i], w);
        double value = 0;
        for (int c = 0; c < 8; ++c) value += w[c] * x[sample_dofs_[i * 8 + static_cast<std::size_t>(c)]];
        out[i] = value;
    }
}

std::size_t LevelSystem::memory_bytes() const {
    return neighbours_.capacity() * 4 + sample_dofs_.capacity() * 4 + sample_cells_.capacity() * 8 + fixed_.capacity() +
           diagonal_.capacity() * 8;
}

}  // namespace surfaced::reconstruct
