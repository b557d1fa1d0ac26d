// OBJ free-form Bézier and B-spline surfaces (see obj_patches.h for what is read and what is refused).
#include "geometry/io/obj_patches.h"

#include <cmath>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include "geometry/io/text_encoding.h"
#include "geometry/io/text_scanner.h"
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
};

class ObjPatchReader {
public:
    ObjPatchReader(std::string_view text, const ObjPatchReadOptions& options) : text_(text), options_(options) {}

    Result<PatchSet> read() {
        auto start = io_detail::check_text_encoding(text_);
        if (!start) return start.error();
        io_detail::LineReader lines(text_, *start, /*continuations=*/true);
        std::string_view line;
        while (lines.next(line)) {
            line_ = lines.line_number();
            if (auto error = parse_line(line)) return std::move(*error);
        }
        if (surface_) return error_at_line(ErrorCode::ParseError, surface_->line, "surf has no matching end");
        if (set_.patches.empty())
            return error_at_line(ErrorCode::ParseError, std::max<std::int64_t>(line_, 1),
                                 "no free-form surfaces (cstype bezier or bspline, deg, surf ... end) in the file");
        return std::move(set_);
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
        if (keyword == "cstype") return parse_cstype(tokens);
        if (keyword == "deg") return parse_degree(tokens);
        if (keyword == "surf") return parse_surf(tokens);
        if (keyword == "parm") return parse_parm(tokens);
        if (keyword == "end") return parse_end();
        if (keyword == "curv" || keyword == "curv2") {
            if (surface_ || in_curve_)
                return error(ErrorCode::ParseError, std::string(keyword) + " inside an open block (missing end)");
            in_curve_ = true;
            return std::nullopt;
        }
        if (keyword == "trim" || keyword == "hole" || keyword == "scrv" || keyword == "sp")
            return error(ErrorCode::Unsupported,
                         std::string(keyword) + ": trimming curves and special points are not supported");
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
        if (points_.size() >= options_.max_vertices)
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
        if (in_curve_) return std::nullopt;  // curves are not read
        if (!surface_) return error(ErrorCode::ParseError, "parm outside a surf ... end block");
        std::vector<double> values;
        double x = 0;
        std::string_view probe;
        while (true) {
            Tokens rest = tokens;
            if (!rest.next(probe)) break;
            if (auto e = number(tokens, "parm value", x)) return e;
            if (!values.empty() && !(x > values.back()) && !(surface_->bspline && x == values.back()))
                return error(ErrorCode::ParseError, "parm " + std::string(direction) + " values must " +
                                                        (surface_->bspline ? "not decrease" : "increase"));
            values.push_back(x);
        }
        if (values.size() < 2)
            return error(ErrorCode::ParseError, "parm " + std::string(direction) + " needs at least two values");
        (direction == "u" ? surface_->parm_u : surface_->parm_v) = std::move(values);
        surface_->parm_line[direction == "u" ? 0 : 1] = line_;
        return std::nullopt;
    }

    std::optional<GeoError> parse_end() {
        if (in_curve_) {
            in_curve_ = false;
            return std::nullopt;
        }
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
        // ku, kv are bounded by the line's length, so these products cannot overflow
        if (s.refs.size() != nu * nv)
            return error_at_line(ErrorCode::ParseError, s.line,
                                 "surf has " + std::to_string(s.refs.size()) + " control points; degree " +
                                     std::to_string(du) + "x" + std::to_string(dv) + " with " + std::to_string(ku) +
                                     "x" + std::to_string(kv) + " segments needs (" + std::to_string(ku) + "*" +
                                     std::to_string(du) + "+1) x (" + std::to_string(kv) + "*" + std::to_string(dv) +
                                     "+1) = " + std::to_string(nu * nv));
        if (set_.patches.size() + ku * kv > options_.max_patches)
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
                set_.patches.push_back(std::move(patch));
            }
        return std::nullopt;
    }

    //! A B-spline surface: its knot vectors are the parm statements; decomposed into Bézier patches.
    std::optional<GeoError> end_bspline(const PendingSurface& s) {
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
        if (set_.patches.size() + count > options_.max_patches)
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
        for (BezierPatch& patch : patches->patches) set_.patches.push_back(std::move(patch));
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
    bool in_curve_ = false;
    std::optional<PendingSurface> surface_;
    PatchSet set_;
};

}  // namespace

Result<PatchSet> read_obj_patches(std::string_view text, const ObjPatchReadOptions& options) {
    return io_detail::with_text(text, [&](std::string_view decoded, io_detail::TextEncoding) {
        return ObjPatchReader(decoded, options).read();
    });
}

}  // namespace surfaced
