// POST /implicit/mesh called through dispatch (no sockets): the issue's example scene meshed closed and manifold
// with the analytic volume, every output format, headers, and errors with field paths and budgets checked first.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <numbers>
#include <string>

#include <nlohmann/json.hpp>

#include "api/routes.h"
#include "geometry/io/gltf.h"
#include "geometry/io/mesh_io.h"
#include "tests/support/mesh_asserts.h"

namespace surfaced::api {
namespace {

std::string header_of(const ApiResponse& response, std::string_view name) {
    for (const auto& [key, value] : response.headers)
        if (key == name) return value;
    return "";
}

ApiResponse post(const std::string& body, const ApiContext& context = {},
                 std::string content_type = "application/json") {
    ApiRequest request;
    request.method = "POST";
    request.path = "/implicit/mesh";
    request.content_type = std::move(content_type);
    request.body = body;
    return dispatch(request, context);
}

void expect_problem(const ApiResponse& response, int status, const std::string& code, const std::string& field) {
    EXPECT_EQ(response.status, status) << response.body;
    EXPECT_EQ(response.content_type, "application/problem+json");
    ASSERT_TRUE(response.error.has_value()) << response.body;
    if (!code.empty()) {
        EXPECT_EQ(response.error->code, code) << response.body;
    }
    if (!field.empty()) {
        EXPECT_EQ(response.error->field.value_or("<none>"), field) << response.body;
    }
}

//! The issue's example: a unit box minus a ball of radius 0.5 centred on its top face.
const std::string kScene =
    R"({"op": "difference", "args": [{"op": "box", "half_size": [1, 1, 1]},
        {"op": "translate", "offset": [0, 0, 1], "arg": {"op": "sphere", "radius": 0.5}}]})";

std::string request_body(const std::string& extra) {
    return R"({"scene": )" + kScene + R"(, "bounds": [[-1.25, -1.25, -1.25], [1.25, 1.25, 1.25]])" +
           (extra.empty() ? "" : ", " + extra) + "}";
}

PolygonMesh mesh_from_json(const std::string& body) {
    const auto doc = nlohmann::json::parse(body);
    PolygonMesh mesh;
    for (const auto& p : doc["mesh"]["positions"]) mesh.positions.push_back({p[0], p[1], p[2]});
    for (const auto& f : doc["mesh"]["faces"]) mesh.add_face({f[0].get<Index>(), f[1].get<Index>(), f[2].get<Index>()});
    return mesh;
}

TEST(ImplicitMeshOperation, IssueExampleIsClosedWithTheAnalyticVolume) {
    const ApiResponse response = post(request_body(R"("resolution": 64, "output": {"format": "json"})"));
    ASSERT_EQ(response.status, 200) << response.body;
    EXPECT_EQ(response.content_type, "application/json");
    const PolygonMesh mesh = mesh_from_json(response.body);
    ASSERT_TRUE(validate(mesh).ok());
    EXPECT_TRUE(testing::is_watertight(mesh));
    const double volume = 8.0 - 2.0 / 3.0 * std::numbers::pi * 0.125;
    EXPECT_NEAR(testing::signed_volume(mesh) / volume, 1.0, 0.005);
    EXPECT_EQ(header_of(response, "X-Grid"), "64x64x64");
    EXPECT_EQ(header_of(response, "X-Grid-Cells"), std::to_string(64 * 64 * 64));
    EXPECT_EQ(header_of(response, "X-Output-Faces"), std::to_string(mesh.face_count()));
    EXPECT_EQ(header_of(response, "X-Output-Vertices"), std::to_string(mesh.vertex_count()));
    EXPECT_FALSE(header_of(response, "X-Field-Evaluations").empty());
    EXPECT_NE(header_of(response, "Server-Timing").find("mesh;dur="), std::string::npos);
    const auto stats = nlohmann::json::parse(response.body)["stats"];
    EXPECT_EQ(stats["output_faces"].get<std::size_t>(), mesh.face_count());
}

TEST(ImplicitMeshOperation, AdaptiveModeEvaluatesLessForTheSameMesh) {
    // bounds with room around the shape: most octree blocks are provably empty
    const std::string body = R"({"scene": )" + kScene + R"(, "bounds": [[-2, -2, -2], [2, 2, 2]], "resolution": 64,
                                 "output": {"format": "json"}})";
    const ApiResponse uniform = post(body);
    const ApiResponse adaptive = post(body.substr(0, body.size() - 1) + R"(, "mode": "adaptive"})");
    ASSERT_EQ(uniform.status, 200) << uniform.body;
    ASSERT_EQ(adaptive.status, 200) << adaptive.body;
    EXPECT_EQ(header_of(adaptive, "X-Output-Faces"), header_of(uniform, "X-Output-Faces"));
    EXPECT_LT(std::stoull(header_of(adaptive, "X-Field-Evaluations")) * 2,
              std::stoull(header_of(uniform, "X-Field-Evaluations")));
    EXPECT_TRUE(testing::is_watertight(mesh_from_json(adaptive.body)));
}

TEST(ImplicitMeshOperation, EveryOutputFormatDecodesToTheSameClosedMesh) {
    const ApiResponse json = post(request_body(R"("resolution": 24, "output": {"format": "json"})"));
    ASSERT_EQ(json.status, 200) << json.body;
    const std::size_t faces = mesh_from_json(json.body).face_count();
    struct Case {
        const char* output;
        const char* media_type;
        MeshFormat format;
    };
    for (const Case& c : {Case{R"({"format": "glb"})", "model/gltf-binary", MeshFormat::Glb},
                          Case{R"({"format": "glb", "compression": "none"})", "model/gltf-binary", MeshFormat::Glb},
                          Case{R"({"format": "obj"})", "model/obj", MeshFormat::Obj},
                          Case{R"({"format": "ply"})", "application/ply", MeshFormat::Ply}}) {
        SCOPED_TRACE(c.output);
        const ApiResponse response = post(request_body(std::string(R"("resolution": 24, "output": )") + c.output));
        ASSERT_EQ(response.status, 200) << response.body;
        EXPECT_EQ(response.content_type, c.media_type);
        auto mesh = read_mesh(response.body, c.format);
        ASSERT_TRUE(mesh.ok()) << mesh.error().message;
        EXPECT_EQ(mesh->face_count(), faces);
        if (c.format != MeshFormat::Glb || std::string(c.output).find("none") != std::string::npos) {
            EXPECT_TRUE(testing::is_watertight(mesh.value()));
        }
    }
    const ApiResponse gltf = post(request_body(R"("resolution": 16, "output": {"format": "gltf"})"));
    EXPECT_EQ(gltf.status, 200) << gltf.body;
}

TEST(ImplicitMeshOperation, BudgetIsCheckedBeforeTheSceneIsEvenParsed) {
    ApiContext context;
    context.limits.max_grid_cells = 32 * 32 * 32;
    // a broken scene: the budget error comes first, so nothing was parsed or evaluated
    const std::string body = R"({"scene": {"op": "nonsense"}, "bounds": [[-1, -1, -1], [1, 1, 1]], "resolution": 33})";
    expect_problem(post(body, context), 422, "budget_exceeded", "resolution");
    const std::string by_size =
        R"({"scene": {"op": "sphere", "radius": 1}, "bounds": [[-1, -1, -1], [1, 1, 1]], "cell_size": 0.01})";
    expect_problem(post(by_size, context), 422, "budget_exceeded", "cell_size");
    // within the budget the same scene error names its path
    const std::string ok_size =
        R"({"scene": {"op": "nonsense"}, "bounds": [[-1, -1, -1], [1, 1, 1]], "resolution": 32})";
    const ApiResponse scene_error = post(ok_size, context);
    EXPECT_EQ(scene_error.status / 100, 4) << scene_error.body;
    ASSERT_TRUE(scene_error.error.has_value());
    EXPECT_EQ(scene_error.error->field.value_or("").rfind("scene", 0), 0u) << scene_error.body;
    // a resolution that would overflow 32-bit cell counts is still a clean 4xx
    expect_problem(post(R"({"scene": {"op": "sphere", "radius": 1}, "bounds": [[-1, -1, -1], [1, 1, 1]],
                           "resolution": 65536})"),
                   422, "budget_exceeded", "resolution");
}

TEST(ImplicitMeshOperation, BadRequestsNameTheField) {
    const std::string sphere = R"("scene": {"op": "sphere", "radius": 1})";
    const std::string bounds = R"("bounds": [[-2, -2, -2], [2, 2, 2]])";
    expect_problem(post("{" + bounds + "}"), 400, "invalid_field", "scene");
    expect_problem(post("{" + sphere + "}"), 400, "invalid_field", "bounds");
    const ApiResponse reversed = post("{" + sphere + R"(, "bounds": [[1, 1, 1], [0, 0, 0]]})");
    EXPECT_EQ(reversed.status / 100, 4) << reversed.body;
    ASSERT_TRUE(reversed.error.has_value());
    EXPECT_EQ(reversed.error->field.value_or("").rfind("bounds", 0), 0u) << reversed.body;
    expect_problem(post("{" + sphere + ", " + bounds + R"(, "resolution": 1})"), 400, "invalid_field", "resolution");
    expect_problem(post("{" + sphere + ", " + bounds + R"(, "resolution": 2.5})"), 400, "invalid_field", "resolution");
    expect_problem(post("{" + sphere + ", " + bounds + R"(, "resolution": 8, "cell_size": 0.1})"), 400, "invalid_field",
                   "cell_size");
    expect_problem(post("{" + sphere + ", " + bounds + R"(, "cell_size": -1})"), 400, "invalid_field", "cell_size");
    expect_problem(post("{" + sphere + ", " + bounds + R"(, "mode": "octree"})"), 400, "invalid_field", "mode");
    expect_problem(post("{" + sphere + ", " + bounds + R"(, "simplify_tolerance": 0.01})"), 400, "invalid_field",
                   "simplify_tolerance");
    expect_problem(post("{" + sphere + ", " + bounds + R"(, "levels": 2})"), 400, "unknown_field", "");
    expect_problem(post("{" + sphere + ", " + bounds + R"(, "output": {"format": "obj", "compression": "draco"}})"),
                   400, "invalid_field", "output.compression");
    expect_problem(post("{" + sphere + ", " + bounds + "}", {}, "model/obj"), 415, "", "");
    expect_problem(post("{\"scene\": "), 400, "invalid_json", "");
    ApiRequest with_query;
    with_query.method = "POST";
    with_query.path = "/implicit/mesh";
    with_query.content_type = "application/json";
    const std::string body = "{" + sphere + ", " + bounds + "}";
    with_query.body = body;
    with_query.query.emplace("resolution", "8");
    EXPECT_EQ(dispatch(with_query, ApiContext{}).status, 400);
}

TEST(ImplicitMeshOperation, OutputBudgetAndCancel) {
    ApiContext small;
    small.limits.max_output_faces = 100;
    expect_problem(post(request_body(R"("resolution": 32)"), small), 422, "budget_exceeded", "resolution");
    std::atomic<bool> abort{true};
    ApiContext cancelled;
    cancelled.cancel.flag = &abort;
    const ApiResponse response = post(request_body(R"("resolution": 32)"), cancelled);
    EXPECT_EQ(response.status, 503) << response.body;
}

TEST(ImplicitMeshOperation, SimplifiedAdaptiveMeshIsSmallerAndClosed) {
    const ApiResponse response = post(request_body(
        R"("resolution": 24, "mode": "adaptive", "simplify_tolerance": 0.01, "output": {"format": "json"})"));
    ASSERT_EQ(response.status, 200) << response.body;
    const ApiResponse full = post(request_body(R"("resolution": 24, "output": {"format": "json"})"));
    const PolygonMesh mesh = mesh_from_json(response.body);
    EXPECT_TRUE(testing::is_watertight(mesh));
    EXPECT_LT(mesh.face_count() * 2, mesh_from_json(full.body).face_count());
}

}  // namespace
}  // namespace surfaced::api
