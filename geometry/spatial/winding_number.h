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

//! Per-node expansion coefficients of the triangles below each node of a TriangleBvh (same indexing). With
//! delta = x - center over the node's triangles and n their unit normals:
struct WindingNode {
    Vec3 center;  //!< area-weighted centroid of the node's triangles (box centre when they have no area)
    //! every vertex of the node's triangles is within this distance of `center` (next to it: a query reads both at
    //! every node it reaches, the rest only where it expands)
    double radius = 0;
    Vec3 area_normal;  //!< integral of n: sum over triangles of area * n (half the cross product of two edges)
    //! integral of delta n^T, row-major: moment[3 j + i] = integral of delta_j n_i
    double moment[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    //! integral of n_i delta_j delta_k, symmetric in j, k: second[6 i + s] for (j, k) = xx, yy, zz, xy, xz, yz
    double second[18] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
    double area = 0;  //!< sum of the triangles' (unsigned) areas
};

struct WindingTree {
    std::vector<WindingNode> nodes;
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
