#include "api/patch_codec.h"

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "api/json_util.h"
#include "api/surface_codec.h"
#include "geometry/io/number_text.h"

namespace surfaced::api {
namespace {

using namespace json;  // the shared readers (api/json_util.h)

std::string at(const std::string& path, std::size_t i) { return path + "[" + std::to_string(i) + "]"; }

ApiResult<BezierPatch> decode_patch(const Json& value, const std::string& path) {
    if (!value.is_object())
        return invalid(path, path + R"( must be an object {"degree": [m, n], "points": [[x, y, z], ...]})");
    if (auto error = check_members(value, path, {"degree", "points", "weights"})) return std::move(*error);
    BezierPatch patch;
    const std::string degree_path = path + ".degree";
    const auto degree = value.find("degree");
    if (degree == value.end() || !degree->is_array() || degree->size() != 2)
        return invalid(degree_path, degree_path + " is required: [m, n], the degrees in u and v");
    int* targets[2] = {&patch.degree_u, &patch.degree_v};
    for (std::size_t k = 0; k < 2; ++k) {
        auto d = read_integer((*degree)[k], at(degree_path, k));
        if (!d) return std::move(d.error());
        if (d.value() < 1 || d.value() > kMaxPatchDegree)
            return invalid(at(degree_path, k), at(degree_path, k) + " must be between 1 and " +
                                                   std::to_string(kMaxPatchDegree) + ", got " +
                                                   std::to_string(d.value()));
        *targets[k] = static_cast<int>(d.value());
    }
    const std::string points_path = path + ".points";
    const auto points = value.find("points");
    if (points == value.end() || !points->is_array())
        return invalid(points_path, points_path + " is required: an array of [x, y, z], u varying fastest");
    const auto expected = static_cast<std::size_t>((patch.degree_u + 1) * (patch.degree_v + 1));
    if (points->size() != expected)
        return invalid(points_path, points_path + " has " + std::to_string(points->size()) + " points; degree [" +
                                        std::to_string(patch.degree_u) + ", " + std::to_string(patch.degree_v) +
                                        "] needs " + std::to_string(expected));
    patch.points.reserve(expected);
    for (std::size_t i = 0; i < expected; ++i) {
        const Json& p = (*points)[i];
        const std::string point_path = at(points_path, i);
        if (!p.is_array() || p.size() != 3) return invalid(point_path, point_path + " must be [x, y, z]");
        Vec3 q;
        for (std::size_t c = 0; c < 3; ++c) {
            if (!p[c].is_number()) return invalid(at(point_path, c), at(point_path, c) + " must be a finite number");
            q[static_cast<int>(c)] = p[c].get<double>();
            if (!std::isfinite(q[static_cast<int>(c)])) {
                ApiError error = from_geo_error(make_error(ErrorCode::NonFinite, at(point_path, c) + " is not finite"));
                error.field = at(point_path, c);
                return error;
            }
        }
        patch.points.push_back(q);
    }
    if (auto weights = value.find("weights"); weights != value.end()) {
        const std::string weights_path = path + ".weights";
        if (!weights->is_array() || weights->size() != expected)
            return invalid(weights_path, weights_path + " must be an array of " + std::to_string(expected) +
                                             " weights > 0, one per control point");
        patch.weights.reserve(expected);
        for (std::size_t i = 0; i < expected; ++i) {
            const Json& w = (*weights)[i];
            if (!w.is_number() || !std::isfinite(w.get<double>()) || !(w.get<double>() > 0))
                return invalid(at(weights_path, i), at(weights_path, i) + " must be a finite number > 0");
            patch.weights.push_back(w.get<double>());
        }
    }
    return patch;
}

}  // namespace

ApiResult<TessellateJsonRequest> decode_tessellate_request(std::string_view body, const Limits& limits) {
    Json root;
    if (auto error = parse(body, root)) return std::move(*error);
    if (!root.is_object())
        return invalid(
            "", R"(the body must be an object {"patches": [...], "tolerance": t | "segments": n, "output": {...}})");
    const auto& spec = *options::operation_options("tessellate");
    if (auto error = check_members(root, "", options::json_members(spec))) return std::move(*error);
    auto values = options::read_json(spec, root);
    if (!values) return std::move(values.error());

    TessellateJsonRequest request;
    request.params = tessellate_params(values.value());
    const auto patches = root.find("patches");
    const auto surfaces = root.find("surfaces");
    const bool have_patches = patches != root.end(), have_surfaces = surfaces != root.end();
    if (!have_patches && !have_surfaces)
        return invalid("patches", R"(patches or surfaces is required: a non-empty array of {"degree": [m, n], )"
                                  R"("points": [...]} or of {"degree": [p, q], "knots_u": [...], "knots_v": [...], )"
                                  R"("points": [...]})");
    if (have_patches && (!patches->is_array() || (patches->empty() && !have_surfaces)))
        return invalid("patches", R"(patches must be a non-empty array of {"degree": [m, n], "points": [...]})");
    if (have_surfaces && (!surfaces->is_array() || (surfaces->empty() && !have_patches)))
        return invalid("surfaces", R"(surfaces must be a non-empty array of {"degree": [p, q], "knots_u": [...], )"
                                   R"("knots_v": [...], "points": [...]})");
    // Budgets first: nothing is copied out of the document for a request we would refuse anyway.
    const std::size_t patch_count = have_patches ? patches->size() : 0;
    const std::size_t surface_count = have_surfaces ? surfaces->size() : 0;
    if (patch_count + surface_count > limits.max_patches)
        return make_problem(
            Problem::BudgetExceeded,
            (have_patches ? "patches has " + std::to_string(patch_count) + " patches" : std::string()) +
                (have_patches && have_surfaces ? " and " : "") +
                (have_surfaces ? "surfaces has " + std::to_string(surface_count) + " surfaces" : std::string()) +
                "; the limit is " + std::to_string(limits.max_patches),
            have_patches ? "patches" : "surfaces");
    std::uint64_t total_points = 0;
    for (const auto* list : {have_patches ? &*patches : nullptr, have_surfaces ? &*surfaces : nullptr})
        if (list)
            for (const Json& item : *list)
                if (item.is_object())
                    if (auto points = item.find("points"); points != item.end() && points->is_array())
                        total_points += points->size();
    if (total_points > limits.max_input_vertices)
        return make_problem(Problem::BudgetExceeded,
                            std::string(have_patches && have_surfaces ? "the patches and surfaces"
                                        : have_patches                ? "the patches"
                                                                      : "the surfaces") +
                                " have " + std::to_string(total_points) + " control points; the limit is " +
                                std::to_string(limits.max_input_vertices),
                            have_patches ? "patches" : "surfaces");
    request.patches.patches.reserve(patch_count);
    for (std::size_t i = 0; i < patch_count; ++i) {
        auto patch = decode_patch((*patches)[i], at("patches", i));
        if (!patch) return std::move(patch.error());
        request.patches.patches.push_back(std::move(patch.value()));
    }
    if (have_surfaces)
        if (auto error = check_trim_budgets(*surfaces)) return std::move(*error);
    request.surfaces.reserve(surface_count);
    request.trims.reserve(surface_count);
    for (std::size_t i = 0; i < surface_count; ++i) {
        const std::string path = at("surfaces", i);
        auto surface = decode_surface((*surfaces)[i], path, limits.max_input_vertices, /*allow_trim=*/true);
        if (!surface) return std::move(surface.error());
        request.surfaces.push_back(std::move(surface.value()));
        std::optional<SurfaceTrim> trim;
        if (const auto it = (*surfaces)[i].find("trim"); it != (*surfaces)[i].end()) {
            auto decoded = decode_trim(*it, path + ".trim");
            if (!decoded) return std::move(decoded.error());
            trim = std::move(decoded.value());
        }
        request.trims.push_back(std::move(trim));
    }

    return request;
}

TessellateParams tessellate_params(const options::OptionValues& values) {
    TessellateParams params;
    values.get("tolerance", params.tolerance);
    values.get("segments", params.segments);
    values.get_output(params.output);
    std::string format;
    values.get("format", format);
    params.patches_format = format == "patches";
    return params;
}

//! {"patches":[{"degree":[m,n],"points":[[x,y,z],...]},...]}: the JSON form of POST /tessellate's body.
std::string patch_set_json(const PatchSet& set) {
    std::string out = "{\"patches\":[";
    for (std::size_t p = 0; p < set.patches.size(); ++p) {
        const BezierPatch& patch = set.patches[p];
        out += (p ? ",{\"degree\":[" : "{\"degree\":[") + std::to_string(patch.degree_u) + "," +
               std::to_string(patch.degree_v) + "],\"points\":[";
        for (std::size_t i = 0; i < patch.points.size(); ++i) {
            const Vec3& q = patch.points[i];
            out += (i ? ",[" : "[") + number_text(q.x) + "," + number_text(q.y) + "," + number_text(q.z) + "]";
        }
        out += "]";
        if (patch.rational()) {
            out += ",\"weights\":[";
            for (std::size_t i = 0; i < patch.weights.size(); ++i)
                out += (i ? "," : "") + number_text(patch.weights[i]);
            out += "]";
        }
        out += "}";
    }
    return out + "]}";
}

}  // namespace surfaced::api
