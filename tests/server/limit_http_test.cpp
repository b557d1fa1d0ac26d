// POST /limit/evaluate over a real loopback socket: the JSON form against LimitSurfaceEvaluator, the mesh as an OBJ
// file part whose subdivision tags reach the evaluator (a sharp crease changes the answer exactly as the evaluator
// says), the packed form, and the transport and budget refusals (413, 415, 422) as problem+json.
#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "geometry/io/mesh_io.h"
#include "geometry/mesh/shapes.h"
#include "geometry/subdivision/limit_evaluation.h"
#include "tests/support/http_test_server.h"

namespace surfaced::server {
namespace {

using Json = nlohmann::json;
using testing::expect_http_problem;

constexpr std::size_t kBodyLimit = 256 << 10;
constexpr std::uint64_t kPointLimit = 500;

class LimitHttp : public testing::SharedServerTest<LimitHttp> {
public:
    static ServerConfig suite_config() {
        ServerConfig config = SharedServerTest::suite_config();
        config.limits.max_body_bytes = kBodyLimit;
        config.limits.max_limit_points = kPointLimit;
        return config;
    }
};

Json mesh_json(const PolygonMesh& mesh) {
    Json positions = Json::array(), faces = Json::array();
    for (const Vec3& p : mesh.positions) positions.push_back({p.x, p.y, p.z});
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const auto face = mesh.face(f);
        faces.push_back(std::vector<Index>(face.begin(), face.end()));
    }
    return {{"positions", positions}, {"faces", faces}};
}

Vec3 vec(const Json& v) { return {v[0].get<double>(), v[1].get<double>(), v[2].get<double>()}; }

TEST_F(LimitHttp, JsonAnswersAreTheEvaluators) {
    const PolygonMesh torus = shapes::irregular_torus();
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> unit(0, 1);
    Json points = Json::array();
    std::vector<std::array<double, 3>> asked;
    for (int k = 0; k < 200; ++k) {
        const std::size_t f = rng() % torus.face_count();
        if (torus.face_size(f) != 4) continue;
        asked.push_back({double(f), unit(rng), unit(rng)});
        points.push_back({{"face", f}, {"uv", {asked.back()[1], asked.back()[2]}}});
    }
    const Json body = {{"mesh", mesh_json(torus)}, {"points", points}, {"derivatives", 2}};
    auto res = client().Post("/limit/evaluate", body.dump(), "application/json");
    ASSERT_TRUE(res) << httplib::to_string(res.error());
    ASSERT_EQ(res->status, 200) << res->body;
    EXPECT_EQ(res->get_header_value("Content-Type"), "application/json");
    const Json out = Json::parse(res->body);
    const auto evaluator = LimitSurfaceEvaluator::create(torus, {});
    ASSERT_TRUE(evaluator.ok());
    ASSERT_EQ(out["points"].size(), asked.size());
    for (std::size_t k = 0; k < asked.size(); ++k) {
        const auto s = evaluator->evaluate(static_cast<std::size_t>(asked[k][0]), asked[k][1], asked[k][2], true);
        ASSERT_TRUE(s.ok());
        EXPECT_LE(norm(vec(out["points"][k]["position"]) - s->position), 1e-12) << k;
        EXPECT_LE(norm(vec(out["points"][k]["dvv"]) - s->dvv), 1e-9) << k;
    }
}

TEST_F(LimitHttp, AnObjFilePartKeepsItsCreaseTags) {
    // the cube with one infinitely sharp crease along the edge of vertices 1 and 2 (OBJ indices 2 and 3)
    const std::string obj = write_obj(shapes::cube()) + "t crease 2/1/0 1 2 10\n";
    const PolygonMesh tagged = read_obj(obj).value();
    ASSERT_EQ(tagged.tags.creases.size(), 1u);
    const std::string request = R"({"points": [{"face": 0, "uv": [0.5, 0.5]}, {"face": 4, "uv": [0.5, 0.1]}]})";
    httplib::MultipartFormDataItems form = {{"file", obj, "cube.obj", "application/octet-stream"},
                                            {"request", request, "request.json", "application/json"}};
    auto res = client().Post("/limit/evaluate", form);
    ASSERT_TRUE(res) << httplib::to_string(res.error());
    ASSERT_EQ(res->status, 200) << res->body;
    const Json out = Json::parse(res->body);
    const auto sharp = LimitSurfaceEvaluator::create(tagged, {});
    const auto smooth = LimitSurfaceEvaluator::create(shapes::cube(), {});
    ASSERT_TRUE(sharp.ok() && smooth.ok());
    const double uv[2][3] = {{0, 0.5, 0.5}, {4, 0.5, 0.1}};
    bool crease_matters = false;
    for (std::size_t k = 0; k < 2; ++k) {
        const auto s = sharp->evaluate(static_cast<std::size_t>(uv[k][0]), uv[k][1], uv[k][2]);
        const auto t = smooth->evaluate(static_cast<std::size_t>(uv[k][0]), uv[k][1], uv[k][2]);
        ASSERT_TRUE(s.ok() && t.ok());
        EXPECT_LE(norm(vec(out["points"][k]["position"]) - s->position), 1e-12) << k;
        crease_matters = crease_matters || norm(s->position - t->position) > 1e-3;
    }
    EXPECT_TRUE(crease_matters);  // the points see the crease, so the check above could fail without the tag
}

TEST_F(LimitHttp, PackedAnswersOverHttp) {
    const Json body = {
        {"mesh", mesh_json(shapes::cube())}, {"points", {{{"face", 0}, {"uv", {0.5, 0.5}}}}}, {"encoding", "float64"}};
    auto res = client().Post("/limit/evaluate", body.dump(), "application/json");
    ASSERT_TRUE(res);
    ASSERT_EQ(res->status, 200) << res->body;
    const Json out = Json::parse(res->body);
    EXPECT_EQ(out["encoding"], "float64");
    EXPECT_EQ(out["points"]["position"].get<std::string>().size(), 32u);  // 24 bytes in base64
}

TEST_F(LimitHttp, RefusalsAreProblems) {
    const Json cube = mesh_json(shapes::cube());
    // more points than the server takes: 422 naming points, before any is read
    Json many = Json::array();
    for (std::uint64_t k = 0; k <= kPointLimit; ++k) many.push_back({{"face", 0}, {"uv", {0.5, 0.5}}});
    expect_http_problem(
        client().Post("/limit/evaluate", Json{{"mesh", cube}, {"points", many}}.dump(), "application/json"), 422,
        "budget_exceeded", "points");
    // a body over the server's limit: 413
    const std::string big(kBodyLimit + 1, ' ');
    expect_http_problem(client().Post("/limit/evaluate", big, "application/json"), 413, "payload_too_large");
    // a media type it does not read: 415
    expect_http_problem(client().Post("/limit/evaluate", "v 0 0 0\n", "model/obj"), 415, "unsupported_media_type");
    // a bad point: 422 naming it
    expect_http_problem(
        client().Post("/limit/evaluate", Json{{"mesh", cube}, {"points", {{{"face", 0}, {"uv", {2, 0}}}}}}.dump(),
                      "application/json"),
        422, "invalid_argument", "points[0].uv");
}

}  // namespace
}  // namespace surfaced::server
