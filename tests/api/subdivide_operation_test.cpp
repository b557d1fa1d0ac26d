// POST /subdivide called directly (no sockets): both request forms, every error class, budgets before work.
#include <gtest/gtest.h>

#include <string>

#include <nlohmann/json.hpp>

#include "api/operations/subdivide.h"
#include "api/routes.h"
#include "geometry/io/gltf.h"
#include "geometry/io/mesh_io.h"
#include "geometry/mesh/shapes.h"
#include "geometry/subdivision/adaptive_tessellation.h"
#include "geometry/subdivision/limit_evaluation.h"
#include "geometry/subdivision/subdivide.h"
#include "tests/support/api_request.h"
#include "tests/support/gltf_validator.h"
#include "tests/support/mesh_asserts.h"

namespace surfaced::api {
namespace {

using namespace fixtures;

ApiResponse call(const std::string& content_type, const std::string& body,
                 std::multimap<std::string, std::string> query = {}, const Limits& limits = {}) {
    return operations::subdivide(make_request("POST", "/subdivide", content_type, body, std::move(query)),
                                 context_with(limits));
}

// A valid cube OBJ, 1-based, outward quads.
constexpr const char* kCubeObj =
    "# cube\n"
    "v -0.5 -0.5 -0.5\nv 0.5 -0.5 -0.5\nv 0.5 0.5 -0.5\nv -0.5 0.5 -0.5\n"
    "v -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv 0.5 0.5 0.5\nv -0.5 0.5 0.5\n"
    "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

// ---- good requests ---------------------------------------------------------------------------------------------

TEST(SubdivideOperation, JsonCubeToJson) {
    const auto response =
        call("application/json", json_request(shapes::cube(), R"(,"levels":1,"output":{"format":"json"})"));
    ASSERT_EQ(response.status, 200) << response.body;
    EXPECT_EQ(response.content_type, "application/json");
    const auto json = nlohmann::json::parse(response.body);
    EXPECT_EQ(json["mesh"]["faces"].size(), 24u);
    EXPECT_EQ(json["mesh"]["positions"].size(), 26u);
    EXPECT_EQ(json["stats"]["input_vertices"], 8);
    EXPECT_EQ(json["stats"]["input_faces"], 6);
    EXPECT_EQ(json["stats"]["output_vertices"], 26);
    EXPECT_EQ(json["stats"]["output_faces"], 24);
    EXPECT_EQ(json["stats"]["scheme"], "catmull-clark");
    EXPECT_EQ(header(response, "X-Input-Faces"), "6");
    EXPECT_EQ(header(response, "X-Input-Vertices"), "8");
    EXPECT_EQ(header(response, "X-Output-Faces"), "24");
    EXPECT_EQ(header(response, "X-Output-Vertices"), "26");
    EXPECT_FALSE(header(response, "X-Elapsed-Ms").empty());
    EXPECT_NE(header(response, "Server-Timing").find("subdivide;dur="), std::string::npos);
    for (const auto& face : json["mesh"]["faces"]) EXPECT_EQ(face.size(), 4u);
}

TEST(SubdivideOperation, JsonDefaultIsValidDracoGlb) {
    const auto response = call("application/json; charset=utf-8", json_request(shapes::cube(), R"(,"levels":2)"));
    ASSERT_EQ(response.status, 200) << response.body;
    EXPECT_EQ(response.content_type, "model/gltf-binary");
    ASSERT_GE(response.body.size(), 12u);
    EXPECT_EQ(response.body.substr(0, 4), "glTF");
    EXPECT_NE(response.body.find("KHR_draco_mesh_compression"), std::string::npos);
    EXPECT_EQ(header(response, "X-Output-Faces"), "96");
    const auto validation = testing::run_gltf_validator(response.body);
    ASSERT_TRUE(validation.ran) << validation.report;
    EXPECT_EQ(validation.errors, 0) << validation.report;
    EXPECT_EQ(validation.warnings, 0) << validation.report;
}

TEST(SubdivideOperation, LoopOnTrianglesUncompressedGlb) {
    const auto response =
        call("application/json",
             json_request(shapes::icosahedron(), R"(,"scheme":"loop","levels":2,"output":{"compression":"none"})"));
    ASSERT_EQ(response.status, 200) << response.body;
    EXPECT_EQ(response.body.find("KHR_draco_mesh_compression"), std::string::npos);
    EXPECT_EQ(header(response, "X-Output-Faces"), "320");
    const auto validation = testing::run_gltf_validator(response.body);
    ASSERT_TRUE(validation.ran) << validation.report;
    EXPECT_EQ(validation.errors, 0) << validation.report;
    EXPECT_EQ(validation.warnings, 0) << validation.report;
}

TEST(SubdivideOperation, RawObjWithQueryToObj) {
    const auto response =
        call("model/obj", kCubeObj, {{"scheme", "catmull-clark"}, {"levels", "2"}, {"format", "obj"}});
    ASSERT_EQ(response.status, 200) << response.body;
    EXPECT_EQ(response.content_type, "model/obj");
    auto mesh = read_obj(response.body);
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    EXPECT_EQ(mesh->face_count(), 96u);
    EXPECT_EQ(mesh->vertex_count(), 98u);
    EXPECT_EQ(header(response, "X-Output-Faces"), "96");
}

TEST(SubdivideOperation, OctetStreamIsSniffed) {
    const auto response = call("application/octet-stream", kCubeObj, {{"format", "ply"}});
    ASSERT_EQ(response.status, 200) << response.body;
    EXPECT_EQ(response.content_type, "application/ply");
    auto mesh = read_ply(response.body);
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    EXPECT_EQ(mesh->face_count(), 24u);
}

TEST(SubdivideOperation, EveryUploadFormat) {
    // The cube in each input format, by its canonical media type and sniffed from application/octet-stream.
    const PolygonMesh cube = shapes::cube();
    GltfOptions plain;
    plain.draco = false;
    auto plain_glb = write_glb(cube, plain);
    ASSERT_TRUE(plain_glb.ok());
    const std::string off =
        "OFF\n8 6 0\n-0.5 -0.5 -0.5\n0.5 -0.5 -0.5\n0.5 0.5 -0.5\n-0.5 0.5 -0.5\n"
        "-0.5 -0.5 0.5\n0.5 -0.5 0.5\n0.5 0.5 0.5\n-0.5 0.5 0.5\n"
        "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n";
    const std::string stl =
        "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n"
        "endsolid t\n";
    struct Case {
        std::string media_type, body;
        std::string output_faces;  // glTF input is triangulated: 12 triangles -> 36 quads at level 1
    };
    const Case cases[] = {
        {"model/obj", kCubeObj, "24"},
        {"model/off", off, "24"},
        {"application/ply", write_ply(cube), "24"},
        {"model/ply", write_ply(cube, PlyEncoding::Ascii), "24"},
        {"model/stl", stl, "3"},
        {"application/sla", stl, "3"},
        {"model/gltf-binary", plain_glb.value(), "36"},
    };
    for (const Case& c : cases) {
        for (const std::string& type : {c.media_type, std::string("application/octet-stream")}) {
            const auto response = call(type, c.body, {{"format", "obj"}});
            EXPECT_EQ(response.status, 200) << c.media_type << " as " << type << ": " << response.body;
            EXPECT_EQ(header(response, "X-Output-Faces"), c.output_faces) << c.media_type << " as " << type;
        }
    }
}

TEST(SubdivideOperation, DracoGlbUploadRoundTrips) {
    // Our own default output must be accepted as input (read_glb decodes KHR_draco_mesh_compression).
    auto glb = write_glb(shapes::cube(), GltfOptions{});
    ASSERT_TRUE(glb.ok());
    for (const std::string type : {"model/gltf-binary", "application/octet-stream"}) {
        const auto response = call(type, glb.value(), {{"format", "obj"}});
        EXPECT_EQ(response.status, 200) << type << ": " << response.body;
        EXPECT_EQ(header(response, "X-Output-Faces"), "36") << type;
    }
}

TEST(SubdivideOperation, LevelsZeroReturnsInput) {
    const auto response = call("model/obj", kCubeObj, {{"levels", "0"}, {"format", "json"}});
    ASSERT_EQ(response.status, 200) << response.body;
    EXPECT_EQ(header(response, "X-Output-Faces"), "6");
}

TEST(SubdivideOperation, RoutesDispatch) {
    ApiContext context;
    ApiRequest health;
    health.method = "GET";
    health.path = "/healthz";
    const auto ok = dispatch(health, context);
    EXPECT_EQ(ok.status, 200);
    EXPECT_EQ(ok.content_type, "application/json");
    EXPECT_EQ(nlohmann::json::parse(ok.body)["status"], "ok");

    ApiRequest missing = health;
    missing.path = "/nope";
    expect_problem(dispatch(missing, context), 404, "not_found");

    ApiRequest wrong_method = health;
    wrong_method.path = "/subdivide";
    const auto not_allowed = dispatch(wrong_method, context);
    expect_problem(not_allowed, 405, "method_not_allowed");
    EXPECT_EQ(header(not_allowed, "Allow"), "POST");
}

// ---- 400 -------------------------------------------------------------------------------------------------------

TEST(SubdivideOperation, MalformedJsonIs400) {
    const auto json = expect_problem(call("application/json", R"({"mesh": )"), 400, "invalid_json");
    EXPECT_TRUE(json.contains("offset"));
}

TEST(SubdivideOperation, UnknownQueryParametersAreNamed) {
    const auto json = expect_problem(call("model/obj", kCubeObj, {{"levels", "1"}, {"colour", "red"}, {"lvl", "2"}}),
                                     400, "unknown_parameter");
    const std::string detail = json["detail"];
    EXPECT_NE(detail.find("\"colour\""), std::string::npos) << detail;
    EXPECT_NE(detail.find("\"lvl\""), std::string::npos) << detail;
}

TEST(SubdivideOperation, QueryWithJsonBodyIs400) {
    expect_problem(call("application/json", json_request(shapes::cube()), {{"levels", "2"}}), 400, "unknown_parameter");
}

TEST(SubdivideOperation, BadQueryValuesAre400) {
    expect_problem(call("model/obj", kCubeObj, {{"levels", "two"}}), 400, "invalid_field");
    expect_problem(call("model/obj", kCubeObj, {{"levels", "-1"}}), 400, "invalid_field");
    expect_problem(call("model/obj", kCubeObj, {{"levels", "1"}, {"levels", "2"}}), 400, "invalid_field");
    const auto scheme = expect_problem(call("model/obj", kCubeObj, {{"scheme", "sqrt3"}}), 400, "invalid_field");
    EXPECT_EQ(scheme.value("field", ""), "scheme");
    EXPECT_NE(scheme.value("detail", "").find("\"loop\""), std::string::npos);
    expect_problem(call("model/obj", kCubeObj, {{"normals", "yes"}}), 400, "invalid_field");
}

TEST(SubdivideOperation, OptionsThatDoNotApplyAre400) {
    const auto compression = expect_problem(
        call("application/json", json_request(shapes::cube(), R"(,"output":{"format":"obj","compression":"draco"})")),
        400, "invalid_field");
    EXPECT_EQ(compression.value("field", ""), "output.compression");
    const auto bits =
        expect_problem(call("application/json", json_request(shapes::cube(), R"(,"output":{"quantize_position":31})")),
                       400, "invalid_field");
    EXPECT_EQ(bits.value("field", ""), "output.quantize_position");
    // STL has facet normals only, OFF none: normals=true given with them names the option
    for (const char* format : {"stl", "off"}) {
        const auto normals = expect_problem(call("model/obj", kCubeObj, {{"format", format}, {"normals", "true"}}), 400,
                                            "invalid_field");
        EXPECT_EQ(normals.value("field", ""), "normals") << format;
        const auto in_json = expect_problem(
            call("application/json", json_request(shapes::cube(), std::string(R"(,"output":{"format":")") + format +
                                                                      R"(","normals":true})")),
            400, "invalid_field");
        EXPECT_EQ(in_json.value("field", ""), "output.normals") << format;
    }
}

TEST(SubdivideOperation, ObjParseErrorNamesTheLine) {
    const std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 x\n";
    const auto json = expect_problem(call("model/obj", obj), 400, "parse_error");
    EXPECT_EQ(json.value("line", 0), 5) << json.dump();
}

TEST(SubdivideOperation, ObjIndexOutOfRangeNamesTheLine) {
    const std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n";
    const auto response = call("model/obj", obj);
    EXPECT_TRUE(response.status == 422 || response.status == 400) << response.body;
    const auto json = nlohmann::json::parse(response.body);
    EXPECT_EQ(json.value("line", 0), 5) << json.dump();
}

// ---- 413 / 415 -------------------------------------------------------------------------------------------------

TEST(SubdivideOperation, BodyOverLimitIs413) {
    Limits limits;
    limits.max_body_bytes = 100;
    expect_problem(call("model/obj", kCubeObj, {}, limits), 413, "payload_too_large");
}

TEST(SubdivideOperation, UnknownMediaTypeIs415) {
    const auto json = expect_problem(call("text/plain", kCubeObj), 415, "unsupported_media_type");
    EXPECT_NE(json.value("detail", "").find("model/obj"), std::string::npos) << "accepted types are listed";
    expect_problem(call("", kCubeObj), 415, "unsupported_media_type");
    expect_problem(call("application/octet-stream", "\x01\x02 not a mesh"), 415, "unsupported_media_type");
}

// ---- 422 -------------------------------------------------------------------------------------------------------

TEST(SubdivideOperation, IndexOutOfRangeHasFieldPath) {
    const std::string body =
        R"({"mesh":{"positions":[[0,0,0],[1,0,0],[0,1,0]],"faces":[[0,1,2],[0,2,3]]},"output":{"format":"json"}})";
    const auto json = expect_problem(call("application/json", body), 422, "index_out_of_range");
    EXPECT_EQ(json.value("field", ""), "mesh.faces[1][2]");
}

TEST(SubdivideOperation, FaceWithTwoVerticesIsDegenerateWithFieldPath) {
    const std::string body = R"({"mesh":{"positions":[[0,0,0],[1,0,0],[0,1,0]],"faces":[[0,1,2],[0,2]]}})";
    const auto json = expect_problem(call("application/json", body), 422, "degenerate_face");
    EXPECT_EQ(json.value("field", ""), "mesh.faces[1]");
}

// Faces that repeat a vertex are refined as OpenSubdiv refines them (tests/geometry/opensubdiv_shapes_test.cpp checks
// the geometry against Far): the service takes them for /subdivide, and only there.
TEST(SubdivideOperation, FacesRepeatingAVertexAreSubdividedLikeOpenSubdiv) {
    const std::string obj =
        testing::read_file(std::string(SURFACED_TEST_DATA_DIR) + "/opensubdiv-shapes/catmark_nonman_edges.obj");
    ReadOptions lenient;
    lenient.allow_repeated_vertices = true;
    auto input = read_obj(obj, lenient);
    ASSERT_TRUE(input.ok()) << input.error().message;
    SubdivisionOptions options;
    options.levels = 2;
    auto expected = subdivide(*input, options);
    ASSERT_TRUE(expected.ok()) << expected.error().message;

    const auto as_obj = call("model/obj", obj, {{"levels", "2"}, {"format", "obj"}});
    ASSERT_EQ(as_obj.status, 200) << as_obj.body;
    auto got = read_obj(as_obj.body, lenient);
    ASSERT_TRUE(got.ok()) << got.error().message;
    EXPECT_EQ(got->face_count(), expected->face_count());
    EXPECT_EQ(got->vertex_count(), expected->vertex_count());
    EXPECT_EQ(got->face_indices, expected->face_indices);

    const auto as_glb = call("model/obj", obj, {{"levels", "2"}});
    ASSERT_EQ(as_glb.status, 200) << as_glb.body;
    const auto validation = testing::run_gltf_validator(as_glb.body);
    ASSERT_TRUE(validation.ran) << validation.report;
    EXPECT_EQ(validation.errors, 0) << validation.report;

    // the same faces in JSON; the operations that need proper faces refuse them with repair "none" (and with the
    // default repair "auto" drop them as degenerate: tests/api/repair_operation_test.cpp)
    const std::string body = R"({"mesh":{"positions":[[0,0,0],[1,0,0],[1,1,0],[0,1,0]],"faces":[[0,1,2,2],[0,2,3]]},)"
                             R"("output":{"format":"json"}})";
    EXPECT_EQ(call("application/json", body).status, 200);
    const auto simplify = dispatch(make_request("POST", "/simplify", "application/json",
                                                R"({"mesh":{"positions":[[0,0,0],[1,0,0],[1,1,0],[0,1,0]],)"
                                                R"("faces":[[0,1,2,2],[0,2,3]]},"ratio":0.5,"repair":"none"})"),
                                   ApiContext{});
    EXPECT_EQ(simplify.status, 422) << simplify.body;
}

TEST(SubdivideOperation, OverflowingNumberIs400WithItsPosition) {
    const std::string body = "{\"mesh\":{\"positions\":[[0,0,0],[1,0,0],\n[0,1e999,0]],\"faces\":[[0,1,2]]}}";
    const auto json = expect_problem(call("application/json", body), 400, "number_out_of_range");
    EXPECT_EQ(json.value("offset", -1), static_cast<int>(body.find("1e999"))) << json.dump();
    EXPECT_NE(json.value("detail", "").find("line 2, column 4"), std::string::npos) << json.dump();
}

TEST(SubdivideOperation, LoopOnQuadsNamesTheFace) {
    const auto json = expect_problem(call("application/json", json_request(shapes::cube(), R"(,"scheme":"loop")")), 422,
                                     "not_triangle_mesh");
    EXPECT_EQ(json.value("field", ""), "mesh.faces[0]");
    EXPECT_NE(json.value("detail", "").find("face 0"), std::string::npos) << json.dump();
}

TEST(SubdivideOperation, LevelsOverLimitIs422) {
    const auto json = expect_problem(call("application/json", json_request(shapes::cube(), R"(,"levels":9)")), 422,
                                     "budget_exceeded");
    EXPECT_EQ(json.value("field", ""), "levels");
}

TEST(SubdivideOperation, PredictedOutputRejectedBeforeWork) {
    // Two triangles at level 12 would be 2 * 4^12 = 33.5M faces: refused from the prediction alone, at once.
    PolygonMesh two;
    two.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    two.add_face({0, 1, 2});
    two.add_face({0, 2, 3});
    Limits limits;
    limits.max_levels = 16;
    const auto response = call("application/json", json_request(two, R"(,"scheme":"loop","levels":12)"), {}, limits);
    const auto json = expect_problem(response, 422, "budget_exceeded");
    EXPECT_EQ(json.value("field", ""), "levels");
    EXPECT_NE(json.value("detail", "").find("33554432"), std::string::npos) << json.dump();
}

TEST(SubdivideOperation, OutputBudgetIsConfigurable) {
    Limits limits;
    limits.max_output_faces = 23;  // the cube at level 1 has 24
    expect_problem(call("model/obj", kCubeObj, {{"levels", "1"}}, limits), 422, "budget_exceeded");
    limits.max_output_faces = 24;
    EXPECT_EQ(call("model/obj", kCubeObj, {{"levels", "1"}, {"format", "obj"}}, limits).status, 200);
}

}  // namespace
}  // namespace surfaced::api

// ---- sharp features, limit surface, max_faces --------------------------------------------------------------------

namespace surfaced::api {
namespace {

std::vector<Vec3> positions_of(const nlohmann::json& response) {
    std::vector<Vec3> out;
    for (const auto& p : response["mesh"]["positions"])
        out.push_back({p[0].get<double>(), p[1].get<double>(), p[2].get<double>()});
    return out;
}

TEST(SubdivideSharpFeatures, JsonCreasesCornersAndHolesReachTheGeometry) {
    PolygonMesh tagged = shapes::cube();
    tagged.tags.creases = {{4, 5, 2.5}, {5, 6, 10}};
    tagged.tags.corners = {{0, 1.5}};
    tagged.tags.holes = {2};
    SubdivisionOptions options;
    options.levels = 2;
    options.crease_method = CreaseMethod::Chaikin;
    const auto expected = surfaced::subdivide(tagged, options);
    ASSERT_TRUE(expected.ok());

    const auto response =
        call("application/json", json_request(shapes::cube(), R"(,"levels":2,"crease_method":"chaikin",
        "creases":[{"edge":[4,5],"sharpness":2.5},{"edge":[5,6],"sharpness":10}],
        "corners":[{"vertex":0,"sharpness":1.5}],"holes":[2],"output":{"format":"json"})"));
    ASSERT_EQ(response.status, 200) << response.body;
    const auto json = nlohmann::json::parse(response.body);
    const auto got = positions_of(json);
    ASSERT_EQ(got.size(), expected->vertex_count());
    for (std::size_t v = 0; v < got.size(); ++v) EXPECT_EQ(got[v], expected->positions[v]) << v;
    EXPECT_EQ(json["mesh"]["faces"].size(), expected->face_count());
    EXPECT_EQ(expected->face_count(), 5u * 16u);  // the hole's 16 children are gone
}

TEST(SubdivideSharpFeatures, TagErrorsNameTheField) {
    auto json = expect_problem(
        call("application/json", json_request(shapes::cube(), R"(,"creases":[{"edge":[4,99],"sharpness":1}])")), 422,
        "index_out_of_range");
    EXPECT_EQ(json.value("field", ""), "creases[0].edge[1]");
    json = expect_problem(
        call("application/json", json_request(shapes::cube(), R"(,"creases":[{"edge":[0,6],"sharpness":1}])")), 422,
        "invalid_argument");
    EXPECT_EQ(json.value("field", ""), "creases[0]");  // 0 and 6 are opposite corners: no edge
    json = expect_problem(call("application/json", json_request(shapes::cube(), R"(,"holes":[6])")), 422,
                          "index_out_of_range");
    EXPECT_EQ(json.value("field", ""), "holes[0]");
    json = expect_problem(
        call("application/json", json_request(shapes::cube(), R"(,"corners":[{"vertex":1,"sharpness":-1}])")), 400,
        "invalid_field");
    EXPECT_EQ(json.value("field", ""), "corners[0].sharpness");
    json = expect_problem(call("application/json", json_request(shapes::cube(), R"(,"crease_method":"fast")")), 400,
                          "invalid_field");
    EXPECT_NE(json.value("detail", "").find("chaikin"), std::string::npos);
}

TEST(SubdivideSharpFeatures, ObjTagsAndQueryOptionsOnRawBodies) {
    const std::string obj = std::string(kCubeObj) + "t crease 2/1/0 4 5 3.0\nt corner 1/1/0 0 10\n";
    const auto response = call("model/obj", obj, {{"levels", "2"}, {"triangle_rule", "smooth"}, {"format", "json"}});
    ASSERT_EQ(response.status, 200) << response.body;
    auto mesh = read_obj(obj);
    ASSERT_TRUE(mesh.ok());
    SubdivisionOptions options;
    options.levels = 2;
    options.triangle_rule = TriangleRule::Smooth;
    const auto expected = surfaced::subdivide(*mesh, options);
    const auto got = positions_of(nlohmann::json::parse(response.body));
    ASSERT_EQ(got.size(), expected->vertex_count());
    for (std::size_t v = 0; v < got.size(); ++v) EXPECT_EQ(got[v], expected->positions[v]);
    EXPECT_EQ(got[0], mesh->positions[0]);  // the infinitely sharp corner stays put
}

TEST(SubdivideSharpFeatures, LimitSurfaceGivesLimitNormalsInObj) {
    const auto response = call("model/obj", kCubeObj,
                               {{"levels", "2"}, {"limit_surface", "true"}, {"normals", "true"}, {"format", "obj"}});
    ASSERT_EQ(response.status, 200) << response.body;
    auto back = read_obj(response.body);
    ASSERT_TRUE(back.ok()) << back.error().message;
    SubdivisionOptions options;
    options.levels = 2;
    options.limit_surface = true;
    const auto expected = surfaced::subdivide(read_obj(kCubeObj).value(), options);
    ASSERT_EQ(back->vertex_count(), expected->vertex_count());
    for (std::size_t v = 0; v < back->vertex_count(); ++v)
        EXPECT_LE(norm(back->positions[v] - expected->positions[v]), 1e-15);
    EXPECT_NE(response.body.find("\nvn "), std::string::npos);
}

TEST(SubdivideSharpFeatures, TargetFacesChoosesTheLargestLevelWithinIt) {
    // cube: 24, 96, 384, 1536 faces at levels 1..4
    auto response =
        call("application/json", json_request(shapes::cube(), R"(,"target_faces":400,"output":{"format":"json"})"));
    ASSERT_EQ(response.status, 200) << response.body;
    auto json = nlohmann::json::parse(response.body);
    EXPECT_EQ(json["stats"]["levels"], 3);
    EXPECT_EQ(json["stats"]["output_faces"], 384);
    EXPECT_EQ(json["stats"]["target_faces"], 400);
    EXPECT_EQ(json["stats"]["achieved_faces"], 384);
    EXPECT_EQ(json["stats"]["target_met"], true);
    // "levels" bounds the choice
    response = call("application/json",
                    json_request(shapes::cube(), R"(,"levels":2,"target_faces":100000,"output":{"format":"json"})"));
    json = nlohmann::json::parse(response.body);
    EXPECT_EQ(json["stats"]["levels"], 2);
    // a target below the input: the input as it is (level 0), reported as not met, as /simplify reports it
    response = call("model/obj", kCubeObj, {{"target_faces", "5"}, {"format", "obj"}});
    ASSERT_EQ(response.status, 200) << response.body;
    EXPECT_EQ(header(response, "X-Target-Faces"), "5");
    EXPECT_EQ(header(response, "X-Achieved-Faces"), "6");
    EXPECT_EQ(header(response, "X-Target-Met"), "false");
    EXPECT_EQ(read_obj(response.body)->face_count(), 6u);
    // the name it had before is a deprecated alias; both at once is a 400
    response = call("model/obj", kCubeObj, {{"max_faces", "30"}, {"format", "obj"}});
    ASSERT_EQ(response.status, 200) << response.body;
    EXPECT_EQ(header(response, "X-Achieved-Faces"), "24");
    expect_problem(call("model/obj", kCubeObj, {{"max_faces", "30"}, {"target_faces", "30"}}), 400, "invalid_field");
}

TEST(SubdivideSharpFeatures, LimitBudgetCountsTheInternalLevels) {
    // sharpness 9 needs 8 more internal levels at level 1: refused before any work
    Limits limits;
    limits.max_output_faces = 100000;
    auto json = expect_problem(
        call("application/json",
             json_request(shapes::cube(), R"(,"limit_surface":true,"creases":[{"edge":[0,1],"sharpness":9}])"), {},
             limits),
        422, "budget_exceeded");
    EXPECT_NE(json.value("detail", "").find("internal levels"), std::string::npos) << json.dump();
}

}  // namespace
}  // namespace surfaced::api

// ---- texture coordinates -------------------------------------------------------------------------------------------

namespace surfaced::api {
namespace {

TEST(SubdivideUvs, JsonUvsAreRefinedWithTheRequestedRule) {
    PolygonMesh mesh = shapes::grid(2, 2);
    std::string uvs = "[", uv_faces = "[";
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        uv_faces += f ? ",[" : "[";
        for (std::size_t k = 0; k < 4; ++k) {
            const Vec3& p = mesh.positions[mesh.face(f)[k]];
            const Index id = static_cast<Index>(mesh.uvs.size());
            mesh.uvs.push_back({p.x + (f == 3 ? 0.5 : 0.0), p.y});  // face 3 is its own chart: seams
            mesh.uv_indices.push_back(id);
            uvs +=
                (id ? ",[" : "[") + std::to_string(mesh.uvs.back().x) + "," + std::to_string(mesh.uvs.back().y) + "]";
            uv_faces += (k ? "," : "") + std::to_string(id);
        }
        uv_faces += "]";
    }
    uvs += "]";
    uv_faces += "]";
    const std::string body = R"({"mesh":{"positions":)" + nlohmann::json::parse(mesh_json(mesh))["positions"].dump() +
                             R"(,"faces":)" + nlohmann::json::parse(mesh_json(mesh))["faces"].dump() + R"(,"uvs":)" +
                             uvs + R"(,"uv_faces":)" + uv_faces +
                             R"(},"levels":2,"uv_interpolation":"boundaries","output":{"format":"json"}})";
    const auto response = call("application/json", body);
    ASSERT_EQ(response.status, 200) << response.body;
    const auto json = nlohmann::json::parse(response.body);

    SubdivisionOptions options;
    options.levels = 2;
    options.uv_interpolation = UvInterpolation::Boundaries;
    // the request's uvs went through text with 6 decimals: use the same values
    for (std::size_t i = 0; i < mesh.uvs.size(); ++i)
        mesh.uvs[i] = {std::stod(std::to_string(mesh.uvs[i].x)), std::stod(std::to_string(mesh.uvs[i].y))};
    const auto expected = surfaced::subdivide(mesh, options);
    ASSERT_TRUE(expected.ok());
    ASSERT_EQ(json["mesh"]["uv_faces"].size(), expected->face_count());
    for (std::size_t f = 0; f < expected->face_count(); ++f)
        for (std::size_t k = 0; k < 4; ++k) {
            const auto index = json["mesh"]["uv_faces"][f][k].get<std::size_t>();
            const Vec2 want = expected->uvs[expected->uv_indices[expected->face_offsets[f] + k]];
            EXPECT_EQ(json["mesh"]["uvs"][index][0].get<double>(), want.x);
            EXPECT_EQ(json["mesh"]["uvs"][index][1].get<double>(), want.y);
        }
}

TEST(SubdivideUvs, UvErrorsNameTheField) {
    const std::string base = R"({"mesh":{"positions":[[0,0,0],[1,0,0],[1,1,0]],"faces":[[0,1,2]],)";
    auto json = expect_problem(call("application/json", base + R"("uvs":[[0,0],[1,0]],"uv_faces":[[0,1,2]]}})"), 422,
                               "index_out_of_range");
    EXPECT_EQ(json.value("field", ""), "mesh.uv_faces[0][2]");
    json = expect_problem(call("application/json", base + R"("uvs":[[0,0]]}})"), 400, "invalid_field");
    EXPECT_EQ(json.value("field", ""), "mesh.uv_faces");
    json = expect_problem(call("application/json", base + R"("uvs":[[0,0],[1,0],[0,1]],"uv_faces":[[0,1]]}})"), 400,
                          "invalid_field");
    EXPECT_EQ(json.value("field", ""), "mesh.uv_faces[0]");
    json =
        expect_problem(call("application/json",
                            base + R"("uvs":[[0,0],[1,0],[0,1]],"uv_faces":[[0,1,2]]},"uv_interpolation":"smooth"})"),
                       400, "invalid_field");
    EXPECT_NE(json.value("detail", "").find("corners-plus1"), std::string::npos);
}

TEST(SubdivideUvs, ObjTexcoordsReachTheGlbAsTexcoord0) {
    const std::string obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n";
    const auto response = call("model/obj", obj, {{"levels", "2"}, {"compression", "none"}});
    ASSERT_EQ(response.status, 200) << response.body;
    const auto validation = testing::run_gltf_validator(response.body);
    ASSERT_TRUE(validation.ran) << validation.report;
    EXPECT_EQ(validation.errors, 0) << validation.report;
    EXPECT_EQ(validation.warnings, 0) << validation.report;
    auto back = read_glb(response.body);
    ASSERT_TRUE(back.ok()) << back.error().message;
    ASSERT_TRUE(back->has_uvs());
    // "corners-plus1" on a single quad chart: the corners stay, the interior is smooth; every uv within [0, 1]
    for (const Vec2& uv : back->uvs) {
        EXPECT_GE(uv.x, -1e-6);
        EXPECT_LE(uv.x, 1 + 1e-6);
    }
}

}  // namespace
}  // namespace surfaced::api

// ---- glTF JSON output ----------------------------------------------------------------------------------------------

namespace surfaced::api {
namespace {

TEST(SubdivideGltf, TextGltfIsValidAndSelfContained) {
    for (const char* compression : {"draco", "none"}) {
        const auto response =
            call("model/obj", kCubeObj, {{"levels", "2"}, {"format", "gltf"}, {"compression", compression}});
        ASSERT_EQ(response.status, 200) << response.body;
        EXPECT_EQ(response.content_type, "model/gltf+json");
        const auto json = nlohmann::json::parse(response.body);
        ASSERT_EQ(json["buffers"].size(), 1u);
        EXPECT_EQ(json["buffers"][0]["uri"].get<std::string>().rfind("data:application/octet-stream;base64,", 0), 0u);
        const auto validation = testing::run_gltf_validator(response.body);
        ASSERT_TRUE(validation.ran) << validation.report;
        EXPECT_EQ(validation.errors, 0) << compression << validation.report;
        EXPECT_EQ(validation.warnings, 0) << compression << validation.report;
        // the same accessors as the GLB form
        const auto glb = call("model/obj", kCubeObj, {{"levels", "2"}, {"compression", compression}});
        auto mesh = read_glb(glb.body);
        ASSERT_TRUE(mesh.ok());
        EXPECT_EQ(
            json["accessors"][json["meshes"][0]["primitives"][0]["indices"].get<int>()]["count"].get<std::size_t>(),
            3 * mesh->face_count());
    }
}

}  // namespace
}  // namespace surfaced::api

namespace surfaced::api {
namespace {

TEST(SubdivideLoopWeights, WarrenIsSelectableAndReachesTheGeometry) {
    SubdivisionOptions options;
    options.scheme = SubdivisionScheme::Loop;
    options.levels = 2;
    options.loop_weights = LoopWeights::Warren;
    const auto expected = surfaced::subdivide(shapes::icosahedron(), options);
    ASSERT_TRUE(expected.ok());
    const auto response =
        call("application/json",
             json_request(shapes::icosahedron(),
                          R"(,"scheme":"loop","levels":2,"loop_weights":"warren","output":{"format":"json"})"));
    ASSERT_EQ(response.status, 200) << response.body;
    const auto got = positions_of(nlohmann::json::parse(response.body));
    ASSERT_EQ(got.size(), expected->vertex_count());
    for (std::size_t v = 0; v < got.size(); ++v) EXPECT_EQ(got[v], expected->positions[v]);
    expect_problem(call("application/json", json_request(shapes::icosahedron(), R"(,"loop_weights":"stam")")), 400,
                   "invalid_field");
}

}  // namespace
}  // namespace surfaced::api

// ---- tolerance: the limit surface tessellated adaptively ---------------------------------------------------------

namespace surfaced::api {
namespace {

// The answer is the geometry's tessellate_limit for the same mesh and tolerance: same triangle count, achieved
// tolerance within the one asked for, the plan's exact count checked against the budget before any work.
namespace {

//! The library's tolerance tessellation of `mesh` (what /subdivide with tolerance must answer).
LimitTessellation library_tessellation(const PolygonMesh& mesh, double tolerance, double straddle = kDefaultStraddle) {
    auto evaluator = LimitSurfaceEvaluator::create(mesh, {});
    EXPECT_TRUE(evaluator.ok());
    LimitTessellationOptions options;
    options.tolerance = tolerance;
    options.straddle = straddle;
    auto result = tessellate_limit(*evaluator, mesh, options);
    EXPECT_TRUE(result.ok());
    return result.ok() ? std::move(result.value()) : LimitTessellation{};
}

}  // namespace

TEST(SubdivideOperation, ToleranceTessellatesTheLimitSurface) {
    const PolygonMesh cube = shapes::cube();
    const auto response =
        call("application/json", json_request(cube, R"(,"tolerance":0.002,"output":{"format":"json"})"));
    ASSERT_EQ(response.status, 200) << response.body;
    const auto json = nlohmann::json::parse(response.body);
    const LimitTessellation expected = library_tessellation(cube, 0.002);
    ASSERT_GT(expected.mesh.face_count(), 0u);
    EXPECT_EQ(json["mesh"]["faces"].size(), expected.mesh.face_count());
    EXPECT_EQ(json["mesh"]["positions"].size(), expected.mesh.vertex_count());
    for (const auto& face : json["mesh"]["faces"]) EXPECT_EQ(face.size(), 3u);
    EXPECT_EQ(header(response, "X-Output-Faces"), std::to_string(expected.mesh.face_count()));
    EXPECT_EQ(header(response, "X-Tolerance"), "0.002");
    const double achieved = std::stod(header(response, "X-Achieved-Tolerance"));
    EXPECT_GT(achieved, 0);
    EXPECT_LE(achieved, 0.002);
    EXPECT_NE(header(response, "Server-Timing").find("tessellate;dur="), std::string::npos);

    // the raw-file form takes it as a query parameter (its faces start at other corners than shapes::cube()'s, so
    // its layout is that of its own mesh)
    const auto raw = call("model/obj", kCubeObj, {{"tolerance", "0.002"}, {"format", "obj"}});
    ASSERT_EQ(raw.status, 200) << raw.body;
    auto mesh = read_obj(raw.body);
    ASSERT_TRUE(mesh.ok());
    auto obj_cube = read_obj(kCubeObj);
    ASSERT_TRUE(obj_cube.ok());
    EXPECT_EQ(mesh->face_count(), library_tessellation(*obj_cube, 0.002).mesh.face_count());
}

// straddle: unset, the library's default (vertices off the surface); 0, every vertex on the surface, more triangles
// on the cube, also within the tolerance; it needs tolerance, and outside [0, 1) it is 400 naming it.
TEST(SubdivideOperation, StraddleMovesVerticesOffTheSurface) {
    const PolygonMesh cube = shapes::cube();
    const LimitTessellation on_surface = library_tessellation(cube, 0.002, 0);
    const LimitTessellation straddled = library_tessellation(cube, 0.002);
    ASSERT_GT(straddled.mesh.face_count(), 0u);
    EXPECT_LT(straddled.mesh.face_count(), on_surface.mesh.face_count());
    for (const auto& [body, expected] :
         {std::pair{R"(,"tolerance":0.002,"output":{"format":"json"})", &straddled},
          std::pair{R"(,"tolerance":0.002,"straddle":0.45,"output":{"format":"json"})", &straddled},
          std::pair{R"(,"tolerance":0.002,"straddle":0,"output":{"format":"json"})", &on_surface}}) {
        const auto response = call("application/json", json_request(cube, body));
        ASSERT_EQ(response.status, 200) << response.body;
        const auto json = nlohmann::json::parse(response.body);
        EXPECT_EQ(json["mesh"]["faces"].size(), expected->mesh.face_count()) << body;
        EXPECT_LE(std::stod(header(response, "X-Achieved-Tolerance")), 0.002) << body;
    }
    const auto raw = call("model/obj", kCubeObj, {{"tolerance", "0.002"}, {"straddle", "0"}, {"format", "obj"}});
    ASSERT_EQ(raw.status, 200) << raw.body;
    auto mesh = read_obj(raw.body);
    ASSERT_TRUE(mesh.ok());
    auto obj_cube = read_obj(kCubeObj);
    ASSERT_TRUE(obj_cube.ok());
    EXPECT_EQ(mesh->face_count(), library_tessellation(*obj_cube, 0.002, 0).mesh.face_count());

    auto json_problem = expect_problem(call("application/json", json_request(cube, R"(,"levels":2,"straddle":0)")), 400,
                                       "invalid_field");
    EXPECT_EQ(json_problem.value("field", ""), "straddle");
    for (const char* bad : {"-0.1", "1", "x"}) {
        const auto problem = expect_problem(call("model/obj", kCubeObj, {{"tolerance", "0.002"}, {"straddle", bad}}),
                                            400, "invalid_field");
        EXPECT_EQ(problem.value("field", ""), "straddle") << bad;
    }
}

// threads 2 gives the same answer as 1 (uniform levels and tolerance alike); outside [1, 2] it is 400 naming it.
TEST(SubdivideOperation, TwoThreadsGiveTheSameAnswer) {
    const PolygonMesh torus = shapes::irregular_torus();
    for (const char* options :
         {R"(,"tolerance":0.005,"output":{"format":"obj"})", R"(,"levels":3,"output":{"format":"obj"})"}) {
        const auto one = call("application/json", json_request(torus, std::string(options)));
        const auto two = call("application/json", json_request(torus, std::string(R"(,"threads":2)") + options));
        ASSERT_EQ(one.status, 200) << one.body;
        ASSERT_EQ(two.status, 200) << two.body;
        EXPECT_EQ(one.body, two.body) << options;
    }
    for (const char* bad : {"0", "3", "x"}) {
        const auto json = expect_problem(call("model/obj", kCubeObj, {{"threads", bad}}), 400, "invalid_field");
        EXPECT_EQ(json.value("field", ""), "threads") << bad;
    }
}

TEST(SubdivideOperation, ToleranceExcludesLevelsAndTargetFaces) {
    for (const char* extra : {R"(,"tolerance":0.01,"levels":2)", R"(,"tolerance":0.01,"target_faces":100)",
                              R"(,"tolerance":0.01,"scheme":"loop")"}) {
        const auto json =
            expect_problem(call("application/json", json_request(shapes::cube(), extra)), 400, "invalid_field");
        EXPECT_EQ(json.value("field", ""), "tolerance") << extra;
    }
    expect_problem(call("model/obj", kCubeObj, {{"tolerance", "0.01"}, {"levels", "1"}}), 400, "invalid_field");
    for (const char* bad : {"0", "-1", "x"})
        expect_problem(call("model/obj", kCubeObj, {{"tolerance", bad}}), 400, "invalid_field");
}

TEST(SubdivideOperation, ToleranceBudgetIsCheckedFromThePrediction) {
    const PolygonMesh cube = shapes::cube();
    auto evaluator = LimitSurfaceEvaluator::create(cube, {});
    ASSERT_TRUE(evaluator.ok());
    LimitTessellationOptions options;
    options.tolerance = 0.002;
    auto plan = plan_limit_tessellation(*evaluator, cube, options);
    ASSERT_TRUE(plan.ok());
    Limits limits;
    limits.max_output_faces = plan->triangles - 1;
    const auto json = expect_problem(call("application/json", json_request(cube, R"(,"tolerance":0.002)"), {}, limits),
                                     422, "budget_exceeded");
    EXPECT_EQ(json.value("field", ""), "tolerance");
    EXPECT_NE(json.value("detail", "").find(std::to_string(plan->triangles)), std::string::npos) << json.dump();
    limits.max_output_faces = plan->triangles;
    EXPECT_EQ(call("application/json", json_request(cube, R"(,"tolerance":0.002)"), {}, limits).status, 200);
    // a tolerance needing more segments per edge than the server allows
    limits.max_output_faces = 4'000'000;
    limits.max_patch_segments = 4;
    expect_problem(call("application/json", json_request(cube, R"(,"tolerance":0.0001)"), {}, limits), 422,
                   "budget_exceeded");
}

}  // namespace
}  // namespace surfaced::api
