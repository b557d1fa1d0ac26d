// Trimmed B-spline / NURBS surfaces: the trim loops in the surface's (u, v) parameter space, their validation and their
// flattening into oriented polygons. The tessellator (trimmed_surface.h) works on the polygons prepare_trims returns.
//
// A trim curve is a 2D B-spline or NURBS curve (bspline.h's conventions: degree, n points, n + degree + 1 knots,
// optional positive weights); a Bézier curve is the B-spline whose knots are degree + 1 zeros and degree + 1 ones.
// A loop is a list of curves, each ending where the next one starts (the last ending where the first starts). The
// trimmed domain is the set of parameters inside an outer loop (the whole rectangle when there is none) and inside no
// hole.
//
// Validation, in this order (the first broken rule is reported, naming the loop and curve):
//  1. every loop has a curve, every curve is a valid B-spline (validate(BSplineCurve)): InvalidCurve;
//  2. closed: each curve ends within closure_tolerance x (the domain's diagonal) of the next curve's start: OpenLoop;
//  3. inside the domain: every point of the flattened loop lies in the parameter rectangle, widened by the same
//     tolerance (points in that margin are clamped onto the rectangle): OutsideDomain;
//  4. not degenerate: at least 3 distinct polygon vertices and a non-zero area: DegenerateLoop;
//  5. not self-intersecting: no two non-adjacent segments of a loop's polygon touch, adjacent ones do not fold back:
//     SelfIntersecting (naming both curves);
//  6. loops do not cross or touch: LoopsCross (naming both loops and curves);
//  7. every hole lies inside an outer loop (when there are outer loops): HoleOutside; no hole inside another hole, no
//     outer loop inside another loop: NestedLoops.
// Rules 3-7 are decided on the polygons: each curve flattened so that it lies within `flatness` (parameter units) of
// its polygon (the convex hull of each Bézier piece's control points, positive weights, lies within flatness of the
// chord), which is exactly the polygon the tessellation uses, so an accepted loop meshes as validated. Orientation is
// then normalised -- outer loops counter-clockwise, holes clockwise in (u, v), so that the trimmed domain is always on
// the left -- and each loop reports whether it was reversed.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "geometry/core/result.h"
#include "geometry/core/types.h"
#include "geometry/surfaces/bspline_surface.h"

namespace surfaced {

struct TrimCurve {
    int degree = 1;
    std::vector<double> knots;    //!< points.size() + degree + 1 non-decreasing values
    std::vector<Vec2> points;     //!< control points (u, v)
    std::vector<double> weights;  //!< empty (polynomial) or one positive weight per point
};

struct TrimLoop {
    std::vector<TrimCurve> curves;  //!< in order, each ending where the next starts
};

struct TrimmedSurface {
    BSplineSurface surface;
    std::vector<TrimLoop> outer;  //!< empty: the whole parameter rectangle
    std::vector<TrimLoop> holes;
};

enum class TrimLoopKind { Outer, Hole };

enum class TrimErrorKind {
    InvalidCurve,      //!< an empty loop or a curve that is not a valid B-spline
    OpenLoop,          //!< a curve does not end where the next starts
    OutsideDomain,     //!< the loop leaves the surface's parameter rectangle
    DegenerateLoop,    //!< fewer than three distinct points or no area
    SelfIntersecting,  //!< the loop touches or crosses itself
    LoopsCross,        //!< two loops touch or cross
    HoleOutside,       //!< a hole is not inside any outer loop
    NestedLoops,       //!< a hole inside a hole, or an outer loop inside another loop
    TooManySegments,   //!< flattening needs more than the segment budget
};

//! "holes[1][0]": the JSON path of a curve (curve -1: the loop, "outer[0]").
std::string trim_path(TrimLoopKind kind, int loop, int curve = -1);

struct TrimError {
    TrimErrorKind kind = TrimErrorKind::InvalidCurve;
    TrimLoopKind loop_kind = TrimLoopKind::Outer;
    int loop = -1;
    int curve = -1;  //!< -1: the loop as a whole
    //! The second loop or curve involved (OpenLoop: the next curve; SelfIntersecting: the other curve of the same loop;
    //! LoopsCross, NestedLoops: the other loop), or loop -1.
    TrimLoopKind other_kind = TrimLoopKind::Outer;
    int other_loop = -1;
    int other_curve = -1;
    std::string message;  //!< begins with trim_path(...) of the loop or curve: "holes[1][0]: ..."
};

//! The GeoError of a trim error: code InvalidArgument (BudgetExceeded for TooManySegments), the message, element =
//! the loop index (ElementKind::None).
GeoError to_geo_error(const TrimError& error);

//! A loop flattened to a closed polygon (first vertex not repeated), oriented (outer counter-clockwise, holes
//! clockwise). Every vertex lies on its trim curve (evaluated, then clamped into the domain); segment k joins
//! points[k] and points[(k + 1) % size] and comes from curve segment_curves[k].
struct TrimPolygon {
    TrimLoopKind kind = TrimLoopKind::Outer;
    int loop = 0;
    std::vector<Vec2> points;
    std::vector<int> segment_curves;
    bool reversed = false;  //!< the loop was given with the other orientation and has been reversed
    double area = 0;        //!< signed area in (u, v) after orientation: > 0 outer, < 0 hole
};

struct TrimValidationOptions {
    double closure_tolerance = 1e-7;  //!< largest gap between consecutive curves, relative to the domain's diagonal
    double flatness = 1e-4;           //!< polygon-to-curve distance, relative to the domain's diagonal
    std::size_t max_segments = 1'000'000;  //!< polygon segments over all loops
};

struct PreparedTrims {
    std::vector<TrimPolygon> loops;  //!< the outer loops, then the holes, in input order
    double max_gap = 0;              //!< largest end-to-start gap closed (parameter units)
    double flatness = 0;             //!< the polygon-to-curve bound used (parameter units)
};

struct TrimValidation {
    std::optional<TrimError> error;  //!< the first broken rule, or none
    PreparedTrims trims;             //!< valid only without error
    bool ok() const { return !error; }
};

//! Validation as listed above, with flatness and closure tolerance relative to the domain's diagonal. Cost: the
//! flattening (O(segments)) and the intersection tests on a uniform grid of buckets (O(segments) for well-spread
//! loops). Precondition: validate(surface) succeeded.
TrimValidation validate_trims(const TrimmedSurface& trimmed, const TrimValidationOptions& options = {});

//! The same with an absolute flatness (parameter units) and an extra refinement rule: a chord a-b is also split
//! while refine(a, b) says so (the tessellator keeps trim segments no longer than its grid spacing). Chord vertices
//! are always points of the curve.
//! Chords whose ends lie on both sides of a line u = cut_u[k] or v = cut_v[k] are first split where the curve crosses
//! it (bisection on the curve), the vertex being set exactly onto the line: the tessellator passes its patch sides, so
//! that trims cross them at curve points and no short chord is left next to a side.
TrimValidation prepare_trims(const TrimmedSurface& trimmed, double flatness, double closure_tolerance,
                             std::size_t max_segments, const std::function<bool(Vec2, Vec2)>& refine = {},
                             const std::vector<double>& cut_u = {}, const std::vector<double>& cut_v = {});

//! True when (u, v) lies in the trimmed domain of `trims` (crossing number over every polygon; points on a polygon
//! count either way).
bool inside_trimmed_domain(const PreparedTrims& trims, Vec2 p);

}  // namespace surfaced
