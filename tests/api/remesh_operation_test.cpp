// POST /remesh called in-process through the route table: both request forms, the quality report in JSON and
// headers, output formats, and every kind of bad input as a problem+json naming the field.
#include <gtest/gtest.h>

#include <atomic>
#include <string>

#include <nlohmann/json.hpp>

#include "api/routes.h"
#include "geometry/io/gltf.h"
#include "geometry/io/mesh_io.h"
#include "geometry/mesh/shapes.h"
#include "tests/support/api_request.h"
#include "tests/support/gltf_validator.h"
#include "tests/support/mesh_asserts.h"
#include "tests/support/simplify_meshes.h"

namespace surfaced::api {
namespace {

using namespace fixtures;

ApiResponse call(const std::string& content_type, const std::string& body,
                 std::multimap<std::string, std::string> query = {}, const Limits& limits = {},
                 const Cancel& cancel = {}) {
    return dispatch(make_request("POST", "/remesh", content_type, body, std::move(query)),
                    context_with(limits, cancel));
}

std::string field_of(const ApiResponse& response, int status = 400, const std::string& code = "invalid_field") {
    return expect_problem(response, status, code).value("field", "");
}

// ---- good requests ---------------------------------------------------------------------------------------------

TEST(RemeshOperation, JsonCubeToJsonWithQualityReport) {
    const auto response =
        call("application/json", json_request(shapes::cube(), R"(,"edge_length":0.2,"output":{"format":"json"})"));
    ASSERT_EQ(response.status, 200) << response.body;
    EXPECT_EQ(response.content_type, "application/json");
    const auto json = nlohmann::json::parse(response.body);
    const auto& stats = json["stats"];
    EXPECT_EQ(stats["input_faces"], 6);
    EXPECT_EQ(stats["triangulated"], true);
    EXPECT_EQ(stats["feature_edges"], 12);
    EXPECT_EQ(stats["edge_length"], 0.2);
    EXPECT_EQ(stats["output_faces"], json["mesh"]["faces"].size());
    EXPECT_EQ(stats["before"]["faces"], 12);  // the triangulated input
    const auto& after = stats["after"];
    EXPECT_EQ(after["faces"], json["mesh"]["faces"].size());
    EXPECT_NEAR(after["mean_edge_length"].get<double>(), 0.2, 0.02);
    EXPECT_GT(after["min_angle"].get<double>(), 30);
    EXPECT_EQ(after["share_below_30"], 0.0);
    EXPECT_GE(after["mean_radius_ratio"].get<double>(), 1.0);
    EXPECT_LT(after["mean_radius_ratio"].get<double>(), stats["before"]["mean_radius_ratio"].get<double>());
    // the valence histogram counts every vertex once
    std::size_t counted = 0;
    for (const auto& [valence, n] : after["valence"].items()) counted += n.get<std::size_t>();
    EXPECT_EQ(counted, json["mesh"]["positions"].size());
    EXPECT_LT(stats["hausdorff"].get<double>(), 1e-9);  // every vertex is on the cube, features are kept
    // the mesh: closed, Euler characteristic 2, on the cube
    PolygonMesh out;
    for (const auto& p : json["mesh"]["positions"]) out.positions.push_back({p[0], p[1], p[2]});
    for (const auto& f : json["mesh"]["faces"]) out.add_face({f[0].get<Index>(), f[1].get<Index>(), f[2].get<Index>()});
    ASSERT_TRUE(validate(out).ok());
    EXPECT_TRUE(testing::is_watertight(out));
    EXPECT_EQ(testing::euler_characteristic(out), 2);
    EXPECT_NEAR(testing::signed_volume(out), 1.0, 1e-9);
    // headers mirror the stats
    EXPECT_EQ(header(response, "X-Input-Faces"), "6");
    EXPECT_EQ(header(response, "X-Output-Faces"), std::to_string(json["mesh"]["faces"].size()));
    EXPECT_EQ(header(response, "X-Triangulated"), "true");
    EXPECT_EQ(header(response, "X-Feature-Edges"), "12");
    EXPECT_EQ(std::stod(header(response, "X-Edge-Length")), 0.2);
    EXPECT_EQ(std::stod(header(response, "X-Min-Angle-Before")), 45.0);
    EXPECT_EQ(std::stod(header(response, "X-Min-Angle-After")), after["min_angle"].get<double>());
    EXPECT_EQ(std::stod(header(response, "X-Below-30-After")), 0.0);
    EXPECT_EQ(std::stod(header(response, "X-Radius-Ratio-After")), after["mean_radius_ratio"].get<double>());
    EXPECT_EQ(std::stod(header(response, "X-Hausdorff")), stats["hausdorff"].get<double>());
    EXPECT_NE(header(response, "Server-Timing").find("remesh;dur="), std::string::npos);
}

TEST(RemeshOperation, DefaultEdgeLengthIsTheInputMean) {
    const PolygonMesh sphere = testing::icosphere(2);
    const auto response = call("application/json", json_request(sphere, R"(,"output":{"format":"json"})"));
    ASSERT_EQ(response.status, 200) << response.body;
    const auto stats = nlohmann::json::parse(response.body)["stats"];
    EXPECT_NEAR(stats["edge_length"].get<double>(), stats["before"]["mean_edge_length"].get<double>(), 1e-12);
    EXPECT_NEAR(stats["after"]["mean_edge_length"].get<double>(), stats["edge_length"].get<double>(),
                0.1 * stats["edge_length"].get<double>());
}

TEST(RemeshOperation, RawObjWithQueryToObjKeepsTheBoundary) {
    const std::string grid = write_obj(shapes::grid(8, 4));  // quads over [0,1]^2, one boundary loop
    const auto response =
        call("model/obj", grid,
             {{"edge_length", "0.05"}, {"iterations", "4"}, {"smoothing", "laplacian"}, {"format", "obj"}});
    ASSERT_EQ(response.status, 200) << response.body;
    EXPECT_EQ(response.content_type, "model/obj");
    EXPECT_EQ(header(response, "X-Triangulated"), "true");
    auto out = read_obj(response.body);
    ASSERT_TRUE(out.ok()) << out.error().message;
    EXPECT_EQ(testing::boundary_loop_count(*out), 1u);
    EXPECT_EQ(testing::edge_stats(*out).non_manifold_edges, 0u);
    for (const auto& p : testing::boundary_positions(*out)) {
        const bool on_side = p[0] < 1e-9 || p[0] > 1 - 1e-9 || p[1] < 1e-9 || p[1] > 1 - 1e-9;
        EXPECT_TRUE(on_side) << p[0] << " " << p[1];
    }
    EXPECT_EQ(std::to_string(out->face_count()), header(response, "X-Output-Faces"));
}

TEST(RemeshOperation, LockBorderFalseFreesTheBoundaryUnderEitherName) {
    const std::string grid = write_obj(shapes::grid(8, 4));
    const std::multimap<std::string, std::string> base = {
        {"edge_length", "0.05"}, {"iterations", "4"}, {"smoothing", "laplacian"}, {"format", "obj"}};
    const auto with = [&](const char* name, const char* value) {
        auto query = base;
        query.emplace(name, value);
        return call("model/obj", grid, query);
    };
    const auto freed = with("lock_border", "false");
    const auto freed_old_name = with("keep_boundary", "false");
    ASSERT_EQ(freed.status, 200) << freed.body;
    ASSERT_EQ(freed_old_name.status, 200) << freed_old_name.body;
    EXPECT_EQ(freed.body, freed_old_name.body);  // one option, two names
    auto out = read_obj(freed.body);
    ASSERT_TRUE(out.ok()) << out.error().message;
    // relaxed like interior vertices, the border shrinks: some boundary vertex leaves the square's sides
    std::size_t off_side = 0;
    for (const auto& p : testing::boundary_positions(*out))
        off_side += !(p[0] < 1e-9 || p[0] > 1 - 1e-9 || p[1] < 1e-9 || p[1] > 1 - 1e-9);
    EXPECT_GT(off_side, 0u);
    // the default (true) is the same as saying so under either name
    const auto locked = call("model/obj", grid, base);
    ASSERT_EQ(locked.status, 200) << locked.body;
    EXPECT_EQ(with("lock_border", "true").body, locked.body);
    EXPECT_EQ(with("keep_boundary", "true").body, locked.body);
    EXPECT_NE(locked.body, freed.body);
    // both names at once: 400
    auto both = base;
    both.emplace("lock_border", "true");
    both.emplace("keep_boundary", "true");
    expect_problem(call("model/obj", grid, both), 400, "invalid_field");
    const auto json_both = expect_problem(
        call("application/json", json_request(shapes::grid(8, 4), R"(,"lock_border":false,"keep_boundary":false)")),
        400, "invalid_field");
    EXPECT_EQ(json_both.value("field", ""), "keep_boundary");
}

TEST(RemeshOperation, DefaultOutputIsValidDracoGlb) {
    const auto response = call("application/json", json_request(testing::icosphere(2), R"(,"iterations":3)"));
    ASSERT_EQ(response.status, 200) << response.body;
    EXPECT_EQ(response.content_type, "model/gltf-binary");
    EXPECT_NE(response.body.find("KHR_draco_mesh_compression"), std::string::npos);
    const auto validation = testing::run_gltf_validator(response.body);
    ASSERT_TRUE(validation.ran) << validation.report;
    EXPECT_EQ(validation.errors, 0) << validation.report;
}

// ---- bad requests ----------------------------------------------------------------------------------------------

TEST(RemeshOperation, OutOfRangeOptionsAre400WithField) {
    const PolygonMesh m = testing::icosphere(1);
    EXPECT_EQ(field_of(call("application/json", json_request(m, R"(,"edge_length":0)"))), "edge_length");
    EXPECT_EQ(field_of(call("application/json", json_request(m, R"(,"edge_length":-0.1)"))), "edge_length");
    EXPECT_EQ(field_of(call("application/json", json_request(m, R"(,"edge_length":"long")"))), "edge_length");
    EXPECT_EQ(field_of(call("application/json", json_request(m, R"(,"iterations":-1)"))), "iterations");
    EXPECT_EQ(field_of(call("application/json", json_request(m, R"(,"iterations":101)"))), "iterations");
    EXPECT_EQ(field_of(call("application/json", json_request(m, R"(,"iterations":2.5)"))), "iterations");
    EXPECT_EQ(field_of(call("application/json", json_request(m, R"(,"feature_angle":181)"))), "feature_angle");
    EXPECT_EQ(field_of(call("application/json", json_request(m, R"(,"lock_border":"yes")"))), "lock_border");
    EXPECT_EQ(field_of(call("application/json", json_request(m, R"(,"keep_boundary":"yes")"))), "keep_boundary");
    EXPECT_EQ(field_of(call("application/json", json_request(m, R"(,"smoothing":"bilateral")"))), "smoothing");
    EXPECT_EQ(field_of(call("model/obj", write_obj(m), {{"edge_length", "inf"}})), "edge_length");
    EXPECT_EQ(field_of(call("model/obj", write_obj(m), {{"iterations", "many"}})), "iterations");
    EXPECT_EQ(field_of(call("model/obj", write_obj(m), {{"smoothing", "x"}})), "smoothing");
    const std::string bad_index = R"({"mesh":{"positions":[[0,0,0],[1,0,0],[0,1,0]],"faces":[[0,1,7]]}})";
    EXPECT_EQ(field_of(call("application/json", bad_index), 422, "index_out_of_range"), "mesh.faces[0][2]");
    EXPECT_EQ(field_of(call("application/json", R"({"edge_length":1})")), "mesh");
}

TEST(RemeshOperation, UnknownFieldsAndParametersAre400) {
    const PolygonMesh m = testing::icosphere(1);
    expect_problem(call("application/json", json_request(m, R"(,"ratio":0.5)")), 400, "unknown_field");
    expect_problem(call("model/obj", write_obj(m), {{"levels", "2"}}), 400, "unknown_parameter");
    expect_problem(call("application/json", json_request(m), {{"edge_length", "0.5"}}), 400, "unknown_parameter");
    expect_problem(call("model/obj", write_obj(m), {{"compression", "draco"}, {"format", "obj"}}), 400,
                   "invalid_field");
}

TEST(RemeshOperation, NonManifoldInputWithRepairNoneIs422) {
    PolygonMesh fin;
    fin.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
    fin.add_face({0, 1, 2});
    fin.add_face({1, 0, 3});
    fin.add_face({0, 1, 4});
    const auto json =
        expect_problem(call("application/json", json_request(fin, R"(,"repair":"none")")), 422, "non_manifold");
    EXPECT_NE(json.value("detail", "").find("(0, 1)"), std::string::npos) << json.dump();
    EXPECT_EQ(json.value("field", ""), "mesh.faces[2]");  // the face that made the edge non-manifold
}

TEST(RemeshOperation, BudgetsAreCheckedBeforeWork) {
    // the unit cube's area 6 at L = 0.001 predicts 6 / (0.433e-6) = 13.9M faces: refused at once
    const auto json = expect_problem(call("application/json", json_request(shapes::cube(), R"(,"edge_length":0.001)")),
                                     422, "budget_exceeded");
    EXPECT_EQ(json.value("field", ""), "edge_length");
    EXPECT_NE(json.value("detail", "").find("13856406"), std::string::npos) << json.dump();
    Limits small;
    small.max_output_faces = 1000;
    expect_problem(call("model/obj", write_obj(shapes::cube()), {{"edge_length", "0.05"}}, small), 422,
                   "budget_exceeded");
    Limits input;
    input.max_input_faces = 100;
    expect_problem(call("application/json", json_request(testing::icosphere(2)), {}, input), 422, "budget_exceeded");
    Limits body;
    body.max_body_bytes = 100;
    expect_problem(call("model/obj", write_obj(testing::icosphere(1)), {}, body), 413, "payload_too_large");
}

TEST(RemeshOperation, CancelledIs503) {
    std::atomic<bool> stop{true};
    Cancel cancel;
    cancel.flag = &stop;
    const auto response = call("application/json", json_request(testing::icosphere(2)), {}, {}, cancel);
    expect_problem(response, 503, "cancelled");
}

TEST(RemeshOperation, MediaTypeAndParseErrors) {
    expect_problem(call("text/plain", "hello"), 415, "unsupported_media_type");
    const auto json = expect_problem(call("model/obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n"), 400, "parse_error");
    EXPECT_EQ(json.value("line", 0), 4);
    expect_problem(call("application/json", "{not json"), 400, "invalid_json");
    expect_problem(call("application/json", R"({"mesh":{"positions":[],"faces":[]}})"), 400, "invalid_field");
}

}  // namespace
}  // namespace surfaced::api
