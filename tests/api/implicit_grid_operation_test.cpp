// POST /implicit/grid called through dispatch (no sockets): the answer is a level_set node with the geometry
// library's values, it goes back into /implicit/mesh as a scene and gives the sphere's volume, a scene is sampled
// and clamped, and every error names its field, budgets before work.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "api/routes.h"
#include "geometry/implicit/distance_grid.h"
#include "geometry/mesh/shapes.h"
#include "tests/support/api_request.h"
#include "tests/support/mesh_asserts.h"
#include "tests/support/simplify_meshes.h"

namespace surfaced::api {
namespace {

using namespace fixtures;

ApiResponse post(const std::string& body, const ApiContext& context = {}, const std::string& path = "/implicit/grid") {
    return dispatch(make_request("POST", path, "application/json", body), context);
}

TEST(ImplicitGridOperation, MeshAnswerIsTheLevelSetNodeOfTheGeometryGrid) {
    const PolygonMesh torus = shapes::torus(16, 8, 1.0, 0.35);
    const ApiResponse response = post(json_request(torus, R"(,"voxel_size":0.125,"band":2)"));
    ASSERT_EQ(response.status, 200) << response.body;
    EXPECT_EQ(response.content_type, "application/json");
    const auto node = nlohmann::json::parse(response.body);
    EXPECT_EQ(node.size(), 5u);
    EXPECT_EQ(node["op"], "level_set");
    implicit::DistanceGridOptions options;
    options.voxel_size = 0.125;
    options.band = 2;
    implicit::DistanceGridStats stats;
    const auto grid = implicit::mesh_distance_grid(torus, options, &stats);
    ASSERT_TRUE(grid.ok());
    EXPECT_EQ(node["dims"], nlohmann::json(grid->dims));
    EXPECT_EQ(node["spacing"], 0.125);
    for (int a = 0; a < 3; ++a) EXPECT_EQ(node["origin"][static_cast<std::size_t>(a)].get<double>(), grid->origin[a]);
    ASSERT_EQ(node["values"].size(), grid->values.size());
    for (std::size_t i = 0; i < grid->values.size(); ++i)
        ASSERT_EQ(node["values"][i].get<double>(), grid->values[i]) << i;  // shortest round trip: exact
    EXPECT_EQ(header(response, "X-Grid"), std::to_string(grid->dims[0]) + "x" + std::to_string(grid->dims[1]) + "x" +
                                              std::to_string(grid->dims[2]));
    EXPECT_EQ(header(response, "X-Grid-Nodes"), std::to_string(grid->values.size()));
    EXPECT_EQ(header(response, "X-Band-Nodes"), std::to_string(stats.band_nodes));
    EXPECT_EQ(header(response, "X-Winding-Queries"), std::to_string(stats.winding_queries));
    EXPECT_FALSE(header(response, "X-Elapsed-Ms").empty());
    EXPECT_NE(header(response, "Server-Timing").find("grid;dur="), std::string::npos);
}

TEST(ImplicitGridOperation, SphereRoundTripsThroughImplicitMesh) {
    // mesh -> /implicit/grid -> the answer as the scene of /implicit/mesh: the mesh's volume to within 1%
    const PolygonMesh sphere = testing::icosphere(4, 1.0);
    const ApiResponse grid = post(json_request(sphere, R"(,"voxel_size":0.04,"band":3)"));
    ASSERT_EQ(grid.status, 200) << grid.body.substr(0, 500);
    const std::string body =
        R"({"scene":)" + grid.body +
        R"(,"bounds":[[-1.1,-1.1,-1.1],[1.1,1.1,1.1]],"cell_size":0.04,"output":{"format":"json"}})";
    const ApiResponse meshed = post(body, {}, "/implicit/mesh");
    ASSERT_EQ(meshed.status, 200) << meshed.body.substr(0, 500);
    const auto doc = nlohmann::json::parse(meshed.body);
    PolygonMesh mesh;
    for (const auto& p : doc["mesh"]["positions"]) mesh.positions.push_back({p[0], p[1], p[2]});
    for (const auto& f : doc["mesh"]["faces"]) mesh.add_face({f[0].get<Index>(), f[1].get<Index>(), f[2].get<Index>()});
    const double expected = testing::signed_volume(sphere);
    EXPECT_NEAR(testing::signed_volume(mesh), expected, 0.01 * expected);
}

TEST(ImplicitGridOperation, SceneIsSampledAndClamped) {
    const ApiResponse response =
        post(R"({"scene":{"op":"sphere","radius":0.5},"bounds":[[-1,-1,-1],[1,1,1]],"voxel_size":0.5,"band":1})");
    ASSERT_EQ(response.status, 200) << response.body;
    const auto node = nlohmann::json::parse(response.body);
    EXPECT_EQ(node["dims"], nlohmann::json({5, 5, 5}));
    EXPECT_EQ(node["origin"], nlohmann::json({-1, -1, -1}));
    // node (2, 2, 2) is the centre: -0.5, clamped to -band * h = -0.5; a corner is sqrt(3) - 0.5, clamped to 0.5;
    // (3, 2, 2) is on the sphere: 0
    EXPECT_EQ(node["values"][62].get<double>(), -0.5);
    EXPECT_EQ(node["values"][0].get<double>(), 0.5);
    EXPECT_EQ(node["values"][63].get<double>(), 0.0);
    EXPECT_FALSE(header(response, "X-Field-Evaluations").empty());
    EXPECT_EQ(header(response, "X-Winding-Queries"), "0");
}

TEST(ImplicitGridOperation, ErrorsNameTheirFields) {
    const std::string tet = R"({"positions":[[1,1,1],[1,-1,-1],[-1,1,-1],[-1,-1,1]],)"
                            R"("faces":[[0,1,2],[0,3,1],[0,2,3],[1,3,2]]})";
    const std::string sphere = R"({"op":"sphere","radius":1})";
    expect_problem(post(R"({"voxel_size":0.1})"), 400, "invalid_field", "mesh");
    expect_problem(post(R"({"mesh":)" + tet + R"(,"scene":)" + sphere + R"(,"voxel_size":0.1})"), 400, "invalid_field",
                   "scene");
    expect_problem(post(R"({"mesh":)" + tet + "}"), 400, "invalid_field", "voxel_size");
    expect_problem(post(R"({"mesh":)" + tet + R"(,"voxel_size":0})"), 400, "invalid_field", "voxel_size");
    expect_problem(post(R"({"mesh":)" + tet + R"(,"voxel_size":0.1,"band":0})"), 400, "invalid_field", "band");
    expect_problem(post(R"({"mesh":)" + tet + R"(,"voxel_size":0.1,"band":65})"), 400, "invalid_field", "band");
    expect_problem(post(R"({"mesh":)" + tet + R"(,"voxel_size":0.1,"bands":2})"), 400, "unknown_field", "bands");
    expect_problem(post(R"({"scene":)" + sphere + R"(,"voxel_size":0.1})"), 400, "invalid_field", "bounds");
    expect_problem(post(R"({"mesh":)" + tet + R"(,"voxel_size":0.1,"bounds":[[0,0,0],[0,1,1]]})"), 422,
                   "invalid_argument", "bounds[1][0]");
    expect_problem(post(R"({"scene":{"op":"sphere","radius":-1},"bounds":[[0,0,0],[1,1,1]],"voxel_size":0.1})"), 422,
                   "invalid_argument", "scene.radius");
    expect_problem(post(R"({"mesh":{"positions":[[0,0,0]],"faces":[[0,1,2]]},"voxel_size":0.1})"), 422,
                   "index_out_of_range", "mesh.faces[0][1]");
    expect_problem(post(R"({"mesh":{"positions":[],"faces":[]},"voxel_size":0.1})"), 422, "invalid_argument",
                   "mesh.faces");
    expect_problem(dispatch(make_request("POST", "/implicit/grid", "model/obj", "v 0 0 0"), {}), 415,
                   "unsupported_media_type");
}

TEST(ImplicitGridOperation, NodeBudgetIsCheckedBeforeWork) {
    Limits limits;
    limits.max_level_set_samples = 1000;
    const std::string tet = R"({"positions":[[1,1,1],[1,-1,-1],[-1,1,-1],[-1,-1,1]],)"
                            R"("faces":[[0,1,2],[0,3,1],[0,2,3],[1,3,2]]})";
    // default bounds (the mesh's box grown by band + 1 voxels): 2 / 0.1 + 9 nodes per axis
    expect_problem(post(R"({"mesh":)" + tet + R"(,"voxel_size":0.1})", context_with(limits)), 422, "budget_exceeded",
                   "voxel_size");
    // bounds given: refused before the scene is even read (its error would be a 400 otherwise)
    expect_problem(
        post(R"({"scene":{"op":"nothing"},"bounds":[[0,0,0],[1,1,1]],"voxel_size":0.01})", context_with(limits)), 422,
        "budget_exceeded", "voxel_size");
    // a coarse grid fits (9 nodes per axis), and is accepted back as a level_set node under the same limits
    const ApiResponse coarse = post(R"({"mesh":)" + tet + R"(,"voxel_size":0.5,"band":1})", context_with(limits));
    ASSERT_EQ(coarse.status, 200) << coarse.body;
    const ApiResponse back =
        post(R"({"scene":)" + coarse.body + R"(,"points":[[0,0,0],[3,0,0]]})", context_with(limits), "/implicit/query");
    ASSERT_EQ(back.status, 200) << back.body;
    const auto points = nlohmann::json::parse(back.body)["points"];
    EXPECT_EQ(points[0]["class"], "inside");
    EXPECT_EQ(points[1]["class"], "outside");
}

TEST(ImplicitGridOperation, CancelledIsServiceUnavailable) {
    std::atomic<bool> abort{true};
    Cancel cancel;
    cancel.flag = &abort;
    expect_problem(post(R"({"scene":{"op":"sphere","radius":1},"bounds":[[-1,-1,-1],[1,1,1]],"voxel_size":0.1})",
                        context_with({}, cancel)),
                   503, "cancelled");
}

}  // namespace
}  // namespace surfaced::api
