#include "api/surface_codec.h"

#include <cmath>
#include <string>
#include <vector>

#include "api/limits.h"

namespace surfaced::api {
namespace {

using namespace json;

std::string at(const std::string& path, std::size_t i) { return path + "[" + std::to_string(i) + "]"; }

ApiError rule(const std::string& field, std::string detail) {
    return geometry_error(ErrorCode::InvalidArgument, field, std::move(detail));
}

ApiResult<std::vector<double>> read_knots(const Json& value, const std::string& field) {
    if (!value.is_array()) return invalid(field, field + " must be an array of non-decreasing numbers");
    std::vector<double> out;
    out.reserve(value.size());
    for (std::size_t i = 0; i < value.size(); ++i) {
        auto t = read_number(value[i], at(field, i));
        if (!t) return std::move(t.error());
        out.push_back(t.value());
    }
    return out;
}

}  // namespace

ApiResult<BSplineSurface> decode_surface(const Json& value, const std::string& path, std::uint64_t max_points,
                                         bool allow_trim) {
    if (!value.is_object())
        return invalid(path, path + R"( must be an object {"degree": [p, q], "knots_u": [...], "knots_v": [...], )"
                                    R"("points": [[x, y, z], ...], "weights"?: [...]})");
    if (auto error = allow_trim
                         ? check_members(value, path, {"degree", "knots_u", "knots_v", "points", "weights", "trim"})
                         : check_members(value, path, {"degree", "knots_u", "knots_v", "points", "weights"}))
        return std::move(*error);
    BSplineSurface s;
    const std::string degree_path = path + ".degree";
    const auto degree = value.find("degree");
    if (degree == value.end() || !degree->is_array() || degree->size() != 2)
        return invalid(degree_path, degree_path + " is required: [p, q], the degrees in u and v");
    int* targets[2] = {&s.degree_u, &s.degree_v};
    for (std::size_t k = 0; k < 2; ++k) {
        auto d = read_integer((*degree)[k], at(degree_path, k));
        if (!d) return std::move(d.error());
        if (d.value() < 1 || d.value() > kMaxBSplineSurfaceDegree)
            return rule(at(degree_path, k), at(degree_path, k) + " must be between 1 and " +
                                                std::to_string(kMaxBSplineSurfaceDegree) + ", got " +
                                                std::to_string(d.value()));
        *targets[k] = static_cast<int>(d.value());
    }
    for (const char* name : {"knots_u", "knots_v"}) {
        const std::string field = path + "." + name;
        const auto it = value.find(name);
        if (it == value.end())
            return invalid(field, field + " is required: the knot vector, count + degree + 1 non-decreasing numbers");
        const bool along_u = name[6] == 'u';
        const int p = along_u ? s.degree_u : s.degree_v;
        const std::size_t least = 2 * static_cast<std::size_t>(p) + 2;
        if (it->is_array() && it->size() < least)
            return rule(field, field + " has " + std::to_string(it->size()) + " values; degree " + std::to_string(p) +
                                   " needs at least " + std::to_string(least) + " (degree + 1 control points)");
        // the net's size follows from the knots: check it against the budget before reading anything large
        if (it->is_array() && it->size() - static_cast<std::size_t>(p) - 1 > max_points)
            return make_problem(
                Problem::BudgetExceeded,
                field + " makes a net of more than " + std::to_string(max_points) + " control points (the limit)",
                field);
        auto knots = read_knots(*it, field);
        if (!knots) return std::move(knots.error());
        (along_u ? s.knots_u : s.knots_v) = std::move(knots.value());
        (along_u ? s.count_u : s.count_v) = static_cast<int>(it->size()) - p - 1;
    }
    const std::uint64_t expected = static_cast<std::uint64_t>(s.count_u) * static_cast<std::uint64_t>(s.count_v);
    const std::string points_path = path + ".points";
    if (expected > max_points)
        return make_problem(Problem::BudgetExceeded,
                            points_path + ": the knot vectors make a net of " + std::to_string(s.count_u) + " x " +
                                std::to_string(s.count_v) + " = " + std::to_string(expected) +
                                " control points; the limit is " + std::to_string(max_points),
                            points_path);
    const auto points = value.find("points");
    if (points == value.end() || !points->is_array())
        return invalid(points_path, points_path + " is required: an array of [x, y, z], u varying fastest");
    if (points->size() != expected)
        return rule(points_path, points_path + " has " + std::to_string(points->size()) +
                                     " points; the knot vectors (" + std::to_string(s.knots_u.size()) + " and " +
                                     std::to_string(s.knots_v.size()) + " values, degrees " +
                                     std::to_string(s.degree_u) + " and " + std::to_string(s.degree_v) +
                                     ") make a net of " + std::to_string(s.count_u) + " x " +
                                     std::to_string(s.count_v) + " = " + std::to_string(expected));
    s.points.reserve(expected);
    for (std::size_t i = 0; i < points->size(); ++i) {
        auto p = read_vec3((*points)[i], at(points_path, i));
        if (!p) return std::move(p.error());
        s.points.push_back(p.value());
    }
    if (auto weights = value.find("weights"); weights != value.end()) {
        const std::string weights_path = path + ".weights";
        if (!weights->is_array() || weights->size() != expected)
            return invalid(weights_path, weights_path + " must be an array of " + std::to_string(expected) +
                                             " weights > 0, one per control point");
        s.weights.reserve(expected);
        for (std::size_t i = 0; i < expected; ++i) {
            auto w = read_number((*weights)[i], at(weights_path, i));
            if (!w) return std::move(w.error());
            if (!(w.value() > 0)) return rule(at(weights_path, i), at(weights_path, i) + " must be > 0");
            s.weights.push_back(w.value());
        }
    }
    if (Status ok = validate(s); !ok) {
        const GeoError& e = ok.error();
        std::string field = path;
        if (e.element >= 0 && e.element_kind == ElementKind::Vertex)
            field = at(path + (s.rational() && e.message.find("weight") != std::string::npos ? ".weights" : ".points"),
                       static_cast<std::size_t>(e.element));
        else if (e.message.starts_with("knots_u") || e.message.starts_with("knots_v"))
            field = e.element >= 0 ? at(path + "." + e.message.substr(0, 7), static_cast<std::size_t>(e.element))
                                   : path + "." + e.message.substr(0, 7);
        return geometry_error(e.code, field, path + ": " + e.message);
    }
    return s;
}

Json surface_json(const BSplineSurface& s) {
    Json points = Json::array();
    for (const Vec3& p : s.points) points.push_back(vec3_json(p));
    Json out = {{"degree", Json::array({s.degree_u, s.degree_v})},
                {"knots_u", s.knots_u},
                {"knots_v", s.knots_v},
                {"points", std::move(points)}};
    if (s.rational()) out["weights"] = s.weights;
    return out;
}

Json patch_json(const BezierPatch& patch) {
    Json points = Json::array();
    for (const Vec3& p : patch.points) points.push_back(vec3_json(p));
    Json out = {{"degree", Json::array({patch.degree_u, patch.degree_v})}, {"points", std::move(points)}};
    if (patch.rational()) out["weights"] = patch.weights;
    return out;
}

}  // namespace surfaced::api
