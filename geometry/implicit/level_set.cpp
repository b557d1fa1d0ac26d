// Trilinear level-set field (see level_set.h).
#include "geometry/implicit/level_set.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

namespace surfaced::implicit {
namespace {

class LevelSet final : public Field {
public:
    explicit LevelSet(LevelSetGrid g) : g_(std::move(g)) {
        for (int a = 0; a < 3; ++a)
            upper_[a] = g_.origin[a] + g_.spacing[a] * static_cast<double>(g_.dims[static_cast<std::size_t>(a)] - 1);
        Vec3 slope;
        const std::size_t nx = g_.dims[0], ny = g_.dims[1], nz = g_.dims[2];
        for (std::size_t k = 0; k < nz; ++k)
            for (std::size_t j = 0; j < ny; ++j)
                for (std::size_t i = 0; i < nx; ++i) {
                    const double v = sample(i, j, k);
                    if (i + 1 < nx) slope.x = std::max(slope.x, std::abs(sample(i + 1, j, k) - v) / g_.spacing.x);
                    if (j + 1 < ny) slope.y = std::max(slope.y, std::abs(sample(i, j + 1, k) - v) / g_.spacing.y);
                    if (k + 1 < nz) slope.z = std::max(slope.z, std::abs(sample(i, j, k + 1) - v) / g_.spacing.z);
                }
        lipschitz_ = std::max(1.0, norm(slope) + 1.0);
    }

    double value(const Vec3& p) const override {
        const Vec3 c = clamp(p);
        return interpolate(c, nullptr) + norm(p - c);
    }

    Vec3 gradient(const Vec3& p) const override {
        const Vec3 c = clamp(p);
        Vec3 g;
        interpolate(c, &g);
        const Vec3 d = p - c;
        const double n = norm(d);
        if (n == 0) return g;
        for (int a = 0; a < 3; ++a)
            if (p[a] != c[a]) g[a] = 0;  // clamped axes do not move f(c)
        return g + d * (1.0 / n);
    }

    FieldKind kind() const override { return FieldKind::DistanceBound; }
    double lipschitz() const override { return lipschitz_; }

private:
    double sample(std::size_t i, std::size_t j, std::size_t k) const {
        return g_.values[i + g_.dims[0] * (j + g_.dims[1] * k)];
    }

    Vec3 clamp(const Vec3& p) const {
        return {std::clamp(p.x, g_.origin.x, upper_[0]), std::clamp(p.y, g_.origin.y, upper_[1]),
                std::clamp(p.z, g_.origin.z, upper_[2])};
    }

    //! Trilinear value at a point inside the box, and optionally its gradient.
    double interpolate(const Vec3& p, Vec3* grad) const {
        std::size_t cell[3];
        double t[3];
        for (int a = 0; a < 3; ++a) {
            const double u = (p[a] - g_.origin[a]) / g_.spacing[a];
            const auto last = static_cast<double>(g_.dims[static_cast<std::size_t>(a)] - 2);
            const double base = std::clamp(std::floor(u), 0.0, last);
            cell[a] = static_cast<std::size_t>(base);
            t[a] = std::clamp(u - base, 0.0, 1.0);
        }
        double c[2][2][2];
        for (int dz = 0; dz < 2; ++dz)
            for (int dy = 0; dy < 2; ++dy)
                for (int dx = 0; dx < 2; ++dx)
                    c[dz][dy][dx] =
                        sample(cell[0] + static_cast<std::size_t>(dx), cell[1] + static_cast<std::size_t>(dy),
                               cell[2] + static_cast<std::size_t>(dz));
        const double tx = t[0], ty = t[1], tz = t[2];
        auto lerp = [](double a, double b, double s) { return a + (b - a) * s; };
        // along x, then y, then z
        const double c00 = lerp(c[0][0][0], c[0][0][1], tx), c10 = lerp(c[0][1][0], c[0][1][1], tx);
        const double c01 = lerp(c[1][0][0], c[1][0][1], tx), c11 = lerp(c[1][1][0], c[1][1][1], tx);
        const double c0 = lerp(c00, c10, ty), c1 = lerp(c01, c11, ty);
        if (grad) {
            const double dx00 = c[0][0][1] - c[0][0][0], dx10 = c[0][1][1] - c[0][1][0];
            const double dx01 = c[1][0][1] - c[1][0][0], dx11 = c[1][1][1] - c[1][1][0];
            const double dfdx = lerp(lerp(dx00, dx10, ty), lerp(dx01, dx11, ty), tz);
            const double dfdy = lerp(c10 - c00, c11 - c01, tz);
            const double dfdz = c1 - c0;
            *grad = {dfdx / g_.spacing.x, dfdy / g_.spacing.y, dfdz / g_.spacing.z};
        }
        return lerp(c0, c1, tz);
    }

    LevelSetGrid g_;
    double upper_[3] = {0, 0, 0};
    double lipschitz_ = 1;
};

}  // namespace

Result<FieldPtr> level_set(LevelSetGrid grid) {
    std::size_t count = 1;
    for (int a = 0; a < 3; ++a) {
        const std::size_t n = grid.dims[static_cast<std::size_t>(a)];
        if (n < 2) return make_error(ErrorCode::InvalidArgument, "a level-set grid needs at least 2 samples per axis");
        if (!(grid.spacing[a] > 0) || !std::isfinite(grid.spacing[a]))
            return make_error(ErrorCode::InvalidArgument, "level-set spacing must be finite and > 0");
        if (!std::isfinite(grid.origin[a])) return make_error(ErrorCode::NonFinite, "level-set origin must be finite");
        count *= n;
    }
    if (grid.values.size() != count)
        return make_error(ErrorCode::InvalidArgument,
                          "a level-set grid of " + std::to_string(grid.dims[0]) + "x" + std::to_string(grid.dims[1]) +
                              "x" + std::to_string(grid.dims[2]) + " needs " + std::to_string(count) + " values, got " +
                              std::to_string(grid.values.size()));
    for (std::size_t i = 0; i < grid.values.size(); ++i)
        if (!std::isfinite(grid.values[i]))
            return element_error(ErrorCode::NonFinite, "level-set value " + std::to_string(i) + " is not finite",
                                 ElementKind::None, static_cast<std::int64_t>(i));
    return FieldPtr(std::make_shared<LevelSet>(std::move(grid)));
}

}  // namespace surfaced::implicit
