// Mandelbulb and Menger sponge distance estimators (see fractals.h).
#include "geometry/implicit/fractals.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace surfaced::implicit {
namespace {

//! The value of points whose orbit stays bounded (the set has diameter about 2, so this is "just inside").
constexpr double kInteriorValue = 1e-3;

class Mandelbulb final : public Field {
public:
    Mandelbulb(double power, int iterations, double bailout) : n_(power), iters_(iterations), bailout_(bailout) {}

    double value(const Vec3& p) const override {
        constexpr double kBound = 2.0;
        const double r = norm(p);
        if (r > kBound) return (r - kBound) + estimate(p * (kBound / r));
        return estimate(p);
    }
    FieldKind kind() const override { return FieldKind::DistanceBound; }

private:
    double estimate(const Vec3& c) const {
        Vec3 z = c;
        double dr = 1.0, r = norm(z);
        for (int i = 0; i < iters_ && r <= bailout_; ++i) {
            if (r < 1e-300) {  // z^n = 0: the next point is c itself
                z = c;
                dr = 1.0;
                r = norm(z);
                continue;
            }
            const double theta = std::acos(std::clamp(z.z / r, -1.0, 1.0)) * n_;
            const double phi = std::atan2(z.y, z.x) * n_;
            const double rn = std::pow(r, n_);
            dr = n_ * std::pow(r, n_ - 1) * dr + 1.0;
            z = Vec3{std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)} * rn + c;
            r = norm(z);
        }
        if (!std::isfinite(r)) return 1e-12;  // escaped so fast the estimate overflowed: outside, tiny step
        if (r > bailout_) return std::max(0.5 * std::log(r) * r / dr, 1e-12);
        return -kInteriorValue;  // no distance is known inside: only the sign
    }

    double n_;
    int iters_;
    double bailout_;
};

//! 2D signed distance to the square [-w, w]^2.
double square(double a, double b, double w) {
    const double qa = std::abs(a) - w, qb = std::abs(b) - w;
    return std::hypot(std::max(qa, 0.0), std::max(qb, 0.0)) + std::min(std::max(qa, qb), 0.0);
}

class Menger final : public Field {
public:
    Menger(int iterations, double half_size) : iters_(iterations), h_(half_size) {}

    double value(const Vec3& p) const override {
        const Vec3 q = p * (1.0 / h_);  // unit sponge [-1, 1]^3, scaled back at the end (exact scaling)
        Vec3 d;
        for (int a = 0; a < 3; ++a) d[a] = std::abs(q[a]) - 1.0;
        double v = std::hypot(std::hypot(std::max(d.x, 0.0), std::max(d.y, 0.0)), std::max(d.z, 0.0)) +
                   std::min(std::max({d.x, d.y, d.z}), 0.0);
        double cell = 2.0;
        for (int l = 1; l <= iters_; ++l) {
            const double w = cell / 6.0;
            Vec3 local;  // coordinates relative to the centre of q's lattice cell
            for (int a = 0; a < 3; ++a) {
                const double u = q[a] + 1.0;
                local[a] = u - cell * std::floor(u / cell) - 0.5 * cell;
            }
            const double bars =
                std::min({square(local.y, local.z, w), square(local.z, local.x, w), square(local.x, local.y, w)});
            v = std::max(v, -bars);
            cell /= 3.0;
        }
        return v * h_;
    }
    FieldKind kind() const override { return FieldKind::DistanceBound; }

private:
    int iters_;
    double h_;
};

}  // namespace

FieldPtr mandelbulb(double power, int iterations, double bailout) {
    assert(power >= 2 && iterations >= 1 && bailout >= 2);
    return std::make_shared<Mandelbulb>(power, iterations, bailout);
}

FieldPtr menger_sponge(int iterations, double half_size) {
    assert(iterations >= 0 && half_size > 0);
    return std::make_shared<Menger>(iterations, half_size);
}

}  // namespace surfaced::implicit
