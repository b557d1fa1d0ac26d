// Wavefront OBJ free-form surfaces of type Bézier and B-spline: the patches of `cstype [rat] bezier` and
// `cstype [rat] bspline` / `surf` blocks (a B-spline surface becomes its Bézier patches, bspline_surface.h).
//
// Statements read (Wavefront OBJ specification 3.0, "Free-form curve/surface attributes" and "body statements"):
//   v x y z [w]            a control point; w (default 1) is its weight, used only by `cstype rat ...`. The
//                          coordinates are Euclidean (not multiplied by w), as the specification defines them.
//   cstype [rat] bezier    the type of the surfaces that follow; bmatrix, cardinal and taylor are refused
//   cstype [rat] bspline   (Unsupported, "line 12: cstype cardinal is not supported").
//   deg du dv              degrees in u and v (1..kMaxPatchDegree).
//   surf u0 u1 v0 v1 c...  a surface over [u0, u1] x [v0, v1]; the control point references (v, v/vt, v/vt/vn, v//vn;
//                          negative = relative to the last vertex) form a (Ku du + 1) x (Kv dv + 1) net, u varying
//                          fastest, where Ku, Kv are the numbers of segments given by `parm u` / `parm v`.
//   parm u p0 p1 ... pK    segment boundaries (strictly increasing; default: the surf range as one segment). A Bézier
//   parm v ...             surface of Ku x Kv segments becomes Ku x Kv patches of (du + 1) x (dv + 1) points, the
//                          neighbouring blocks sharing their boundary row/column of control points.
//                          For a bspline surface `parm u` and `parm v` are required and are the knot vectors
//                          (non-decreasing; |parm u| - du - 1 points along u): the net has that many points per
//                          direction, u varying fastest, and the surf range must be the knot vectors' domain
//                          [parm u[du], parm u[n]] x ... (else Unsupported). Knot errors are reported at the parm
//                          line ("line 9: parm u value 5 ..."), net errors at the surf line.
//   end                    closes the surf (or curv/curv2) block.
// Ignored: polygonal elements and their data (f, l, p, vt, vn, vp), grouping and display statements, curv/curv2
// blocks. Refused (Unsupported, with the line): trimming (trim, hole, scrv, sp) and a surf range narrower than its
// parm range. Each Bézier patch is parametrised over its own [0, 1]^2; the patches of a B-spline surface carry the
// surface's (u, v) at their corners (BezierPatch::corner_uvs), and neighbouring ones share their edges bit for bit.
#pragma once

#include <cstddef>
#include <string_view>

#include "geometry/core/result.h"
#include "geometry/surfaces/bezier_patch.h"

namespace surfaced {

struct ObjPatchReadOptions {
    std::size_t max_patches = 1'000'000;
    std::size_t max_vertices = 10'000'000;
};

//! Errors carry the 1-based line (GeoError::line, and "line N: " in the message): ParseError (malformed statement,
//! bad reference, wrong control point count, surf without end, no surfaces), NonFinite, Unsupported (another cstype,
//! trimming, sub-ranges), InvalidArgument (degree out of range, weight <= 0, a B-spline's knot vector or net
//! breaking bspline_surface.h's validate()), BudgetExceeded (max_patches, max_vertices; checked before the patches
//! are allocated, for a B-spline surface from its knot vectors before decomposing it, the control points of its
//! Bézier patches then counting against max_vertices too).
Result<PatchSet> read_obj_patches(std::string_view text, const ObjPatchReadOptions& options = {});

}  // namespace surfaced
