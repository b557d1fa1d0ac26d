// SVG path data ("d" attribute) to Bézier chains, one chain per subpath, in the plane z = 0 (SVG's y axis points
// down; coordinates are taken as written).
//
// References:
//  - SVG 1.1 (Second Edition), 8.3 "Path data" and its grammar; SVG 2, 9.3 (number syntax with exponents, "0.5.5"
//    is two numbers; flags are single characters that need no separator).
//  - SVG 1.1, Appendix F.6 "Elliptical arc implementation notes": endpoint to centre parameterisation, radius
//    correction (F.6.6), out-of-range parameters (F.6.2).
#pragma once

#include <cstddef>
#include <string_view>
#include <vector>

#include "geometry/core/result.h"
#include "geometry/curves/piecewise.h"

namespace surfaced {

enum class SvgArcConversion {
    RationalQuadratic,  //!< exact: one rational quadratic (middle weight cos(delta/2)) per <= 90 degree piece
    Cubic,              //!< polynomial cubics, k = 4/3 tan(delta/4) per piece, split so that every point of the
                        //!< cubics is within arc_tolerance of the ellipse
    Reject,             //!< an A/a command is a ParseError ("arcs are not accepted")
};

struct SvgPathOptions {
    std::size_t max_commands = 100'000;  //!< drawing commands, counting implicit repeats ("L1 2 3 4" is 2)
    std::size_t max_pieces = 400'000;    //!< Bézier pieces produced in total (an arc gives up to 4 or more)
    SvgArcConversion arcs = SvgArcConversion::RationalQuadratic;
    double arc_tolerance = 1e-6;  //!< SvgArcConversion::Cubic only: absolute, model units; must be > 0
};

//! Parses SVG path data into one BezierChain per subpath, in order.
//!  - Commands M m L l H h V v C c S s Q q T t A a Z z, implicit repeats (after M/m they are L/l), numbers as in
//!    SVG 2 (sign, fraction, exponent; separators are whitespace and at most one comma between numbers; "1-2" and
//!    "0.5.5" are two numbers each). Empty or whitespace-only data gives no chains.
//!  - Pieces: L/H/V are degree-1, Q/T quadratic, C/S cubic, arcs as `options.arcs` says. Every piece starts
//!    bit-exactly at the previous piece's end point.
//!  - S (T) reflects the previous command's second (only) control point about the current point only when the
//!    previous command was C/c/S/s (Q/q/T/t); otherwise the first control point is the current point.
//!  - Z/z: a line back to the subpath's start unless the current point already equals it exactly; the chain is
//!    marked closed; the current point becomes the subpath's start, and a drawing command after Z without an M
//!    starts a new subpath (a new chain) there.
//!  - A subpath without any segment ("M1 2" alone, "M1 2 Z") gives no chain.
//!  - Arcs follow the F.6 notes: identical end points omit the arc, rx = 0 or ry = 0 gives a line, negative radii
//!    are made positive, too-small radii are scaled up, the rotation is in degrees. The arc's first and last points
//!    are bit-exactly the current point and the given end point.
//! Errors: ParseError with GeoError::offset = the byte offset of the offending token and a message such as
//! "svg path: offset 12: expected a number after 'C'" (also for a number out of double range, a first command other
//! than M/m, an unknown command letter, a flag other than 0/1, or coordinates that overflow to infinity);
//! BudgetExceeded when more than max_commands commands or max_pieces pieces would be produced (checked before the
//! pieces are added); InvalidArgument for options out of range.
Result<std::vector<BezierChain>> parse_svg_path(std::string_view data, const SvgPathOptions& options = {});

}  // namespace surfaced
