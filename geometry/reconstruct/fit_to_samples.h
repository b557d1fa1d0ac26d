// After meshing: each vertex of the reconstructed surface moved onto the tangent planes of the samples around it.
//
// Why: chi is a sum of trilinear hats on the finest grid, so its iso-surface is smooth at the scale of a cell: it
// rounds a sharp edge over about a cell and sits a fraction of a cell off a curved surface. Wherever the cloud is
// about as dense as the grid or denser, the samples' positions and normals say more than that.
//
// Method: a vertex x moves by minus the weighted mean of s_i n_i over the samples (p_i, n_i) around it, where s_i is
// its offset from sample i's tangent plane: the mean of its displacements onto those planes. Two such steps. Where the
// surface is flat or sharp (a crease sampled on both sides) the planes themselves are right, and the steps settle on
// the surface or the crease; where it curves, a plane misses it by about d^2 / 2R at distance d, so for samples whose
// normal is within 20 degrees of the samples' mean normal m at x the offset gets the curvature term,
// s_i = n_i . (x - p_i) + 1/2 (m - n_i) . (x - p_i) (exact on a sphere), faded out between 20 and 30 degrees so that
// the two sides of a crease stay planes. Compare the projections of point-set surfaces (Alexa et al. 2003; Kolluri
// 2005's IMLS), which fit one surface through all the samples and so round creases at the kernel's scale.
// Weights: the kernel (1 - d^2 / 4h^2)^3 times the sample's confidence, with h about the distance to the 6th nearest
// sample (from the count of samples around) and at least a finest cell; a sample facing away from the mesh's normal at
// x (the far side of a thin part) has weight 0.
// Noise shrinks the step: over k_eff = (sum w)^2 / sum w^2 samples the offsets have weighted mean m_s and variance v,
// and the step is scaled by m_s^2 / (m_s^2 + 4 v / k_eff), so that a mean within about two standard errors of zero,
// which is what noise alone gives, moves the vertex little. Each step moves a vertex by at most a finest cell. Where
// the samples are sparser than the grid (h above 3 finest cells) chi was splatted on coarser levels and is smoother than
// far-reaching planes: the fit fades out, and stops at 5 cells.
//
// The samples near a vertex are found in a uniform grid over the unit cube whose cells are at least 2.5 typical sample
// spacings (sqrt(area / samples)) and two finest cells wide: those in the 3 x 3 x 3 cells around the vertex's cell.
// Vertices are visited grouped by grid cell, so each group gathers its candidates once, and the candidates are
// processed four at a time in single precision, relative to a corner of the group's cell. Every vertex's new position
// depends only on its old one, its normal and the samples, so the result is the same in any order and with one
// thread or two.
#pragma once

#include "geometry/core/cancel.h"
#include "geometry/core/result.h"
#include "geometry/mesh/polygon_mesh.h"
#include "geometry/reconstruct/poisson_system.h"

namespace surfaced::reconstruct {

//! Moves `mesh`'s vertices (unit-cube coordinates, as extract_surface gives them) onto the samples' tangent planes
//! (see the top of this file). `cell`: the finest cell's width. `threaded`: the vertices in two halves on two threads
//! for large meshes (the same positions either way). Errors: Cancelled (polled every few thousand vertices).
Status fit_to_samples(PolygonMesh& mesh, const OrientedSamples& samples, double cell, const Cancel& cancel,
                      bool threaded = false);

}  // namespace surfaced::reconstruct
