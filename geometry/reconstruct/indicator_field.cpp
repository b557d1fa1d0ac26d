#include "geometry/reconstruct/indicator_field.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry/reconstruct/poisson_system.h"

namespace surfaced::reconstruct {

IndicatorField::IndicatorField(const PoissonOctree& tree, const IndicatorValues& values, const Vec3& origin,
                               double size, double iso_value)
    : tree_(tree), values_(values), origin_(origin), size_(size), iso_(iso_value) {}

Vec3 IndicatorField::to_unit(const Vec3& p) const {
    const Vec3 q = (p - origin_) * (1.0 / size_);
    return {std::clamp(q.x, 0.0, 1.0), std::clamp(q.y, 0.0, 1.0), std::clamp(q.z, 0.0, 1.0)};
}

void IndicatorField::locate(const Vec3& q, std::size_t& level, double corners[8]) const {
    // the finest cell once; coarser cells by shifting its coordinates
    const std::uint64_t finest = cell_key(q, tree_.max_depth);
    const std::uint32_t fi = key_i(finest), fj = key_j(finest), fk = key_k(finest);
    auto cell_at = [&](std::size_t l) {
        const int shift = tree_.max_depth - tree_.levels[l].depth;
        return pack_key(fi >> shift, fj >> shift, fk >> shift);
    };
    level = 0;
    while (level + 1 < tree_.levels.size() &&
           tree_.levels[level + 1].support_cells.find(cell_at(level + 1)) != RowIndex::kNone)
        ++level;
    const OctreeLevel& l = tree_.levels[level];
    const std::uint64_t cell = cell_at(level);
    const std::vector<double>& values = values_.values[level];
    for (std::uint32_t c = 0; c < 8; ++c) {
        const std::uint32_t v = l.support_vertices.find(
            pack_key(key_i(cell) + (c & 1), key_j(cell) + ((c >> 1) & 1), key_k(cell) + (c >> 2)));
        corners[c] = values[v];
    }
}

double IndicatorField::value(const Vec3& p) const {
    const Vec3 q = to_unit(p);
    std::size_t level = 0;
    double corners[8];
    locate(q, level, corners);
    const int depth = tree_.levels[level].depth;
    double w[8];
    corner_weights(q, depth, cell_key(q, depth), w);
    double sum = 0;
    for (int c = 0; c < 8; ++c) sum += w[c] * corners[c];
    return sum - iso_;
}

Vec3 IndicatorField::gradient(const Vec3& p) const {
    const Vec3 q = to_unit(p);
    std::size_t level = 0;
    double corners[8];
    locate(q, level, corners);
    const int depth = tree_.levels[level].depth;
    const double n = std::ldexp(1.0, depth);
    const std::uint64_t cell = cell_key(q, depth);
    const double t[3] = {std::clamp(q.x * n - key_i(cell), 0.0, 1.0), std::clamp(q.y * n - key_j(cell), 0.0, 1.0),
                         std::clamp(q.z * n - key_k(cell), 0.0, 1.0)};
    Vec3 g;
    for (int axis = 0; axis < 3; ++axis) {
        double d = 0;
        for (int c = 0; c < 8; ++c) {
            double w = 1;
            for (int a = 0; a < 3; ++a) {
                const bool bit = (c >> a) & 1;
                if (a == axis)
                    w *= bit ? 1.0 : -1.0;
                else
                    w *= bit ? t[a] : 1 - t[a];
            }
            d += w * corners[c];
        }
        g[axis] = d * n / size_;
    }
    return g;
}

double IndicatorField::lipschitz() const { return std::numeric_limits<double>::infinity(); }

}  // namespace surfaced::reconstruct
