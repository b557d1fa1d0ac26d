// POST /pointcloud (see pointcloud.h): decode (file, JSON points or a sampling request), check budgets, sample /
// estimate normals, encode (GLB POINTS, PLY, JSON).
#include "api/operations/pointcloud.h"

#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "api/json_codec.h"
#include "api/json_util.h"
#include "api/operations/point_input.h"
#include "api/operations/request_forms.h"
#include "api/options/option_reader.h"
#include "geometry/io/gltf.h"
#include "api/scene_codec.h"
#include "geometry/io/pointcloud_glb.h"
#include "geometry/io/pointcloud_io.h"
#include "geometry/pointcloud/normals.h"
#include "geometry/pointcloud/sampling.h"

namespace surfaced::api::operations {
namespace {

using namespace json;  // the shared readers (api/json_util.h)

constexpr std::int64_t kDefaultK = 16;  // the table's default for k

struct Params {
    std::optional<std::int64_t> k;  //!< set: estimate normals with k neighbours
    OutputOptions output;
};

const options::OperationOptions& pointcloud_options() { return *options::operation_options("pointcloud"); }

//! The output options that do not fit the format (the formats themselves are the table's: glb, gltf, ply, json;
//! every one of them holds normals).
std::optional<ApiError> check_output(const OutputOptions& out, Source source) {
    return check_output_options(out, source);
}

//! "sample": {"mesh" | "scene" + "bounds", "count", "seed"}: budgets first, then the sampling.
ApiResult<PointCloud> run_sampling(const Json& sample, const ApiContext& context) {
    const Limits& limits = context.limits;
    if (!sample.is_object())
        return invalid("sample", R"(sample must be an object {"mesh" or "scene", "bounds", "count", "seed"})");
    if (auto error = check_members(sample, "sample", {"mesh", "scene", "bounds", "count", "seed"}))
        return std::move(*error);
    const bool has_mesh = sample.contains("mesh"), has_scene = sample.contains("scene");
    if (has_mesh == has_scene) return invalid("sample", "sample needs exactly one of \"mesh\" and \"scene\"");
    if (!sample.contains("count")) return invalid("sample.count", "sample.count (the number of points) is required");
    auto count = read_integer(sample["count"], "sample.count");
    if (!count) return std::move(count.error());
    if (count.value() < 1) return invalid("sample.count", "sample.count must be >= 1");
    if (static_cast<std::uint64_t>(count.value()) > limits.max_points)
        return make_problem(Problem::BudgetExceeded,
                            "sample.count " + std::to_string(count.value()) + " is over the limit of " +
                                std::to_string(limits.max_points) + " points",
                            "sample.count");
    std::uint64_t seed = 1;
    if (auto it = sample.find("seed"); it != sample.end()) {
        auto s = read_integer(*it, "sample.seed");
        if (!s) return std::move(s.error());
        if (s.value() < 0) return invalid("sample.seed", "sample.seed must be >= 0");
        seed = static_cast<std::uint64_t>(s.value());
    }

    if (has_mesh) {
        if (sample.contains("bounds")) return invalid("sample.bounds", "sample.bounds applies only to a scene");
        auto mesh = decode_mesh(sample["mesh"].dump(), limits, "sample.mesh");
        if (!mesh) return std::move(mesh.error());
        if (auto error = check_input_budget(mesh.value(), limits)) return std::move(*error);
        MeshSamplingOptions options;
        options.count = static_cast<std::size_t>(count.value());
        options.seed = seed;
        options.cancel = context.cancel;
        auto sampled = sample_mesh(mesh.value(), options);
        if (!sampled) {
            ApiError error = geometry_error(sampled.error(), Source::Json);
            if (error.field)
                error.field = "sample." + *error.field;
            else
                error.field = "sample.mesh";
            return error;
        }
        return std::move(sampled.value());
    }
    if (!sample.contains("bounds"))
        return invalid("sample.bounds", "sample.bounds [[xmin,ymin,zmin],[xmax,ymax,zmax]] is required with a scene");
    auto bounds = parse_bounds(sample["bounds"], "sample.bounds");
    if (!bounds) return std::move(bounds.error());
    auto field = parse_scene(sample["scene"], limits, "sample.scene", context.cancel);
    if (!field) return std::move(field.error());
    FieldSamplingOptions options;
    options.count = static_cast<std::size_t>(count.value());
    options.seed = seed;
    options.cancel = context.cancel;
    auto sampled = sample_field(*field.value(), bounds.value(), options);
    if (!sampled) {
        ApiError error = from_geo_error(sampled.error());
        if (sampled.error().code == ErrorCode::InvalidArgument) error.field = "sample.scene";
        return error;
    }
    return std::move(sampled.value());
}

ApiResult<Params> params_from_query(const std::multimap<std::string, std::string>& query) {
    auto values = options::read_query(pointcloud_options(), query);
    if (!values) return std::move(values.error());
    Params params;
    bool estimate = false;
    values->get("estimate_normals", estimate);
    if (values->has("k") && !estimate)
        return make_problem(Problem::InvalidField, "k applies only with estimate_normals=true", "k");
    if (estimate) {
        std::int64_t k = kDefaultK;
        values->get("k", k);
        params.k = k;
    }
    values->get_output(params.output);
    return params;
}

ApiResult<Params> params_from_json(const Json& root) {
    Params params;
    if (auto it = root.find("estimate_normals"); it != root.end()) {
        if (it->is_boolean()) {
            if (it->get<bool>()) params.k = kDefaultK;
        } else if (it->is_object()) {
            if (auto error = check_members(*it, "estimate_normals", {"k"})) return std::move(*error);
            params.k = kDefaultK;
            if (auto k = it->find("k"); k != it->end()) {
                auto v = read_integer(*k, "estimate_normals.k");
                if (!v) return std::move(v.error());
                if (auto error = options::check_range(*options::find_option(pointcloud_options(), "k"), v.value(),
                                                      "estimate_normals.k"))
                    return std::move(*error);
                params.k = v.value();
            }
        } else {
            return invalid("estimate_normals", R"(estimate_normals must be a boolean or {"k": 3..256})");
        }
    }
    auto values = options::read_json(pointcloud_options(), root);
    if (!values) return std::move(values.error());
    values->get_output(params.output);
    return params;
}

std::string encode_json(const PointCloud& cloud, double elapsed_ms) {
    Json out = Json::object();
    Json points = Json::array();
    for (const Vec3& p : cloud.positions) points.push_back(Json::array({p.x, p.y, p.z}));
    out["points"] = std::move(points);
    if (cloud.has_normals()) {
        Json list = Json::array();
        for (const Vec3& n : cloud.normals) list.push_back(Json::array({n.x, n.y, n.z}));
        out["normals"] = std::move(list);
    }
    if (cloud.has_colors()) {
        Json list = Json::array();
        for (const Color& c : cloud.colors) {
            Json rgb = Json::array({c.r, c.g, c.b});
            if (cloud.has_alpha) rgb.push_back(c.a);
            list.push_back(std::move(rgb));
        }
        out["colors"] = std::move(list);
    }
    out["stats"] = {{"points", cloud.size()}, {"elapsed_ms", elapsed_ms}};
    return json_text(out);
}

//! A decoded request: where the options came from, the options, the cloud, and how many points the request sent.
struct Decoded {
    Source source = Source::File;
    Params params;
    PointCloud cloud;
    std::size_t input_points = 0;
};

//! A JSON body: {"points": ..., "normals", "colors"} or {"sample": ...} (sampled here), plus the options.
std::optional<ApiError> decode_json_request(const ApiRequest& request, const ApiContext& context, Decoded& d) {
    d.source = Source::Json;
    if (auto error = reject_query_with_json(request)) return error;
    Json root;
    if (auto error = parse(request.body, root)) return error;
    if (!root.is_object()) return invalid("", "the body must be a JSON object");
    if (auto error = check_members(root, "", options::json_members(pointcloud_options()))) return error;
    auto decoded_params = params_from_json(root);
    if (!decoded_params) return std::move(decoded_params.error());
    d.params = std::move(decoded_params.value());
    if (auto error = negotiate_output_format(request, d.params.output)) return error;
    if (auto error = check_output(d.params.output, d.source)) return error;
    const bool has_points = root.contains("points"), has_sample = root.contains("sample");
    if (has_points == has_sample) return invalid("points", "give exactly one of \"points\" and \"sample\"");
    if (has_sample && (root.contains("normals") || root.contains("colors")))
        return invalid(root.contains("normals") ? "normals" : "colors",
                       "normals and colors go with \"points\", not with \"sample\"");
    auto points = has_points ? decode_json_points(root, context.limits) : run_sampling(root["sample"], context);
    if (!points) return std::move(points.error());
    d.cloud = std::move(points.value());
    d.input_points = has_points ? d.cloud.size() : 0;
    return std::nullopt;
}

//! A point file as the body (PLY, OBJ, XYZ, or sniffed), options in the query.
std::optional<ApiError> decode_file_request(const ApiRequest& request, const ApiContext& context,
                                            const std::string& media_type, Decoded& d) {
    auto format = uploaded_point_format(media_type, request.body);
    if (!format) return std::move(format.error());
    auto query_params = params_from_query(request.query);
    if (!query_params) return worded_for_form(request, std::move(query_params.error()));
    d.params = std::move(query_params.value());
    if (auto error = negotiate_output_format(request, d.params.output)) return error;
    if (auto error = check_output(d.params.output, d.source)) return worded_for_form(request, std::move(*error));
    auto read = read_uploaded_points(request.body, format.value(), context.limits);
    if (!read) return std::move(read.error());
    d.cloud = std::move(read.value());
    d.input_points = d.cloud.size();
    return std::nullopt;
}

//! Normal estimation and orientation with k neighbours, after the budget on points x k.
std::optional<ApiError> run_normal_estimation(Decoded& d, const ApiContext& context) {
    const bool json = d.source == Source::Json;
    return estimate_point_normals(d.cloud, *d.params.k, context.limits, context.cancel, d.source,
                                  json ? "estimate_normals.k" : "k",
                                  json ? std::optional<std::string>("estimate_normals") : std::nullopt);
}

ApiResponse run(const ApiRequest& sent, const ApiContext& context) {
    const auto t_start = Clock::now();
    Upload upload;
    if (auto error = check_upload(sent, context.limits, kPointMediaTypes, reads_point_media_type, upload))
        return error_response(std::move(*error));
    const ApiRequest& request = *upload.request;
    const std::string& media_type = upload.media_type;

    Decoded d;
    auto decode_error = media_type == "application/json" ? decode_json_request(request, context, d)
                                                         : decode_file_request(request, context, media_type, d);
    if (decode_error) return error_response(std::move(*decode_error));
    const auto t_decoded = Clock::now();

    if (d.params.k)
        if (auto error = run_normal_estimation(d, context)) return error_response(std::move(*error));
    if (Status s = validate(d.cloud); !s) return error_response(point_error(s.error(), d.source));
    const auto t_computed = Clock::now();

    PointCloud& cloud = d.cloud;
    const OutputOptions& output = d.params.output;
    if (!output.normals.value_or(true)) cloud.normals.clear();  // "normals": false leaves them out
    ApiResponse response;
    response.content_type = std::string(output_media_type(output.format));
    if (output.format == OutputFormat::Json) {
        response.body = encode_json(cloud, ms_between(t_start, t_computed));
    } else if (output.format == OutputFormat::Ply) {
        response.body = write_ply_points(cloud);
    } else {
        // Points sent as JSON keep their indices through conversion and normal estimation: name the field then.
        const bool sent_points = d.source == Source::Json && d.input_points == cloud.size();
        if (auto error = check_float32_range(cloud.positions, output.format, "point",
                                             sent_points ? std::optional<std::string_view>("points") : std::nullopt))
            return error_response(std::move(*error));
        PointGlbOptions options;
        options.draco = output.draco.value_or(true);
        if (output.quantize_position) options.quantize_position = static_cast<int>(*output.quantize_position);
        auto glb = write_points_glb(cloud, options);
        if (!glb) return error_response(point_error(glb.error(), d.source));
        if (output.format == OutputFormat::Gltf) {
            auto text = gltf_from_glb(glb.value());
            if (!text) return error_response(point_error(text.error(), d.source));
            response.body = std::move(text.value());
        } else {
            response.body = std::move(glb.value());
        }
    }
    const auto t_encoded = Clock::now();
    response.headers = {
        {"X-Input-Points", std::to_string(d.input_points)},
        {"X-Output-Points", std::to_string(cloud.size())},
        {"X-Normals", cloud.has_normals() ? "true" : "false"},
        {"X-Colors", cloud.has_colors() ? "true" : "false"},
    };
    append_timing_headers(response.headers,
                          Timing{t_start, {{"decode", t_decoded}, {"compute", t_computed}, {"encode", t_encoded}}});
    return response;
}

}  // namespace

ApiResponse pointcloud(const ApiRequest& request, const ApiContext& context) noexcept {
    return guarded([&] { return run(request, context); });
}

}  // namespace surfaced::api::operations
