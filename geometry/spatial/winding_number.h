// Generalized winding number of a triangle mesh: the sum of the signed solid angles its triangles subtend at a point,
// over 4 pi. 1 inside and 0 outside a closed, outward-oriented surface, 2 inside two overlapping closed surfaces,
// and a smooth value in between near holes: a robust inside test (w >= 1/2) for meshes with holes,
// self-intersections and non-manifold parts, where ray parity fails.
//
// References: A. Jacobson, L. Kavan, O. Sorkine-Hornung, "Robust Inside-Outside Segmentation using Generalized
//               Winding Numbers", SIGGRAPH 2013 (the definition, the exact direct sum).
//             G. Barill, N. Dickson, R. Schmidt, D. Levin, A. Jacobson, "Fast Winding Numbers for Soups and Clouds",
//               SIGGRAPH 2018 (the hierarchical approximation: a node far from the query by beta times its radius
//               is replaced by a Taylor expansion of its triangles' solid angles about their area-weighted centre).
//             A. Van Oosterom, J. Strackee, "The Solid Angle of a Plane Triangle", IEEE TBME 30(2), 1983.
#pragma once

#include <vector>

#include "geometry/core/result.h"
#include "geometry/spatial/bvh.h"

namespace surfaced {

//! The expansion of the triangles below one node of a TriangleBvh, to second order, in the form a query evaluates:
//! with y = center - q and d = |y|, their solid angle at q is about
//!   (dot(area_normal, y) + trace) / d^3 - (y^T Q y + dot(linear, y)) / d^5 + cubic(y) / d^7,
//! the integrals of n, delta n^T and n delta delta^T over the triangles (delta = x - center, n the unit normal)
//! contracted with the derivatives of y / |y|^3 (winding_number.cpp).
struct WindingFarField {
    Vec3 center;        //!< area-weighted centroid of the node's triangles (box centre when they have no area)
    double radius = 0;  //!< every vertex of the node's triangles is within this distance of `center`
    Vec3 area_normal;   //!< sum over triangles of area * n
    double trace = 0;   //!< trace of the integral of delta n^T
    double quadratic[6] = {0, 0, 0,
                           0, 0, 0};  //!< Q, 3 times the symmetric part of that integral: xx, yy, zz, xy, xz, yz
    Vec3 linear;
    //! coefficients of x^3, y^3, z^3, x^2 y, x^2 z, y^2 x, y^2 z, z^2 x, z^2 y, xyz
    double cubic[10] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
    double area = 0;  //!< sum of the triangles' (unsigned) areas
};

//! Per node of the hierarchy (same indexing), its expansion in the form a query evaluates.
struct WindingTree {
    std::vector<WindingFarField> nodes;
};

//! The expansion coefficients for every node, bottom-up: O(nodes + triangles). Reuse it for every query on `bvh`.
WindingTree build_winding_tree(const TriangleBvh& bvh);

struct WindingNumberOptions {
    //! Jacobson et al.'s exact sum over every triangle, O(F) per query, instead of the hierarchy.
    bool exact = false;
    //! Barill et al.'s beta: a node is expanded instead of descended into when the query is farther from its centre
    //! than accuracy * its radius. > 1; larger is more accurate and slower (2 is Barill et al.'s choice). Largest
    //! errors seen against the exact sum (docs/benchmarks.md): about 5e-3 at 2, below 1e-3 at 3. An inside test
    //! (w >= 1/2) needs far less than either.
    double accuracy = 2.0;
};

struct WindingNumber {
    double value = 0;
    //! Guaranteed bound on |value - exact sum| in exact arithmetic: the sum, over the nodes that were expanded, of the
    //! Taylor remainder bound 4 A r^3 / (4 pi (d - r)^5) (A area, r radius, d distance of the query from the centre).
    //! 0 for the exact sum. The error seen is usually orders of magnitude below it.
    double error_bound = 0;
};

//! The winding number of the surface at `query`. `tree` must come from build_winding_tree(bvh) (unused for the exact
//! sum). InvalidArgument for accuracy <= 1 or not finite, or a non-finite query. 0 for an empty hierarchy. On the
//! surface itself the value is that of a nearby point on either side.
Result<WindingNumber> winding_number(const TriangleBvh& bvh, const WindingTree& tree, const Vec3& query,
                                     const WindingNumberOptions& options = {});

//! winding_number(...).value without the error bound, which costs a division per expanded node: for callers that
//! only compare the value (inside tests over many points).
Result<double> winding_number_value(const TriangleBvh& bvh, const WindingTree& tree, const Vec3& query,
                                    const WindingNumberOptions& options = {});

//! Solid angle subtended at q by the triangle (a, b, c), signed: positive when q sees its back (the side its
//! counter-clockwise normal points away from). In (-2 pi, 2 pi].
double triangle_solid_angle(const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace surfaced
