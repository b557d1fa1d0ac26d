// Piecewise Bézier chains: parameter mapping, continuity at the joints, the mirror rule, tessellation.
#include "geometry/curves/piecewise.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <string>

#include "geometry/core/format_number.h"

namespace surfaced {
namespace {

//! Angle in [0, pi] between two non-zero vectors (atan2 form: accurate near 0 and pi).
double angle_between(const Vec3& a, const Vec3& b) { return std::atan2(norm(cross(a, b)), dot(a, b)); }

//! Direction of the first non-vanishing derivative at an end, pointing along the curve's travel at that end:
//! `at_end` = false: the start, t = 0 (b_j - b_0); true: the end, t = 1 (b_n - b_{n-j}). `order` receives j, or 0
//! when every control point lies within `tolerance` of the end point.
Vec3 end_direction(const BezierCurve& curve, bool at_end, double tolerance, int& order) {
    const std::size_t n = curve.points.size();
    const Vec3& end = at_end ? curve.points.back() : curve.points.front();
    for (std::size_t j = 1; j < n; ++j) {
        const Vec3& q = at_end ? curve.points[n - 1 - j] : curve.points[j];
        const Vec3 d = at_end ? end - q : q - end;
        if (norm(d) > tolerance) {
            order = static_cast<int>(j);
            return d;
        }
    }
    order = 0;
    return {};
}

bool is_finite_non_negative(double x) { return std::isfinite(x) && x >= 0; }

JointContinuity measure_joint(const BezierCurve& left, const BezierCurve& right, std::size_t li, std::size_t ri,
                              const ContinuityOptions& options) {
    JointContinuity j;
    j.left = li;
    j.right = ri;
    j.gap = norm(right.points.front() - left.points.back());
    j.derivative_mismatch = norm(derivative(left, 1.0, 1) - derivative(right, 0.0, 1));
    const Vec3 dl = end_direction(left, true, options.position_tolerance, j.left_order);
    const Vec3 dr = end_direction(right, false, options.position_tolerance, j.right_order);
    const bool directions = j.left_order > 0 && j.right_order > 0;
    j.angle = directions ? angle_between(dl, dr) : 0.0;
    if (j.gap > options.position_tolerance)
        j.continuity = Continuity::None;
    else if (!directions || j.angle > options.angle_tolerance)
        j.continuity = Continuity::C0;
    else if (j.derivative_mismatch > options.derivative_tolerance)
        j.continuity = Continuity::G1;
    else
        j.continuity = Continuity::C1;
    return j;
}

std::size_t joint_count(const BezierChain& chain) {
    const std::size_t n = chain.pieces.size();
    return n == 0 ? 0 : (chain.closed ? n : n - 1);
}

Vec3 unit(const Vec3& v) {
    const double l = norm(v);
    return l > 0 ? v * (1.0 / l) : Vec3{};
}

//! The mirror rule at one joint (pieces already meet at P bit-exactly). Returns false when neither side can move.
bool mirror(BezierCurve& left, BezierCurve& right, JointSide side, EnforceMode mode) {
    const int n = left.degree(), m = right.degree();
    const bool left_movable = n >= 2, right_movable = m >= 2;
    if (!left_movable && !right_movable) return false;
    if (!left_movable) side = JointSide::Right;
    if (!right_movable) side = JointSide::Left;
    const Vec3 p = right.points.front();
    // b_{n-1} and c_1. A piece of degree 0 is a point, with derivative 0 and no control point beside the joint: it
    // never moves (degree < 2), so it gets a stand-in that is read only as 0 x something (found by fuzz_json_curves:
    // c_1 of a one-point piece was read past its end).
    Vec3 no_b{}, no_c{};
    Vec3& b = n >= 1 ? left.points[static_cast<std::size_t>(n - 1)] : no_b;
    Vec3& c = m >= 1 ? right.points[1] : no_c;
    const Vec3 dl = static_cast<double>(n) * (p - b), dr = static_cast<double>(m) * (c - p);
    if (mode == EnforceMode::C1) {
        if (dl == dr) return true;  // already C1: leave bit-identical
        switch (side) {
            case JointSide::Left: b = p - dr * (1.0 / n); break;
            case JointSide::Right: c = p + dl * (1.0 / m); break;
            case JointSide::Both: {
                const Vec3 d = 0.5 * (dl + dr);
                b = p - d * (1.0 / n);
                c = p + d * (1.0 / m);
                break;
            }
        }
        return true;
    }
    // G1: directions of the first non-vanishing derivatives (exact coincidence: the rule is on exact points)
    int lo = 0, ro = 0;
    const Vec3 ul = unit(end_direction(left, true, 0.0, lo)), ur = unit(end_direction(right, false, 0.0, ro));
    const double len_b = norm(p - b), len_c = norm(c - p);
    // fallback lengths when the adjacent control point sits on the joint: the fixed side's derivative, else the
    // distance to the control point that gave its direction (any positive length makes the joint G1)
    const auto fallback = [&](const Vec3& fixed_derivative, const BezierCurve& fixed, bool fixed_is_left, int degree) {
        if (norm(fixed_derivative) > 0) return norm(fixed_derivative) / degree;
        int order = 0;
        return norm(end_direction(fixed, fixed_is_left, 0.0, order)) / degree;
    };
    // a zero-length moved side gets the C1 length: |D| / n resp. |D| / m with D the fixed side's derivative
    switch (side) {
        case JointSide::Left: {
            if (ro == 0) return true;  // the right piece is a point: no direction to follow
            if (lo > 0 && ul == ur) return true;
            const double len = len_b > 0 ? len_b : fallback(dr, right, false, n);
            if (len == 0) return true;
            b = p - ur * len;
            break;
        }
        case JointSide::Right: {
            if (lo == 0) return true;
            if (ro > 0 && ul == ur) return true;
            const double len = len_c > 0 ? len_c : fallback(dl, left, true, m);
            if (len == 0) return true;
            c = p + ul * len;
            break;
        }
        case JointSide::Both: {
            if (lo == 0 || ro == 0) return true;
            if (ul == ur) return true;
            Vec3 u = unit(ul + ur);
            if (norm(u) == 0) u = ul;  // opposite tangents (a 180 degree cusp): follow the left piece
            if (len_b > 0) b = p - u * len_b;
            if (len_c > 0) c = p + u * len_c;
            if (len_b == 0 && len_c > 0) b = p - u * (len_c * m / n);
            if (len_c == 0 && len_b > 0) c = p + u * (len_b * n / m);
            if (len_b == 0 && len_c == 0) {
                const double len = fallback(Vec3{}, left, true, n);
                b = p - u * len;
                c = p + u * (len * n / m);
            }
            break;
        }
    }
    return true;
}

}  // namespace

Status validate(const BezierChain& chain) {
    if (chain.pieces.empty()) return make_error(ErrorCode::InvalidArgument, "a chain needs at least one piece");
    for (std::size_t i = 0; i < chain.pieces.size(); ++i) {
        if (auto valid = validate(chain.pieces[i]); !valid) {
            GeoError e = valid.error();
            e.message = "piece " + std::to_string(i) + ": " + e.message;
            e.element = static_cast<std::int64_t>(i);
            e.element_kind = ElementKind::None;
            return e;
        }
    }
    return Ok{};
}

const char* to_string(Continuity continuity) {
    switch (continuity) {
        case Continuity::None: return "none";
        case Continuity::C0: return "C0";
        case Continuity::G1: return "G1";
        case Continuity::C1: return "C1";
    }
    return "none";
}

ChainParameter chain_parameter(const BezierChain& chain, double s) {
    assert(!chain.pieces.empty());
    const double n = static_cast<double>(chain.pieces.size());
    if (!(s > 0)) return {0, 0.0};  // also NaN
    if (s >= n) return {chain.pieces.size() - 1, 1.0};
    const double k = std::floor(s);
    return {static_cast<std::size_t>(k), s - k};
}

Vec3 evaluate(const BezierChain& chain, std::size_t piece, double t) {
    assert(piece < chain.pieces.size());
    return evaluate(chain.pieces[piece], t);
}

Vec3 evaluate(const BezierChain& chain, double s) {
    const ChainParameter p = chain_parameter(chain, s);
    return evaluate(chain.pieces[p.piece], p.t);
}

Vec3 derivative(const BezierChain& chain, std::size_t piece, double t, int order) {
    assert(piece < chain.pieces.size());
    return derivative(chain.pieces[piece], t, order);
}

Result<ContinuityReport> continuity(const BezierChain& chain, const ContinuityOptions& options) {
    if (auto valid = validate(chain); !valid) return valid.error();
    if (!is_finite_non_negative(options.position_tolerance) || !is_finite_non_negative(options.angle_tolerance) ||
        !is_finite_non_negative(options.derivative_tolerance))
        return make_error(ErrorCode::InvalidArgument, "continuity tolerances must be finite numbers >= 0");
    ContinuityReport report;
    const std::size_t n = chain.pieces.size();
    for (std::size_t i = 0; i < joint_count(chain); ++i) {
        const std::size_t r = (i + 1) % n;
        JointContinuity j = measure_joint(chain.pieces[i], chain.pieces[r], i, r, options);
        report.weakest = std::min(report.weakest, j.continuity);
        report.max_gap = std::max(report.max_gap, j.gap);
        report.max_derivative_mismatch = std::max(report.max_derivative_mismatch, j.derivative_mismatch);
        report.max_angle = std::max(report.max_angle, j.angle);
        report.joints.push_back(j);
    }
    return report;
}

Result<EnforceResult> enforce_c1(const BezierChain& chain, const EnforceOptions& options) {
    if (auto valid = validate(chain); !valid) return valid.error();
    const std::size_t n = chain.pieces.size();
    for (std::size_t i = 0; i < n; ++i)
        if (chain.pieces[i].is_rational())
            return element_error(ErrorCode::InvalidArgument,
                                 "piece " + std::to_string(i) + " is rational: the mirror rule needs polynomial pieces",
                                 ElementKind::None, static_cast<std::int64_t>(i));
    const std::size_t joints = joint_count(chain);
    std::vector<std::size_t> selected = options.joints;
    if (selected.empty())
        for (std::size_t i = 0; i < joints; ++i) selected.push_back(i);
    for (std::size_t j : selected)
        if (j >= joints)
            return make_error(
                ErrorCode::InvalidArgument,
                "joint " + std::to_string(j) + " does not exist: the chain has " + std::to_string(joints) + " joints");
    std::sort(selected.begin(), selected.end());
    selected.erase(std::unique(selected.begin(), selected.end()), selected.end());

    EnforceResult result;
    result.chain = chain;
    std::vector<BezierCurve>& pieces = result.chain.pieces;

    // 1. close the gaps (midpoint of the two end points)
    for (std::size_t j : selected) {
        BezierCurve &left = pieces[j], &right = pieces[(j + 1) % n];
        if (left.points.back() != right.points.front()) {
            const Vec3 mid = 0.5 * (left.points.back() + right.points.front());
            left.points.back() = mid;
            right.points.front() = mid;
        }
    }

    // 2. the mirror rule, in cascade order
    if (options.side == JointSide::Left) std::reverse(selected.begin(), selected.end());
    for (std::size_t j : selected)
        if (!mirror(pieces[j], pieces[(j + 1) % n], options.side, options.mode)) result.skipped_joints.push_back(j);
    std::sort(result.skipped_joints.begin(), result.skipped_joints.end());

    // 3. measure
    ContinuityOptions measure;
    measure.position_tolerance = 0;
    for (std::size_t j : selected) {
        if (std::binary_search(result.skipped_joints.begin(), result.skipped_joints.end(), j)) continue;
        const JointContinuity c = measure_joint(pieces[j], pieces[(j + 1) % n], j, (j + 1) % n, measure);
        result.max_derivative_mismatch = std::max(result.max_derivative_mismatch, c.derivative_mismatch);
        result.max_angle = std::max(result.max_angle, c.angle);
    }
    return result;
}

Result<ChainTessellation> tessellate(const BezierChain& chain, const ChainTessellationOptions& options) {
    if (auto valid = validate(chain); !valid) return valid.error();
    if (!(std::isfinite(options.tolerance) && options.tolerance > 0))
        return make_error(ErrorCode::InvalidArgument, "tolerance must be a finite number > 0");
    ChainTessellation out;
    std::size_t used = 0;
    for (std::size_t i = 0; i < chain.pieces.size(); ++i) {
        if (options.cancel.requested()) return make_error(ErrorCode::Cancelled, "tessellation cancelled");
        const std::size_t remaining = options.max_segments - std::min(used, options.max_segments);
        auto piece = tessellate(chain.pieces[i], options.tolerance, remaining);
        if (!piece) {
            GeoError e = piece.error();
            if (e.code == ErrorCode::BudgetExceeded)
                e.message = "tolerance " + shortest_text(options.tolerance) + " needs more than " +
                            std::to_string(options.max_segments) + " segments for the chain (at piece " +
                            std::to_string(i) + ")";
            else
                e.message = "piece " + std::to_string(i) + ": " + e.message;
            return e;
        }
        const CurveTessellation& t = *piece;
        const double base = static_cast<double>(i);
        // join: skip the piece's first point when it repeats the previous end bit-exactly (else: a bridge)
        std::size_t first = 0;
        if (!out.points.empty() && out.points.back() == t.points.front())
            first = 1;
        else if (!out.points.empty())
            ++used;  // the bridging segment
        out.piece_start.push_back(first == 1 ? out.points.size() - 1 : out.points.size());
        for (std::size_t k = first; k < t.points.size(); ++k) {
            out.points.push_back(t.points[k]);
            out.params.push_back(base + t.params[k]);
        }
        used += t.segments;
        if (used > options.max_segments)
            return make_error(ErrorCode::BudgetExceeded,
                              "tolerance " + shortest_text(options.tolerance) + " needs more than " +
                                  std::to_string(options.max_segments) + " segments for the chain");
        out.max_deviation = std::max(out.max_deviation, t.max_deviation);
        out.bound = std::max(out.bound, t.bound);
    }
    if (chain.closed && out.points.back() != out.points.front()) {
        if (used + 1 > options.max_segments)
            return make_error(ErrorCode::BudgetExceeded,
                              "tolerance " + shortest_text(options.tolerance) + " needs more than " +
                                  std::to_string(options.max_segments) + " segments for the chain");
        // the closing joint has a gap: bridge it so that the polyline is closed
        out.points.push_back(out.points.front());
        out.params.push_back(static_cast<double>(chain.pieces.size()));
    }
    out.segments = out.points.size() - 1;
    return out;
}

}  // namespace surfaced
