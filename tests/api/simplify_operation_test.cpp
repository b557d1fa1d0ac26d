// POST /simplify called directly (no sockets): both request forms, the stats it reports, every error class, and
// budgets checked before any work.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/operations/simplify.h"
#include "api/routes.h"
#include "geometry/io/gltf.h"
#include "geometry/io/mesh_io.h"
#include "geometry/mesh/shapes.h"
#include "geometry/simplify/mesh_distance.h"
#include "tests/support/api_request.h"
#include "tests/support/gltf_validator.h"
#include "tests/support/mesh_asserts.h"
#include "tests/support/simplify_meshes.h"

namespace surfaced::api {
namespace {

using namespace fixtures;

ApiResponse call(const std::string& content_type, const std::string& body,
                 std::multimap<std::string, std::string> query = {}, const Limits& limits = {}) {
    // through the route table, as the server and the CLI do
    return dispatch(make_request("POST", "/simplify", content_type, body, std::move(query)), context_with(limits));
}

void expect_valid_glb(const std::string& bytes) {
    const auto validation = testing::run_gltf_validator(bytes);
    ASSERT_TRUE(validation.ran) << validation.report;
    EXPECT_EQ(validation.errors, 0) << validation.report;
    EXPECT_EQ(validation.warnings, 0) << validation.report;
}

// ---- good requests ---------------------------------------------------------------------------------------------

TEST(SimplifyOperation, JsonSphereToJsonWithStats) {
    const PolygonMesh sphere = testing::icosphere(3);  // 1280 faces
    const auto response =
        call("application/json", json_request(sphere, R"(,"target_faces":200,"output":{"format":"json"})"));
    ASSERT_EQ(response.status, 200) << response.body;
    EXPECT_EQ(response.content_type, "application/json");
    const auto json = nlohmann::json::parse(response.body);
    EXPECT_LE(json["mesh"]["faces"].size(), 200u);
    EXPECT_GE(json["mesh"]["faces"].size(), 198u);
    const auto& stats = json["stats"];
    EXPECT_EQ(stats["input_faces"], 1280);
    EXPECT_EQ(stats["output_faces"], json["mesh"]["faces"].size());
    EXPECT_EQ(stats["triangulated"], false);
    EXPECT_GT(stats["achieved_error"].get<double>(), 0);
    EXPECT_GT(stats["relative_error"].get<double>(), 0);
    EXPECT_FALSE(stats.contains("hausdorff"));
    EXPECT_EQ(header(response, "X-Input-Faces"), "1280");
    EXPECT_EQ(header(response, "X-Output-Faces"), std::to_string(json["mesh"]["faces"].size()));
    EXPECT_EQ(header(response, "X-Triangulated"), "false");
    EXPECT_FALSE(header(response, "X-Achieved-Error").empty());
    EXPECT_FALSE(header(response, "X-Relative-Error").empty());
    EXPECT_TRUE(header(response, "X-Hausdorff").empty());
    EXPECT_NE(header(response, "Server-Timing").find("simplify;dur="), std::string::npos);
}

TEST(SimplifyOperation, ReportErrorAndMaxErrorInJson) {
    const PolygonMesh sphere = testing::icosphere(4);
    const auto response =
        call("application/json",
             json_request(sphere, R"(,"max_error":0.01,"report_error":true,"output":{"format":"json"})"));
    ASSERT_EQ(response.status, 200) << response.body;
    const auto json = nlohmann::json::parse(response.body);
    const auto& stats = json["stats"];
    ASSERT_TRUE(stats.contains("hausdorff"));
    ASSERT_TRUE(stats.contains("rms"));
    EXPECT_LE(stats["hausdorff"].get<double>(), 0.01);
    EXPECT_LE(stats["rms"].get<double>(), stats["hausdorff"].get<double>());
    EXPECT_LE(stats["achieved_error"].get<double>(), 0.01);
    EXPECT_LT(stats["output_faces"].get<int>(), 5120 / 2);
    EXPECT_EQ(std::stod(header(response, "X-Hausdorff")), stats["hausdorff"].get<double>());
    EXPECT_EQ(std::stod(header(response, "X-RMS")), stats["rms"].get<double>());
}

TEST(SimplifyOperation, JsonDefaultIsValidDracoGlb) {
    const auto response = call("application/json", json_request(testing::icosphere(3), R"(,"ratio":0.25)"));
    ASSERT_EQ(response.status, 200) << response.body;
    EXPECT_EQ(response.content_type, "model/gltf-binary");
    EXPECT_NE(response.body.find("KHR_draco_mesh_compression"), std::string::npos);
    EXPECT_EQ(header(response, "X-Output-Faces"), "320");
    expect_valid_glb(response.body);
}

TEST(SimplifyOperation, RawObjWithQueryTriangulatesQuadsToObj) {
    const std::string torus = write_obj(shapes::torus(32, 16));
    const auto response =
        call("model/obj", torus, {{"target_faces", "200"}, {"format", "obj"}, {"report_error", "true"}});
    ASSERT_EQ(response.status, 200) << response.body;
    EXPECT_EQ(response.content_type, "model/obj");
    EXPECT_EQ(header(response, "X-Triangulated"), "true");
    EXPECT_EQ(header(response, "X-Input-Faces"), "512");
    auto mesh = read_obj(response.body);
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    EXPECT_LE(mesh->face_count(), 200u);
    EXPECT_TRUE(mesh->is_triangle_mesh());
    EXPECT_TRUE(testing::is_watertight(mesh.value()));
    EXPECT_EQ(testing::euler_characteristic(mesh.value()), 0);
    EXPECT_FALSE(header(response, "X-Hausdorff").empty());
}

TEST(SimplifyOperation, ObjWithUvsKeepsThemInUncompressedGlb) {
    const std::string cylinder = write_obj(testing::uv_cylinder(32, 8));
    const auto response = call("model/obj", cylinder, {{"ratio", "0.5"}, {"compression", "none"}});
    ASSERT_EQ(response.status, 200) << response.body;
    EXPECT_NE(response.body.find("TEXCOORD_0"), std::string::npos);
    expect_valid_glb(response.body);
    auto back = read_glb(response.body);
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_TRUE(back->has_uvs());
    EXPECT_LE(back->face_count(), 256u);
}

TEST(SimplifyOperation, RestoreVolumeKeepsTheVolumeOfASphere) {
    const PolygonMesh sphere = testing::icosphere(4);
    const double before = testing::signed_volume(sphere);
    // plain quadrics leave the coarse sphere inside the fine one; restore_volume=1 keeps the volume
    auto volume_after = [&](const char* restore) {
        const auto response = call("model/obj", write_obj(sphere),
                                   {{"target_faces", "200"}, {"restore_volume", restore}, {"format", "obj"}});
        EXPECT_EQ(response.status, 200) << response.body;
        auto mesh = read_obj(response.body);
        EXPECT_TRUE(mesh.ok());
        return mesh.ok() ? testing::signed_volume(mesh.value()) : 0.0;
    };
    const double plain = volume_after("0"), restored = volume_after("1");
    EXPECT_LT(plain, before);
    EXPECT_LT(std::fabs(restored - before), 0.2 * std::fabs(plain - before))
        << before << " " << plain << " " << restored;
}

// threads=2 reaches the same count through the same operation, as query parameter and as JSON field; on a mesh above
// the two-thread minimum (20,000 triangles) the result is its own (not threads=1's), the same on every call.
TEST(SimplifyOperation, TwoThreadsReachTheTargetAndRepeat) {
    const PolygonMesh sphere = testing::icosphere(5);  // 20,480 faces
    auto simplify = [&](const char* threads) {
        const auto response =
            call("model/obj", write_obj(sphere), {{"target_faces", "2000"}, {"threads", threads}, {"format", "obj"}});
        EXPECT_EQ(response.status, 200) << response.body;
        auto mesh = read_obj(response.body);
        EXPECT_TRUE(mesh.ok());
        return mesh.ok() ? std::move(mesh.value()) : PolygonMesh{};
    };
    const PolygonMesh one = simplify("1"), two = simplify("2"), again = simplify("2");
    EXPECT_EQ(one.face_count(), 2000u);
    EXPECT_EQ(two.face_count(), 2000u);
    EXPECT_TRUE(testing::is_watertight(two));
    EXPECT_EQ(two.positions, again.positions);
    EXPECT_NE(two.positions, one.positions);
    const auto json = call("application/json", json_request(sphere, R"(,"target_faces":2000,"threads":2)"));
    ASSERT_EQ(json.status, 200) << json.body.substr(0, 300);
}

TEST(SimplifyOperation, LockBorderKeepsTheBoundaryOfAGrid) {
    const PolygonMesh grid = shapes::grid(16, 16, true);
    const auto response =
        call("application/ply", write_ply(grid), {{"ratio", "0.2"}, {"lock_border", "true"}, {"format", "ply"}});
    ASSERT_EQ(response.status, 200) << response.body;
    auto mesh = read_ply(response.body);
    ASSERT_TRUE(mesh.ok());
    EXPECT_EQ(testing::boundary_positions(mesh.value()), testing::boundary_positions(grid));
    EXPECT_EQ(testing::boundary_loop_count(mesh.value()), 1u);
}

//! How many of `vertices` (indices into `input`) appear in a JSON response's mesh at exactly their input position.
std::size_t kept_exactly(const ApiResponse& response, const PolygonMesh& input, const std::vector<Index>& vertices) {
    const auto json = nlohmann::json::parse(response.body);
    std::size_t kept = 0;
    for (Index v : vertices) {
        const Vec3& p = input.positions[v];
        bool found = false;
        for (const auto& q : json["mesh"]["positions"])
            found = found || (q[0].get<double>() == p.x && q[1].get<double>() == p.y && q[2].get<double>() == p.z);
        kept += found ? 1 : 0;
    }
    return kept;
}

TEST(SimplifyOperation, LockedVerticesKeepTheirPositionsInBothForms) {
    const PolygonMesh sphere = testing::icosphere(3);  // 642 vertices, 1280 faces
    const std::vector<Index> locked = {0, 5, 100, 300, 641};
    const std::string list = R"(,"locked_vertices":[0,5,100,300,641])";
    // without the lock most of them move or go: the test below can fail
    const auto free =
        call("application/json", json_request(sphere, R"(,"target_faces":80,"output":{"format":"json"})"));
    ASSERT_EQ(free.status, 200) << free.body;
    EXPECT_LT(kept_exactly(free, sphere, locked), locked.size());

    const auto json =
        call("application/json", json_request(sphere, R"(,"target_faces":80,"output":{"format":"json"})" + list));
    ASSERT_EQ(json.status, 200) << json.body;
    EXPECT_EQ(kept_exactly(json, sphere, locked), locked.size());
    EXPECT_LE(std::stoi(header(json, "X-Output-Faces")), 80);

    const auto query = call("model/obj", write_obj(sphere),
                            {{"target_faces", "80"}, {"format", "json"}, {"locked_vertices", "0,5,100,300,641"}});
    ASSERT_EQ(query.status, 200) << query.body;
    EXPECT_EQ(kept_exactly(query, sphere, locked), locked.size());
    // an empty list locks nothing
    const auto empty =
        call("model/obj", write_obj(sphere), {{"target_faces", "80"}, {"format", "json"}, {"locked_vertices", ""}});
    ASSERT_EQ(empty.status, 200) << empty.body;
}

TEST(SimplifyOperation, LockedVerticesOutOfRangeAre422NamingTheItem) {
    const PolygonMesh m = testing::icosphere(1);  // 42 vertices
    expect_problem(call("application/json", json_request(m, R"(,"ratio":0.5,"locked_vertices":[0,42])")), 422,
                   "index_out_of_range", "locked_vertices[1]");
    expect_problem(call("application/json", json_request(m, R"(,"ratio":0.5,"locked_vertices":[3,-1])")), 400,
                   "invalid_field", "locked_vertices[1]");
    expect_problem(call("application/json", json_request(m, R"(,"ratio":0.5,"locked_vertices":[1.5])")), 400,
                   "invalid_field", "locked_vertices[0]");
    expect_problem(call("application/json", json_request(m, R"(,"ratio":0.5,"locked_vertices":7)")), 400,
                   "invalid_field", "locked_vertices");
    expect_problem(call("model/obj", write_obj(m), {{"ratio", "0.5"}, {"locked_vertices", "1,2,1000"}}), 422,
                   "index_out_of_range", "locked_vertices[2]");
    expect_problem(call("model/obj", write_obj(m), {{"ratio", "0.5"}, {"locked_vertices", "1,x"}}), 400,
                   "invalid_field", "locked_vertices[1]");
    expect_problem(call("model/obj", write_obj(m), {{"ratio", "0.5"}, {"locked_vertices", "1,,2"}}), 400,
                   "invalid_field", "locked_vertices[1]");
    expect_problem(call("model/obj", write_obj(m), {{"ratio", "0.5"}, {"locked_vertices", "-4"}}), 400, "invalid_field",
                   "locked_vertices[0]");
}

TEST(SimplifyOperation, OctetStreamIsSniffed) {
    const auto response =
        call("application/octet-stream", write_obj(testing::icosphere(2)), {{"ratio", "0.5"}, {"format", "ply"}});
    ASSERT_EQ(response.status, 200) << response.body;
    EXPECT_EQ(response.content_type, "application/ply");
}

TEST(SimplifyOperation, GltfJsonBodyByMediaTypeOrSniffed) {
    auto gltf = write_gltf(testing::icosphere(2), GltfOptions{.draco = false});
    ASSERT_TRUE(gltf.ok());
    for (const char* content_type : {"model/gltf+json", "application/octet-stream"}) {
        const auto response = call(content_type, *gltf, {{"ratio", "0.5"}, {"format", "obj"}});
        ASSERT_EQ(response.status, 200) << content_type << ": " << response.body;
        auto mesh = read_obj(response.body);
        ASSERT_TRUE(mesh.ok()) << mesh.error().message;
        EXPECT_LE(mesh->face_count(), testing::icosphere(2).face_count() / 2);
    }
}

// ---- errors, all before any work ---------------------------------------------------------------------------------

TEST(SimplifyOperation, NoStopCriterionIs400) {
    const auto json =
        expect_problem(call("application/json", json_request(testing::icosphere(1))), 400, "invalid_field");
    EXPECT_EQ(json.value("field", ""), "target_faces");
    expect_problem(call("model/obj", write_obj(testing::icosphere(1)), {{"format", "obj"}}), 400, "invalid_field");
}

TEST(SimplifyOperation, OutOfRangeOptionsAre400WithField) {
    const PolygonMesh m = testing::icosphere(1);
    // the field a 400 invalid_field names, for JSON members after "mesh" and for query parameters with an OBJ body
    const auto json_field = [&](const char* members) {
        return expect_problem(call("application/json", json_request(m, members)), 400, "invalid_field")
            .value("field", "");
    };
    const auto query_field = [&](std::multimap<std::string, std::string> query) {
        return expect_problem(call("model/obj", write_obj(m), std::move(query)), 400, "invalid_field")
            .value("field", "");
    };
    EXPECT_EQ(json_field(R"(,"ratio":0)"), "ratio");
    EXPECT_EQ(json_field(R"(,"ratio":1.5)"), "ratio");
    EXPECT_EQ(json_field(R"(,"max_error":-1)"), "max_error");
    EXPECT_EQ(json_field(R"(,"target_faces":-3)"), "target_faces");
    EXPECT_EQ(json_field(R"(,"ratio":"half")"), "ratio");
    EXPECT_EQ(json_field(R"(,"lock_border":1,"ratio":0.5)"), "lock_border");
    EXPECT_EQ(json_field(R"(,"ratio":0.5,"restore_volume":1.5)"), "restore_volume");
    EXPECT_EQ(json_field(R"(,"ratio":0.5,"threads":3)"), "threads");
    EXPECT_EQ(json_field(R"(,"ratio":0.5,"threads":1.5)"), "threads");
    EXPECT_EQ(query_field({{"ratio", "0.5"}, {"restore_volume", "-0.1"}}), "restore_volume");
    EXPECT_EQ(query_field({{"ratio", "0.5"}, {"threads", "0"}}), "threads");
    EXPECT_EQ(query_field({{"ratio", "abc"}}), "ratio");
    EXPECT_EQ(query_field({{"ratio", "inf"}}), "ratio");
}

TEST(SimplifyOperation, UnknownFieldsAndParametersAre400) {
    const PolygonMesh m = testing::icosphere(1);
    expect_problem(call("application/json", json_request(m, R"(,"ratio":0.5,"levels":2)")), 400, "unknown_field");
    expect_problem(call("model/obj", write_obj(m), {{"ratio", "0.5"}, {"levels", "2"}}), 400, "unknown_parameter");
    expect_problem(call("application/json", json_request(m, R"(,"ratio":0.5)"), {{"ratio", "0.5"}}), 400,
                   "unknown_parameter");
    expect_problem(call("model/obj", write_obj(m), {{"ratio", "0.5"}, {"compression", "draco"}, {"format", "obj"}}),
                   400, "invalid_field");
}

TEST(SimplifyOperation, NonManifoldInputWithRepairNoneIs422NamingTheEdge) {
    PolygonMesh fin;
    fin.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
    fin.add_face({0, 1, 2});
    fin.add_face({1, 0, 3});
    fin.add_face({0, 1, 4});
    const auto json = expect_problem(
        call("application/json", json_request(fin, R"(,"target_faces":1,"repair":"none")")), 422, "non_manifold");
    EXPECT_NE(json.value("detail", "").find("(0, 1)"), std::string::npos) << json.dump();
    EXPECT_EQ(json.value("field", ""), "mesh.faces[2]");  // the face that made the edge non-manifold, as /remesh
}

TEST(SimplifyOperation, BudgetsAreCheckedBeforeWork) {
    Limits limits;
    limits.max_input_faces = 100;
    expect_problem(call("application/json", json_request(testing::icosphere(2), R"(,"ratio":0.5)"), {}, limits), 422,
                   "budget_exceeded");
    // 60 quads are within 100 faces but triangulate to 120 triangles
    Limits tri_limits;
    tri_limits.max_input_faces = 100;
    expect_problem(call("model/obj", write_obj(shapes::grid(10, 6)), {{"ratio", "0.5"}}, tri_limits), 422,
                   "budget_exceeded");
    Limits body;
    body.max_body_bytes = 100;
    expect_problem(call("model/obj", write_obj(testing::icosphere(1)), {{"ratio", "0.5"}}, body), 413,
                   "payload_too_large");
}

TEST(SimplifyOperation, MediaTypeAndParseErrors) {
    expect_problem(call("text/plain", "hello", {{"ratio", "0.5"}}), 415, "unsupported_media_type");
    expect_problem(call("", "hello"), 415, "unsupported_media_type");
    const auto json = expect_problem(call("model/obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n", {{"ratio", "0.5"}}), 400,
                                     "parse_error");
    EXPECT_EQ(json.value("line", 0), 4);
    expect_problem(call("application/json", "{not json"), 400, "invalid_json");
}

}  // namespace
}  // namespace surfaced::api
