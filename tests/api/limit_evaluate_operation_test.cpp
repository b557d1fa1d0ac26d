// POST /limit/evaluate through dispatch (no sockets): answers against LimitSurfaceEvaluator and UvLimitEvaluator
// called directly, the analytic limit of a flat grid (the plane, constant derivatives), the cube's limit at a face
// centre against OpenSubdiv's limit stencils, the packed and multipart forms against the JSON one, and every error
// with the field it names.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/routes.h"
#include "geometry/io/base64.h"
#include "geometry/io/mesh_io.h"
#include "geometry/mesh/shapes.h"
#include "geometry/subdivision/limit_evaluation.h"
#include "geometry/subdivision/uv_limit.h"
#include "tests/support/uv_seams.h"
#include "tests/support/api_request.h"
#include "tests/support/osd_reference.h"

namespace surfaced::api {
namespace {

using Json = nlohmann::json;

using namespace fixtures;

ApiResponse post(const std::string& body, const ApiContext& context = {}) {
    return dispatch(make_request("POST", "/limit/evaluate", "application/json", body), context);
}

//! The JSON mesh with its UVs when it has them.
Json mesh_value(const PolygonMesh& mesh) {
    Json out = Json::parse(mesh_json(mesh));
    if (mesh.has_uvs()) {
        Json uvs = Json::array(), faces = Json::array();
        for (const Vec2& uv : mesh.uvs) uvs.push_back({uv.x, uv.y});
        for (std::size_t f = 0; f < mesh.face_count(); ++f)
            faces.push_back(std::vector<Index>(mesh.uv_indices.begin() + mesh.face_offsets[f],
                                               mesh.uv_indices.begin() + mesh.face_offsets[f + 1]));
        out["uvs"] = uvs;
        out["uv_faces"] = faces;
    }
    return out;
}

struct Query {
    std::size_t face;
    double u, v;
};

Json points_json(const std::vector<Query>& points) {
    Json out = Json::array();
    for (const Query& q : points) out.push_back({{"face", q.face}, {"uv", {q.u, q.v}}});
    return out;
}

//! A uniformly random point of face f's domain (Bfr's quad sub-face tiles for N-gons).
Query random_point(const PolygonMesh& mesh, std::size_t f, std::mt19937_64& rng) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const std::size_t n = mesh.face_size(f);
    if (n == 4) return {f, unit(rng), unit(rng)};
    const int columns = n < 10 ? 2 + (n > 4 ? 1 : 0) : 1 + static_cast<int>(std::sqrt(static_cast<double>(n - 1)));
    const int sub = static_cast<int>(rng() % n);
    return {f, sub % columns + 0.5 * unit(rng), sub / columns + 0.5 * unit(rng)};
}

Vec3 vec(const Json& value) { return {value[0].get<double>(), value[1].get<double>(), value[2].get<double>()}; }

using testing::with_seams;

// ---- answers ------------------------------------------------------------------------------------------------------

TEST(LimitEvaluateOperation, FlatGridLimitIsThePlaneWithConstantDerivatives) {
    // A uniform grid whose corners are sharp (edge-and-corner): B-splines reproduce linear functions, so the limit is
    // the grid's own bilinear map: face (i, j) at (u, v) is ((i + u) / 4, (j + v) / 3, 0), du = (1/4, 0, 0),
    // dv = (0, 1/3, 0), normal +z, second derivatives zero.
    const PolygonMesh grid = shapes::grid(4, 3);
    std::vector<Query> points;
    for (std::size_t f = 0; f < grid.face_count(); ++f)
        for (double u : {0.0, 0.25, 0.5, 1.0})
            for (double v : {0.0, 0.7, 1.0}) points.push_back({f, u, v});
    Json body = {{"mesh", mesh_value(grid)},
                 {"boundary", "edge-and-corner"},
                 {"points", points_json(points)},
                 {"derivatives", 2}};
    const ApiResponse response = post(body.dump());
    ASSERT_EQ(response.status, 200) << response.body;
    const Json out = Json::parse(response.body);
    ASSERT_EQ(out["points"].size(), points.size());
    for (std::size_t k = 0; k < points.size(); ++k) {
        const Json& p = out["points"][k];
        const double i = static_cast<double>(points[k].face % 4), j = static_cast<double>(points[k].face / 4);
        const Vec3 expected{(i + points[k].u) / 4, (j + points[k].v) / 3, 0};
        EXPECT_LE(norm(vec(p["position"]) - expected), 1e-14) << k;
        EXPECT_LE(norm(vec(p["du"]) - Vec3{0.25, 0, 0}), 1e-14) << k;
        EXPECT_LE(norm(vec(p["dv"]) - Vec3{0, 1.0 / 3, 0}), 1e-14) << k;
        EXPECT_LE(norm(vec(p["normal"]) - Vec3{0, 0, 1}), 1e-14) << k;
        for (const char* second : {"duu", "duv", "dvv"}) EXPECT_LE(norm(vec(p[second])), 1e-12) << k << second;
        EXPECT_TRUE(p["exact"].get<bool>());
        EXPECT_FALSE(p.contains("uv"));  // the grid has no UVs
    }
}

TEST(LimitEvaluateOperation, AnswersAreTheEvaluators) {
    std::mt19937_64 rng(7);
    struct Case {
        const char* name;
        PolygonMesh mesh;
        std::string options;  // extra members
        SubdivisionOptions geometry;
    };
    SubdivisionOptions smooth_tris;
    smooth_tris.triangle_rule = TriangleRule::Smooth;
    SubdivisionOptions chaikin_none;
    chaikin_none.crease_method = CreaseMethod::Chaikin;
    chaikin_none.uv_interpolation = UvInterpolation::None;
    const std::vector<Case> cases = {
        {"irregular_torus", shapes::irregular_torus(), "", {}},
        {"mixed_polygons (smooth triangles)", shapes::mixed_polygons(), R"("triangle_rule":"smooth")", smooth_tris},
        {"seamed torus (chaikin, uv none)", with_seams(shapes::torus(8, 6)),
         R"("crease_method":"chaikin","uv_interpolation":"none")", chaikin_none},
        {"seamed mixed polygons", with_seams(shapes::mixed_polygons()), "", {}},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        // many points on some faces (more than kFaceSurfacePoints: prepared with face_surface), one on others
        std::vector<Query> points;
        for (std::size_t f = 0; f < c.mesh.face_count(); ++f)
            for (int k = 0; k < (f % 3 == 0 ? 40 : 1); ++k) points.push_back(random_point(c.mesh, f, rng));
        std::shuffle(points.begin(), points.end(), rng);
        Json body = Json::parse("{" + c.options + "}");
        body["mesh"] = mesh_value(c.mesh);
        body["points"] = points_json(points);
        body["derivatives"] = 2;
        const ApiResponse response = post(body.dump());
        ASSERT_EQ(response.status, 200) << response.body;
        const Json out = Json::parse(response.body);
        auto evaluator = LimitSurfaceEvaluator::create(c.mesh, c.geometry);
        ASSERT_TRUE(evaluator.ok());
        std::optional<UvLimitEvaluator> uvs;
        if (c.mesh.has_uvs()) uvs = UvLimitEvaluator::create(c.mesh, c.geometry).value();
        const double diag = norm(c.mesh.bounds().max - c.mesh.bounds().min);
        for (std::size_t k = 0; k < points.size(); ++k) {
            const Json& p = out["points"][k];
            auto s = evaluator->evaluate(points[k].face, points[k].u, points[k].v, true);
            ASSERT_TRUE(s.ok());
            EXPECT_LE(norm(vec(p["position"]) - s->position), 1e-12 * diag) << k;
            EXPECT_LE(norm(vec(p["du"]) - s->du), 1e-12 * diag) << k;
            EXPECT_LE(norm(vec(p["dv"]) - s->dv), 1e-12 * diag) << k;
            EXPECT_LE(norm(vec(p["duv"]) - s->duv), 1e-9 * diag) << k;
            EXPECT_LE(norm(vec(p["normal"]) - s->normal), 1e-12) << k;
            bool exact = s->exact;
            if (uvs) {
                auto uv = uvs->evaluate(points[k].face, points[k].u, points[k].v);
                ASSERT_TRUE(uv.ok());
                EXPECT_NEAR(p["uv"][0].get<double>(), uv->uv.x, 1e-12) << k;
                EXPECT_NEAR(p["uv"][1].get<double>(), uv->uv.y, 1e-12) << k;
                exact = exact && uv->exact;
            }
            EXPECT_EQ(p["exact"].get<bool>(), exact) << k;
        }
    }
}

TEST(LimitEvaluateOperation, CubeFaceCentreIsOpenSubdivsLimit) {
    // The centre of a face, (1/2, 1/2), is its face point after one refinement: Far's level-1 vertex 8 + f (vertex
    // children first), whose limit PrimvarRefiner::Limit computes from the limit stencils.
    const PolygonMesh cube = shapes::cube();
    const testing::OsdLimit osd = testing::osd_limit(cube, {}, 1, 8 + cube.face_count());
    std::vector<Query> points;
    for (std::size_t f = 0; f < cube.face_count(); ++f) points.push_back({f, 0.5, 0.5});
    const ApiResponse response = post(json_request(cube, R"(,"points":)" + points_json(points).dump()));
    ASSERT_EQ(response.status, 200) << response.body;
    const Json out = Json::parse(response.body);
    for (std::size_t f = 0; f < cube.face_count(); ++f) {
        const Json& p = out["points"][f];
        EXPECT_LE(norm(vec(p["position"]) - osd.positions[8 + f]), 1e-12) << f;
        EXPECT_LE(norm(vec(p["normal"]) - osd.normals[8 + f]), 1e-12) << f;
        // by symmetry the centre's limit lies on the face's axis: two of its coordinates are zero
        const Vec3 q = vec(p["position"]);
        const double a[3] = {std::abs(q.x), std::abs(q.y), std::abs(q.z)};
        EXPECT_LE(a[0] + a[1] + a[2] - std::max({a[0], a[1], a[2]}), 1e-14) << f;
    }
}

TEST(LimitEvaluateOperation, LoopIsWhateverTheEvaluatorAnswers) {
    const PolygonMesh ico = shapes::icosahedron();
    SubdivisionOptions loop;
    loop.scheme = SubdivisionScheme::Loop;
    const auto evaluator = LimitSurfaceEvaluator::create(ico, loop);
    const ApiResponse response = post(json_request(ico, R"(,"scheme":"loop","points":[{"face":0,"uv":[0.25,0.25]}])"));
    if (evaluator.ok()) {
        ASSERT_EQ(response.status, 200) << response.body;
        const auto s = evaluator->evaluate(0, 0.25, 0.25);
        ASSERT_TRUE(s.ok());
        EXPECT_LE(norm(vec(Json::parse(response.body)["points"][0]["position"]) - s->position), 1e-12);
    } else {
        const Json problem = expect_problem(response, 422, "unsupported");
        EXPECT_EQ(problem.value("field", ""), "scheme");
    }
}

// ---- packed and multipart forms -----------------------------------------------------------------------------------

std::string packed(const std::vector<Query>& points, bool single) {
    std::string bytes;
    const auto add = [&](double x) {
        const std::uint64_t bits =
            single ? std::bit_cast<std::uint32_t>(static_cast<float>(x)) : std::bit_cast<std::uint64_t>(x);
        for (std::size_t b = 0; b < (single ? 4u : 8u); ++b) bytes += static_cast<char>((bits >> (8 * b)) & 0xff);
    };
    for (const Query& q : points) {
        add(static_cast<double>(q.face));
        add(q.u);
        add(q.v);
    }
    return encode_base64(bytes);
}

std::vector<double> unpack(const Json& text, bool single) {
    const auto bytes = decode_base64(text.get<std::string>()).value();
    std::vector<double> out;
    const std::size_t size = single ? 4 : 8;
    for (std::size_t i = 0; i + size <= bytes.size(); i += size) {
        std::uint64_t bits = 0;
        for (std::size_t b = 0; b < size; ++b) bits |= std::uint64_t(bytes[i + b]) << (8 * b);
        out.push_back(single ? double(std::bit_cast<float>(static_cast<std::uint32_t>(bits)))
                             : std::bit_cast<double>(bits));
    }
    return out;
}

TEST(LimitEvaluateOperation, PackedPointsAndAnswersAreTheJsonOnes) {
    const PolygonMesh mesh = with_seams(shapes::irregular_torus());
    std::mt19937_64 rng(11);
    std::vector<Query> points;
    for (int k = 0; k < 40; ++k) points.push_back(random_point(mesh, rng() % mesh.face_count(), rng));
    // exactly representable in float32, so that both packings name the same points
    for (Query& q : points) q.u = static_cast<float>(q.u), q.v = static_cast<float>(q.v);
    Json body = {{"mesh", mesh_value(mesh)}, {"points", points_json(points)}};
    const ApiResponse plain = post(body.dump());
    ASSERT_EQ(plain.status, 200) << plain.body;
    const Json expected = Json::parse(plain.body)["points"];
    for (const bool single : {false, true}) {
        SCOPED_TRACE(single ? "float32" : "float64");
        body["points"] = {{single ? "float32" : "float64", packed(points, single)}};
        body["encoding"] = single ? "float32" : "float64";
        const ApiResponse response = post(body.dump());
        ASSERT_EQ(response.status, 200) << response.body;
        const Json out = Json::parse(response.body);
        EXPECT_EQ(out["encoding"], single ? "float32" : "float64");
        const double tolerance = single ? 1e-6 : 0.0;
        for (const char* member : {"position", "du", "dv", "normal"}) {
            const std::vector<double> values = unpack(out["points"][member], single);
            ASSERT_EQ(values.size(), 3 * points.size()) << member;
            for (std::size_t k = 0; k < points.size(); ++k)
                for (int c = 0; c < 3; ++c)
                    EXPECT_NEAR(values[3 * k + c], expected[k][member][c].get<double>(),
                                tolerance * (1 + std::abs(values[3 * k + c])))
                        << member << " " << k;
        }
        const std::vector<double> uv = unpack(out["points"]["uv"], single);
        ASSERT_EQ(uv.size(), 2 * points.size());
        for (std::size_t k = 0; k < points.size(); ++k)
            EXPECT_NEAR(uv[2 * k], expected[k]["uv"][0].get<double>(), tolerance * 10);
        const auto exact = decode_base64(out["points"]["exact"].get<std::string>()).value();
        ASSERT_EQ(exact.size(), points.size());
        for (std::size_t k = 0; k < points.size(); ++k) EXPECT_EQ(exact[k] != 0, expected[k]["exact"].get<bool>());
        EXPECT_FALSE(out["points"].contains("duu"));  // derivatives 1
    }
}

std::string form(const std::vector<std::array<std::string, 4>>& parts) {  // name, filename, content type, body
    std::string body;
    for (const auto& part : parts) {
        body += "--B0undary\r\nContent-Disposition: form-data; name=\"" + part[0] + "\"";
        if (!part[1].empty()) body += "; filename=\"" + part[1] + "\"";
        body += "\r\n";
        if (!part[2].empty()) body += "Content-Type: " + part[2] + "\r\n";
        body += "\r\n" + part[3] + "\r\n";
    }
    return body + "--B0undary--\r\n";
}

ApiResponse post_form(const std::string& body) {
    return dispatch(make_request("POST", "/limit/evaluate", "multipart/form-data; boundary=B0undary", body), {});
}

TEST(LimitEvaluateOperation, MultipartMeshFileGivesTheSameAnswersAsJson) {
    PolygonMesh cube = shapes::cube();
    const std::string query = R"({"points":[{"face":0,"uv":[0.5,0.5]},{"face":3,"uv":[0.1,0.9]}],"derivatives":2})";
    Json body = Json::parse(query);
    body["mesh"] = mesh_value(cube);
    const ApiResponse plain = post(body.dump());
    ASSERT_EQ(plain.status, 200) << plain.body;
    const ApiResponse from_obj =
        post_form(form({{"file", "cube.obj", "", write_obj(cube)}, {"request", "", "", query}}));
    ASSERT_EQ(from_obj.status, 200) << from_obj.body;
    EXPECT_EQ(Json::parse(from_obj.body), Json::parse(plain.body));
    const ApiResponse from_json =
        post_form(form({{"file", "cube.json", "", mesh_json(cube)}, {"request", "q.json", "application/json", query}}));
    ASSERT_EQ(from_json.status, 200) << from_json.body;
    EXPECT_EQ(Json::parse(from_json.body), Json::parse(plain.body));

    expect_problem(post_form(form({{"file", "cube.obj", "", write_obj(cube)}})), 400, "malformed_multipart");
    expect_problem(post_form(form({{"file", "cube.obj", "", write_obj(cube)}, {"request", "", "", body.dump()}})), 400,
                   "invalid_field", "mesh");
}

// ---- errors -------------------------------------------------------------------------------------------------------

TEST(LimitEvaluateOperation, BadPointsAreNamed) {
    const PolygonMesh mesh = shapes::mixed_polygons();  // has triangles, quads and a pentagon
    std::size_t triangle = 0, quad = 0;
    while (mesh.face_size(triangle) != 3) ++triangle;
    while (mesh.face_size(quad) != 4) ++quad;
    const auto with = [&](const std::string& points, const std::string& extra = "") {
        return post(json_request(mesh, R"(,"points":)" + points + extra));
    };
    const std::string good = R"({"face":0,"uv":[0.25,0.25]})";
    const std::string faces = std::to_string(mesh.face_count());
    expect_problem(with("[" + good + R"(,{"face":)" + faces + R"(,"uv":[0.1,0.1]}])"), 422, "index_out_of_range",
                   "points[1].face");
    expect_problem(with(R"([{"face":-1,"uv":[0.1,0.1]}])"), 400, "invalid_field", "points[0].face");
    expect_problem(with(R"([{"face":0.5,"uv":[0.1,0.1]}])"), 400, "invalid_field", "points[0].face");
    expect_problem(with(R"([{"face":)" + std::to_string(quad) + R"(,"uv":[1.5,0.1]}])"), 422, "invalid_argument",
                   "points[0].uv");
    // a triangle's domain is three tiles of [0, 1/2]^2 in two columns: (0.75, 0.25) is between tiles
    expect_problem(with("[" + good + R"(,{"face":)" + std::to_string(triangle) + R"(,"uv":[0.75,0.25]}])"), 422,
                   "invalid_argument", "points[1].uv");
    expect_problem(with(R"([{"face":0,"uv":[0.1]}])"), 400, "invalid_field", "points[0].uv");
    expect_problem(with(R"([{"face":0}])"), 400, "invalid_field", "points[0].uv");
    expect_problem(with(R"([{"uv":[0.1,0.1]}])"), 400, "invalid_field", "points[0].face");
    expect_problem(with(R"([[0,0.1,0.1]])"), 400, "invalid_field", "points[0]");
    expect_problem(with(R"([{"face":0,"uv":[0.1,0.1],"w":1}])"), 400, "unknown_field");
    expect_problem(with("[]"), 400, "invalid_field", "points");
    expect_problem(post(json_request(mesh, "")), 400, "invalid_field", "points");
    expect_problem(with("[" + good + "]", R"(,"derivatives":3)"), 400, "invalid_field", "derivatives");
    expect_problem(with("[" + good + "]", R"(,"levels":2)"), 400, "unknown_field");
    // a hole has no limit surface: its points are named, the rest of the mesh answers
    expect_problem(with("[" + good + R"(,{"face":1,"uv":[0.25,0.25]}])", R"(,"holes":[1])"), 422, "invalid_argument",
                   "points[1].face");
    // packed: a non-finite (u, v) is named per point, a face that is not a whole number too
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const std::string packed_nan = packed({{0, 0.2, 0.2}, {0, nan, 0.2}}, false);
    expect_problem(with(R"({"float64":")" + packed_nan + R"("})"), 422, "non_finite", "points[1].uv");
    std::string fraction = packed({{0, 0.2, 0.2}}, false);
    {
        auto bytes = decode_base64(fraction).value();
        const std::uint64_t bits = std::bit_cast<std::uint64_t>(0.5);
        for (std::size_t b = 0; b < 8; ++b) bytes[b] = static_cast<std::uint8_t>((bits >> (8 * b)) & 0xff);
        fraction = encode_base64(std::string(bytes.begin(), bytes.end()));
    }
    expect_problem(with(R"({"float64":")" + fraction + R"("})"), 400, "invalid_field", "points[0].face");
    expect_problem(with(R"({"float64":"AAAA"})"), 400, "invalid_field", "points.float64");
}

TEST(LimitEvaluateOperation, BudgetsAreCheckedBeforeWork) {
    const PolygonMesh cube = shapes::cube();
    Limits limits;
    limits.max_limit_points = 2;
    const std::string three = R"([{"face":0,"uv":[0,0]},{"face":0,"uv":[1,0]},{"face":0,"uv":[0,1]}])";
    // the count is checked before the points are read: the mesh and the bad third point are never looked at
    expect_problem(post(json_request(cube, R"(,"points":)" + three), context_with(limits)), 422, "budget_exceeded",
                   "points");
    limits = {};
    limits.max_input_faces = 5;
    expect_problem(post(json_request(cube, R"(,"points":[{"face":0,"uv":[0,0]}])"), context_with(limits)), 422,
                   "budget_exceeded");
    Cancel cancel;
    cancel.deadline = Cancel::Clock::now() - std::chrono::seconds(1);
    expect_problem(post(json_request(cube, R"(,"points":[{"face":0,"uv":[0,0]}])"), context_with({}, cancel)), 503,
                   "cancelled", "");
}

}  // namespace
}  // namespace surfaced::api
