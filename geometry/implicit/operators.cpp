// Transforms, CSG, blends, offset and shell. The kind/Lipschitz rules are argued in operators.h.
#include "geometry/implicit/operators.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>
#include <utility>

namespace surfaced::implicit {

Vec3 Mat3::operator*(const Vec3& v) const {
    return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z, m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
            m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
}

Mat3 Mat3::operator*(const Mat3& o) const {
    Mat3 r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) r.m[i][j] = m[i][0] * o.m[0][j] + m[i][1] * o.m[1][j] + m[i][2] * o.m[2][j];
    return r;
}

Mat3 Mat3::transposed() const {
    Mat3 r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) r.m[i][j] = m[j][i];
    return r;
}

Mat3 rotation_axis_angle(const Vec3& axis, double degrees) {
    assert(norm(axis) > 0);
    const Vec3 u = axis * (1.0 / norm(axis));
    const double a = degrees * std::numbers::pi / 180.0, c = std::cos(a), s = std::sin(a), t = 1 - c;
    // Rodrigues: R = c I + s [u]x + (1 - c) u u^T.
    Mat3 r;
    r.m[0][0] = c + t * u.x * u.x;
    r.m[0][1] = t * u.x * u.y - s * u.z;
    r.m[0][2] = t * u.x * u.z + s * u.y;
    r.m[1][0] = t * u.y * u.x + s * u.z;
    r.m[1][1] = c + t * u.y * u.y;
    r.m[1][2] = t * u.y * u.z - s * u.x;
    r.m[2][0] = t * u.z * u.x - s * u.y;
    r.m[2][1] = t * u.z * u.y + s * u.x;
    r.m[2][2] = c + t * u.z * u.z;
    return r;
}

Mat3 rotation_euler(const Vec3& degrees) {
    return rotation_axis_angle({0, 0, 1}, degrees.z) * rotation_axis_angle({0, 1, 0}, degrees.y) *
           rotation_axis_angle({1, 0, 0}, degrees.x);
}

double smooth_min(double a, double b, double k) {
    const double h = std::max(k - std::abs(a - b), 0.0) / k;
    return std::min(a, b) - h * h * k * 0.25;
}

namespace {

FieldKind combine(FieldKind a, FieldKind b) {
    return (a == FieldKind::General || b == FieldKind::General) ? FieldKind::General : FieldKind::DistanceBound;
}

FieldKind bound_of(FieldKind a) { return a == FieldKind::General ? FieldKind::General : FieldKind::DistanceBound; }

class Translate final : public Field {
public:
    Translate(FieldPtr c, const Vec3& o) : c_(std::move(c)), o_(o) {}
    double value(const Vec3& p) const override { return c_->value(p - o_); }
    Vec3 gradient(const Vec3& p) const override { return c_->gradient(p - o_); }
    FieldKind kind() const override { return c_->kind(); }
    double lipschitz() const override { return c_->lipschitz(); }

private:
    FieldPtr c_;
    Vec3 o_;
};

class Rotate final : public Field {
public:
    Rotate(FieldPtr c, const Mat3& r) : c_(std::move(c)), r_(r), rt_(r.transposed()) {}
    double value(const Vec3& p) const override { return c_->value(rt_ * p); }
    Vec3 gradient(const Vec3& p) const override { return r_ * c_->gradient(rt_ * p); }
    FieldKind kind() const override { return c_->kind(); }
    double lipschitz() const override { return c_->lipschitz(); }

private:
    FieldPtr c_;
    Mat3 r_, rt_;
};

class UniformScale final : public Field {
public:
    UniformScale(FieldPtr c, double s) : c_(std::move(c)), s_(s) {}
    double value(const Vec3& p) const override { return s_ * c_->value(p * (1.0 / s_)); }
    Vec3 gradient(const Vec3& p) const override { return c_->gradient(p * (1.0 / s_)); }
    FieldKind kind() const override { return c_->kind(); }
    double lipschitz() const override { return c_->lipschitz(); }

private:
    FieldPtr c_;
    double s_;
};

class NonUniformScale final : public Field {
public:
    NonUniformScale(FieldPtr c, const Vec3& s) : c_(std::move(c)), s_(s), m_(std::min({s.x, s.y, s.z})) {}
    double value(const Vec3& p) const override { return m_ * c_->value(inverse(p)); }
    Vec3 gradient(const Vec3& p) const override {
        const Vec3 g = c_->gradient(inverse(p));
        return Vec3{g.x / s_.x, g.y / s_.y, g.z / s_.z} * m_;
    }
    FieldKind kind() const override { return bound_of(c_->kind()); }
    double lipschitz() const override { return c_->lipschitz(); }

private:
    Vec3 inverse(const Vec3& p) const { return {p.x / s_.x, p.y / s_.y, p.z / s_.z}; }
    FieldPtr c_;
    Vec3 s_;
    double m_;
};

enum class BinaryOp { Min, Max, MaxNegB, Blend, SmoothMin, SmoothMax, SmoothMaxNegB };

class Binary final : public Field {
public:
    Binary(BinaryOp op, FieldPtr a, FieldPtr b, double param)
        : op_(op), a_(std::move(a)), b_(std::move(b)), k_(param) {}

    double value(const Vec3& p) const override {
        double w;
        return eval(a_->value(p), b_->value(p), w);
    }
    Vec3 gradient(const Vec3& p) const override {
        double wa;  // d result / d a; d result / d b = +-(1 - wa) (negated when b enters negated)
        eval(a_->value(p), b_->value(p), wa);
        const double wb = (1.0 - wa) * (negates_b() ? -1.0 : 1.0);
        Vec3 g;
        if (wa != 0) g += a_->gradient(p) * wa;
        if (wb != 0) g += b_->gradient(p) * wb;
        return g;
    }
    FieldKind kind() const override { return combine(a_->kind(), b_->kind()); }
    double lipschitz() const override {
        if (op_ == BinaryOp::Blend) return (1 - k_) * a_->lipschitz() + k_ * b_->lipschitz();
        return std::max(a_->lipschitz(), b_->lipschitz());
    }

private:
    bool negates_b() const { return op_ == BinaryOp::MaxNegB || op_ == BinaryOp::SmoothMaxNegB; }

    //! The combined value; `wa` receives the weight of a's gradient.
    double eval(double a, double b, double& wa) const {
        switch (op_) {
            case BinaryOp::Min: wa = a <= b ? 1 : 0; return std::min(a, b);
            case BinaryOp::Max: wa = a >= b ? 1 : 0; return std::max(a, b);
            case BinaryOp::MaxNegB: wa = a >= -b ? 1 : 0; return std::max(a, -b);
            case BinaryOp::Blend: wa = 1 - k_; return (1 - k_) * a + k_ * b;
            case BinaryOp::SmoothMin: return smooth(a, b, wa);
            case BinaryOp::SmoothMax: return -smooth(-a, -b, wa);
            case BinaryOp::SmoothMaxNegB: return -smooth(-a, b, wa);
        }
        wa = 1;
        return a;
    }
    //! smooth_min(a, b) and its derivative with respect to a (1 - h/2 on a's side, h/2 on the other).
    double smooth(double a, double b, double& wa) const {
        const double h = std::max(k_ - std::abs(a - b), 0.0) / k_;
        wa = a <= b ? 1 - 0.5 * h : 0.5 * h;
        return std::min(a, b) - h * h * k_ * 0.25;
    }

    BinaryOp op_;
    FieldPtr a_, b_;
    double k_;
};

class Offset final : public Field {
public:
    Offset(FieldPtr c, double d, bool shell) : c_(std::move(c)), d_(d), shell_(shell) {}
    double value(const Vec3& p) const override {
        const double v = c_->value(p);
        return (shell_ ? std::abs(v) : v) - d_;
    }
    Vec3 gradient(const Vec3& p) const override {
        const Vec3 g = c_->gradient(p);
        return (shell_ && c_->value(p) < 0) ? g * -1.0 : g;
    }
    FieldKind kind() const override { return bound_of(c_->kind()); }
    double lipschitz() const override { return c_->lipschitz(); }

private:
    FieldPtr c_;
    double d_;
    bool shell_;
};

FieldPtr fold(BinaryOp op, std::vector<FieldPtr> args, double k) {
    assert(!args.empty());
    FieldPtr out = std::move(args.front());
    for (std::size_t i = 1; i < args.size(); ++i)
        out = std::make_shared<Binary>(op, std::move(out), std::move(args[i]), k);
    return out;
}

}  // namespace

FieldPtr translate(FieldPtr child, const Vec3& offset) { return std::make_shared<Translate>(std::move(child), offset); }

FieldPtr rotate(FieldPtr child, const Mat3& rotation) { return std::make_shared<Rotate>(std::move(child), rotation); }

FieldPtr scale(FieldPtr child, double factor) {
    assert(factor > 0);
    return std::make_shared<UniformScale>(std::move(child), factor);
}

FieldPtr scale(FieldPtr child, const Vec3& factors) {
    assert(factors.x > 0 && factors.y > 0 && factors.z > 0);
    if (factors.x == factors.y && factors.y == factors.z) return scale(std::move(child), factors.x);
    return std::make_shared<NonUniformScale>(std::move(child), factors);
}

FieldPtr csg_union(std::vector<FieldPtr> args) { return fold(BinaryOp::Min, std::move(args), 0); }
FieldPtr csg_intersection(std::vector<FieldPtr> args) { return fold(BinaryOp::Max, std::move(args), 0); }
FieldPtr csg_difference(std::vector<FieldPtr> args) { return fold(BinaryOp::MaxNegB, std::move(args), 0); }

FieldPtr blend(FieldPtr a, FieldPtr b, double t) {
    assert(t >= 0 && t <= 1);
    return std::make_shared<Binary>(BinaryOp::Blend, std::move(a), std::move(b), t);
}

FieldPtr smooth_union(std::vector<FieldPtr> args, double k) {
    assert(k > 0);
    return fold(BinaryOp::SmoothMin, std::move(args), k);
}
FieldPtr smooth_intersection(std::vector<FieldPtr> args, double k) {
    assert(k > 0);
    return fold(BinaryOp::SmoothMax, std::move(args), k);
}
FieldPtr smooth_difference(std::vector<FieldPtr> args, double k) {
    assert(k > 0);
    return fold(BinaryOp::SmoothMaxNegB, std::move(args), k);
}

FieldPtr offset(FieldPtr child, double distance) { return std::make_shared<Offset>(std::move(child), distance, false); }

FieldPtr shell(FieldPtr child, double thickness) {
    assert(thickness > 0);
    return std::make_shared<Offset>(std::move(child), 0.5 * thickness, true);
}

}  // namespace surfaced::implicit
