// Piecewise Bézier curves ("chains"): pieces of any degree, polynomial or rational, joined end to start. Evaluation
// at a global parameter, a continuity report per joint (C0 gap, C1 derivative mismatch, G1 tangent angle), C1/G1
// enforcement by the mirror rule, and tessellation of the whole chain within a guaranteed tolerance.
//
// References:
//  - G. Farin, "Curves and Surfaces for CAGD", 5th ed., ch. 7 (piecewise Bézier curves, C1 condition
//    n (b_n - b_{n-1}) = m (c_1 - c_0) for degrees n and m, G1 as collinear end tangents).
//  - Endpoint tangents of Bézier curves: if b_0 = ... = b_{j-1} != b_j, the first j-1 derivatives at t = 0 vanish
//    and the j-th is a positive multiple of b_j - b_0 (also for rational curves, weights being positive).
#pragma once

#include <cstddef>
#include <vector>

#include "geometry/core/cancel.h"
#include "geometry/core/result.h"
#include "geometry/core/types.h"
#include "geometry/curves/bezier_curve.h"

namespace surfaced {

//! Pieces joined in order: piece i's last control point should equal piece i+1's first (a gap is allowed and
//! reported by continuity()). `closed`: the last piece's end also joins the first piece's start (a closing joint).
struct BezierChain {
    std::vector<BezierCurve> pieces;
    bool closed = false;
};

//! At least one piece, and every piece passes validate(BezierCurve). Errors name the piece ("piece 3: control point
//! 2 is not finite"); GeoError::element is the piece index (ElementKind::None).
Status validate(const BezierChain& chain);

//! A global chain parameter s in [0, n] (n = pieces) split into a piece index and that piece's local t in [0, 1].
struct ChainParameter {
    std::size_t piece = 0;
    double t = 0;
};
//! s is clamped to [0, n] (NaN counts as 0); s = k (an integer 0 < k < n) maps to (k, 0), s = n to (n - 1, 1).
//! Precondition: at least one piece.
ChainParameter chain_parameter(const BezierChain& chain, double s);

//! Point of piece `piece` at local t. Precondition: piece < pieces.size().
Vec3 evaluate(const BezierChain& chain, std::size_t piece, double t);
//! Point at the global parameter s in [0, n] (through chain_parameter()).
Vec3 evaluate(const BezierChain& chain, double s);
//! order-th derivative of piece `piece` with respect to its local t (the global s has the same speed: ds = dt).
Vec3 derivative(const BezierChain& chain, std::size_t piece, double t, int order);

// ---- continuity ------------------------------------------------------------------------------------------------

//! Continuity classes in increasing order; a joint gets the highest one whose conditions all hold.
enum class Continuity { None, C0, G1, C1 };
//! "none", "C0", "G1", "C1".
const char* to_string(Continuity continuity);

struct ContinuityOptions {
    double position_tolerance = 1e-9;    //!< C0 when the gap is <= this (absolute, model units)
    double angle_tolerance = 1e-9;       //!< G1 when C0 and the tangent angle is <= this (radians)
    double derivative_tolerance = 1e-9;  //!< C1 when G1 and |left'(1) - right'(0)| <= this (absolute)
};

//! One joint: the end of piece `left` meets the start of piece `right` (right = 0 for a closed chain's closing joint).
struct JointContinuity {
    std::size_t left = 0;
    std::size_t right = 0;
    double gap = 0;                  //!< |left(1) - right(0)|
    double derivative_mismatch = 0;  //!< |left'(1) - right'(0)| with the pieces' actual first derivatives
    //! Angle in [0, pi] between the tangent directions (left's incoming, right's outgoing). The directions are those
    //! of the first non-vanishing derivative: when control points coincide with the end point (a zero-length end
    //! derivative), the first control point farther than position_tolerance from the end point gives the direction.
    //! 0 when a side has no direction (every control point of that piece within position_tolerance of its end).
    double angle = 0;
    //! Which derivative gave each side's direction: 1 normally, j > 1 when the j-1 control points next to the end
    //! coincide with it (within position_tolerance), 0 when the piece has no direction at all.
    int left_order = 1;
    int right_order = 1;
    //! None if gap > position_tolerance; else C0 unless both directions exist and angle <= angle_tolerance; else G1
    //! unless derivative_mismatch <= derivative_tolerance, then C1. So two vanishing derivatives with opposite
    //! higher-order directions (a cusp) are C0, not C1, although parametrically C1.
    Continuity continuity = Continuity::None;
};

struct ContinuityReport {
    std::vector<JointContinuity> joints;  //!< pieces - 1 interior joints in order, then the closing joint if closed
    Continuity weakest = Continuity::C1;  //!< the lowest class over all joints (C1 when there is no joint)
    double max_gap = 0;
    double max_derivative_mismatch = 0;
    double max_angle = 0;
};

//! Errors: InvalidArgument (validate(), or a tolerance that is negative or not finite).
Result<ContinuityReport> continuity(const BezierChain& chain, const ContinuityOptions& options = {});

// ---- enforcing C1 / G1 -----------------------------------------------------------------------------------------

enum class JointSide {
    Left,   //!< move b_{n-1} of the piece ending at the joint
    Right,  //!< move c_1 of the piece starting at the joint
    Both,   //!< move both, symmetrically: C1 to the average derivative, G1 to the bisecting direction
};
enum class EnforceMode {
    C1,  //!< one-sided derivatives equal: n (b_n - b_{n-1}) = m (c_1 - c_0)
    G1,  //!< tangent directions equal; each moved side keeps its length |b_n - b_{n-1}| (a zero-length side gets
         //!< the length the C1 rule would give it)
};

struct EnforceOptions {
    JointSide side = JointSide::Both;
    EnforceMode mode = EnforceMode::C1;
    //! Joints to enforce, by index as in ContinuityReport::joints (joint i joins piece i and i + 1; joint n - 1 is
    //! the closing joint of a closed chain). Empty: every joint.
    std::vector<std::size_t> joints;
};

struct EnforceResult {
    BezierChain chain;
    //! Joints left as they were because neither side can move: both pieces have degree <= 1 (see enforce_c1).
    std::vector<std::size_t> skipped_joints;
    //! Measured on the result over the enforced joints: max |left'(1) - right'(0)| and max tangent angle (radians).
    double max_derivative_mismatch = 0;
    double max_angle = 0;
};

//! Makes the selected joints C1 (or G1) by the mirror rule, moving only the control points next to each joint.
//!  1. C0 first: a joint with a gap moves both end points to their midpoint (a joint without gap keeps them
//!     bit-identical).
//!  2. Then the mirror rule at each joint with joint point P, left piece b (degree n), right piece c (degree m):
//!     Left: b_{n-1} = P - (m/n)(c_1 - P); Right: c_1 = P + (n/m)(P - b_{n-1}); Both: both to the average
//!     derivative D = (n (P - b_{n-1}) + m (c_1 - P)) / 2. A joint whose derivatives are already bit-equal (C1) or
//!     whose directions are already identical (G1) is left untouched, so pieces away from changed joints are
//!     bit-identical to the input.
//! Lines: a piece of degree 1 (or 0) has no interior control point, and moving b_{n-1} = b_0 would move the
//! previous joint, so such pieces never move: the other side takes the whole correction whatever `side` says, and
//! a joint between two such pieces is left as is and listed in skipped_joints.
//! Order and quadratics: a quadratic's single interior point serves both of its joints. Joints are processed first
//! to last for Right and Both, last to first for Left, so that Right (Left) cascades along an open chain and leaves
//! every joint C1; with Both, or at a closed chain's closing joint, the later joint's move wins for a shared point,
//! and the result's measured max_derivative_mismatch tells.
//! Errors: InvalidArgument (validate(); a rational piece, naming it: "piece 2 is rational: the mirror rule needs
//! polynomial pieces"; a joint index out of range).
Result<EnforceResult> enforce_c1(const BezierChain& chain, const EnforceOptions& options = {});

// ---- tessellation ----------------------------------------------------------------------------------------------

struct ChainTessellationOptions {
    double tolerance = 1e-3;               //!< max distance of the curve from the polyline (absolute)
    std::size_t max_segments = 1'000'000;  //!< for the whole chain
    Cancel cancel;                         //!< polled between pieces
};

struct ChainTessellation {
    //! One polyline through all pieces: a joint point appears once when the pieces meet bit-exactly; a gap between
    //! pieces appears as a straight bridging segment (not on the curve, not covered by `bound`). A closed chain ends
    //! with its first point again (points.back() == points.front() when the closing joint has no gap).
    std::vector<Vec3> points;
    std::vector<double> params;            //!< the global parameter s = piece + t of each point
    std::vector<std::size_t> piece_start;  //!< index into points where each piece begins
    std::size_t segments = 0;              //!< points.size() - 1
    double max_deviation = 0;              //!< measured: max over pieces of tessellate()'s sampled deviation
    double bound = 0;                      //!< guaranteed: max over pieces of tessellate()'s bound (<= tolerance)
};

//! tessellate(BezierCurve) on every piece with the chain's remaining segment budget, merged into one polyline.
//! Errors: InvalidArgument (validate(), tolerance not > 0), BudgetExceeded (more than max_segments in total),
//! Cancelled.
Result<ChainTessellation> tessellate(const BezierChain& chain, const ChainTessellationOptions& options);

}  // namespace surfaced
