// POST /tessellate and GET /patches/{name} called through dispatch (no sockets): both request forms, budgets and
// errors with field paths, ETag / If-None-Match, and the route table's path parameters.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "api/routes.h"
#include "geometry/io/bez.h"
#include "tests/support/api_request.h"
#include "tests/support/gltf_validator.h"

namespace surfaced::api {
namespace {

using namespace fixtures;

ApiResponse post_json(const std::string& body, const ApiContext& context = {}) {
    return dispatch(make_request("POST", "/tessellate", "application/json", body), context);
}

ApiResponse get_sample(const std::string& name, std::multimap<std::string, std::string> query = {},
                       std::string if_none_match = "") {
    ApiRequest request = make_request("GET", "/patches/" + name, "", {}, std::move(query));
    if (!if_none_match.empty()) request.headers.emplace("if-none-match", if_none_match);
    return dispatch(request, ApiContext{});
}

void expect_valid_glb(const std::string& bytes) {
    const auto report = testing::run_gltf_validator(bytes);
    ASSERT_TRUE(report.ran) << report.report;
    EXPECT_EQ(report.errors, 0) << report.report;
    EXPECT_EQ(report.warnings, 0) << report.report;
}

//! The teapot as a JSON request body.
std::string teapot_json(const std::string& options) {
    auto set = read_bez(patch_sample_text("teapot"));
    EXPECT_TRUE(set.ok());
    nlohmann::json patches = nlohmann::json::array();
    for (const BezierPatch& patch : set->patches) {
        nlohmann::json points = nlohmann::json::array();
        for (const Vec3& p : patch.points) points.push_back({p.x, p.y, p.z});
        patches.push_back({{"degree", {patch.degree_u, patch.degree_v}}, {"points", points}});
    }
    std::string body = nlohmann::json{{"patches", patches}}.dump();
    body.pop_back();
    return body + options + "}";
}

constexpr const char* kBilinear = R"({"patches":[{"degree":[1,1],"points":[[0,0,0],[1,0,0],[0,1,0],[1,1,1]]}])";

TEST(TessellateOperation, JsonBilinearPatchToValidGlb) {
    // z = u v: its only second derivative is S_uv = (0, 0, 1), so the bound (1/8) 2 Muv / (nu nv) <= 0.01 needs
    // nu = nv = ceil(sqrt(1 / 0.04)) = 5, i.e. 50 triangles and 36 vertices.
    const ApiResponse response = post_json(std::string(kBilinear) + R"(,"tolerance":0.01})");
    ASSERT_EQ(response.status, 200) << response.body;
    EXPECT_EQ(response.content_type, "model/gltf-binary");
    EXPECT_EQ(header(response, "X-Patches"), "1");
    EXPECT_EQ(header(response, "X-Output-Faces"), "50");
    EXPECT_EQ(header(response, "X-Output-Vertices"), "36");
    // the header is the bound as computed, to the last bit: here 0.01 up to the rounding of its floating-point terms
    EXPECT_LE(std::stod(header(response, "X-Error-Bound")), 0.01 * (1 + 1e-12));
    EXPECT_NE(response.body.find("\"NORMAL\""), std::string::npos);
    EXPECT_NE(response.body.find("\"TEXCOORD_0\""), std::string::npos);
    EXPECT_NE(response.body.find("KHR_draco_mesh_compression"), std::string::npos);
    expect_valid_glb(response.body);
}

TEST(TessellateOperation, JsonTeapotWithinTolerance) {
    const ApiResponse response = post_json(teapot_json(R"(,"tolerance":0.005,"output":{"compression":"none"})"));
    ASSERT_EQ(response.status, 200) << response.body;
    EXPECT_EQ(header(response, "X-Patches"), "32");
    EXPECT_LE(std::stod(header(response, "X-Error-Bound")), 0.005);
    EXPECT_EQ(response.body.find("KHR_draco_mesh_compression"), std::string::npos);
    expect_valid_glb(response.body);
}

TEST(TessellateOperation, RawBezBodyWithSegments) {
    ApiRequest request;
    request.method = "POST";
    request.path = "/tessellate";
    request.content_type = "text/plain; charset=utf-8";
    request.body = patch_sample_text("teapot");
    request.query = {{"segments", "4"}, {"format", "obj"}};
    const ApiResponse response = dispatch(request, ApiContext{});
    ASSERT_EQ(response.status, 200) << response.body;
    EXPECT_EQ(response.content_type, "model/obj");
    // 32 patches x 4 x 4 cells x 2 triangles, minus one triangle per cell along the collapsed edges of the lid apex
    // (patches 20-23) and the bottom centre (28-31): 1024 - 8 x 4.
    EXPECT_EQ(header(response, "X-Output-Faces"), "992");
}

TEST(TessellateOperation, ErrorsNameTheField) {
    expect_problem(post_json(std::string(kBilinear) + R"(,"tolerance":0.1,"segments":3})"), 400, "invalid_field",
                   "segments");
    expect_problem(post_json(std::string(kBilinear) + R"(,"tolerance":-1})"), 400, "invalid_field", "tolerance");
    expect_problem(post_json(std::string(kBilinear) + R"(,"tolerance":"small"})"), 400, "invalid_field", "tolerance");
    expect_problem(post_json(R"({"patches":[{"degree":[1,1],"points":[[0,0,0],[1,0,0],[0,1,0]]}]})"), 400,
                   "invalid_field", "patches[0].points");
    expect_problem(post_json(R"({"patches":[{"degree":[0,1],"points":[]}]})"), 400, "invalid_field",
                   "patches[0].degree[0]");
    expect_problem(post_json(R"({"patches":[{"degree":[1,1],"points":[[0,0,0],[1,0,0],[0,1,0],[1,"x",0]]}]})"), 400,
                   "invalid_field", "patches[0].points[3][1]");
    expect_problem(post_json(R"({"patches":[]})"), 400, "invalid_field", "patches");
    expect_problem(post_json(std::string(kBilinear) + R"(,"colour":1})"), 400, "unknown_field", "colour");
    expect_problem(post_json(std::string(kBilinear) + R"(,"output":{"format":"xyz"}})"), 400, "invalid_field",
                   "output.format");
    expect_problem(post_json(std::string(kBilinear) + R"(,"output":{"format":"stl","normals":true}})"), 400,
                   "invalid_field", "output.normals");
    expect_problem(post_json("{\"patches\":"), 400, "invalid_json", "");
}

TEST(TessellateOperation, BudgetsBeforeWork) {
    expect_problem(post_json(std::string(kBilinear) + R"(,"segments":100000})"), 422, "budget_exceeded", "segments");
    expect_problem(post_json(std::string(kBilinear) + R"(,"tolerance":1e-12})"), 422, "budget_exceeded", "tolerance");
    const auto fine =
        expect_problem(post_json(std::string(kBilinear) + R"(,"tolerance":1e-12})"), 422, "budget_exceeded");
    EXPECT_NE(fine.value("detail", "").find("tolerance 1e-12 needs"), std::string::npos) << fine.dump();
    ApiContext small;
    small.limits.max_output_faces = 100;
    expect_problem(post_json(std::string(kBilinear) + R"(,"segments":8})", small), 422, "budget_exceeded", "segments");
    small.limits.max_patches = 1;
    expect_problem(post_json(R"({"patches":[{"degree":[1,1],"points":[]},{"degree":[1,1],"points":[]}]})", small), 422,
                   "budget_exceeded", "patches");
}

TEST(TessellateOperation, RawBodyErrors) {
    ApiRequest request;
    request.method = "POST";
    request.path = "/tessellate";
    request.content_type = "text/plain";
    request.body = "BEZ113\n0 0 0 1 0 0\n0 1 0 1 x 0\n";
    ApiResponse response = dispatch(request, ApiContext{});
    expect_problem(response, 400, "parse_error", "");
    EXPECT_EQ(response.error->line.value_or(-1), 3);

    request.content_type = "model/stl";
    expect_problem(dispatch(request, ApiContext{}), 415, "unsupported_media_type", "");

    request.content_type = "text/plain";
    request.query = {{"resolution", "3"}};
    expect_problem(dispatch(request, ApiContext{}), 400, "unknown_parameter", "resolution");
}

ApiResponse post_raw(const std::string& content_type, const std::string& body,
                     std::multimap<std::string, std::string> query = {}) {
    return dispatch(make_request("POST", "/tessellate", content_type, body, std::move(query)), ApiContext{});
}

TEST(TessellateOperation, ObjFreeFormSurfaces) {
    const std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 1\ncstype bezier\ndeg 1 1\nsurf 0 1 0 1 1 2 3 4\nend\n";
    // the same bilinear patch as kBilinear: 50 triangles at tolerance 0.01, like the JSON form
    const ApiResponse response = post_raw("model/obj", obj, {{"tolerance", "0.01"}, {"format", "obj"}});
    ASSERT_EQ(response.status, 200) << response.body;
    EXPECT_EQ(header(response, "X-Patches"), "1");
    EXPECT_EQ(header(response, "X-Output-Faces"), "50");

    std::string cardinal = obj;
    cardinal.replace(cardinal.find("cstype bezier"), 13, "cstype cardinal");
    const ApiResponse refused = post_raw("model/obj", cardinal);
    expect_problem(refused, 422, "unsupported", "");
    EXPECT_EQ(refused.error->line.value_or(-1), 5);
    EXPECT_NE(refused.body.find("line 5: cstype cardinal is not supported"), std::string::npos) << refused.body;

    const ApiResponse bad = post_raw("model/obj", "v 0 0 0\ncstype bezier\ndeg 1 1\nsurf 0 1 0 1 1 1 1 7\nend\n");
    expect_problem(bad, 400, "parse_error", "");
    EXPECT_EQ(bad.error->line.value_or(-1), 4);
}

TEST(TessellateOperation, RationalPatchesFromJsonAndBez) {
    // a quarter cylinder of radius 2: every output vertex at distance 2 from the z axis
    const double s = std::sqrt(0.5);
    nlohmann::json patch = {{"degree", {2, 1}},
                            {"points", {{2, 0, 0}, {2, 2, 0}, {0, 2, 0}, {2, 0, 1}, {2, 2, 1}, {0, 2, 1}}},
                            {"weights", {1, s, 1, 1, s, 1}}};
    nlohmann::json body = {{"patches", {patch}}, {"tolerance", 1e-3}, {"output", {{"format", "obj"}}}};
    const ApiResponse response = post_json(body.dump());
    ASSERT_EQ(response.status, 200) << response.body;
    EXPECT_LE(std::stod(header(response, "X-Error-Bound")), 1e-3);
    std::size_t vertices = 0;
    for (std::size_t at = response.body.find("\nv "); at != std::string::npos;
         at = response.body.find("\nv ", at + 1)) {
        double x = 0, y = 0, z = 0;
        ASSERT_EQ(std::sscanf(response.body.c_str() + at + 3, "%lf %lf %lf", &x, &y, &z), 3);
        EXPECT_NEAR(std::hypot(x, y), 2.0, 1e-9);  // the OBJ writer's precision
        ++vertices;
    }
    EXPECT_GT(vertices, 20u);

    // the same patch as BEZ214 (homogeneous points) gives the same mesh
    char bez[512];
    std::snprintf(bez, sizeof bez,
                  "BEZ214\n2 0 0 1 %.17g %.17g 0 %.17g 0 2 0 1\n2 0 1 1 %.17g %.17g %.17g %.17g 0 2 1 1\n", 2 * s,
                  2 * s, s, 2 * s, 2 * s, s, s);
    const ApiResponse from_bez =
        post_raw("application/x-geomview-bez", bez, {{"tolerance", "0.001"}, {"format", "obj"}});
    ASSERT_EQ(from_bez.status, 200) << from_bez.body;
    EXPECT_EQ(header(from_bez, "X-Output-Faces"), header(response, "X-Output-Faces"));

    // weights: field paths
    patch["weights"] = {1, s, 1, 1, -1, 1};
    expect_problem(post_json(nlohmann::json{{"patches", {patch}}}.dump()), 400, "invalid_field",
                   "patches[0].weights[4]");
    patch["weights"] = {1, 2};
    expect_problem(post_json(nlohmann::json{{"patches", {patch}}}.dump()), 400, "invalid_field", "patches[0].weights");
    patch["weights"] = {1, 1e13, 1, 1, 1, 1};
    expect_problem(post_json(nlohmann::json{{"patches", {patch}}}.dump()), 422, "invalid_argument", "patches[0]");
}

TEST(PatchSamples, TeapotWithETagAndNotModified) {
    const ApiResponse first = get_sample("teapot", {{"tolerance", "0.01"}});
    ASSERT_EQ(first.status, 200) << first.body;
    EXPECT_EQ(first.content_type, "model/gltf-binary");
    const std::string etag = header(first, "ETag");
    ASSERT_GE(etag.size(), 3u);
    EXPECT_EQ(etag.front(), '"');
    EXPECT_EQ(etag.back(), '"');
    EXPECT_NE(header(first, "Cache-Control").find("max-age"), std::string::npos);
    EXPECT_LE(std::stod(header(first, "X-Error-Bound")), 0.01);
    expect_valid_glb(first.body);

    // the same request gives the same ETag; If-None-Match with it (alone, in a list, weak, or *) gives 304
    EXPECT_EQ(header(get_sample("teapot", {{"tolerance", "0.01"}}), "ETag"), etag);
    for (const std::string& inm : {etag, "\"other\", " + etag, "W/" + etag, std::string("*")}) {
        const ApiResponse cached = get_sample("teapot", {{"tolerance", "0.01"}}, inm);
        EXPECT_EQ(cached.status, 304) << inm;
        EXPECT_TRUE(cached.body.empty());
        EXPECT_EQ(header(cached, "ETag"), etag);
    }
    // other options, other entity
    const ApiResponse other = get_sample("teapot", {{"segments", "6"}}, etag);
    EXPECT_EQ(other.status, 200);
    EXPECT_NE(header(other, "ETag"), etag);
    EXPECT_NE(header(get_sample("teapot", {{"tolerance", "0.02"}}), "ETag"), etag);
}

TEST(PatchSamples, OutOfRangeOptionsAre400NamingTheOption) {
    // the glTF writer takes at most 24 bits: refused before any work, as every mesh operation refuses it
    auto json = expect_problem(get_sample("teapot", {{"quantize_position", "25"}}), 400, "invalid_field");
    EXPECT_EQ(json.value("field", ""), "quantize_position");
    EXPECT_NE(json.value("detail", "").find("[1, 24]"), std::string::npos) << json.dump();
    expect_problem(post_json(std::string(kBilinear) + R"(,"output":{"quantize_position":25}})"), 400, "invalid_field",
                   "output.quantize_position");
    json = expect_problem(get_sample("teapot", {{"tolerance", "-1e-9"}}), 400, "invalid_field");
    EXPECT_EQ(json.value("field", ""), "tolerance");
    EXPECT_NE(json.value("detail", "").find("got -1e-09"), std::string::npos) << json.dump();
    // format patches (the control points) is allowed here, so it is listed when a value is not
    json = expect_problem(get_sample("teapot", {{"format", "xyz"}}), 400, "invalid_field");
    EXPECT_EQ(json.value("field", ""), "format");
    EXPECT_NE(json.value("detail", "").find("\"patches\""), std::string::npos) << json.dump();
}

TEST(PatchSamples, Errors) {
    expect_problem(get_sample("kettle"), 404, "not_found", "");
    expect_problem(get_sample("teapot", {{"tolerance", "abc"}}), 400, "invalid_field", "tolerance");
    expect_problem(get_sample("teapot", {{"tolerance", "0.1"}, {"segments", "2"}}), 400, "invalid_field", "segments");
    expect_problem(get_sample("teapot", {{"levels", "2"}}), 400, "unknown_parameter", "levels");
    const ApiResponse wrong_method = dispatch(make_request("POST", "/patches/teapot"), ApiContext{});
    expect_problem(wrong_method, 405, "method_not_allowed", "");
    EXPECT_EQ(header(wrong_method, "Allow"), "GET, HEAD");
}

TEST(Routes, PathParameters) {
    std::map<std::string, std::string> params;
    EXPECT_TRUE(match_path("/patches/{name}", "/patches/teapot", &params));
    EXPECT_EQ(params["name"], "teapot");
    EXPECT_FALSE(match_path("/patches/{name}", "/patches/"));
    EXPECT_FALSE(match_path("/patches/{name}", "/patches"));
    EXPECT_FALSE(match_path("/patches/{name}", "/patches/a/b"));
    EXPECT_FALSE(match_path("/patches/{name}", "/patch/teapot"));
    EXPECT_TRUE(match_path("/a/{x}/c/{y}", "/a/1/c/2", &params));
    EXPECT_EQ(params["x"], "1");
    EXPECT_EQ(params["y"], "2");
    EXPECT_TRUE(match_path("/subdivide", "/subdivide"));
    EXPECT_FALSE(match_path("/subdivide", "/subdivide/"));
}

ApiResponse post_curves(const std::string& body) {
    return dispatch(make_request("POST", "/curves", "application/json", body), ApiContext{});
}

TEST(CurvesOperation, AnswersEveryQuery) {
    // the parabola (t, t^2) as a 2D quadratic, and the rational quarter circle
    const ApiResponse response =
        post_curves(R"({"points":[[0,0],[0.5,0],[1,1]],"evaluate":[0,0.5,1],"derivatives":{"t":[0.5],"order":1},)"
                    R"("curvature":[0],"split":0.5,"elevate":1,"bounding_box":true,"length":{"tolerance":1e-9},)"
                    R"("closest":[0,1],"tessellate":{"tolerance":0.001}})");
    ASSERT_EQ(response.status, 200) << response.body;
    const auto json = nlohmann::json::parse(response.body);
    EXPECT_EQ(json["degree"], 2);
    EXPECT_EQ(json["rational"], false);
    EXPECT_EQ(json["evaluate"][1], nlohmann::json::parse("[0.5, 0.25]"));
    EXPECT_EQ(json["derivatives"][0], nlohmann::json::parse("[1.0, 1.0]"));
    EXPECT_NEAR(json["curvature"][0].get<double>(), 2.0, 1e-12);
    EXPECT_EQ(json["split"].size(), 2u);
    EXPECT_EQ(json["elevate"]["points"].size(), 4u);
    EXPECT_EQ(json["bounding_box"]["max"], nlohmann::json::parse("[1.0, 1.0]"));
    const double exact = (2 * std::sqrt(5.0) + std::asinh(2.0)) / 4;
    EXPECT_NEAR(json["length"]["length"].get<double>(), exact, 1e-9);
    EXPECT_TRUE(json["length"]["guaranteed"].get<bool>());
    // closest point of (t, t^2) to (0, 1): minimise t^2 + (t^2 - 1)^2 -> t^2 = 1/2
    EXPECT_NEAR(json["closest"]["t"].get<double>(), std::sqrt(0.5), 1e-9);
    EXPECT_LE(json["tessellate"]["bound"].get<double>(), 0.001);
    EXPECT_EQ(json["tessellate"]["points"].size(), json["tessellate"]["segments"].get<std::size_t>() + 1);

    const ApiResponse circle =
        post_curves(R"({"points":[[1,0,0],[1,1,0],[0,1,0]],"weights":[1,0.7071067811865476,1],"curvature":[0.3]})");
    ASSERT_EQ(circle.status, 200) << circle.body;
    EXPECT_NEAR(nlohmann::json::parse(circle.body)["curvature"][0].get<double>(), 1.0, 1e-9);
}

TEST(CurvesOperation, ErrorsNameTheField) {
    expect_problem(post_curves(R"({"evaluate":[0.5]})"), 400, "invalid_field", "points");
    expect_problem(post_curves(R"({"points":[[0,0],[1,"a"]]})"), 400, "invalid_field", "points[1][1]");
    expect_problem(post_curves(R"({"points":[[0,0],[1,1,1]]})"), 400, "invalid_field", "points[1]");
    expect_problem(post_curves(R"({"points":[[0,0],[1,1]],"evaluate":[0.5,2]})"), 400, "invalid_field", "evaluate[1]");
    expect_problem(post_curves(R"({"points":[[0,0],[1,1]],"weights":[1,0]})"), 400, "invalid_field", "weights[1]");
    expect_problem(post_curves(R"({"points":[[0,0],[1,1]],"tessellate":{"tolerance":0}})"), 400, "invalid_field",
                   "tessellate.tolerance");
    expect_problem(post_curves(R"({"points":[[0,0],[1,1]],"spline":true})"), 400, "unknown_field", "spline");
}

}  // namespace
}  // namespace surfaced::api
