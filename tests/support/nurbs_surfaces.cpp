#include "tests/support/nurbs_surfaces.h"

#include <algorithm>
#include <cmath>

namespace surfaced::testing {
namespace {

//! The 9-point rational quadratic circle (The NURBS Book, ex. 7.2): square corners with weight sqrt(2)/2.
struct Circle {
    double x[9] = {1, 1, 0, -1, -1, -1, 0, 1, 1};
    double y[9] = {0, 1, 1, 1, 0, -1, -1, -1, 0};
    double w[9] = {1, std::sqrt(0.5), 1, std::sqrt(0.5), 1, std::sqrt(0.5), 1, std::sqrt(0.5), 1};
    std::vector<double> knots{0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1};
};

}  // namespace

//! A surface of revolution about the z axis through `center`: u the 9-point circle, v the profile (radius, height)
//! with its weights and knots, degree 2 along u.
BSplineSurface revolve(const Vec3& center, const std::vector<double>& radius, const std::vector<double>& height,
                       const std::vector<double>& profile_weights, const std::vector<double>& knots_v, int degree_v) {
    const Circle c;
    BSplineSurface s;
    s.degree_u = 2;
    s.degree_v = degree_v;
    s.count_u = 9;
    s.count_v = static_cast<int>(radius.size());
    s.knots_u = c.knots;
    s.knots_v = knots_v;
    for (std::size_t j = 0; j < radius.size(); ++j)
        for (int i = 0; i < 9; ++i) {
            s.points.push_back(center + Vec3{radius[j] * c.x[i], radius[j] * c.y[i], height[j]});
            s.weights.push_back(c.w[i] * profile_weights[j]);
        }
    return s;
}

//! The standard 9 x 5 NURBS sphere: the half circle from the south pole to the north pole, revolved.
BSplineSurface sphere(const Vec3& center, double r) {
    const double h = std::sqrt(0.5);
    return revolve(center, {0, r, r, r, 0}, {-r, -r, 0, r, r}, {1, h, 1, h, 1}, {0, 0, 0, 0.5, 0.5, 1, 1, 1}, 2);
}

//! Torus of major radius R, minor radius r: the 9-point circle of radius r about (R, 0) in the (radius, z) plane.
BSplineSurface torus(const Vec3& center, double R, double r) {
    const Circle c;
    std::vector<double> radius, height, weights;
    for (int j = 0; j < 9; ++j) {
        radius.push_back(R + r * c.x[j]);
        height.push_back(r * c.y[j]);
        weights.push_back(c.w[j]);
    }
    return revolve(center, radius, height, weights, c.knots, 2);
}

//! Cylinder of radius r from z = 0 to z = h, linear along v with an interior knot.
BSplineSurface cylinder(const Vec3& center, double r, double h) {
    return revolve(center, {r, r, r}, {0, 0.4 * h, h}, {1, 1, 1}, {0, 0, 0.4, 1, 1}, 1);
}

//! Random knots for n points of degree p: steps in [0.2, 1], interior values repeated up to p times (often once),
//! the ends p + 1 times when clamped.
std::vector<double> random_knots(int n, int p, bool clamped, std::mt19937& rng) {
    std::uniform_real_distribution<double> step(0.2, 1.0);
    std::uniform_int_distribution<int> mult(1, p), coin(0, 3);
    const auto m = static_cast<std::size_t>(n + p + 1), ps = static_cast<std::size_t>(p);
    std::vector<double> knots;
    double value = -0.7;
    if (clamped) knots.assign(ps + 1, value);
    const std::size_t interior_end = clamped ? m - ps - 1 : m;
    while (knots.size() < interior_end) {
        value += step(rng);
        const std::size_t r = std::min<std::size_t>(coin(rng) == 0 ? static_cast<std::size_t>(mult(rng)) : 1,
                                                    interior_end - knots.size());
        knots.insert(knots.end(), r, value);
    }
    if (clamped) knots.insert(knots.end(), ps + 1, value + step(rng));
    return knots;
}

BSplineSurface random_surface(unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> degree(1, 5), extra(0, 4), coin(0, 1);
    std::uniform_real_distribution<double> coord(-3.0, 3.0), weight(0.3, 3.0);
    for (;;) {
        BSplineSurface s;
        s.degree_u = degree(rng);
        s.degree_v = degree(rng);
        s.count_u = s.degree_u + 1 + extra(rng);
        s.count_v = s.degree_v + 1 + extra(rng);
        const bool rational = coin(rng) == 1;
        for (int k = 0; k < s.count_u * s.count_v; ++k) {
            s.points.push_back({coord(rng), coord(rng), coord(rng)});
            if (rational) s.weights.push_back(weight(rng));
        }
        s.knots_u = random_knots(s.count_u, s.degree_u, coin(rng) == 1, rng);
        s.knots_v = random_knots(s.count_v, s.degree_v, coin(rng) == 1, rng);
        if (validate(s)) return s;  // an unclamped vector can have an empty domain: draw again
    }
}

}  // namespace surfaced::testing
