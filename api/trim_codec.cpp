#include "api/trim_codec.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>
#include <vector>

#include "api/json_util.h"
#include "geometry/curves/bspline.h"

namespace surfaced::api {
namespace {

using namespace json;

std::string at(const std::string& path, std::size_t i) { return path + "[" + std::to_string(i) + "]"; }

ApiResult<TrimCurve> decode_curve(const Json& value, const std::string& path) {
    if (!value.is_object())
        return invalid(path, path + R"( must be an object {"degree": d, "points": [[u, v], ...], "knots"?: [...], )"
                                    R"("weights"?: [...]})");
    if (auto error = check_members(value, path, {"degree", "points", "knots", "weights"})) return std::move(*error);
    TrimCurve curve;
    const std::string degree_path = path + ".degree";
    const auto degree = value.find("degree");
    if (degree == value.end())
        return invalid(degree_path,
                       degree_path + " is required: an integer in 1.." + std::to_string(kMaxTrimCurveDegree));
    auto d = read_integer(*degree, degree_path);
    if (!d) return std::move(d.error());
    if (d.value() < 1 || d.value() > kMaxTrimCurveDegree)
        return invalid(degree_path, degree_path + " must be in 1.." + std::to_string(kMaxTrimCurveDegree) + ", got " +
                                        std::to_string(d.value()));
    curve.degree = static_cast<int>(d.value());
    const std::string points_path = path + ".points";
    const auto points = value.find("points");
    if (points == value.end() || !points->is_array())
        return invalid(points_path, points_path + " is required: an array of [u, v] parameter points");
    const std::size_t n = points->size(), least = static_cast<std::size_t>(curve.degree) + 1;
    if (n < least)
        return invalid(points_path, points_path + " has " + std::to_string(n) + " points; degree " +
                                        std::to_string(curve.degree) + " needs at least " + std::to_string(least));
    curve.points.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        const Json& p = (*points)[i];
        const std::string point_path = at(points_path, i);
        if (!p.is_array() || p.size() != 2) return invalid(point_path, point_path + " must be [u, v]");
        auto u = read_number(p[0], at(point_path, 0));
        if (!u) return std::move(u.error());
        auto v = read_number(p[1], at(point_path, 1));
        if (!v) return std::move(v.error());
        curve.points.push_back({u.value(), v.value()});
    }
    if (const auto weights = value.find("weights"); weights != value.end()) {
        const std::string weights_path = path + ".weights";
        if (!weights->is_array() || weights->size() != n)
            return invalid(weights_path,
                           weights_path + " must be an array of " + std::to_string(n) + " weights > 0, one per point");
        curve.weights.reserve(n);
        for (std::size_t i = 0; i < n; ++i) {
            auto w = read_number((*weights)[i], at(weights_path, i));
            if (!w) return std::move(w.error());
            if (!(w.value() > 0)) return invalid(at(weights_path, i), at(weights_path, i) + " must be > 0");
            curve.weights.push_back(w.value());
        }
    }
    const std::string knots_path = path + ".knots";
    if (const auto knots = value.find("knots"); knots != value.end()) {
        const std::size_t expected = n + static_cast<std::size_t>(curve.degree) + 1;
        if (!knots->is_array() || knots->size() != expected)
            return invalid(knots_path, knots_path + " must be an array of points + degree + 1 = " +
                                           std::to_string(expected) + " non-decreasing numbers");
        curve.knots.reserve(expected);
        for (std::size_t i = 0; i < expected; ++i) {
            auto t = read_number((*knots)[i], at(knots_path, i));
            if (!t) return std::move(t.error());
            curve.knots.push_back(t.value());
        }
    } else {
        auto clamped = clamped_uniform_knots(n, curve.degree);
        if (!clamped) return invalid(knots_path, knots_path + ": " + clamped.error().message);
        curve.knots = std::move(clamped.value());
    }
    return curve;
}

ApiResult<TrimLoop> decode_loop(const Json& value, const std::string& path) {
    if (!value.is_array() || value.empty())
        return invalid(path, path + " must be a non-empty array of curves, each ending where the next starts");
    TrimLoop loop;
    loop.curves.reserve(value.size());
    for (std::size_t j = 0; j < value.size(); ++j) {
        auto curve = decode_curve(value[j], at(path, j));
        if (!curve) return std::move(curve.error());
        loop.curves.push_back(std::move(curve.value()));
    }
    return loop;
}

//! Reads "outer[i]" or "holes[i]" optionally followed by "[j]" at text[pos]: true and the end, loop and curve.
bool read_path(const std::string& text, std::size_t pos, std::size_t& end, int& loop, int& curve) {
    auto index = [&](std::size_t& i, int& out) {
        if (i >= text.size() || text[i] != '[') return false;
        std::size_t k = i + 1;
        long long value = 0;
        while (k < text.size() && std::isdigit(static_cast<unsigned char>(text[k])) && value < 1'000'000'000)
            value = value * 10 + (text[k++] - '0');
        if (k == i + 1 || k >= text.size() || text[k] != ']') return false;
        out = static_cast<int>(value);
        i = k + 1;
        return true;
    };
    std::size_t i = pos + 5;  // after "outer" or "holes"
    if (!index(i, loop)) return false;
    curve = -1;
    std::size_t j = i;
    if (index(j, curve)) i = j;
    end = i;
    return true;
}

}  // namespace

std::optional<ApiError> check_trim_budgets(const Json& surfaces) {
    std::size_t loops = 0, curves = 0, points = 0;
    std::string where = "surfaces";
    const auto count_loop = [&](const Json& loop) {
        ++loops;
        if (!loop.is_array()) return;
        curves += loop.size();
        for (const Json& curve : loop)
            if (curve.is_object())
                if (const auto p = curve.find("points"); p != curve.end() && p->is_array()) points += p->size();
    };
    for (std::size_t i = 0; i < surfaces.size(); ++i) {
        const Json& surface = surfaces[i];
        if (!surface.is_object()) continue;
        const auto trim = surface.find("trim");
        if (trim == surface.end() || !trim->is_object()) continue;
        if (const auto outer = trim->find("outer"); outer != trim->end()) count_loop(*outer);
        if (const auto holes = trim->find("holes"); holes != trim->end() && holes->is_array())
            for (const Json& hole : *holes) count_loop(hole);
        if (loops > kMaxTrimLoops || curves > kMaxTrimCurves || points > kMaxTrimPoints) {
            where = at("surfaces", i) + ".trim";
            break;
        }
    }
    const auto over = [&](const char* what, std::size_t count, std::size_t limit) {
        return make_problem(
            Problem::BudgetExceeded,
            "the trims have " + std::to_string(count) + " " + what + " or more; the limit is " + std::to_string(limit),
            where);
    };
    if (loops > kMaxTrimLoops) return over("loops", loops, kMaxTrimLoops);
    if (curves > kMaxTrimCurves) return over("curves", curves, kMaxTrimCurves);
    if (points > kMaxTrimPoints) return over("control points", points, kMaxTrimPoints);
    return std::nullopt;
}

ApiResult<SurfaceTrim> decode_trim(const Json& value, const std::string& path) {
    if (!value.is_object())
        return invalid(path, path + R"( must be an object {"outer"?: [curve, ...], "holes"?: [[curve, ...], ...]})");
    if (auto error = check_members(value, path, {"outer", "holes"})) return std::move(*error);
    SurfaceTrim trim;
    if (const auto outer = value.find("outer"); outer != value.end()) {
        auto loop = decode_loop(*outer, path + ".outer");
        if (!loop) return std::move(loop.error());
        trim.outer.push_back(std::move(loop.value()));
    }
    if (const auto holes = value.find("holes"); holes != value.end()) {
        const std::string holes_path = path + ".holes";
        if (!holes->is_array()) return invalid(holes_path, holes_path + " must be an array of loops");
        trim.holes.reserve(holes->size());
        for (std::size_t i = 0; i < holes->size(); ++i) {
            auto loop = decode_loop((*holes)[i], at(holes_path, i));
            if (!loop) return std::move(loop.error());
            trim.holes.push_back(std::move(loop.value()));
        }
    }
    return trim;
}

std::string trim_field(const std::string& trim_path, TrimLoopKind kind, int loop, int curve) {
    std::string field = trim_path + (kind == TrimLoopKind::Outer ? ".outer" : ".holes[" + std::to_string(loop) + "]");
    if (curve >= 0) field += "[" + std::to_string(curve) + "]";
    return field;
}

ApiError trim_error(const TrimError& error, const std::string& trim_path) {
    // every "outer[i][j]" / "holes[i][j]" of the message (trim_loops.h's paths) becomes its JSON path
    const std::string& text = error.message;
    std::string detail;
    std::size_t pos = 0;
    while (pos < text.size()) {
        const std::size_t outer = text.find("outer[", pos), holes = text.find("holes[", pos);
        const std::size_t next = std::min(outer, holes);
        if (next == std::string::npos) break;
        detail.append(text, pos, next - pos);
        std::size_t end = 0;
        int loop = 0, curve = -1;
        if (read_path(text, next, end, loop, curve)) {
            detail += trim_field(trim_path, next == outer ? TrimLoopKind::Outer : TrimLoopKind::Hole, loop, curve);
            pos = end;
        } else {
            detail.append(text, next, 6);
            pos = next + 6;
        }
    }
    detail.append(text, pos, std::string::npos);
    return geometry_error(to_geo_error(error).code, trim_field(trim_path, error.loop_kind, error.loop, error.curve),
                          std::move(detail));
}

}  // namespace surfaced::api
