// POST /limit/evaluate (see limit_evaluate.h): decode, check budgets, build the evaluators, answer by face, encode.
#include "api/operations/limit_evaluate.h"

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "api/json_codec.h"
#include "api/json_util.h"
#include "api/operations/json_request.h"
#include "api/operations/query_forms.h"
#include "api/operations/request_forms.h"
#include "api/options/mesh_params.h"
#include "api/options/option_reader.h"
#include "geometry/subdivision/limit_evaluation.h"
#include "geometry/subdivision/uv_limit.h"

namespace surfaced::api::operations {
namespace {

using namespace json;  // the shared readers (api/json_util.h)

//! Points answered between two looks at the deadline.
constexpr std::size_t kBatch = 1024;
//! A face with at least this many points is prepared once (face_surface) and its points evaluated on its patches;
//! below it, preparing costs more than it saves: bench_limit_api measures the break-even at about 12 points on a face
//! with one extraordinary corner and about 40 on one with four (docs/benchmarks.md).
constexpr std::size_t kFaceSurfacePoints = 32;

constexpr std::string_view kPoint = R"({"face": f, "uv": [u, v]})";

struct Point {
    double face = 0;  //!< as sent (a packed face is a number); checked against the mesh once it is read
    double u = 0, v = 0;
};

//! Points[i] of a JSON batch: {"face": f, "uv": [u, v]}, f a non-negative integer, u and v finite.
std::optional<ApiError> read_point(const Json& item, const std::string& path, Point& out) {
    if (!item.is_object()) return invalid(path, path + " must be " + std::string(kPoint));
    if (auto error = check_members(item, path, {"face", "uv"})) return error;
    const std::string face_path = member_path(path, "face"), uv_path = member_path(path, "uv");
    const auto face = item.find("face");
    const auto uv = item.find("uv");
    if (face == item.end()) return invalid(face_path, face_path + " is required (a face index)");
    if (uv == item.end()) return invalid(uv_path, uv_path + " is required ([u, v])");
    auto f = read_integer(*face, face_path);
    if (!f) return std::move(f.error());
    if (f.value() < 0) return invalid(face_path, face_path + " must be a non-negative integer face index");
    if (!uv->is_array() || uv->size() != 2) return invalid(uv_path, uv_path + " must be [u, v]");
    auto u = read_number((*uv)[0], index_path(uv_path, 0));
    if (!u) return std::move(u.error());
    auto v = read_number((*uv)[1], index_path(uv_path, 1));
    if (!v) return std::move(v.error());
    out = Point{static_cast<double>(f.value()), u.value(), v.value()};
    return std::nullopt;
}

//! The answers, per member, in the request's order.
struct Answers {
    Column position{Column::Vector, {}}, du{Column::Vector, {}}, dv{Column::Vector, {}}, normal{Column::Vector, {}};
    Column duu{Column::Vector, {}}, duv{Column::Vector, {}}, dvv{Column::Vector, {}};
    Column uv{Column::Vector2, {}};
    Column exact{Column::Bool, {}};
};

void put(Column& column, std::size_t i, const Vec3& v) {
    column.values[3 * i] = v.x;
    column.values[3 * i + 1] = v.y;
    column.values[3 * i + 2] = v.z;
}

//! The error for point `i` from the evaluator: the face (out of range, a hole, a face it cannot take) or the uv.
ApiError point_error(const GeoError& error, std::size_t i) {
    const std::string path = index_path("points", i);
    const bool about_uv = error.code == ErrorCode::NonFinite;
    const std::string field = member_path(path, about_uv ? "uv" : "face");
    return json::geometry_error(error.code, field, field + ": " + error.message);
}

ApiResponse run(const ApiRequest& request, const ApiContext& context) {
    const Limits& limits = context.limits;
    QueryIntake in;
    if (auto error = take_query_request(request, limits, "POST /limit/evaluate", "the points", in))
        return error_response(std::move(*error));
    const Json& root = in.root;
    if (!root.is_object()) return error_response(invalid("", "the body must be a JSON object"));
    const auto& spec = *options::operation_options("limit_evaluate");
    std::vector<std::string_view> members = options::json_members(spec);
    if (in.multipart) std::erase(members, std::string_view("mesh"));
    if (auto error = check_members(root, "", members)) return error_response(std::move(*error));
    auto values = options::read_json(spec, root);
    if (!values) return error_response(std::move(values.error()));
    const SubdivideParams params = options::subdivide_params(values.value());
    std::int64_t derivatives = 1;
    values->get("derivatives", derivatives);
    Encoding encoding = Encoding::Json;
    values->get("encoding", kEncodingNames, encoding);

    // The points' shape and count against the budget first, before any is decoded or the mesh is read.
    const auto points_it = root.find("points");
    if (points_it == root.end())
        return error_response(invalid("points", R"(points is required: [{"face": f, "uv": [u, v]}, ...])"));
    auto shape = batch_shape(*points_it, "points", 3, kPoint);
    if (!shape) return error_response(std::move(shape.error()));
    Batch batch = std::move(shape.value());
    const std::size_t count = batch.count;
    if (count == 0) return error_response(invalid("points", "points is empty: give at least one (face, u, v)"));
    if (count > limits.max_limit_points)
        return error_response(make_problem(Problem::BudgetExceeded,
                                           std::to_string(count) + " points; the limit is " +
                                               std::to_string(limits.max_limit_points) + " in one request",
                                           "points"));
    // packed numbers may be non-finite here: a non-finite (u, v) is named per point below
    if (auto error = decode_packed(*points_it, "points", 3, batch, false)) return error_response(std::move(*error));
    std::vector<Point> points(count);
    for (std::size_t i = 0; i < count; ++i) {
        if (batch.array) {
            if (auto error = read_point((*batch.array)[i], index_path("points", i), points[i]))
                return error_response(std::move(*error));
            continue;
        }
        const double* p = batch.packed.data() + 3 * i;
        if (!(p[0] >= 0) || p[0] != std::floor(p[0])) {
            const std::string field = member_path(index_path("points", i), "face");
            return error_response(invalid(
                field, field + " must be a non-negative integer face index (packed: " + format_double(p[0]) + ")"));
        }
        points[i] = Point{p[0], p[1], p[2]};
    }

    // The mesh (within the input budget, valid as subdivision takes it) and its tags.
    Source source = Source::Json;
    auto mesh = query_mesh(in, limits, MeshRules::Subdivision, source);
    if (!mesh) return error_response(std::move(mesh.error()));
    if (auto error = decode_subdivision_tags(root, mesh.value())) return error_response(std::move(*error));
    if (mesh->face_count() == 0)
        return error_response(json::geometry_error(ErrorCode::InvalidArgument, "mesh.faces",
                                                   "mesh.faces is empty: a mesh without faces has no limit surface"));

    // Every point's face and (u, v) in the request's order, so that the first bad one is the one named.
    const std::size_t faces = mesh->face_count();
    for (std::size_t i = 0; i < count; ++i) {
        const Point& p = points[i];
        const std::string path = index_path("points", i);
        if (p.face >= static_cast<double>(faces)) {
            const std::string field = member_path(path, "face");
            return error_response(json::geometry_error(ErrorCode::IndexOutOfRange, field,
                                                       field + ": face " + format_double(p.face) + " out of range (" +
                                                           std::to_string(faces) +
                                                           (faces == 1 ? " face)" : " faces)")));
        }
        const std::string field = member_path(path, "uv");
        if (!std::isfinite(p.u) || !std::isfinite(p.v))
            return error_response(
                json::geometry_error(ErrorCode::NonFinite, field, field + ": u and v must be finite numbers"));
        const std::size_t size = mesh->face_size(static_cast<std::size_t>(p.face));
        if (!limit_domain_contains(size, p.u, p.v))
            return error_response(json::geometry_error(
                ErrorCode::InvalidArgument, field,
                field + ": (" + format_double(p.u) + ", " + format_double(p.v) + ") is outside the domain of face " +
                    format_double(p.face) + " (" + std::to_string(size) + " corners; " +
                    (size == 4 ? std::string("a quad's is [0, 1] x [0, 1]")
                               : std::string("an N-gon's is N tiles [x, x + 1/2] x [y, y + 1/2], see "
                                             "docs/subdivision.md")) +
                    ")"));
    }

    // The surface under /subdivide's options (the mesh's boundary tag unless the request names one).
    SubdivisionOptions options;
    options.scheme = params.scheme;
    options.crease_method = params.crease_method;
    options.triangle_rule = params.triangle_rule;
    options.uv_interpolation = params.uv_interpolation;
    options.loop_weights = params.loop_weights;
    if (params.boundary) {
        options.boundary = *params.boundary;
        options.use_mesh_boundary_tag = false;
    }
    auto evaluator = LimitSurfaceEvaluator::create(mesh.value(), options);
    if (!evaluator) {
        if (evaluator.error().code == ErrorCode::Unsupported)
            return error_response(json::geometry_error(ErrorCode::Unsupported, "scheme",
                                                       "scheme \"" +
                                                           std::string(enum_name(kSchemeNames, params.scheme)) +
                                                           "\": " + evaluator.error().message));
        return error_response(geometry_error(evaluator.error(), source));
    }
    std::optional<UvLimitEvaluator> uvs;
    if (mesh->has_uvs()) {
        auto created = UvLimitEvaluator::create(mesh.value(), options);
        if (!created) return error_response(geometry_error(created.error(), source));
        uvs = std::move(created).value();
    }
    if (auto error = deadline_passed(context.cancel)) return error_response(std::move(*error));

    // Answer face by face (a counting sort of the points by face), each face prepared once when it has many points.
    std::vector<std::size_t> offsets(faces + 1, 0), order(count);
    for (const Point& p : points) ++offsets[static_cast<std::size_t>(p.face) + 1];
    for (std::size_t f = 0; f < faces; ++f) offsets[f + 1] += offsets[f];
    {
        std::vector<std::size_t> fill(offsets.begin(), offsets.end() - 1);
        for (std::size_t i = 0; i < count; ++i) order[fill[static_cast<std::size_t>(points[i].face)]++] = i;
    }
    const bool second = derivatives == 2;
    Answers out;
    for (Column* c : {&out.position, &out.du, &out.dv, &out.normal}) c->values.resize(3 * count);
    if (second)
        for (Column* c : {&out.duu, &out.duv, &out.dvv}) c->values.resize(3 * count);
    if (uvs) out.uv.values.resize(2 * count);
    out.exact.values.resize(count);
    std::size_t done = 0;
    // the first failing point in the request's order (points of one face fail alike, so a face stops at its first)
    std::optional<std::pair<std::size_t, ApiError>> failed;
    const auto fail = [&](const GeoError& error, std::size_t i) {
        if (!failed || i < failed->first) failed.emplace(i, point_error(error, i));
    };
    for (std::size_t f = 0; f < faces; ++f) {
        const std::size_t begin = offsets[f], end = offsets[f + 1];
        if (begin == end) continue;
        const bool prepare = end - begin >= kFaceSurfacePoints;
        std::optional<LimitFaceSurface> surface;
        std::optional<UvFaceSurface> uv_surface;
        if (prepare) {
            auto prepared = evaluator->face_surface(f);
            if (!prepared) {
                fail(prepared.error(), order[begin]);
                continue;
            }
            surface = std::move(prepared).value();
            if (uvs) {
                auto uv_prepared = uvs->face_surface(f);
                if (!uv_prepared) {
                    fail(uv_prepared.error(), order[begin]);
                    continue;
                }
                uv_surface = std::move(uv_prepared).value();
            }
        }
        for (std::size_t k = begin; k < end; ++k, ++done) {
            if (done % kBatch == 0)
                if (auto error = deadline_passed(context.cancel)) return error_response(std::move(*error));
            const std::size_t i = order[k];
            const Point& p = points[i];
            auto sample = surface ? surface->evaluate(p.u, p.v, second) : evaluator->evaluate(f, p.u, p.v, second);
            if (!sample) {
                fail(sample.error(), i);
                break;
            }
            put(out.position, i, sample->position);
            put(out.du, i, sample->du);
            put(out.dv, i, sample->dv);
            put(out.normal, i, sample->normal);
            if (second) {
                put(out.duu, i, sample->duu);
                put(out.duv, i, sample->duv);
                put(out.dvv, i, sample->dvv);
            }
            bool exact = sample->exact;
            if (uvs) {
                auto uv = uv_surface ? uv_surface->evaluate(p.u, p.v) : uvs->evaluate(f, p.u, p.v);
                if (!uv) {
                    fail(uv.error(), i);
                    break;
                }
                out.uv.values[2 * i] = uv->uv.x;
                out.uv.values[2 * i + 1] = uv->uv.y;
                exact = exact && uv->exact;
            }
            out.exact.values[i] = exact ? 1 : 0;
        }
    }
    if (failed) return error_response(std::move(failed->second));
    if (auto error = check_deadline_before_encoding(context.cancel)) return error_response(std::move(*error));

    // Encode: an object per point, or a packed array per member.
    std::vector<std::pair<std::string_view, const Column*>> columns = {
        {"position", &out.position}, {"du", &out.du}, {"dv", &out.dv}, {"normal", &out.normal}};
    if (second) columns.insert(columns.end(), {{"duu", &out.duu}, {"duv", &out.duv}, {"dvv", &out.dvv}});
    if (uvs) columns.emplace_back("uv", &out.uv);
    columns.emplace_back("exact", &out.exact);
    Json body = Json::object();
    if (encoding == Encoding::Json) {
        Json list = Json::array();
        for (std::size_t i = 0; i < count; ++i) {
            Json point = Json::object();
            for (const auto& column : columns) point[std::string(column.first)] = column_item(*column.second, i);
            list.push_back(std::move(point));
        }
        body["points"] = std::move(list);
    } else {
        body["encoding"] = std::string(enum_name(kEncodingNames, encoding));
        Json packed = Json::object();
        for (const auto& column : columns) packed[std::string(column.first)] = encode_column(*column.second, encoding);
        body["points"] = std::move(packed);
    }
    return json_response(body);
}

}  // namespace

ApiResponse limit_evaluate(const ApiRequest& request, const ApiContext& context) noexcept {
    return guarded([&] { return run(request, context); });
}

}  // namespace surfaced::api::operations
