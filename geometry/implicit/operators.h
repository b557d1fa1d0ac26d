// Transforms, CSG, blends, offset and shell over implicit::Field (f < 0 inside). Each returns a new immutable node
// that holds its children by shared_ptr, so one child may feed several parents (a DAG evaluates each node object
// once per call path, never copies it).
//
// What the result promises (FieldKind and lipschitz()): a General child makes the result General. Otherwise
//   translate, rotate, uniform scale    keep the child's kind and Lipschitz constant (exact stays exact);
//   non-uniform scale s                 f(p / s) * min(s): a DistanceBound with the child's Lipschitz constant
//                                       (p -> p/s is 1/min(s)-Lipschitz), never overestimating the distance;
//   union/intersection/difference       min / max / max(a, -b): DistanceBound, L = max(La, Lb) (exact outside a
//                                       union, but not inside);
//   blend(a, b, t)                      (1 - t) a + t b, t in [0, 1]: DistanceBound, L = (1 - t) La + t Lb;
//   smooth_*(k)                         the quadratic polynomial smooth minimum smin(a, b) = min(a, b) -
//                                       h^2 k / 4, h = max(k - |a - b|, 0) / k: <= min(a, b), equal to it where
//                                       |a - b| >= k; its partial derivatives are weights in [0, 1] summing to 1,
//                                       so L = max(La, Lb); DistanceBound;
//   offset(d)                           f - d (round, d > 0 grows); shell(t) |f| - t / 2 (a wall of thickness t
//                                       around the surface): DistanceBound with the child's L.
// For any Lipschitz-L field that vanishes on its surface, |f(p)| / L <= distance(p, surface): sphere tracing steps
// |f| / L (query.h).
#pragma once

#include <vector>

#include "geometry/implicit/primitives.h"

namespace surfaced::implicit {

//! Row-major 3x3 matrix.
struct Mat3 {
    double m[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    Vec3 operator*(const Vec3& v) const;
    Mat3 operator*(const Mat3& o) const;
    Mat3 transposed() const;
};

//! Rotation by `degrees` (right-handed) around `axis` (non-zero, normalised here).
Mat3 rotation_axis_angle(const Vec3& axis, double degrees);
//! Rotation by Euler angles in degrees, about the fixed x, then y, then z axes: R = Rz * Ry * Rx.
Mat3 rotation_euler(const Vec3& degrees);

FieldPtr translate(FieldPtr child, const Vec3& offset);
//! The child rotated by `rotation` (a proper rotation matrix): value(p) = child(R^T p).
FieldPtr rotate(FieldPtr child, const Mat3& rotation);
//! Uniform scale s > 0: s * child(p / s), kind kept.
FieldPtr scale(FieldPtr child, double factor);
//! Non-uniform scale s > 0 per axis: child(p / s) * min(s). Equal factors give the uniform (exact) form.
FieldPtr scale(FieldPtr child, const Vec3& factors);

//! Boolean operations; `args` non-empty. difference: args[0] minus every other.
FieldPtr csg_union(std::vector<FieldPtr> args);
FieldPtr csg_intersection(std::vector<FieldPtr> args);
FieldPtr csg_difference(std::vector<FieldPtr> args);

//! The lecture's linear interpolation (1 - t) a + t b, t in [0, 1].
FieldPtr blend(FieldPtr a, FieldPtr b, double t);

//! Polynomial smooth boolean operations with radius k > 0, folded left over `args` (non-empty).
FieldPtr smooth_union(std::vector<FieldPtr> args, double k);
FieldPtr smooth_intersection(std::vector<FieldPtr> args, double k);
FieldPtr smooth_difference(std::vector<FieldPtr> args, double k);

//! child - distance (distance > 0 grows the solid by that much, < 0 shrinks it).
FieldPtr offset(FieldPtr child, double distance);
//! |child| - thickness / 2: a hollow wall of the given thickness centred on the child's surface.
FieldPtr shell(FieldPtr child, double thickness);

//! The quadratic polynomial smooth minimum (exposed for tests).
double smooth_min(double a, double b, double k);

}  // namespace surfaced::implicit
