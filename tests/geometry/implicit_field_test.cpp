// Implicit primitives, transforms and combinations: exact distances against analytic values and brute force,
// |∇f| = 1 for exact fields, bounds that never overestimate, CSG and smooth-min properties, Lipschitz constants.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "geometry/implicit/operators.h"
#include "geometry/implicit/primitives.h"

namespace surfaced::implicit {
namespace {

std::vector<Vec3> random_points(int n, double extent, unsigned seed = 7) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-extent, extent);
    std::vector<Vec3> out;
    for (int i = 0; i < n; ++i) out.push_back({u(rng), u(rng), u(rng)});
    return out;
}

//! Distance from p to the nearest of `samples` (a brute-force reference, within the sampling density).
double nearest(const Vec3& p, const std::vector<Vec3>& samples) {
    double best = std::numeric_limits<double>::infinity();
    for (const Vec3& s : samples) best = std::min(best, norm(p - s));
    return best;
}

//! The ellipsoid with semi-axes r sampled densely (by latitude / longitude).
std::vector<Vec3> ellipsoid_samples(const Vec3& r, int n) {
    std::vector<Vec3> out;
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j < 2 * n; ++j) {
            const double th = std::numbers::pi * i / n, ph = std::numbers::pi * j / n;
            out.push_back({r.x * std::sin(th) * std::cos(ph), r.y * std::sin(th) * std::sin(ph), r.z * std::cos(th)});
        }
    return out;
}

TEST(ImplicitPrimitives, SphereIsExact) {
    const auto s = sphere(1.5);
    EXPECT_EQ(s->kind(), FieldKind::ExactDistance);
    for (const Vec3& p : random_points(200, 3)) {
        EXPECT_NEAR(s->value(p), norm(p) - 1.5, 1e-14);
        EXPECT_NEAR(norm(s->gradient(p)), 1.0, 1e-12);
    }
}

TEST(ImplicitPrimitives, BoxAtFacesEdgesCornersAndInside) {
    const auto b = box({1, 2, 3});
    EXPECT_NEAR(b->value({2, 0, 0}), 1.0, 1e-15);              // face
    EXPECT_NEAR(b->value({0, -2.5, 0}), 0.5, 1e-15);           // face
    EXPECT_NEAR(b->value({2, 3, 0}), std::sqrt(2.0), 1e-15);   // edge
    EXPECT_NEAR(b->value({-2, 3, 4}), std::sqrt(3.0), 1e-15);  // corner
    EXPECT_NEAR(b->value({0, 0, 0}), -1.0, 1e-15);             // inside: nearest face x
    EXPECT_NEAR(b->value({0.5, 1.8, 0}), -0.2, 1e-15);         // inside: nearest face y
    EXPECT_NEAR(b->value({1, 0, 0}), 0.0, 1e-15);              // on
    const Vec3 g = b->gradient({-2, 3, 4});
    EXPECT_NEAR(g.x, -1 / std::sqrt(3.0), 1e-12);
    EXPECT_NEAR(g.y, 1 / std::sqrt(3.0), 1e-12);
    EXPECT_NEAR(g.z, 1 / std::sqrt(3.0), 1e-12);
    EXPECT_EQ(b->gradient({0.5, 1.8, 0}), (Vec3{0, 1, 0}));
}

TEST(ImplicitPrimitives, RoundedBoxTorusCylinderCapsulePlaneAnalytic) {
    const auto rb = rounded_box({1, 1, 1}, 0.25);
    EXPECT_NEAR(rb->value({2, 0, 0}), 1.0, 1e-15);
    // corner: distance to the sphere of radius 0.25 around (0.75, 0.75, 0.75)
    EXPECT_NEAR(rb->value({2, 2, 2}), std::sqrt(3.0) * 1.25 - 0.25, 1e-14);

    const auto t = torus(2, 0.5);
    EXPECT_NEAR(t->value({2, 0, 0}), -0.5, 1e-15);
    EXPECT_NEAR(t->value({0, 0, 0}), 1.5, 1e-15);
    EXPECT_NEAR(t->value({0, 3, 1}), std::sqrt(2.0) - 0.5, 1e-14);
    EXPECT_NEAR(t->value({0, 0, 2}), std::sqrt(8.0) - 0.5, 1e-14);

    const auto c = cylinder(1, 2);
    EXPECT_NEAR(c->value({0, 0, 0}), -1.0, 1e-15);
    EXPECT_NEAR(c->value({3, 0, 0}), 2.0, 1e-15);
    EXPECT_NEAR(c->value({0, 0, 5}), 3.0, 1e-15);
    EXPECT_NEAR(c->value({0, 4, 6}), 5.0, 1e-14);  // rim: (3, 4)
    EXPECT_NEAR(c->value({0, 0.5, 1.8}), -0.2, 1e-14);

    const auto cap = capsule({0, 0, -1}, {0, 0, 1}, 0.5);
    EXPECT_NEAR(cap->value({2, 0, 0}), 1.5, 1e-15);
    EXPECT_NEAR(cap->value({0, 0, 3}), 1.5, 1e-15);
    EXPECT_NEAR(cap->value({0, 0, 0}), -0.5, 1e-15);

    const auto pl = plane({0, 0, 2}, 1);
    EXPECT_NEAR(pl->value({5, 7, 3}), 2.0, 1e-15);
    EXPECT_NEAR(pl->value({5, 7, -1}), -2.0, 1e-15);
}

//! The cone's exact distance against a brute-force distance to its profile boundary, revolved.
TEST(ImplicitPrimitives, ConeMatchesBruteForceDistance) {
    const double r1 = 1.0, h = 1.5, r2 = 0.25;
    const auto c = cone(r1, h, r2);
    EXPECT_EQ(c->kind(), FieldKind::ExactDistance);
    // Profile boundary in (rho, z): bottom, side, top segments, densely sampled.
    std::vector<std::pair<double, double>> profile;
    const int n = 4000;
    for (int i = 0; i <= n; ++i) {
        const double s = double(i) / n;
        profile.push_back({r1 * s, -h});
        profile.push_back({r1 + (r2 - r1) * s, -h + 2 * h * s});
        profile.push_back({r2 * s, h});
    }
    for (const Vec3& p : random_points(300, 2.5, 11)) {
        const double rho = std::hypot(p.x, p.y);
        double d = 1e9;
        for (auto [pr, pz] : profile) d = std::min(d, std::hypot(rho - pr, p.z - pz));
        const bool inside = p.z > -h && p.z < h && rho < r1 + (r2 - r1) * (p.z + h) / (2 * h);
        EXPECT_NEAR(c->value(p), inside ? -d : d, 2e-3) << p.x << " " << p.y << " " << p.z;
        EXPECT_NEAR(norm(c->gradient(p)), 1.0, 1e-4);
    }
}

TEST(ImplicitPrimitives, GradientOfExactFieldsHasUnitLength) {
    const FieldPtr fields[] = {
        sphere(1),          box({1, 0.5, 2}), rounded_box({1, 1, 1}, 0.3),         torus(1.5, 0.4),
        cylinder(0.7, 1.2), cone(1, 1),       capsule({1, 0, 0}, {-1, 1, 0}, 0.3), plane({1, 1, 0}, 0.2)};
    for (const auto& f : fields) {
        EXPECT_EQ(f->kind(), FieldKind::ExactDistance);
        for (const Vec3& p : random_points(100, 3, 3)) EXPECT_NEAR(norm(f->gradient(p)), 1.0, 1e-6);
    }
}

TEST(ImplicitPrimitives, EllipsoidNeverOverestimatesTheDistance) {
    const Vec3 r{2, 1, 0.5};
    const auto e = ellipsoid(r);
    EXPECT_EQ(e->kind(), FieldKind::DistanceBound);
    const auto samples = ellipsoid_samples(r, 300);
    for (const Vec3& p : random_points(200, 3, 5)) {
        const double inside = (p.x / r.x) * (p.x / r.x) + (p.y / r.y) * (p.y / r.y) + (p.z / r.z) * (p.z / r.z);
        const double v = e->value(p);
        EXPECT_EQ(v < 0, inside < 1);
        EXPECT_LE(std::abs(v), nearest(p, samples) + 1e-9);
    }
    EXPECT_NEAR(e->value({3, 0, 0}), 0.25, 1e-15);  // (3/2 - 1) * 0.5
}

TEST(ImplicitTransforms, TranslatedRotatedScaledSphereAreExact) {
    const auto s = sphere(1);
    const auto moved = translate(s, {1, 2, 3});
    EXPECT_EQ(moved->kind(), FieldKind::ExactDistance);
    EXPECT_NEAR(moved->value({1, 2, 6}), 2.0, 1e-15);
    const auto scaled = scale(s, 2.0);
    EXPECT_EQ(scaled->kind(), FieldKind::ExactDistance);
    EXPECT_NEAR(scaled->value({5, 0, 0}), 3.0, 1e-15);
    EXPECT_NEAR(scaled->value({0, 1, 0}), -1.0, 1e-15);
    // a rotated, translated sphere is the sphere around the rotated centre
    const auto turned = rotate(translate(s, {1, 0, 0}), rotation_axis_angle({0, 0, 1}, 90));
    for (const Vec3& p : random_points(50, 3)) EXPECT_NEAR(turned->value(p), norm(p - Vec3{0, 1, 0}) - 1, 1e-12);
}

TEST(ImplicitTransforms, RotationsMapAxesAsDocumented) {
    // 90 degrees about z: a box of half sizes (1, 2, 3) becomes (2, 1, 3).
    const auto turned = rotate(box({1, 2, 3}), rotation_axis_angle({0, 0, 1}, 90));
    const auto expected = box({2, 1, 3});
    for (const Vec3& p : random_points(100, 5)) EXPECT_NEAR(turned->value(p), expected->value(p), 1e-12);
    // Euler: x first, then y, then z (fixed axes). (90, 0, 0) maps y to z; (90, 90, 0) then maps z to -x.
    const Vec3 a = rotation_euler({90, 0, 0}) * Vec3{0, 1, 0};
    EXPECT_NEAR(a.z, 1, 1e-15);
    const Vec3 b = rotation_euler({90, 90, 0}) * Vec3{0, 1, 0};
    EXPECT_NEAR(b.x, 1, 1e-15);  // y -> z -> (about y by 90) x
    const Vec3 g = turned->gradient({3, 0, 0});
    EXPECT_NEAR(g.x, 1, 1e-12);
}

TEST(ImplicitTransforms, NonUniformScaleNeverOverestimates) {
    const Vec3 s{2, 1, 0.5};
    const auto f = scale(sphere(1), s);  // the ellipsoid with semi-axes s
    EXPECT_EQ(f->kind(), FieldKind::DistanceBound);
    EXPECT_DOUBLE_EQ(f->lipschitz(), 1.0);
    const auto samples = ellipsoid_samples(s, 300);
    for (const Vec3& p : random_points(200, 3, 9)) EXPECT_LE(std::abs(f->value(p)), nearest(p, samples) + 1e-9);
    // non-uniform scale of a box: never more than the exact distance to the scaled box
    const auto b = scale(box({1, 1, 1}), Vec3{3, 1, 1});
    const auto exact = box({3, 1, 1});
    for (const Vec3& p : random_points(200, 5, 10)) {
        EXPECT_LE(std::abs(b->value(p)), std::abs(exact->value(p)) + 1e-12);
        EXPECT_EQ(b->value(p) < 0, exact->value(p) < 0);
    }
}

TEST(ImplicitCsg, UnionIntersectionDifferenceAreMinMax) {
    const auto a = sphere(1), b = translate(sphere(1), {1.5, 0, 0});
    const auto u = csg_union({a, b}), i = csg_intersection({a, b}), d = csg_difference({a, b});
    EXPECT_EQ(u->kind(), FieldKind::DistanceBound);
    for (const Vec3& p : random_points(100, 3)) {
        EXPECT_DOUBLE_EQ(u->value(p), std::min(a->value(p), b->value(p)));
        EXPECT_DOUBLE_EQ(i->value(p), std::max(a->value(p), b->value(p)));
        EXPECT_DOUBLE_EQ(d->value(p), std::max(a->value(p), -b->value(p)));
    }
    EXPECT_LT(d->value({-0.5, 0, 0}), 0);
    EXPECT_GT(d->value({0.8, 0, 0}), 0);  // inside both: removed
    EXPECT_EQ(d->gradient({0.8, 0, 0}), b->gradient({0.8, 0, 0}) * -1.0);
}

TEST(ImplicitCsg, SmoothUnionIsBelowMinAndEqualWhenFarApart) {
    const double k = 0.5;
    EXPECT_DOUBLE_EQ(smooth_min(0.3, 0.3, k), 0.3 - k / 4);
    EXPECT_DOUBLE_EQ(smooth_min(0.1, 0.9, k), 0.1);  // |a - b| >= k
    const auto a = sphere(1), b = translate(sphere(1), {2.2, 0, 0});
    const auto su = smooth_union({a, b}, k);
    const auto si = smooth_intersection({a, b}, k);
    for (const Vec3& p : random_points(300, 3)) {
        const double va = a->value(p), vb = b->value(p);
        EXPECT_LE(su->value(p), std::min(va, vb) + 1e-15);
        EXPECT_GE(si->value(p), std::max(va, vb) - 1e-15);
        if (std::abs(va - vb) >= k) {
            EXPECT_DOUBLE_EQ(su->value(p), std::min(va, vb));
        }
    }
    // the bridge between two spheres 0.2 apart is filled
    EXPECT_LT(su->value({1.1, 0, 0}), 0);
    EXPECT_GT(csg_union({a, b})->value({1.1, 0, 0}), 0);
    // its gradient matches finite differences
    const Vec3 p{1.0, 0.3, 0.1};
    const Vec3 g = su->gradient(p);
    const double h = 1e-6;
    EXPECT_NEAR(g.x, (su->value(p + Vec3{h, 0, 0}) - su->value(p - Vec3{h, 0, 0})) / (2 * h), 1e-6);
    EXPECT_NEAR(g.y, (su->value(p + Vec3{0, h, 0}) - su->value(p - Vec3{0, h, 0})) / (2 * h), 1e-6);
    const auto sd = smooth_difference({box({1, 1, 1}), sphere(1.2)}, 0.2);
    const Vec3 q{0.95, 0.9, 0.85};
    const Vec3 gd = sd->gradient(q);
    EXPECT_NEAR(gd.z, (sd->value(q + Vec3{0, 0, h}) - sd->value(q - Vec3{0, 0, h})) / (2 * h), 1e-6);
}

TEST(ImplicitCsg, CombinationsRespectTheirLipschitzConstants) {
    const auto a = box({1, 0.5, 0.7}), b = torus(1, 0.3);
    const FieldPtr fields[] = {
        smooth_union({a, b}, 0.4), smooth_difference({a, b}, 0.3), blend(a, b, 0.3), shell(a, 0.2), offset(b, 0.3),
        scale(b, Vec3{1, 2, 3}),   csg_difference({a, b})};
    std::mt19937 rng(1);
    std::normal_distribution<double> step(0, 0.05);
    for (const auto& f : fields) {
        const double l = f->lipschitz();
        EXPECT_GE(l, 1.0);
        for (const Vec3& p : random_points(300, 2, 4)) {
            const Vec3 q = p + Vec3{step(rng), step(rng), step(rng)};
            EXPECT_LE(std::abs(f->value(p) - f->value(q)), l * norm(p - q) * (1 + 1e-12) + 1e-15);
        }
    }
}

TEST(ImplicitCsg, BlendOffsetShellAndSharedSubtrees) {
    const auto a = sphere(1), b = box({1, 1, 1});
    const auto mix = blend(a, b, 0.25);
    for (const Vec3& p : random_points(50, 2))
        EXPECT_NEAR(mix->value(p), 0.75 * a->value(p) + 0.25 * b->value(p), 1e-15);
    const auto grown = offset(a, 0.5);
    EXPECT_NEAR(grown->value({2, 0, 0}), 0.5, 1e-15);
    const auto wall = shell(a, 0.2);  // |f| - 0.1
    EXPECT_NEAR(wall->value({0, 0, 0}), 0.9, 1e-15);
    EXPECT_NEAR(wall->value({1.05, 0, 0}), -0.05, 1e-15);
    EXPECT_NEAR(wall->gradient({0.5, 0, 0}).x, -1.0, 1e-15);
    // one node object evaluated from two parents
    const auto shared = sphere(0.5);
    const auto pair = csg_union({translate(shared, {-1, 0, 0}), translate(shared, {1, 0, 0})});
    EXPECT_NEAR(pair->value({1, 0, 0}), -0.5, 1e-15);
    EXPECT_NEAR(pair->value({-1, 0, 0}), -0.5, 1e-15);
    EXPECT_EQ(shared.use_count(), 3);
}

}  // namespace
}  // namespace surfaced::implicit
