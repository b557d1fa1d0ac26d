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
// Trimming (specification 3.0, "Free-form curve/surface body statements"):
//   vp u v [w]             a parameter vertex (w, default 1, is its weight in `cstype rat ...` curves).
//   curv2 vp1 vp2 ...      a 2D curve over parameter vertices (references as for surf; negative = relative to the
//                          last vp), of the current cstype and the first degree of the current deg. `parm u` inside
//                          its block (before end) is its knot vector (bspline: |parm u| - deg - 1 points; required)
//                          or its segment breaks (bezier: K segments of deg + 1 points sharing their ends, K deg + 1
//                          points; default [0, 1]). Checked at its end by validate(BSplineCurve) (bspline.h).
//   trim u0 u1 c ...       inside a surf block: one outer loop, the curv2 curves c (1-based, negative = relative to
//   hole u0 u1 c ...       the last curv2) in order, each used from u0 to u1: its whole domain, forwards or
//                          backwards (a part of a curve is refused, Unsupported). hole: one hole loop. The curves
//                          must be defined before the statement. Loops are in the surf's (u, v): a bspline surface's
//                          knot domain, a bezier surface's parm range.
// A surf with trim or hole statements becomes an ObjTrimmedSurface (a bezier surf the B-spline with its breaks as
// knots of multiplicity deg) whose loops passed validate_trims (trim_loops.h); a TrimError is reported at the line of
// the trim or hole statement (an invalid curve: at the curv2 line), its message naming the loop as outer[i][j] /
// holes[i][j] (the surf's i-th trim or hole statement, its j-th curve).
// Ignored: polygonal elements and their data (f, l, p, vt, vn), grouping and display statements, curv blocks (3D
// curves). Refused (Unsupported, with the line): special curves and points (scrv, sp), a trim over part of a curve, a
// surf range narrower than its parm range. Each Bézier patch is parametrised over its own [0, 1]^2; the patches of a
// B-spline surface carry the surface's (u, v) at their corners (BezierPatch::corner_uvs), and neighbouring ones share
// their edges bit for bit.
#pragma once

#include <cstddef>
#include <string_view>
#include <vector>

#include "geometry/core/result.h"
#include "geometry/surfaces/bezier_patch.h"
#include "geometry/surfaces/trim_loops.h"

namespace surfaced {

struct ObjPatchReadOptions {
    std::size_t max_patches = 1'000'000;
    std::size_t max_vertices = 10'000'000;      //!< v plus vp statements
    std::size_t max_trim_loops = 100'000;       //!< trim plus hole statements
    std::size_t max_trim_segments = 1'000'000;  //!< chords of the validated loops' polygons, over all surfaces
};

//! A surf with trim or hole statements, its loops validated.
struct ObjTrimmedSurface {
    TrimmedSurface trimmed;
    std::int64_t line = 0;  //!< the surf statement's line
};

struct ObjSurfaces {
    PatchSet patches;                        //!< the untrimmed surfaces' Bézier patches
    std::vector<ObjTrimmedSurface> trimmed;  //!< in file order
};

//! Every surface, trimmed ones apart. Errors carry the 1-based line (GeoError::line, and "line N: " in the message):
//! ParseError (malformed statement, bad reference, wrong control point count, surf without end, no surfaces),
//! NonFinite, Unsupported (another cstype, scrv/sp, sub-ranges), InvalidArgument (degree out of range, weight <= 0, a B-spline's knot vector or net
//! breaking bspline_surface.h's validate()), BudgetExceeded (max_patches, max_vertices; checked before the patches
//! are allocated, for a B-spline surface from its knot vectors before decomposing it, the control points of its
//! Bézier patches then counting against max_vertices too).
//! The trims add: ParseError (a bad curv2, vp, trim or hole statement, a reference to an undefined curve),
//! InvalidArgument (a curv2 breaking validate(BSplineCurve), a loop breaking validate_trims), BudgetExceeded
//! (max_trim_loops, max_trim_segments). "No surfaces" means neither patches nor trimmed surfaces.
Result<ObjSurfaces> read_obj_surfaces(std::string_view text, const ObjPatchReadOptions& options = {});

//! The Bézier patches only: as read_obj_surfaces, a trimmed surface refused (Unsupported at its surf line: patches
//! carry no trims).
Result<PatchSet> read_obj_patches(std::string_view text, const ObjPatchReadOptions& options = {});

}  // namespace surfaced
