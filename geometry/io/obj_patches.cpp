// OBJ free-form Bézier and B-spline surfaces (see obj_patches.h for what is read and what is refused).
#include "geometry/io/obj_patches.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "geometry/io/number_text.h"
#include "geometry/io/text_encoding.h"
#include "geometry/io/text_scanner.h"
#include "geometry/curves/bspline.h"
#include "geometry/surfaces/bspline_surface.h"

namespace surfaced {
namespace {

using io_detail::error_at_line;
using io_detail::NumberStatus;
using io_detail::quote;
using io_detail::Tokens;

//! A surf statement waiting for its `end`.
struct PendingSurface {
    std::int64_t line = 0;
    int degree_u = 0, degree_v = 0;
    bool rational = false;
    bool bspline = false;
    std::int64_t parm_line[2] = {0, 0};  // lines of parm u and parm v
    double range[4] = {0, 1, 0, 1};      // u0 u1 v0 v1
    std::vector<std::size_t> refs;       // 0-based vertex indices
    std::optional<std::vector<double>> parm_u, parm_v;
    // trim and hole statements: the loops, the statements' lines and the curv2 index of each curve
    std::vector<TrimLoop> loops[2];  // outer (trim), holes (hole)
    std::vector<std::int64_t> loop_lines[2];
    std::vector<std::vector<std::size_t>> loop_curves[2];
};

//! A curv2 statement waiting for its `end`.
struct PendingCurve {
    std::int64_t line = 0;
    int degree = 0;
    bool rational = false;
    bool bspline = false;
    std::vector<std::size_t> refs;  // 0-based parameter vertex indices
    std::optional<std::vector<double>> parm;
    std::int64_t parm_line = 0;
};

//! The curve run backwards over the same domain: reversed points and weights, knots mirrored.
TrimCurve reversed(const TrimCurve& c) {
    TrimCurve out = c;
    std::reverse(out.points.begin(), out.points.end());
    std::reverse(out.weights.begin(), out.weights.end());
    const double sum = c.knots.front() + c.knots.back();
    for (std::size_t i = 0; i < c.knots.size(); ++i) out.knots[i] = sum - c.knots[c.knots.size() - 1 - i];
    return out;
}

//! Knots of a Bézier curve or surface direction of K segments over `breaks`: the ends degree + 1 times, each
//! interior break degree times (K degree + 1 control points, the segments sharing their end points).
std::vector<double> bezier_knots(const std::vector<double>& breaks, int degree) {
    std::vector<double> knots;
    for (std::size_t k = 0; k < breaks.size(); ++k) {
        const bool end = k == 0 || k + 1 == breaks.size();
        knots.insert(knots.end(), static_cast<std::size_t>(end ? degree + 1 : degree), breaks[k]);
    }
    return knots;
}

class ObjPatchReader {
public:
    ObjPatchReader(std::string_view text, const ObjPatchReadOptions& options) : text_(text), options_(options) {}

    Result<ObjSurfaces> read() {
        auto start = io_detail::check_text_encoding(text_);
        if (!start) return start.error();
        io_detail::LineReader lines(text_, *start, /*continuations=*/true);
        std::string_view line;
        while (lines.next(line)) {
            line_ = lines.line_number();
            if (auto error = parse_line(line)) return std::move(*error);
        }
        if (surface_) return error_at_line(ErrorCode::ParseError, surface_->line, "surf has no matching end");
        if (curve2_) return error_at_line(ErrorCode::ParseError, curve2_->line, "curv2 has no matching end");
        if (out_.patches.patches.empty() && out_.trimmed.empty())
            return error_at_line(ErrorCode::ParseError, std::max<std::int64_t>(line_, 1),
                                 "no free-form surfaces (cstype bezier or bspline, deg, surf ... end) in the file");
        return std::move(out_);
    }

private:
    GeoError error(ErrorCode code, const std::string& what) const { return error_at_line(code, line_, what); }

    std::optional<GeoError> parse_line(std::string_view line) {
        if (const void* hash = std::memchr(line.data(), '#', line.size()))
            line = line.substr(0, static_cast<std::size_t>(static_cast<const char*>(hash) - line.data()));
        Tokens tokens(line);
        std::string_view keyword;
        if (!tokens.next(keyword)) return std::nullopt;
        if (keyword == "v") return parse_vertex(tokens);
        if (keyword == "vp") return parse_parameter_vertex(tokens);
        if (keyword == "curv2") return parse_curve2(tokens);
        if (keyword == "trim" || keyword == "hole") return parse_loop(tokens, keyword == "hole");
        if (keyword == "cstype") return parse_cstype(tokens);
        if (keyword == "deg") return parse_degree(tokens);
        if (keyword == "surf") return parse_surf(tokens);
        if (keyword == "parm") return parse_parm(tokens);
        if (keyword == "end") return parse_end();
        if (keyword == "curv") {
            if (surface_ || in_curve_ || curve2_)
                return error(ErrorCode::ParseError, std::string(keyword) + " inside an open block (missing end)");
            in_curve_ = true;
            return std::nullopt;
        }
        if (keyword == "scrv" || keyword == "sp")
            return error(ErrorCode::Unsupported,
                         std::string(keyword) + ": special curves and points are not supported (trim and hole are)");
        if (keyword == "bmat" || keyword == "step")
            return error(ErrorCode::Unsupported,
                         std::string(keyword) + " applies to cstype bmatrix/cardinal/taylor, which are not supported");
        return std::nullopt;  // polygons, groups, materials, display attributes: not ours
    }

    std::optional<GeoError> number(Tokens& tokens, const char* what, double& out, bool required = true) {
        std::string_view token;
        if (!tokens.next(token)) {
            if (!required) return std::nullopt;
            return error(ErrorCode::ParseError, std::string("missing ") + what);
        }
        if (io_detail::parse_double(token, out) != NumberStatus::Ok)
            return error(ErrorCode::ParseError, std::string(what) + " " + quote(token) + " is not a number");
        if (!std::isfinite(out)) return error(ErrorCode::NonFinite, std::string(what) + " is not finite");
        return std::nullopt;
    }

    std::optional<GeoError> parse_vertex(Tokens& tokens) {
        if (points_.size() + parameter_points_.size() >= options_.max_vertices)
            return error(ErrorCode::BudgetExceeded,
                         "more than max_vertices (" + std::to_string(options_.max_vertices) + ") vertices");
        Vec3 p;
        for (int c = 0; c < 3; ++c)
            if (auto e = number(tokens, c == 0 ? "v x" : c == 1 ? "v y" : "v z", p[c])) return e;
        double w = 1.0;
        std::string_view extra;
        Tokens rest = tokens;
        if (rest.next(extra)) {
            if (auto e = number(tokens, "v weight", w)) return e;
            if (!tokens.empty()) return error(ErrorCode::ParseError, "v has more than 4 numbers");
        }
        points_.push_back(p);
        weights_.push_back(w);
        return std::nullopt;
    }

    //! vp u [v [w]]: v is needed only by the curv2 statements that use the vertex.
    std::optional<GeoError> parse_parameter_vertex(Tokens& tokens) {
        if (points_.size() + parameter_points_.size() >= options_.max_vertices)
            return error(ErrorCode::BudgetExceeded,
                         "more than max_vertices (" + std::to_string(options_.max_vertices) + ") vertices");
        Vec2 p{0, std::numeric_limits<double>::quiet_NaN()};
        double w = 1.0;
        if (auto e = number(tokens, "vp u", p.x)) return e;
        if (auto e = number(tokens, "vp v", p.y, /*required=*/false)) return e;
        if (auto e = number(tokens, "vp weight", w, /*required=*/false)) return e;
        if (!tokens.empty()) return error(ErrorCode::ParseError, "vp has more than 3 numbers");
        parameter_points_.push_back(p);
        parameter_weights_.push_back(w);
        return std::nullopt;
    }

    //! A 1-based (or negative, relative) reference among `count` items: the 0-based index, or nullopt.
    static std::optional<std::size_t> resolve(std::string_view text, std::size_t count) {
        std::int64_t index = 0;
        if (io_detail::parse_int(text, index) != NumberStatus::Ok) return std::nullopt;
        const auto n = static_cast<std::int64_t>(count);
        const std::int64_t resolved = index < 0 ? n + index : index - 1;
        if (index == 0 || resolved < 0 || resolved >= n) return std::nullopt;
        return static_cast<std::size_t>(resolved);
    }

    std::optional<GeoError> parse_curve2(Tokens& tokens) {
        if (surface_ || in_curve_ || curve2_)
            return error(ErrorCode::ParseError, "curv2 inside an open block (missing end)");
        if (cstype_ == CsType::None) return error(ErrorCode::ParseError, "curv2 before any cstype statement");
        if (degree_u_ < 1) return error(ErrorCode::ParseError, "curv2 needs a preceding deg statement (deg d)");
        PendingCurve c;
        c.line = line_;
        c.degree = degree_u_;
        c.rational = cstype_ == CsType::RationalBezier;
        c.bspline = bspline_;
        std::string_view token;
        while (tokens.next(token)) {
            const auto index = resolve(token, parameter_points_.size());
            if (!index)
                return error(ErrorCode::ParseError, "curv2 control point " + quote(token) + " is not one of the " +
                                                        std::to_string(parameter_points_.size()) +
                                                        " parameter vertices (vp) defined so far");
            c.refs.push_back(*index);
        }
        if (c.refs.empty()) return error(ErrorCode::ParseError, "curv2 has no control points");
        curve2_ = std::move(c);
        return std::nullopt;
    }

    //! The curv2 block's end: the curve, as a B-spline, checked by validate(BSplineCurve).
    std::optional<GeoError> end_curve2() {
        const PendingCurve c = std::move(*curve2_);
        curve2_.reset();
        TrimCurve curve;
        curve.degree = c.degree;
        const std::size_t n = c.refs.size(), d = static_cast<std::size_t>(c.degree);
        if (c.bspline) {
            if (!c.parm)
                return error_at_line(ErrorCode::ParseError, c.line,
                                     "a bspline curv2 needs parm u (its knot vector) before end");
            if (c.parm->size() != n + d + 1)
                return error_at_line(ErrorCode::ParseError, c.parm_line,
                                     "parm u has " + std::to_string(c.parm->size()) + " values; the curv2's " +
                                         std::to_string(n) + " control points of degree " + std::to_string(d) +
                                         " need " + std::to_string(n + d + 1));
            curve.knots = *c.parm;
        } else {
            const std::vector<double> breaks = c.parm.value_or(std::vector<double>{0, 1});
            const std::size_t segments = breaks.size() - 1;
            if (n != segments * d + 1)
                return error_at_line(ErrorCode::ParseError, c.line,
                                     "curv2 has " + std::to_string(n) + " control points; degree " + std::to_string(d) +
                                         " with " + std::to_string(segments) + " segments needs " +
                                         std::to_string(segments * d + 1));
            curve.knots = bezier_knots(breaks, c.degree);
        }
        BSplineCurve check;  // validate() reads 3D curves
        check.degree = c.degree;
        check.knots = curve.knots;
        for (std::size_t ref : c.refs) {
            const Vec2 p = parameter_points_[ref];
            if (std::isnan(p.y))
                return error_at_line(ErrorCode::ParseError, c.line,
                                     "curv2 uses vp " + std::to_string(ref + 1) + ", which has no v");
            curve.points.push_back(p);
            check.points.push_back({p.x, p.y, 0});
            if (c.rational) curve.weights.push_back(parameter_weights_[ref]);
        }
        check.weights = curve.weights;
        if (Status valid = validate(check); !valid) {
            const bool knot = valid.error().message.starts_with("knot");
            return error_at_line(valid.error().code, knot && c.parm ? c.parm_line : c.line,
                                 (knot && c.parm ? "curv2 parm u: " : "curv2: ") + valid.error().message);
        }
        curves2_.push_back(std::move(curve));
        curve2_lines_.push_back(c.line);
        return std::nullopt;
    }

    //! trim|hole u0 u1 curv2 ...: one loop of the open surf.
    std::optional<GeoError> parse_loop(Tokens& tokens, bool hole) {
        const std::string keyword = hole ? "hole" : "trim";
        if (!surface_) return error(ErrorCode::ParseError, keyword + " outside a surf ... end block");
        if (trim_loops_ >= options_.max_trim_loops)
            return error(
                ErrorCode::BudgetExceeded,
                "more than max_trim_loops (" + std::to_string(options_.max_trim_loops) + ") trim and hole statements");
        ++trim_loops_;
        TrimLoop loop;
        std::vector<std::size_t> ids;
        std::string_view token;
        while (true) {
            Tokens rest = tokens;
            if (!rest.next(token)) break;
            double range[2];
            if (auto e = number(tokens, (keyword + " u0").c_str(), range[0])) return e;
            if (auto e = number(tokens, (keyword + " u1").c_str(), range[1])) return e;
            if (!tokens.next(token)) return error(ErrorCode::ParseError, keyword + ": missing the curv2 of a u0 u1");
            const auto index = resolve(token, curves2_.size());
            if (!index)
                return error(ErrorCode::ParseError, keyword + " curve " + quote(token) + " is not one of the " +
                                                        std::to_string(curves2_.size()) +
                                                        " curv2 curves defined so far");
            const TrimCurve& curve = curves2_[*index];
            const double a = curve.knots[static_cast<std::size_t>(curve.degree)];
            const double b = curve.knots[curve.points.size()];
            if (range[0] == a && range[1] == b) {
                loop.curves.push_back(curve);
            } else if (range[0] == b && range[1] == a) {
                loop.curves.push_back(reversed(curve));
            } else {
                return error(ErrorCode::Unsupported, keyword + " uses curv2 " + std::to_string(*index + 1) + " over [" +
                                                         number_text(range[0]) + ", " + number_text(range[1]) +
                                                         "]; only a whole curve is supported, its domain [" +
                                                         number_text(a) + ", " + number_text(b) + "] either way");
            }
            ids.push_back(*index);
        }
        if (loop.curves.empty()) return error(ErrorCode::ParseError, keyword + " needs u0 u1 curv2 triples");
        const int k = hole ? 1 : 0;
        surface_->loops[k].push_back(std::move(loop));
        surface_->loop_lines[k].push_back(line_);
        surface_->loop_curves[k].push_back(std::move(ids));
        return std::nullopt;
    }

    //! A surf with trim or hole statements: its loops validated, kept with the surface.
    std::optional<GeoError> add_trimmed(BSplineSurface surface, PendingSurface& s) {
        const std::size_t count = bezier_patch_count(surface);
        if (out_.patches.patches.size() + trimmed_patches_ + count > options_.max_patches)
            return error_at_line(ErrorCode::BudgetExceeded, s.line,
                                 "more than max_patches (" + std::to_string(options_.max_patches) +
                                     ") patches: this trimmed surface has " + std::to_string(count));
        trimmed_patches_ += count;
        ObjTrimmedSurface out;
        out.line = s.line;
        out.trimmed.surface = std::move(surface);
        out.trimmed.outer = std::move(s.loops[0]);
        out.trimmed.holes = std::move(s.loops[1]);
        TrimValidationOptions validation;
        validation.max_segments = options_.max_trim_segments - trim_segments_;
        TrimValidation valid = validate_trims(out.trimmed, validation);
        if (!valid.ok()) {
            const TrimError& e = *valid.error;
            const int k = e.loop_kind == TrimLoopKind::Outer ? 0 : 1;
            const auto loop = static_cast<std::size_t>(e.loop);
            std::int64_t line = s.loop_lines[k][loop];
            std::string what = (k == 0 ? "trim: " : "hole: ") + e.message;
            if (e.kind == TrimErrorKind::InvalidCurve && e.curve >= 0) {
                const std::size_t id = s.loop_curves[k][loop][static_cast<std::size_t>(e.curve)];
                line = curve2_lines_[id];
                what = "curv2 " + std::to_string(id + 1) + " (" + e.message + ")";
            }
            return error_at_line(to_geo_error(e).code, line, what);
        }
        for (const TrimPolygon& polygon : valid.trims.loops) trim_segments_ += polygon.points.size();
        out_.trimmed.push_back(std::move(out));
        return std::nullopt;
    }

    std::optional<GeoError> parse_cstype(Tokens& tokens) {
        std::string_view type;
        if (!tokens.next(type)) return error(ErrorCode::ParseError, "cstype needs a type (bezier)");
        bool rational = false;
        if (type == "rat") {
            rational = true;
            if (!tokens.next(type)) return error(ErrorCode::ParseError, "cstype rat needs a type (bezier)");
        }
        if (type == "bmatrix" || type == "cardinal" || type == "taylor")
            return error(ErrorCode::Unsupported, "cstype " + std::string(rational ? "rat " : "") + std::string(type) +
                                                     " is not supported (only [rat] bezier and [rat] bspline)");
        if (type != "bezier" && type != "bspline") return error(ErrorCode::ParseError, "unknown cstype " + quote(type));
        if (!tokens.empty()) return error(ErrorCode::ParseError, "cstype: unexpected text after the type");
        cstype_ = rational ? CsType::RationalBezier : CsType::Bezier;
        bspline_ = type == "bspline";
        return std::nullopt;
    }

    std::optional<GeoError> parse_degree(Tokens& tokens) {
        int* targets[2] = {&degree_u_, &degree_v_};
        degree_v_ = 0;  // a curve's deg has one number
        for (int k = 0; k < 2; ++k) {
            std::string_view token;
            if (!tokens.next(token)) {
                if (k == 1) break;
                return error(ErrorCode::ParseError, "deg needs the degrees in u and v");
            }
            std::int64_t d = 0;
            if (io_detail::parse_int(token, d) != NumberStatus::Ok)
                return error(ErrorCode::ParseError, "deg " + quote(token) + " is not an integer");
            if (d < 1 || d > kMaxPatchDegree)
                return error(ErrorCode::InvalidArgument,
                             "deg " + std::to_string(d) + " is outside 1.." + std::to_string(kMaxPatchDegree));
            *targets[k] = static_cast<int>(d);
        }
        if (!tokens.empty()) return error(ErrorCode::ParseError, "deg has more than two numbers");
        return std::nullopt;
    }

    std::optional<GeoError> parse_surf(Tokens& tokens) {
        if (surface_ || in_curve_) return error(ErrorCode::ParseError, "surf inside an open block (missing end)");
        if (cstype_ == CsType::None) return error(ErrorCode::ParseError, "surf before any cstype statement");
        if (degree_u_ < 1 || degree_v_ < 1)
            return error(ErrorCode::ParseError, "surf needs a preceding deg statement with two degrees (deg du dv)");
        PendingSurface s;
        s.line = line_;
        s.degree_u = degree_u_;
        s.degree_v = degree_v_;
        s.rational = cstype_ == CsType::RationalBezier;
        s.bspline = bspline_;
        const char* names[4] = {"surf u0", "surf u1", "surf v0", "surf v1"};
        for (int k = 0; k < 4; ++k)
            if (auto e = number(tokens, names[k], s.range[k])) return e;
        if (!(s.range[0] < s.range[1]) || !(s.range[2] < s.range[3]))
            return error(ErrorCode::ParseError, "surf parameter ranges must be increasing (u0 < u1, v0 < v1)");
        std::string_view token;
        while (tokens.next(token)) {
            const std::size_t slash = token.find('/');
            const std::string_view index_text = token.substr(0, slash);
            std::int64_t index = 0;
            if (io_detail::parse_int(index_text, index) != NumberStatus::Ok)
                return error(ErrorCode::ParseError, "surf control point " + quote(token) + " is not a vertex index");
            const auto count = static_cast<std::int64_t>(points_.size());
            const std::int64_t resolved = index < 0 ? count + index : index - 1;
            if (index == 0 || resolved < 0 || resolved >= count)
                return error(ErrorCode::ParseError, "surf control point " + quote(token) + " refers to vertex " +
                                                        std::to_string(index) + ", but " + std::to_string(count) +
                                                        " vertices are defined so far");
            s.refs.push_back(static_cast<std::size_t>(resolved));
        }
        if (s.refs.empty()) return error(ErrorCode::ParseError, "surf has no control points");
        surface_ = std::move(s);
        return std::nullopt;
    }

    std::optional<GeoError> parse_parm(Tokens& tokens) {
        std::string_view direction;
        if (!tokens.next(direction) || (direction != "u" && direction != "v"))
            return error(ErrorCode::ParseError, "parm needs a direction u or v");
        if (in_curve_) return std::nullopt;  // 3D curves are not read
        if (curve2_ && direction != "u") return error(ErrorCode::ParseError, "a curv2 has only parm u");
        if (!surface_ && !curve2_) return error(ErrorCode::ParseError, "parm outside a surf or curv2 ... end block");
        const bool bspline = curve2_ ? curve2_->bspline : surface_->bspline;
        std::vector<double> values;
        double x = 0;
        std::string_view probe;
        while (true) {
            Tokens rest = tokens;
            if (!rest.next(probe)) break;
            if (auto e = number(tokens, "parm value", x)) return e;
            if (!values.empty() && !(x > values.back()) && !(bspline && x == values.back()))
                return error(ErrorCode::ParseError, "parm " + std::string(direction) + " values must " +
                                                        (bspline ? "not decrease" : "increase"));
            values.push_back(x);
        }
        if (values.size() < 2)
            return error(ErrorCode::ParseError, "parm " + std::string(direction) + " needs at least two values");
        if (curve2_) {
            curve2_->parm = std::move(values);
            curve2_->parm_line = line_;
            return std::nullopt;
        }
        (direction == "u" ? surface_->parm_u : surface_->parm_v) = std::move(values);
        surface_->parm_line[direction == "u" ? 0 : 1] = line_;
        return std::nullopt;
    }

    std::optional<GeoError> parse_end() {
        if (in_curve_) {
            in_curve_ = false;
            return std::nullopt;
        }
        if (curve2_) return end_curve2();
        if (!surface_) return error(ErrorCode::ParseError, "end without a surf");
        PendingSurface s = std::move(*surface_);
        surface_.reset();
        if (s.bspline) return end_bspline(s);
        const std::vector<double> parm_u = s.parm_u.value_or(std::vector<double>{s.range[0], s.range[1]});
        const std::vector<double> parm_v = s.parm_v.value_or(std::vector<double>{s.range[2], s.range[3]});
        if (s.range[0] != parm_u.front() || s.range[1] != parm_u.back() || s.range[2] != parm_v.front() ||
            s.range[3] != parm_v.back()) {
            GeoError e =
                error_at_line(ErrorCode::Unsupported, s.line,
                              "surf range differs from its parm u/v range (trimmed sub-ranges are not supported)");
            return e;
        }
        const std::size_t ku = parm_u.size() - 1, kv = parm_v.size() - 1;
        const std::size_t du = static_cast<std::size_t>(s.degree_u), dv = static_cast<std::size_t>(s.degree_v);
        const std::size_t nu = ku * du + 1, nv = kv * dv + 1;
        const bool trimmed = !s.loops[0].empty() || !s.loops[1].empty();
        // ku, kv are bounded by the line's length, so these products cannot overflow
        if (s.refs.size() != nu * nv)
            return error_at_line(ErrorCode::ParseError, s.line,
                                 "surf has " + std::to_string(s.refs.size()) + " control points; degree " +
                                     std::to_string(du) + "x" + std::to_string(dv) + " with " + std::to_string(ku) +
                                     "x" + std::to_string(kv) + " segments needs (" + std::to_string(ku) + "*" +
                                     std::to_string(du) + "+1) x (" + std::to_string(kv) + "*" + std::to_string(dv) +
                                     "+1) = " + std::to_string(nu * nv));
        if (trimmed) {
            // the net is the B-spline's whose knots are the breaks, interior ones of multiplicity degree
            BSplineSurface b;
            b.degree_u = s.degree_u;
            b.degree_v = s.degree_v;
            b.count_u = static_cast<int>(nu);
            b.count_v = static_cast<int>(nv);
            b.knots_u = bezier_knots(parm_u, s.degree_u);
            b.knots_v = bezier_knots(parm_v, s.degree_v);
            for (std::size_t ref : s.refs) {
                b.points.push_back(points_[ref]);
                if (s.rational) b.weights.push_back(weights_[ref]);
            }
            if (Status valid = validate(b); !valid)
                return error_at_line(valid.error().code, s.line, "surf: " + valid.error().message);
            return add_trimmed(std::move(b), s);
        }
        if (out_.patches.patches.size() + trimmed_patches_ + ku * kv > options_.max_patches)
            return error_at_line(ErrorCode::BudgetExceeded, s.line,
                                 "more than max_patches (" + std::to_string(options_.max_patches) + ") patches");
        for (std::size_t b = 0; b < kv; ++b)
            for (std::size_t a = 0; a < ku; ++a) {
                BezierPatch patch;
                patch.degree_u = s.degree_u;
                patch.degree_v = s.degree_v;
                for (std::size_t j = 0; j <= dv; ++j)
                    for (std::size_t i = 0; i <= du; ++i) {
                        const std::size_t ref = s.refs[(b * dv + j) * nu + a * du + i];
                        patch.points.push_back(points_[ref]);
                        if (s.rational) patch.weights.push_back(weights_[ref]);
                    }
                if (auto valid = validate(std::span<const BezierPatch>(&patch, 1)); !valid) {
                    const std::string& message = valid.error().message;  // "patch 0: ..."
                    const std::size_t colon = message.find(": ");
                    return error_at_line(valid.error().code, s.line,
                                         "surf " + (colon == std::string::npos ? message : message.substr(colon + 2)));
                }
                out_.patches.patches.push_back(std::move(patch));
            }
        return std::nullopt;
    }

    //! A B-spline surface: its knot vectors are the parm statements; decomposed into Bézier patches.
    std::optional<GeoError> end_bspline(PendingSurface& s) {
        for (int k = 0; k < 2; ++k)
            if (!(k == 0 ? s.parm_u : s.parm_v))
                return error_at_line(
                    ErrorCode::ParseError, s.line,
                    std::string("a bspline surf needs parm ") + (k == 0 ? "u" : "v") + " (its knot vector) before end");
        BSplineSurface b;
        b.degree_u = s.degree_u;
        b.degree_v = s.degree_v;
        b.knots_u = *s.parm_u;
        b.knots_v = *s.parm_v;
        for (int k = 0; k < 2; ++k) {
            const std::size_t size = (k == 0 ? b.knots_u : b.knots_v).size();
            const auto degree = static_cast<std::size_t>(k == 0 ? s.degree_u : s.degree_v);
            if (size < 2 * degree + 2)
                return error_at_line(ErrorCode::InvalidArgument, s.parm_line[k],
                                     std::string("parm ") + (k == 0 ? "u" : "v") + " has " + std::to_string(size) +
                                         " values; a bspline of degree " + std::to_string(degree) + " needs at least " +
                                         std::to_string(2 * degree + 2) + " (degree + 1 control points)");
            (k == 0 ? b.count_u : b.count_v) = static_cast<int>(size - degree - 1);
        }
        // the counts are bounded by the lines' lengths, so the product cannot overflow
        const std::size_t expected = static_cast<std::size_t>(b.count_u) * static_cast<std::size_t>(b.count_v);
        if (s.refs.size() != expected)
            return error_at_line(ErrorCode::ParseError, s.line,
                                 "surf has " + std::to_string(s.refs.size()) + " control points; the knot vectors (" +
                                     std::to_string(b.knots_u.size()) + " and " + std::to_string(b.knots_v.size()) +
                                     " values, degree " + std::to_string(b.degree_u) + "x" +
                                     std::to_string(b.degree_v) + ") make a net of " + std::to_string(b.count_u) +
                                     " x " + std::to_string(b.count_v) + " = " + std::to_string(expected));
        for (std::size_t ref : s.refs) {
            b.points.push_back(points_[ref]);
            if (s.rational) b.weights.push_back(weights_[ref]);
        }
        if (Status valid = validate(b); !valid) {
            const std::string& message = valid.error().message;
            for (int k = 0; k < 2; ++k)
                if (message.starts_with(k == 0 ? "knots_u" : "knots_v")) {
                    // "knots_u[5] (0.2) is smaller than knots_u[4] ..." -> "parm u[5] (0.2) is smaller than ..."
                    std::string what = message;
                    const std::string from = k == 0 ? "knots_u" : "knots_v", to = k == 0 ? "parm u" : "parm v";
                    for (std::size_t at = what.find(from); at != std::string::npos; at = what.find(from, at))
                        what.replace(at, from.size(), to);
                    return error_at_line(valid.error().code, s.parm_line[k], what + " (values counted from 0)");
                }
            return error_at_line(valid.error().code, s.line, "surf: " + message);
        }
        const auto [u0, u1] = domain_u(b);
        const auto [v0, v1] = domain_v(b);
        if (s.range[0] != u0 || s.range[1] != u1 || s.range[2] != v0 || s.range[3] != v1)
            return error_at_line(ErrorCode::Unsupported, s.line,
                                 "surf range differs from the knot vectors' domain (trimmed sub-ranges are not "
                                 "supported)");
        const std::size_t count = bezier_patch_count(b);
        if (!s.loops[0].empty() || !s.loops[1].empty()) return add_trimmed(std::move(b), s);
        if (out_.patches.patches.size() + trimmed_patches_ + count > options_.max_patches)
            return error_at_line(ErrorCode::BudgetExceeded, s.line,
                                 "more than max_patches (" + std::to_string(options_.max_patches) +
                                     ") patches: this bspline surface decomposes into " + std::to_string(count));
        // the decomposition multiplies the net by up to (du + 1)(dv + 1): its control points count as vertices
        const std::size_t points = count * static_cast<std::size_t>((b.degree_u + 1) * (b.degree_v + 1));
        if (points > options_.max_vertices || decomposed_points_ + points > options_.max_vertices)
            return error_at_line(ErrorCode::BudgetExceeded, s.line,
                                 "more than max_vertices (" + std::to_string(options_.max_vertices) +
                                     ") control points: this bspline surface's Bézier patches have " +
                                     std::to_string(points));
        decomposed_points_ += points;
        auto patches = to_bezier(b);
        if (!patches) return error_at_line(patches.error().code, s.line, "surf: " + patches.error().message);
        for (BezierPatch& patch : patches->patches) out_.patches.patches.push_back(std::move(patch));
        return std::nullopt;
    }

    enum class CsType { None, Bezier, RationalBezier };

    std::string_view text_;
    const ObjPatchReadOptions& options_;
    std::int64_t line_ = 0;
    std::vector<Vec3> points_;
    std::vector<double> weights_;
    CsType cstype_ = CsType::None;
    bool bspline_ = false;               // cstype [rat] bspline
    std::size_t decomposed_points_ = 0;  // control points of the bspline surfaces' Bézier patches so far
    int degree_u_ = 0, degree_v_ = 0;
    bool in_curve_ = false;  // inside a curv block (3D curves are not read)
    std::optional<PendingSurface> surface_;
    std::vector<Vec2> parameter_points_;  // vp u v (v NaN when not given)
    std::vector<double> parameter_weights_;
    std::optional<PendingCurve> curve2_;
    std::vector<TrimCurve> curves2_;  // the curv2 curves so far, as B-splines
    std::vector<std::int64_t> curve2_lines_;
    std::size_t trim_loops_ = 0;       // trim and hole statements so far
    std::size_t trim_segments_ = 0;    // chords of the validated loops so far
    std::size_t trimmed_patches_ = 0;  // Bézier patches of the trimmed surfaces so far
    ObjSurfaces out_;
};

}  // namespace

Result<ObjSurfaces> read_obj_surfaces(std::string_view text, const ObjPatchReadOptions& options) {
    return io_detail::with_text(text, [&](std::string_view decoded, io_detail::TextEncoding) {
        return ObjPatchReader(decoded, options).read();
    });
}

Result<PatchSet> read_obj_patches(std::string_view text, const ObjPatchReadOptions& options) {
    auto surfaces = read_obj_surfaces(text, options);
    if (!surfaces) return surfaces.error();
    if (!surfaces->trimmed.empty())
        return error_at_line(ErrorCode::Unsupported, surfaces->trimmed.front().line,
                             "surf has trim or hole statements: Bézier patches cannot carry trim loops");
    return std::move(surfaces->patches);
}

}  // namespace surfaced
