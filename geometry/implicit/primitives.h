// Signed distance primitives (f < 0 inside). Every primitive is centred at the origin; move it with translate(),
// rotate() and scale() from operators.h. Axis-symmetric shapes (torus, cylinder, cone) have their axis along z.
//
// Exact (FieldKind::ExactDistance, |∇f| = 1 almost everywhere, inside and outside): sphere, box, rounded_box,
// torus, cylinder, cone, capsule, plane. A bound (DistanceBound, lipschitz 1): ellipsoid, which has no closed-form
// distance; its value is (|p/r| - 1) * min(r), a lower bound on the distance inside and outside.
//
// Preconditions (asserted; the API validates them first): sizes finite and > 0, rounded_box radius <= min half
// size, plane normal non-zero, capsule radius > 0.
#pragma once

#include <memory>

#include "geometry/implicit/field.h"

namespace surfaced::implicit {

using FieldPtr = std::shared_ptr<const Field>;

FieldPtr sphere(double radius);
//! Axis-aligned box [-h, h].
FieldPtr box(const Vec3& half_size);
//! The box [-h, h] with edges and corners rounded by `radius`: box(h - radius) offset by radius (outer size h).
FieldPtr rounded_box(const Vec3& half_size, double radius);
//! Ring of radius `major` in the xy plane, tube radius `minor`.
FieldPtr torus(double major, double minor);
//! Capped cylinder: radius r around z, z in [-half_height, half_height].
FieldPtr cylinder(double radius, double half_height);
//! Capped cone (a frustum when top_radius > 0): radius `radius` at z = -half_height, `top_radius` at +half_height.
FieldPtr cone(double radius, double half_height, double top_radius = 0.0);
//! Points within `radius` of the segment a-b.
FieldPtr capsule(const Vec3& a, const Vec3& b, double radius);
//! Half-space dot(n, p) <= offset, with n = normal / |normal|. Value dot(n, p) - offset.
FieldPtr plane(const Vec3& normal, double offset);
//! Axis-aligned ellipsoid with semi-axes `radii` (a DistanceBound).
FieldPtr ellipsoid(const Vec3& radii);

}  // namespace surfaced::implicit
