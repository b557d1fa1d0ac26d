// POST /remesh, /implicit/mesh, /implicit/query, /mesh/query, /pointcloud and /reconstruct through the real server on an ephemeral loopback
// port: status, media type, a decoded-body invariant, and one problem+json naming its field for each. And every JSON
// request example of the OpenAPI document (`example` and named `examples`) sent to the live server.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "api/openapi.h"
#include "geometry/io/gltf.h"
#include "geometry/io/pointcloud_io.h"
#include "tests/support/http_test_server.h"
#include "tests/support/mesh_asserts.h"

namespace surfaced::server {
namespace {

using Json = nlohmann::json;
using testing::expect_http_problem;

constexpr const char* kCubeObj =
    "v -0.5 -0.5 -0.5\nv 0.5 -0.5 -0.5\nv 0.5 0.5 -0.5\nv -0.5 0.5 -0.5\n"
    "v -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv 0.5 0.5 0.5\nv -0.5 0.5 0.5\n"
    "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

constexpr const char* kUnitSphere = R"({"op": "sphere", "radius": 1})";

class GeometryHttp : public testing::SharedServerTest<GeometryHttp> {
protected:
    static httplib::Client client() { return SharedServerTest::client(60); }
};

double length(const Vec3& p) { return std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z); }

TEST_F(GeometryHttp, RemeshObjToClosedGlb) {
    auto res = client().Post("/remesh?edge_length=0.2&iterations=3", kCubeObj, "model/obj");
    ASSERT_TRUE(res) << httplib::to_string(res.error());
    ASSERT_EQ(res->status, 200) << res->body;
    EXPECT_EQ(res->get_header_value("Content-Type"), "model/gltf-binary");
    EXPECT_EQ(res->get_header_value("X-Triangulated"), "true");  // quads in, triangles out
    auto mesh = read_glb(res->body);
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    ASSERT_GT(mesh->face_count(), 12u);  // refined from the 12 triangles of the triangulated cube
    EXPECT_EQ(std::to_string(mesh->face_count()), res->get_header_value("X-Output-Faces"));
    EXPECT_TRUE(testing::is_watertight(mesh.value()));
    EXPECT_NEAR(testing::signed_volume(mesh.value()), 1.0, 1e-3);  // the cube's features are kept

    const std::string bad = std::string(R"({"mesh": {"positions": [[0,0,0],[1,0,0],[0,1,0]], "faces": [[0,1,2]]},)") +
                            R"( "edge_length": 0})";
    expect_http_problem(client().Post("/remesh", bad, "application/json"), 400, "invalid_field", "edge_length");
}

TEST_F(GeometryHttp, ImplicitMeshSphereToClosedGlb) {
    const std::string body = std::string(R"({"scene": )") + kUnitSphere +
                             R"(, "bounds": [[-1.5,-1.5,-1.5],[1.5,1.5,1.5]], "resolution": 24})";
    auto res = client().Post("/implicit/mesh", body, "application/json");
    ASSERT_TRUE(res) << httplib::to_string(res.error());
    ASSERT_EQ(res->status, 200) << res->body;
    EXPECT_EQ(res->get_header_value("Content-Type"), "model/gltf-binary");
    auto mesh = read_glb(res->body);
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    ASSERT_GT(mesh->face_count(), 0u);
    EXPECT_EQ(std::to_string(mesh->face_count()), res->get_header_value("X-Output-Faces"));
    EXPECT_TRUE(testing::is_watertight(mesh.value()));
    for (const Vec3& p : mesh->positions) EXPECT_NEAR(length(p), 1.0, 0.01);  // on the sphere (cell 0.125)
    EXPECT_NEAR(testing::signed_volume(mesh.value()) / (4.0 / 3.0 * std::numbers::pi), 1.0, 0.02);

    expect_http_problem(
        client().Post("/implicit/mesh", std::string(R"({"scene": )") + kUnitSphere + "}", "application/json"), 400,
        "invalid_field", "bounds");
}

TEST_F(GeometryHttp, ImplicitQueryUnitSphere) {
    const std::string body = std::string(R"({"scene": )") + kUnitSphere +
                             R"(, "points": [[0,0,0],[2,0,0],[0,1,0],[0,0,-0.25]], "tolerance": 1e-9,)"
                             R"( "rays": [{"origin": [-5,0,0], "direction": [1,0,0]},)"
                             R"( {"origin": [0,5,0], "direction": [0,1,0]}], "max_distance": 20})";
    auto res = client().Post("/implicit/query", body, "application/json");
    ASSERT_TRUE(res) << httplib::to_string(res.error());
    ASSERT_EQ(res->status, 200) << res->body;
    EXPECT_EQ(res->get_header_value("Content-Type"), "application/json");
    const Json out = Json::parse(res->body);
    EXPECT_EQ(out["kind"], "exact_distance");
    const auto& points = out["points"];
    ASSERT_EQ(points.size(), 4u);
    EXPECT_EQ(points[0]["class"], "inside");
    EXPECT_DOUBLE_EQ(points[0]["value"].get<double>(), -1.0);
    EXPECT_EQ(points[1]["class"], "outside");
    EXPECT_DOUBLE_EQ(points[1]["value"].get<double>(), 1.0);
    EXPECT_EQ(points[1]["gradient"], Json::array({1.0, 0.0, 0.0}));
    EXPECT_EQ(points[2]["class"], "on");
    EXPECT_EQ(points[2]["gradient"], Json::array({0.0, 1.0, 0.0}));
    EXPECT_DOUBLE_EQ(points[3]["value"].get<double>(), -0.75);
    const auto& rays = out["rays"];
    ASSERT_EQ(rays.size(), 2u);
    EXPECT_TRUE(rays[0]["hit"].get<bool>());
    EXPECT_NEAR(rays[0]["t"].get<double>(), 4.0, 1e-6);
    EXPECT_NEAR(rays[0]["normal"][0].get<double>(), -1.0, 1e-6);
    EXPECT_FALSE(rays[1]["hit"].get<bool>());  // pointing away

    const std::string bad = std::string(R"({"scene": )") + kUnitSphere + R"(, "points": [[0,0,0],[1,0,"x"]]})";
    const Json problem =
        expect_http_problem(client().Post("/implicit/query", bad, "application/json"), 400, "invalid_field");
    EXPECT_EQ(problem.value("field", "").rfind("points[1]", 0), 0u) << problem.dump();
}

TEST_F(GeometryHttp, MeshQueryCubeSignedDistanceAndRays) {
    const std::string body =
        R"({"mesh": {"positions": [[-0.5,-0.5,-0.5],[0.5,-0.5,-0.5],[0.5,0.5,-0.5],[-0.5,0.5,-0.5],)"
        R"([-0.5,-0.5,0.5],[0.5,-0.5,0.5],[0.5,0.5,0.5],[-0.5,0.5,0.5]],)"
        R"( "faces": [[0,3,2,1],[4,5,6,7],[0,1,5,4],[2,3,7,6],[1,2,6,5],[0,4,7,3]]},)"
        R"( "points": [[0,0,0],[2,0,0],[1.5,1.5,0]], "want": ["inside", "distance", "closest"],)"
        R"( "rays": [[-5,0,0.25,1,0,0],[0,5,0,0,1,0]]})";
    auto res = client().Post("/mesh/query", body, "application/json");
    ASSERT_TRUE(res) << httplib::to_string(res.error());
    ASSERT_EQ(res->status, 200) << res->body;
    EXPECT_EQ(res->get_header_value("Content-Type"), "application/json");
    const Json out = Json::parse(res->body);
    const Json& points = out["points"];
    EXPECT_EQ(points["inside"], Json::array({true, false, false}));
    EXPECT_DOUBLE_EQ(points["distance"][0].get<double>(), -0.5);
    EXPECT_DOUBLE_EQ(points["distance"][1].get<double>(), 1.5);
    EXPECT_DOUBLE_EQ(points["distance"][2].get<double>(), std::sqrt(2.0));  // to the edge x = y = 0.5
    EXPECT_EQ(points["closest"][2], Json::array({0.5, 0.5, 0}));
    EXPECT_FALSE(points.contains("winding_number"));
    const Json& rays = out["rays"];
    EXPECT_EQ(rays["hit"], Json::array({true, false}));
    EXPECT_DOUBLE_EQ(rays["t"][0].get<double>(), 4.5);
    EXPECT_EQ(rays["face"][0], 5);
    EXPECT_TRUE(rays["point"][1].is_null());

    const std::string bad = R"({"mesh": {"positions": [[0,0,0],[1,0,0],[0,1,0]], "faces": [[0,1,2]]},)"
                            R"( "rays": [[0,0,1,0,0,-1],[0,0,1,0,0,0]]})";
    expect_http_problem(client().Post("/mesh/query", bad, "application/json"), 422, "invalid_argument", "rays[1]");
}

TEST_F(GeometryHttp, PointcloudSampledSphereWithOutwardNormals) {
    const std::string body = std::string(R"({"sample": {"scene": )") + kUnitSphere +
                             R"(, "bounds": [[-2,-2,-2],[2,2,2]], "count": 300, "seed": 5},)"
                             R"( "estimate_normals": {"k": 12}, "output": {"format": "json"}})";
    auto res = client().Post("/pointcloud", body, "application/json");
    ASSERT_TRUE(res) << httplib::to_string(res.error());
    ASSERT_EQ(res->status, 200) << res->body;
    EXPECT_EQ(res->get_header_value("Content-Type"), "application/json");
    EXPECT_EQ(res->get_header_value("X-Output-Points"), "300");
    const Json out = Json::parse(res->body);
    ASSERT_EQ(out["points"].size(), 300u);
    ASSERT_EQ(out["normals"].size(), 300u);
    for (std::size_t i = 0; i < 300; ++i) {
        const Vec3 p{out["points"][i][0], out["points"][i][1], out["points"][i][2]};
        const Vec3 n{out["normals"][i][0], out["normals"][i][1], out["normals"][i][2]};
        EXPECT_NEAR(length(p), 1.0, 1e-5) << i;
        EXPECT_GT((p.x * n.x + p.y * n.y + p.z * n.z) / length(p), 0.9) << i;  // outward
    }

    // the same points as binary PLY, read back
    auto ply = client().Post("/pointcloud", R"({"points": [[0,0,0],[1,0,0],[0,1,0]], "output": {"format": "ply"}})",
                             "application/json");
    ASSERT_TRUE(ply);
    ASSERT_EQ(ply->status, 200) << ply->body;
    EXPECT_EQ(ply->get_header_value("Content-Type"), "application/ply");
    auto cloud = read_ply_points(ply->body);
    ASSERT_TRUE(cloud.ok()) << cloud.error().message;
    ASSERT_EQ(cloud->positions.size(), 3u);
    EXPECT_EQ(cloud->positions[1].x, 1.0);

    expect_http_problem(client().Post("/pointcloud", R"({"points": 3})", "application/json"), 400, "invalid_field",
                        "points");
}

//! A unit sphere sampled on a Fibonacci lattice: positions and outward normals.
std::vector<std::pair<Vec3, Vec3>> sphere_samples(std::size_t n) {
    std::vector<std::pair<Vec3, Vec3>> out;
    const double golden = std::numbers::pi * (3 - std::sqrt(5.0));
    for (std::size_t i = 0; i < n; ++i) {
        const double z = 1 - (2 * static_cast<double>(i) + 1) / static_cast<double>(n);
        const double rho = std::sqrt(1 - z * z), t = golden * static_cast<double>(i);
        const Vec3 p{rho * std::cos(t), rho * std::sin(t), z};
        out.emplace_back(p, p);
    }
    return out;
}

TEST_F(GeometryHttp, ReconstructPlyBodyWithQueryOptionsAndJsonBody) {
    const auto samples = sphere_samples(2000);
    // an ascii PLY with normals as the raw body, the options in the query
    std::string ply = "ply\nformat ascii 1.0\nelement vertex " + std::to_string(samples.size()) +
                      "\nproperty double x\nproperty double y\nproperty double z\n"
                      "property float nx\nproperty float ny\nproperty float nz\nend_header\n";
    for (const auto& [p, n] : samples)
        ply += std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + " " + std::to_string(n.x) +
               " " + std::to_string(n.y) + " " + std::to_string(n.z) + "\n";
    auto res = client().Post("/reconstruct?depth=5&point_weight=4&format=obj", ply, "application/ply");
    ASSERT_TRUE(res) << httplib::to_string(res.error());
    ASSERT_EQ(res->status, 200) << res->body;
    EXPECT_EQ(res->get_header_value("Content-Type"), "model/obj");
    EXPECT_EQ(res->get_header_value("X-Input-Points"), "2000");
    EXPECT_EQ(res->get_header_value("X-Normals-Estimated"), "false");
    EXPECT_EQ(res->get_header_value("X-Depth"), "5");
    auto mesh = read_obj(res->body);
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    EXPECT_EQ(std::to_string(mesh->face_count()), res->get_header_value("X-Output-Faces"));
    EXPECT_TRUE(testing::is_watertight(mesh.value()));
    double worst = 0;
    for (const Vec3& p : mesh->positions) worst = std::max(worst, std::abs(length(p) - 1));
    EXPECT_LT(worst, 0.5 * 2.2 / 32);  // half the finest cell
    EXPECT_NEAR(testing::signed_volume(mesh.value()), 4.0 / 3.0 * std::numbers::pi, 0.05 * 4.19);

    // the points without normals as JSON, answered as Draco GLB: normals estimated and outward
    Json points = Json::array();
    for (const auto& sample : samples) points.push_back({sample.first.x, sample.first.y, sample.first.z});
    const Json body = {{"points", points}, {"depth", 5}, {"k", 12}};
    auto glb = client().Post("/reconstruct", body.dump(), "application/json");
    ASSERT_TRUE(glb) << httplib::to_string(glb.error());
    ASSERT_EQ(glb->status, 200) << glb->body;
    EXPECT_EQ(glb->get_header_value("Content-Type"), "model/gltf-binary");
    EXPECT_EQ(glb->get_header_value("X-Normals-Estimated"), "true");
    auto glb_mesh = read_glb(glb->body);
    ASSERT_TRUE(glb_mesh.ok()) << glb_mesh.error().message;
    EXPECT_GT(testing::signed_volume(glb_mesh.value()), 0.9 * 4.0 / 3.0 * std::numbers::pi);

    // that GLB posted back as the body: a mesh GLB's vertices are the points (normals estimated: it has none)
    auto again = client().Post("/reconstruct?depth=5&format=obj", glb->body, "model/gltf-binary");
    ASSERT_TRUE(again) << httplib::to_string(again.error());
    ASSERT_EQ(again->status, 200) << again->body;
    EXPECT_EQ(again->get_header_value("X-Input-Points"), glb->get_header_value("X-Output-Vertices"));
    auto again_mesh = read_obj(again->body);
    ASSERT_TRUE(again_mesh.ok()) << again_mesh.error().message;
    EXPECT_TRUE(testing::is_watertight(again_mesh.value()));
    EXPECT_GT(testing::signed_volume(again_mesh.value()), 0.9 * 4.0 / 3.0 * std::numbers::pi);
    expect_http_problem(client().Post("/reconstruct", std::string("glTF\x02\0\0\0", 8), "model/gltf-binary"), 400,
                        "parse_error");

    expect_http_problem(client().Post("/reconstruct?depth=1", ply, "application/ply"), 400, "invalid_field", "depth");
    expect_http_problem(client().Post("/reconstruct?depth=9", ply, "application/ply"), 422, "budget_exceeded", "depth");
}

// The document's request examples are what users copy: each one, sent over HTTP as documented, must succeed.
TEST_F(GeometryHttp, EveryOpenApiRequestExampleSucceedsOnTheLiveServer) {
    const Json doc = Json::parse(api::openapi_document());
    int sent = 0;
    for (const auto& [path, item] : doc["paths"].items())
        for (const auto& [method, operation] : item.items()) {
            if (method != "post" || !operation.contains("requestBody")) continue;
            const auto& content = operation["requestBody"]["content"];
            if (!content.contains("application/json")) continue;
            const auto& media = content["application/json"];
            std::vector<std::pair<std::string, std::string>> bodies;
            if (media.contains("example")) bodies.emplace_back("example", media["example"].dump());
            if (media.contains("examples"))
                for (const auto& [name, entry] : media["examples"].items())
                    if (entry.contains("value")) bodies.emplace_back(name, entry["value"].dump());
            for (const auto& [name, body] : bodies) {
                auto res = client().Post(path, body, "application/json");
                ASSERT_TRUE(res) << path << " (" << name << "): " << httplib::to_string(res.error());
                EXPECT_EQ(res->status, 200) << path << " (" << name << "): " << res->body;
                EXPECT_FALSE(res->body.empty()) << path << " (" << name << ")";
                ++sent;
            }
        }
    EXPECT_GE(sent, 10);
}

}  // namespace
}  // namespace surfaced::server
