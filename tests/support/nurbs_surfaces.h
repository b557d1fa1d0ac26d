// NURBS surfaces for tests: the exact sphere, torus and cylinder of revolution (The NURBS Book, ch. 7-8), a cone
// by revolve(), and random B-spline/NURBS surfaces (random degrees 1..5, nets, weights, clamped or unclamped knots
// with repeated interior values).
#pragma once

#include <random>
#include <vector>

#include "geometry/core/types.h"
#include "geometry/surfaces/bspline_surface.h"

namespace surfaced::testing {

//! A surface of revolution about the z axis through `center`: u the 9-point circle, v the profile (radius, height)
//! with its weights and knots, degree 2 along u.
BSplineSurface revolve(const Vec3& center, const std::vector<double>& radius, const std::vector<double>& height,
                       const std::vector<double>& profile_weights, const std::vector<double>& knots_v, int degree_v);
//! The standard 9 x 5 NURBS sphere: the half circle from the south pole to the north pole, revolved.
BSplineSurface sphere(const Vec3& center, double r);
//! Torus of major radius R, minor radius r: the 9-point circle of radius r about (R, 0) in the (radius, z) plane.
BSplineSurface torus(const Vec3& center, double R, double r);
//! Cylinder of radius r from z = 0 to z = h (above center), linear along v with an interior knot.
BSplineSurface cylinder(const Vec3& center, double r, double h);

//! Random knots for n points of degree p: steps in [0.2, 1], interior values repeated up to p times (often once),
//! the ends p + 1 times when clamped.
std::vector<double> random_knots(int n, int p, bool clamped, std::mt19937& rng);
//! A random valid surface: degrees 1..5, nets up to degree + 5 points per direction, coordinates in [-3, 3], rational
//! half of the time (weights in [0.3, 3]), each knot vector clamped or not.
BSplineSurface random_surface(unsigned seed);

}  // namespace surfaced::testing
