// Signed distance primitives. Axis-symmetric solids reduce to a 2D signed distance in the half-plane (rho, z),
// rho = |p.xy|: the closest point of a solid of revolution lies in the half-plane through p and the axis.
#include "geometry/implicit/primitives.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace surfaced::implicit {
namespace {

struct V2 {
    double x = 0, y = 0;
};
V2 operator-(V2 a, V2 b) { return {a.x - b.x, a.y - b.y}; }
double dot2(V2 a, V2 b) { return a.x * b.x + a.y * b.y; }
double len2(V2 a) { return std::hypot(a.x, a.y); }

//! Unit vector along p.xy, or +x on the axis (any direction is a valid subgradient there).
V2 radial_direction(const Vec3& p) {
    const double rho = std::hypot(p.x, p.y);
    return rho > 0 ? V2{p.x / rho, p.y / rho} : V2{1, 0};
}

//! Lifts a gradient in (rho, z) back to 3D.
Vec3 lift(const V2& g, const Vec3& p) {
    const V2 r = radial_direction(p);
    return {g.x * r.x, g.x * r.y, g.y};
}

//! Signed distance to the 2D box [-h, h] and its gradient.
double box2(V2 p, V2 h, V2* grad) {
    const V2 q{std::abs(p.x) - h.x, std::abs(p.y) - h.y};
    const V2 out{std::max(q.x, 0.0), std::max(q.y, 0.0)};
    const double outside = len2(out);
    const double sx = p.x < 0 ? -1.0 : 1.0, sy = p.y < 0 ? -1.0 : 1.0;
    if (outside > 0) {
        if (grad) *grad = {sx * out.x / outside, sy * out.y / outside};
        return outside;
    }
    if (grad) *grad = q.x > q.y ? V2{sx, 0} : V2{0, sy};
    return std::max(q.x, q.y);
}

//! Distance from p to the segment a-b (a == b allowed).
double segment_distance(V2 p, V2 a, V2 b) {
    const V2 ab = b - a, ap = p - a;
    const double l2 = dot2(ab, ab);
    const double t = l2 > 0 ? std::clamp(dot2(ap, ab) / l2, 0.0, 1.0) : 0.0;
    return len2(V2{ap.x - t * ab.x, ap.y - t * ab.y});
}

class Sphere final : public Field {
public:
    explicit Sphere(double r) : r_(r) {}
    double value(const Vec3& p) const override { return norm(p) - r_; }
    Vec3 gradient(const Vec3& p) const override {
        const double n = norm(p);
        return n > 0 ? p * (1.0 / n) : Vec3{1, 0, 0};
    }
    FieldKind kind() const override { return FieldKind::ExactDistance; }

private:
    double r_;
};

class Box final : public Field {
public:
    Box(const Vec3& h, double rounding) : h_(h), r_(rounding) {}
    double value(const Vec3& p) const override { return eval(p, nullptr) - r_; }
    Vec3 gradient(const Vec3& p) const override {
        Vec3 g;
        eval(p, &g);
        return g;
    }
    FieldKind kind() const override { return FieldKind::ExactDistance; }

private:
    //! Distance to the inner box [-(h - r), h - r].
    double eval(const Vec3& p, Vec3* grad) const {
        Vec3 q, out;
        for (int i = 0; i < 3; ++i) {
            q[i] = std::abs(p[i]) - (h_[i] - r_);
            out[i] = std::max(q[i], 0.0);
        }
        const double outside = norm(out);
        if (outside > 0) {
            if (grad)
                for (int i = 0; i < 3; ++i) (*grad)[i] = (p[i] < 0 ? -out[i] : out[i]) / outside;
            return outside;
        }
        int axis = 0;
        for (int i = 1; i < 3; ++i)
            if (q[i] > q[axis]) axis = i;
        if (grad) {
            *grad = Vec3{};
            (*grad)[axis] = p[axis] < 0 ? -1.0 : 1.0;
        }
        return q[axis];
    }
    Vec3 h_;
    double r_;
};

class Torus final : public Field {
public:
    Torus(double major, double minor) : big_(major), small_(minor) {}
    double value(const Vec3& p) const override { return std::hypot(std::hypot(p.x, p.y) - big_, p.z) - small_; }
    Vec3 gradient(const Vec3& p) const override {
        const V2 q{std::hypot(p.x, p.y) - big_, p.z};
        const double l = len2(q);
        if (l == 0) return Vec3{0, 0, 1};
        return lift(V2{q.x / l, q.y / l}, p);
    }
    FieldKind kind() const override { return FieldKind::ExactDistance; }

private:
    double big_, small_;
};

class Cylinder final : public Field {
public:
    Cylinder(double r, double h) : r_(r), h_(h) {}
    double value(const Vec3& p) const override { return box2({std::hypot(p.x, p.y), p.z}, {r_, h_}, nullptr); }
    Vec3 gradient(const Vec3& p) const override {
        V2 g;
        box2({std::hypot(p.x, p.y), p.z}, {r_, h_}, &g);
        return lift(g, p);
    }
    FieldKind kind() const override { return FieldKind::ExactDistance; }

private:
    double r_, h_;
};

//! The trapezoid profile (0,-h) (r1,-h) (r2,h) (0,h) revolved around z.
class Cone final : public Field {
public:
    Cone(double r1, double h, double r2) : r1_(r1), h_(h), r2_(r2) {
        const double len = std::hypot(2 * h, r1 - r2);
        side_normal_ = {2 * h / len, (r1 - r2) / len};
    }
    double value(const Vec3& p) const override {
        const V2 q{std::hypot(p.x, p.y), p.z};
        // Signed distances to the three supporting lines (bottom, top, side): inside a convex polygon the distance
        // to the boundary is the smallest distance to an edge line.
        const double side = dot2(q - V2{r1_, -h_}, side_normal_);
        const double inside = std::max({-q.y - h_, q.y - h_, side});
        if (inside <= 0) return inside;
        // Outside: the distance to the boundary segments (the axis segment is interior, not boundary).
        return std::min({segment_distance(q, {0, -h_}, {r1_, -h_}), segment_distance(q, {r1_, -h_}, {r2_, h_}),
                         segment_distance(q, {r2_, h_}, {0, h_})});
    }
    FieldKind kind() const override { return FieldKind::ExactDistance; }

private:
    double r1_, h_, r2_;
    V2 side_normal_;
};

class Capsule final : public Field {
public:
    Capsule(const Vec3& a, const Vec3& b, double r) : a_(a), ab_(b - a), r_(r) {}
    double value(const Vec3& p) const override { return norm(p - closest(p)) - r_; }
    Vec3 gradient(const Vec3& p) const override {
        const Vec3 d = p - closest(p);
        const double n = norm(d);
        return n > 0 ? d * (1.0 / n) : Vec3{1, 0, 0};
    }
    FieldKind kind() const override { return FieldKind::ExactDistance; }

private:
    Vec3 closest(const Vec3& p) const {
        const double l2 = dot(ab_, ab_);
        const double t = l2 > 0 ? std::clamp(dot(p - a_, ab_) / l2, 0.0, 1.0) : 0.0;
        return a_ + ab_ * t;
    }
    Vec3 a_, ab_;
    double r_;
};

class Plane final : public Field {
public:
    Plane(const Vec3& n, double offset) : n_(n * (1.0 / norm(n))), d_(offset) {}
    double value(const Vec3& p) const override { return dot(n_, p) - d_; }
    Vec3 gradient(const Vec3&) const override { return n_; }
    FieldKind kind() const override { return FieldKind::ExactDistance; }

private:
    Vec3 n_;
    double d_;
};

//! (|p/r| - 1) * min(r): p -> p/r is (1/min r)-Lipschitz and maps the ellipsoid to the unit sphere, whose exact
//! distance is |x| - 1, so the value never exceeds the true distance and its gradient has length <= 1.
class Ellipsoid final : public Field {
public:
    explicit Ellipsoid(const Vec3& r) : r_(r), m_(std::min({r.x, r.y, r.z})) {}
    double value(const Vec3& p) const override { return (norm(scaled(p)) - 1.0) * m_; }
    Vec3 gradient(const Vec3& p) const override {
        const Vec3 s = scaled(p);
        const double n = norm(s);
        if (n == 0) return Vec3{0, 0, 0};
        return Vec3{s.x / r_.x, s.y / r_.y, s.z / r_.z} * (m_ / n);
    }
    FieldKind kind() const override { return FieldKind::DistanceBound; }

private:
    Vec3 scaled(const Vec3& p) const { return {p.x / r_.x, p.y / r_.y, p.z / r_.z}; }
    Vec3 r_;
    double m_;
};

[[maybe_unused]] bool positive(const Vec3& v) { return v.x > 0 && v.y > 0 && v.z > 0; }

}  // namespace

FieldPtr sphere(double radius) {
    assert(radius > 0);
    return std::make_shared<Sphere>(radius);
}

FieldPtr box(const Vec3& half_size) {
    assert(positive(half_size));
    return std::make_shared<Box>(half_size, 0.0);
}

FieldPtr rounded_box(const Vec3& half_size, double radius) {
    assert(positive(half_size) && radius >= 0 && radius <= std::min({half_size.x, half_size.y, half_size.z}));
    return std::make_shared<Box>(half_size, radius);
}

FieldPtr torus(double major, double minor) {
    assert(major > 0 && minor > 0);
    return std::make_shared<Torus>(major, minor);
}

FieldPtr cylinder(double radius, double half_height) {
    assert(radius > 0 && half_height > 0);
    return std::make_shared<Cylinder>(radius, half_height);
}

FieldPtr cone(double radius, double half_height, double top_radius) {
    assert(radius >= 0 && top_radius >= 0 && radius + top_radius > 0 && half_height > 0);
    return std::make_shared<Cone>(radius, half_height, top_radius);
}

FieldPtr capsule(const Vec3& a, const Vec3& b, double radius) {
    assert(radius > 0);
    return std::make_shared<Capsule>(a, b, radius);
}

FieldPtr plane(const Vec3& normal, double offset) {
    assert(norm(normal) > 0);
    return std::make_shared<Plane>(normal, offset);
}

FieldPtr ellipsoid(const Vec3& radii) {
    assert(positive(radii));
    return std::make_shared<Ellipsoid>(radii);
}

}  // namespace surfaced::implicit
