// Regular Loop patches for limit evaluation (limit_evaluation.h). Internal to geometry/subdivision.
//
// Over a triangle whose three corners are regular the Loop limit surface is the quartic three-direction box spline
// of the 12 points of the corners' 1-rings (J. Stam, "Evaluation of Loop subdivision surfaces", SIGGRAPH 1998).
// The 12 points sit on the triangular lattice spanned by the triangle's edges, in the triangle's (u, v) (corner 0
// at (0, 0), corner 1 at (1, 0), corner 2 at (0, 1)): kLoopPatchLattice. The basis polynomials (loop_patch.cpp)
// were derived from the subdivision rules themselves: two levels of regular Loop refinement of a unit impulse and
// the valence-6 limit mask give the patch's values at the 15 points (i, j) / 4, which fix the quartic, checked
// against three levels (45 points) exactly in rational arithmetic.
//
// "Regular" corners:
//  * smooth: interior, six triangles, no sharp edge, no vertex sharpness;
//  * on a straight crease: exactly two sharp edges at the corner, both infinitely sharp (boundary edges or infinite
//    creases), no vertex sharpness, and the face's side of the crease holds three triangles (so that the crease is a
//    lattice line). The lattice points beyond it are phantoms, reflections through the crease: a point X beyond the
//    line next to its line points A and B is A + B - C, C being the point across the line from X (the crease rules,
//    1/2 1/2 for edges and 3/4 1/8 1/8 for vertices, are the smooth rules applied with those phantoms).
// Corners (the corner rule), darts, semi-sharp features and other valences are irregular: the caller refines.
#pragma once

#include <array>

#include "geometry/core/types.h"
#include "geometry/subdivision/limit_piece.h"

namespace surfaced::subdivision {

//! The lattice coordinates (in the triangle's (u, v)) of the 12 control points of a regular Loop patch.
inline constexpr int kLoopPatchLattice[12][2] = {{0, 0},  {1, 0},  {0, 1}, {-1, 1}, {-1, 0}, {0, -1},
                                                 {1, -1}, {2, -1}, {2, 0}, {1, 1},  {0, 2},  {-1, 2}};

//! Corner j of triangle f: whether it is regular (see the header); `semi_sharp` is set when a semi-sharp vertex or
//! edge at the corner is what prevents it (it decays with refinement).
bool loop_corner_regular(const Piece& p, const Adjacency& adj, Index f, int j, bool* semi_sharp = nullptr);

//! The 12 control points (kLoopPatchLattice order) of triangle `f` of `p` when its limit surface is one box-spline
//! patch, false otherwise. Face f's corners must have all their faces in the piece.
bool loop_regular_patch(const Piece& p, const Adjacency& adj, Index f, std::array<Vec3, 12>& points);

//! The patch as a polynomial: its coefficients of u^a v^b (15 of them; the 16th is zero), from its 12 points.
void loop_patch_polynomial(const std::array<Vec3, 12>& points, std::array<Vec3, 16>& coefficients);

//! The polynomial at (u, v): position, d/du, d/dv, and when `second` d2/du2, d2/dudv, d2/dv2 (zero otherwise).
void evaluate_loop_polynomial(const std::array<Vec3, 16>& coefficients, double u, double v, bool second, Vec3 out[6]);

}  // namespace surfaced::subdivision
