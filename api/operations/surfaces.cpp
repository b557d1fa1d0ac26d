// POST /surfaces (see surfaces.h). Order: the request's shape and the surface, then every query's arguments and the
// budgets, and only then any work. Decoding and encoding live together here because the response mirrors the
// request's members.
#include "api/operations/surfaces.h"

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "api/json_util.h"
#include "api/operations/json_request.h"
#include "api/operations/request_forms.h"
#include "api/surface_codec.h"
#include "geometry/surfaces/bspline_surface.h"
#include "geometry/surfaces/surface_search.h"

namespace surfaced::api::operations {
namespace {

using namespace json;  // the shared readers (api/json_util.h)

struct Domain {
    double u0, u1, v0, v1;
};

//! [[u, v], ...] in the domain: 400 for the shape, 422 naming the coordinate outside the domain.
ApiResult<std::vector<std::pair<double, double>>> read_parameters(const Json& value, const std::string& field,
                                                                  const Domain& d) {
    if (!value.is_array()) return invalid(field, field + " must be an array of [u, v]");
    std::vector<std::pair<double, double>> out;
    out.reserve(value.size());
    for (std::size_t i = 0; i < value.size(); ++i) {
        const std::string item = index_path(field, i);
        if (!value[i].is_array() || value[i].size() != 2) return invalid(item, item + " must be [u, v]");
        double uv[2];
        for (std::size_t c = 0; c < 2; ++c) {
            auto x = read_number(value[i][c], index_path(item, c));
            if (!x) return std::move(x.error());
            const double lo = c == 0 ? d.u0 : d.v0, hi = c == 0 ? d.u1 : d.v1;
            if (x.value() < lo || x.value() > hi)
                return json::geometry_error(ErrorCode::InvalidArgument, index_path(item, c),
                                            index_path(item, c) + " = " + format_double(x.value()) +
                                                " is outside the domain of " + (c == 0 ? "u" : "v") + " [" +
                                                format_double(lo) + ", " + format_double(hi) + "]");
            uv[c] = x.value();
        }
        out.emplace_back(uv[0], uv[1]);
    }
    return out;
}

ApiResult<SurfaceDirection> read_direction(const Json& object, const std::string& path) {
    const std::string field = path + ".direction";
    const auto it = object.find("direction");
    if (it == object.end() || !it->is_string() ||
        (it->get_ref<const std::string&>() != "u" && it->get_ref<const std::string&>() != "v"))
        return invalid(field, field + R"( is required: "u" or "v")");
    return it->get_ref<const std::string&>() == "u" ? SurfaceDirection::U : SurfaceDirection::V;
}

//! "times" in 1..most (400 outside: the documented range); what the surface allows is checked by the caller (422).
ApiResult<int> read_times(const Json& object, const std::string& path, int most) {
    const auto it = object.find("times");
    if (it == object.end()) return 1;
    auto k = read_integer(*it, path + ".times");
    if (!k) return std::move(k.error());
    if (k.value() < 1 || k.value() > most)
        return invalid(path + ".times", path + ".times must be in 1.." + std::to_string(most));
    return static_cast<int>(k.value());
}

//! What a request asks, read and checked in full before any work.
struct Queries {
    std::optional<std::vector<std::pair<double, double>>> evaluate, derivatives;
    std::optional<std::vector<Vec3>> closest;
    struct Insert {
        SurfaceDirection direction;
        double value;
        int times;
    };
    std::optional<Insert> insert;
    struct Elevate {
        SurfaceDirection direction;
        int times;
    };
    std::optional<Elevate> elevate;
    bool to_bezier = false, bounding_box = false;
};

std::optional<ApiError> read_queries(const Json& root, const BSplineSurface& s, const Domain& d, const Limits& limits,
                                     Queries& q) {
    for (const char* name : {"evaluate", "derivatives"})
        if (auto it = root.find(name); it != root.end()) {
            auto uvs = read_parameters(*it, name, d);
            if (!uvs) return std::move(uvs.error());
            (name[0] == 'e' ? q.evaluate : q.derivatives) = std::move(uvs.value());
        }
    const std::size_t parameters = (q.evaluate ? q.evaluate->size() : 0) + (q.derivatives ? q.derivatives->size() : 0);
    if (parameters > kMaxSurfaceQueries)
        return budget(std::to_string(parameters) + " parameters requested in evaluate and derivatives; the limit is " +
                          std::to_string(kMaxSurfaceQueries),
                      q.evaluate ? "evaluate" : "derivatives");
    if (auto it = root.find("closest"); it != root.end()) {
        if (!it->is_array()) return invalid("closest", "closest must be an array of [x, y, z]");
        if (it->size() > kMaxSurfaceClosest)
            return budget("closest has " + std::to_string(it->size()) + " points; the limit is " +
                              std::to_string(kMaxSurfaceClosest),
                          "closest");
        std::vector<Vec3> points;
        for (std::size_t i = 0; i < it->size(); ++i) {
            auto p = read_vec3((*it)[i], index_path("closest", i));
            if (!p) return std::move(p.error());
            points.push_back(p.value());
        }
        q.closest = std::move(points);
    }
    const std::uint64_t nu = static_cast<std::uint64_t>(s.count_u), nv = static_cast<std::uint64_t>(s.count_v);
    if (auto it = root.find("insert_knot"); it != root.end()) {
        if (!it->is_object() || !it->contains("value"))
            return invalid("insert_knot", R"(insert_knot must be {"direction": "u" | "v", "value": t, "times"?: k})");
        if (auto error = check_members(*it, "insert_knot", {"direction", "value", "times"})) return error;
        auto direction = read_direction(*it, "insert_knot");
        if (!direction) return std::move(direction.error());
        auto value = read_number((*it)["value"], "insert_knot.value");
        if (!value) return std::move(value.error());
        const bool along_u = direction.value() == SurfaceDirection::U;
        const double lo = along_u ? d.u0 : d.v0, hi = along_u ? d.u1 : d.v1;
        if (value.value() < lo || value.value() > hi)
            return json::geometry_error(ErrorCode::InvalidArgument, "insert_knot.value",
                                        "insert_knot.value = " + format_double(value.value()) +
                                            " is outside the domain [" + format_double(lo) + ", " + format_double(hi) +
                                            "]");
        auto times = read_times(*it, "insert_knot", kMaxBSplineSurfaceDegree);
        if (!times) return std::move(times.error());
        const std::uint64_t points = (along_u ? nu + static_cast<std::uint64_t>(times.value()) : nu) *
                                     (along_u ? nv : nv + static_cast<std::uint64_t>(times.value()));
        if (points > limits.max_input_vertices)
            return budget("the refined surface would have " + std::to_string(points) +
                              " control points; the limit is " + std::to_string(limits.max_input_vertices),
                          "insert_knot");
        q.insert = Queries::Insert{direction.value(), value.value(), times.value()};
    }
    if (auto it = root.find("elevate"); it != root.end()) {
        if (!it->is_object()) return invalid("elevate", R"(elevate must be {"direction": "u" | "v", "times"?: k})");
        if (auto error = check_members(*it, "elevate", {"direction", "times"})) return error;
        auto direction = read_direction(*it, "elevate");
        if (!direction) return std::move(direction.error());
        auto times = read_times(*it, "elevate", kMaxBSplineSurfaceDegree - 1);
        if (!times) return std::move(times.error());
        const bool along_u = direction.value() == SurfaceDirection::U;
        const int degree = along_u ? s.degree_u : s.degree_v;
        if (degree + times.value() > kMaxBSplineSurfaceDegree)
            return json::geometry_error(ErrorCode::InvalidArgument, "elevate.times",
                                        "elevating degree " + std::to_string(degree) + " by " +
                                            std::to_string(times.value()) + " would exceed the largest degree " +
                                            std::to_string(kMaxBSplineSurfaceDegree));
        // clamping adds at most 2 p points, each step one per distinct knot span (at most count + 1)
        const std::uint64_t n = along_u ? nu : nv, other = along_u ? nv : nu;
        const auto t = static_cast<std::uint64_t>(times.value());
        const std::uint64_t points = (n + 2 * static_cast<std::uint64_t>(degree) + t * (n + 2 * degree + 1)) * other;
        if (points > limits.max_input_vertices)
            return budget("the elevated surface could have up to " + std::to_string(points) +
                              " control points; the limit is " + std::to_string(limits.max_input_vertices),
                          "elevate");
        q.elevate = Queries::Elevate{direction.value(), times.value()};
    }
    auto to_bezier_asked = read_switch(root, "to_bezier");
    if (!to_bezier_asked) return std::move(to_bezier_asked.error());
    q.to_bezier = to_bezier_asked.value();
    auto box_asked = read_switch(root, "bounding_box");
    if (!box_asked) return std::move(box_asked.error());
    q.bounding_box = box_asked.value();
    if (q.to_bezier || q.bounding_box || q.closest) {
        const std::uint64_t patches = bezier_patch_count(s);
        const std::uint64_t points = patches * static_cast<std::uint64_t>((s.degree_u + 1) * (s.degree_v + 1));
        const char* field = q.to_bezier ? "to_bezier" : q.bounding_box ? "bounding_box" : "closest";
        if (patches > limits.max_patches)
            return budget("the surface decomposes into " + std::to_string(patches) + " Bézier patches; the limit is " +
                              std::to_string(limits.max_patches),
                          field);
        if (points > limits.max_input_vertices)
            return budget("the surface's Bézier patches would have " + std::to_string(points) +
                              " control points; the limit is " + std::to_string(limits.max_input_vertices),
                          field);
    }
    if (!q.evaluate && !q.derivatives && !q.closest && !q.insert && !q.elevate && !q.to_bezier && !q.bounding_box)
        return invalid("surface",
                       "no query: give at least one of evaluate, derivatives, closest, insert_knot, elevate, "
                       "to_bezier, bounding_box");
    return std::nullopt;
}

Json box_json(const Box3& box) { return {{"min", vec3_json(box.min)}, {"max", vec3_json(box.max)}}; }

ApiResponse run(const ApiRequest& request, const ApiContext& context) {
    const Limits& limits = context.limits;
    if (auto error = check_json_only_body(request, limits, "POST /surfaces")) return error_response(std::move(*error));
    Json root;
    if (auto error = json::parse(request.body, root)) return error_response(std::move(*error));
    if (!root.is_object()) return error_response(invalid("", "the body must be a JSON object"));
    if (auto error = check_members(
            root, "",
            {"surface", "evaluate", "derivatives", "closest", "insert_knot", "elevate", "to_bezier", "bounding_box"}))
        return error_response(std::move(*error));
    const auto surface_it = root.find("surface");
    if (surface_it == root.end())
        return error_response(invalid("surface", R"(surface is required: {"degree": [p, q], "knots_u": [...], )"
                                                 R"("knots_v": [...], "points": [[x, y, z], ...]})"));
    auto decoded = decode_surface(*surface_it, "surface", limits.max_input_vertices);
    if (!decoded) return error_response(std::move(decoded.error()));
    const BSplineSurface& s = decoded.value();
    const auto [u0, u1] = domain_u(s);
    const auto [v0, v1] = domain_v(s);
    Queries q;
    if (auto error = read_queries(root, s, Domain{u0, u1, v0, v1}, limits, q)) return error_response(std::move(*error));

    Json out = {{"degree", Json::array({s.degree_u, s.degree_v})},
                {"rational", s.rational()},
                {"domain", {{"u", Json::array({u0, u1})}, {"v", Json::array({v0, v1})}}}};
    if (q.evaluate) {
        Json answers = Json::array();
        for (const auto& [u, v] : *q.evaluate) {
            const PatchDerivatives d = *evaluate_derivatives(s, u, v);
            answers.push_back({{"position", vec3_json(d.position)},
                               {"du", vec3_json(d.du)},
                               {"dv", vec3_json(d.dv)},
                               {"normal", vec3_json(*unit_normal(s, u, v))}});
        }
        out["evaluate"] = std::move(answers);
    }
    if (q.derivatives) {
        Json answers = Json::array();
        for (const auto& [u, v] : *q.derivatives) {
            const PatchDerivatives d = *evaluate_derivatives(s, u, v);
            answers.push_back({{"position", vec3_json(d.position)},
                               {"du", vec3_json(d.du)},
                               {"dv", vec3_json(d.dv)},
                               {"duu", vec3_json(d.duu)},
                               {"duv", vec3_json(d.duv)},
                               {"dvv", vec3_json(d.dvv)}});
        }
        out["derivatives"] = std::move(answers);
    }
    std::optional<SurfaceBezierPatches> patches;
    if (q.closest || q.to_bezier || q.bounding_box) {
        auto decomposed = to_bezier(s, context.cancel);
        if (!decomposed) return error_response(error_at(decomposed.error(), "surface"));
        patches = std::move(decomposed.value());
    }
    if (q.closest) {
        SurfaceSearchOptions options;
        options.cancel = context.cancel;
        Json answers = Json::array();
        for (std::size_t i = 0; i < q.closest->size(); ++i) {
            auto c = closest_point(*patches, (*q.closest)[i], options);
            if (!c) return error_response(error_at(c.error(), index_path("closest", i)));
            answers.push_back({{"uv", Json::array({c->u, c->v})},
                               {"point", vec3_json(c->point)},
                               {"distance", c->distance},
                               {"converged", c->converged},
                               {"gap", c->gap}});
        }
        out["closest"] = std::move(answers);
    }
    if (q.insert) {
        auto inserted = insert_knot(s, q.insert->direction, q.insert->value, q.insert->times);
        if (!inserted) return error_response(error_at(inserted.error(), "insert_knot.times"));
        out["insert_knot"] = surface_json(*inserted);
    }
    if (q.elevate) {
        auto elevated = elevate_degree(s, q.elevate->direction, q.elevate->times);
        if (!elevated) return error_response(error_at(elevated.error(), "elevate.times"));
        out["elevate"] = surface_json(*elevated);
    }
    if (q.to_bezier) {
        Json list = Json::array();
        for (const BezierPatch& patch : patches->patches) list.push_back(patch_json(patch));
        out["to_bezier"] = {
            {"patches", std::move(list)}, {"breaks_u", patches->breaks_u}, {"breaks_v", patches->breaks_v}};
    }
    if (q.bounding_box) {
        auto tight = tight_bounding_box(*patches, SurfaceSearchOptions{.cancel = context.cancel});
        if (!tight) return error_response(error_at(tight.error(), "bounding_box"));
        out["bounding_box"] = {{"control_hull", box_json(control_hull_box(s))}, {"tight", box_json(*tight)}};
    }
    return json_response(out);
}

}  // namespace

ApiResponse surfaces(const ApiRequest& request, const ApiContext& context) noexcept {
    return guarded([&] { return run(request, context); });
}

}  // namespace surfaced::api::operations
