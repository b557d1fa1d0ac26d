// Fractals as distance estimators (FieldKind::DistanceBound, lipschitz 1).
//
// Mandelbulb (White/Nylander triplex power, z <- z^n + p, spherical coordinates): outside (the orbit passes
// `bailout` within `iterations`) the value is the classical estimate 0.5 ln r · r / |dz| (Hart et al. 1989, the
// running derivative dz <- n r^(n-1) dz + 1). The set lies in the ball of radius 2 (|z^n| = |z|^n, so |p| > 2
// escapes as for the Mandelbrot set); beyond it the value is (|p| - 2) + the estimate at the radius-2 point towards
// p, which keeps far points from being overestimated. Points whose orbit stays bounded are inside; no interior
// distance is known, so their value is the constant -1e-3 (only the sign is meaningful there: a point query with a
// tolerance >= 1e-3 reports them "on").
//
// Menger sponge in the cube [-h, h]^3: the box minus, at each level l = 1..iterations, a lattice of square bars of
// half-width h/3^l along x, y and z (period 2h/3^(l-1)). Value max(box, -(distance to the nearest bar)), a max of
// bounds, so a DistanceBound; the nearest bar of a lattice is always the one in the point's own cell.
//
// Preconditions (asserted; the API checks them): power >= 2, iterations >= 1 (Mandelbulb) or >= 0 (Menger),
// bailout >= 2, half_size > 0.
#pragma once

#include "geometry/implicit/primitives.h"

namespace surfaced::implicit {

FieldPtr mandelbulb(double power = 8, int iterations = 16, double bailout = 2);
FieldPtr menger_sponge(int iterations, double half_size = 1.0);

}  // namespace surfaced::implicit
