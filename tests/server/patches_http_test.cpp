// GET /patches/teapot, POST /tessellate (patches and B-spline surfaces), POST /curves, POST /surfaces and
// GET /openapi.json over real HTTP (ephemeral loopback port), and `surfaced tessellate` and `surfaced surfaces`;
// trimmed surfaces from JSON and OBJ, over HTTP and from the command line.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <array>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <cmath>
#include <random>
#include <sstream>
#include <vector>
#include <string>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "api/openapi.h"
#include "geometry/io/bez.h"
#include "server/http_server.h"
#include "tests/support/gltf_validator.h"
#include "tests/support/http_test_server.h"

namespace surfaced::server {
namespace {

namespace fs = std::filesystem;

class PatchesHttp : public testing::SharedServerTest<PatchesHttp> {
protected:
    static httplib::Client client() { return SharedServerTest::client(30); }
};

TEST_F(PatchesHttp, TeapotGlbThenNotModified) {
    auto res = client().Get("/patches/teapot?tolerance=0.01");
    ASSERT_TRUE(res) << httplib::to_string(res.error());
    ASSERT_EQ(res->status, 200) << res->body;
    EXPECT_EQ(res->get_header_value("Content-Type"), "model/gltf-binary");
    EXPECT_NE(res->get_header_value("Cache-Control").find("max-age="), std::string::npos);
    const std::string etag = res->get_header_value("ETag");
    ASSERT_FALSE(etag.empty());
    EXPECT_EQ(res->body.substr(0, 4), "glTF");
    EXPECT_NE(res->body.find("KHR_draco_mesh_compression"), std::string::npos);
    const auto report = testing::run_gltf_validator(res->body);
    ASSERT_TRUE(report.ran) << report.report;
    EXPECT_EQ(report.errors, 0) << report.report;
    EXPECT_EQ(report.warnings, 0) << report.report;

    auto cached = client().Get("/patches/teapot?tolerance=0.01", {{"If-None-Match", etag}});
    ASSERT_TRUE(cached) << httplib::to_string(cached.error());
    EXPECT_EQ(cached->status, 304);
    EXPECT_TRUE(cached->body.empty());
    EXPECT_EQ(cached->get_header_value("ETag"), etag);

    auto stale = client().Get("/patches/teapot?tolerance=0.01", {{"If-None-Match", "\"0000000000000000\""}});
    ASSERT_TRUE(stale);
    EXPECT_EQ(stale->status, 200);
}

TEST_F(PatchesHttp, UnknownSampleAndBadRequestAreProblems) {
    auto missing = client().Get("/patches/kettle");
    ASSERT_TRUE(missing);
    EXPECT_EQ(missing->status, 404);
    EXPECT_EQ(missing->get_header_value("Content-Type"), "application/problem+json");

    const std::string body = R"({"patches":[{"degree":[3,3],"points":[[0,0,0]]}],"tolerance":0.01})";
    auto bad = client().Post("/tessellate", body, "application/json");
    ASSERT_TRUE(bad) << httplib::to_string(bad.error());
    EXPECT_EQ(bad->status, 400);
    EXPECT_EQ(bad->get_header_value("Content-Type"), "application/problem+json");
    const auto json = nlohmann::json::parse(bad->body, nullptr, false);
    ASSERT_FALSE(json.is_discarded()) << bad->body;
    EXPECT_EQ(json.value("code", ""), "invalid_field");
    EXPECT_EQ(json.value("field", ""), "patches[0].points");
    EXPECT_EQ(json.value("status", 0), 400);
}

TEST_F(PatchesHttp, RawBezUpload) {
    auto res = client().Post("/tessellate?segments=3&compression=none", std::string(patch_sample_text("teapot")),
                             "application/x-geomview-bez");
    ASSERT_TRUE(res) << httplib::to_string(res.error());
    ASSERT_EQ(res->status, 200) << res->body;
    EXPECT_EQ(res->get_header_value("X-Patches"), "32");
    const auto report = testing::run_gltf_validator(res->body);
    ASSERT_TRUE(report.ran) << report.report;
    EXPECT_EQ(report.errors, 0) << report.report;
    EXPECT_EQ(report.warnings, 0) << report.report;
}

// format=patches gives the control points, exactly as the built-in BEZ text has them, in the form POST /tessellate
// accepts: posting them back tessellates to the same mesh as GET /patches/teapot with the same options.
TEST_F(PatchesHttp, TeapotControlPointsRoundTrip) {
    auto res = client().Get("/patches/teapot?format=patches");
    ASSERT_TRUE(res) << httplib::to_string(res.error());
    ASSERT_EQ(res->status, 200) << res->body;
    EXPECT_EQ(res->get_header_value("Content-Type"), "application/json");
    EXPECT_FALSE(res->get_header_value("ETag").empty());
    const auto json = nlohmann::json::parse(res->body, nullptr, false);
    ASSERT_FALSE(json.is_discarded()) << res->body.substr(0, 200);
    auto expected = read_bez(patch_sample_text("teapot"));
    ASSERT_TRUE(expected);
    ASSERT_EQ(json["patches"].size(), expected->patches.size());
    ASSERT_EQ(json["patches"].size(), 32u);
    for (std::size_t p = 0; p < expected->patches.size(); ++p) {
        const auto& patch = json["patches"][p];
        const BezierPatch& want = expected->patches[p];
        ASSERT_EQ(patch["degree"], nlohmann::json::array({want.degree_u, want.degree_v}));
        ASSERT_EQ(patch["points"].size(), want.points.size());
        for (std::size_t i = 0; i < want.points.size(); ++i) {
            EXPECT_EQ(patch["points"][i][0].get<double>(), want.points[i].x);
            EXPECT_EQ(patch["points"][i][1].get<double>(), want.points[i].y);
            EXPECT_EQ(patch["points"][i][2].get<double>(), want.points[i].z);
        }
    }
    nlohmann::json body = json;
    body["segments"] = 5;
    body["output"] = {{"format", "obj"}};
    auto posted = client().Post("/tessellate", body.dump(), "application/json");
    auto direct = client().Get("/patches/teapot?segments=5&format=obj");
    ASSERT_TRUE(posted && direct);
    ASSERT_EQ(posted->status, 200) << posted->body;
    ASSERT_EQ(direct->status, 200) << direct->body;
    EXPECT_EQ(posted->body, direct->body);

    auto mixed = client().Get("/patches/teapot?format=patches&segments=4");
    ASSERT_TRUE(mixed);
    EXPECT_EQ(mixed->status, 400);
    const auto problem = nlohmann::json::parse(mixed->body, nullptr, false);
    ASSERT_FALSE(problem.is_discarded()) << mixed->body;
    EXPECT_EQ(problem.value("field", ""), "segments");
}

int run(const std::string& command) {
    const int status = std::system(command.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(TessellateCli, SampleAndFile) {
    std::random_device rd;
    const fs::path dir = fs::temp_directory_path() / ("surfaced-tess-" + std::to_string(rd()));
    fs::create_directories(dir);
    const std::string cli = SURFACED_CLI_PATH;
    const fs::path bez = dir / "teapot.bez", glb = dir / "teapot.glb", obj = dir / "teapot.obj";
    std::ofstream(bez, std::ios::binary) << patch_sample_text("teapot");

    EXPECT_EQ(run(cli + " tessellate sample:teapot -o " + glb.string() + " --tolerance 0.02 > /dev/null"), 0);
    std::ifstream in(glb, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), {});
    const auto report = testing::run_gltf_validator(bytes);
    ASSERT_TRUE(report.ran) << report.report;
    EXPECT_EQ(report.errors, 0) << report.report;

    EXPECT_EQ(run(cli + " tessellate " + bez.string() + " -o " + obj.string() + " --segments 4 > /dev/null"), 0);
    EXPECT_GT(fs::file_size(obj), 1000u);
    // usage errors exit 2, failures 1
    EXPECT_EQ(
        run(cli + " tessellate " + bez.string() + " -o " + obj.string() + " --segments 4 --tolerance 0.1 2> /dev/null"),
        2);
    EXPECT_EQ(run(cli + " tessellate sample:kettle -o " + glb.string() + " 2> /dev/null"), 1);
    std::error_code ec;
    fs::remove_all(dir, ec);
}

TEST_F(PatchesHttp, CurvesOverHttp) {
    // the parabola (t, t^2): point at t = 1/2 and curvature 2 at the vertex
    auto res = client().Post("/curves", R"({"points":[[0,0],[0.5,0],[1,1]],"evaluate":[0.5],"curvature":[0]})",
                             "application/json");
    ASSERT_TRUE(res) << httplib::to_string(res.error());
    ASSERT_EQ(res->status, 200) << res->body;
    const auto json = nlohmann::json::parse(res->body);
    EXPECT_EQ(json["evaluate"][0], nlohmann::json::parse("[0.5, 0.25]"));
    EXPECT_NEAR(json["curvature"][0].get<double>(), 2.0, 1e-12);

    auto bad = client().Post("/curves", R"({"evaluate":[0.5]})", "application/json");
    ASSERT_TRUE(bad);
    EXPECT_EQ(bad->status, 400);
    EXPECT_EQ(bad->get_header_value("Content-Type"), "application/problem+json");
    EXPECT_EQ(nlohmann::json::parse(bad->body).value("field", ""), "points");
}

TEST_F(PatchesHttp, SurfacesOverHttp) {
    // the plane z = 0 over [0, 2] x [0, 1] as a bilinear B-spline of two spans along u: S(u, v) = (u, v, 0)
    const std::string surface = R"({"degree":[1,1],"knots_u":[0,0,1,2,2],"knots_v":[0,0,1,1],)"
                                R"("points":[[0,0,0],[1,0,0],[2,0,0],[0,1,0],[1,1,0],[2,1,0]]})";
    auto res = client().Post(
        "/surfaces",
        R"({"surface":)" + surface + R"(,"evaluate":[[1.5,0.25]],"closest":[[0.3,0.6,2]],"to_bezier":true})",
        "application/json");
    ASSERT_TRUE(res) << httplib::to_string(res.error());
    ASSERT_EQ(res->status, 200) << res->body;
    const auto json = nlohmann::json::parse(res->body);
    EXPECT_EQ(json["evaluate"][0]["position"], nlohmann::json::parse("[1.5, 0.25, 0]"));
    EXPECT_EQ(json["evaluate"][0]["normal"], nlohmann::json::parse("[0, 0, 1]"));
    EXPECT_NEAR(json["closest"][0]["distance"].get<double>(), 2.0, 1e-12);
    EXPECT_NEAR(json["closest"][0]["uv"][0].get<double>(), 0.3, 1e-9);
    EXPECT_NEAR(json["closest"][0]["uv"][1].get<double>(), 0.6, 1e-9);
    EXPECT_EQ(json["to_bezier"]["patches"].size(), 2u);

    auto bad = client().Post("/surfaces", R"({"surface":)" + surface + R"(,"evaluate":[[0.5,3]]})", "application/json");
    ASSERT_TRUE(bad);
    EXPECT_EQ(bad->status, 422);
    EXPECT_EQ(bad->get_header_value("Content-Type"), "application/problem+json");
    EXPECT_EQ(nlohmann::json::parse(bad->body).value("field", ""), "evaluate[0][1]");

    auto mesh =
        client().Post("/tessellate", R"({"surfaces":[)" + surface + R"(],"segments":2,"output":{"format":"json"}})",
                      "application/json");
    ASSERT_TRUE(mesh);
    ASSERT_EQ(mesh->status, 200) << mesh->body;
    EXPECT_EQ(mesh->get_header_value("X-Patches"), "2");
    EXPECT_EQ(mesh->get_header_value("X-Output-Faces"), "16");
    EXPECT_EQ(mesh->get_header_value("X-Output-Vertices"), "15");  // 5 x 3 grid, the shared column welded
}

//! The plane z = 0 over [0, 2]^2 with the hole [0.5, 1.5]^2 ((u, v) in [0.25, 0.75]^2), as JSON and as OBJ.
constexpr const char* kTrimmedPlaneJson =
    R"({"surfaces":[{"degree":[1,1],"knots_u":[0,0,1,1],"knots_v":[0,0,1,1],)"
    R"("points":[[0,0,0],[2,0,0],[0,2,0],[2,2,0]],"trim":{"holes":[[)"
    R"({"degree":1,"points":[[0.25,0.25],[0.75,0.25]]},{"degree":1,"points":[[0.75,0.25],[0.75,0.75]]},)"
    R"({"degree":1,"points":[[0.75,0.75],[0.25,0.75]]},{"degree":1,"points":[[0.25,0.75],[0.25,0.25]]}]]}}],)"
    R"("tolerance":0.01,"output":{"format":"obj"}})";
constexpr const char* kTrimmedPlaneObj =
    "v 0 0 0\nv 2 0 0\nv 0 2 0\nv 2 2 0\nvp 0.25 0.25\nvp 0.75 0.25\nvp 0.75 0.75\nvp 0.25 0.75\n"
    "cstype bezier\ndeg 1\ncurv2 1 2\nend\ncurv2 2 3\nend\ncurv2 3 4\nend\ncurv2 4 1\nend\n"
    "cstype bspline\ndeg 1 1\nsurf 0 1 0 1 1 2 3 4\nparm u 0 0 1 1\nparm v 0 0 1 1\nhole 0 1 1 0 1 2 0 1 3 0 1 "
    "4\nend\n";

//! The area of the triangles of an OBJ text (v and f lines only).
double obj_area(const std::string& text) {
    std::vector<std::array<double, 3>> v;
    double area = 0;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream fields(line);
        std::string keyword;
        fields >> keyword;
        if (keyword == "v") {
            std::array<double, 3> p{};
            fields >> p[0] >> p[1] >> p[2];
            v.push_back(p);
        } else if (keyword == "f") {
            std::size_t index[3];
            for (std::size_t& k : index) {
                std::string corner;
                fields >> corner;
                k = std::stoul(corner.substr(0, corner.find('/'))) - 1;
            }
            const auto& a = v[index[0]];
            const auto& b = v[index[1]];
            const auto& c = v[index[2]];
            area += 0.5 * std::fabs((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]));  // z = 0
        }
    }
    return area;
}

TEST_F(PatchesHttp, TrimmedSurfacesOverHttp) {
    auto json = client().Post("/tessellate", kTrimmedPlaneJson, "application/json");
    ASSERT_TRUE(json) << httplib::to_string(json.error());
    ASSERT_EQ(json->status, 200) << json->body;
    EXPECT_NEAR(obj_area(json->body), 3.0, 1e-12);
    // the same surface and hole from an OBJ upload: the same mesh
    auto obj = client().Post("/tessellate?tolerance=0.01&format=obj", kTrimmedPlaneObj, "model/obj");
    ASSERT_TRUE(obj) << httplib::to_string(obj.error());
    ASSERT_EQ(obj->status, 200) << obj->body;
    EXPECT_EQ(obj->get_header_value("X-Output-Faces"), json->get_header_value("X-Output-Faces"));
    EXPECT_NEAR(obj_area(obj->body), 3.0, 1e-12);
    // a hole outside the domain: 422 naming the curve; over OBJ, the hole statement's line
    std::string outside = kTrimmedPlaneJson;
    outside.replace(outside.find("[0.75,0.25],[0.75,0.75]"), 23, "[1.75,0.25],[0.75,0.75]");
    auto bad = client().Post("/tessellate", outside, "application/json");
    ASSERT_TRUE(bad);
    EXPECT_EQ(bad->status, 422) << bad->body;
    EXPECT_EQ(bad->get_header_value("Content-Type"), "application/problem+json");
    EXPECT_EQ(nlohmann::json::parse(bad->body).value("field", ""), "surfaces[0].trim.holes[0][0]");
    std::string open = kTrimmedPlaneObj;
    open.replace(open.find("curv2 4 1"), 9, "curv2 4 2");
    auto bad_obj = client().Post("/tessellate?tolerance=0.01", open, "model/obj");
    ASSERT_TRUE(bad_obj);
    EXPECT_EQ(bad_obj->status, 422) << bad_obj->body;
    EXPECT_EQ(nlohmann::json::parse(bad_obj->body).value("line", 0), 24) << bad_obj->body;  // the hole
}

TEST(TessellateCli, TrimmedJsonAndObj) {
    std::random_device rd;
    const fs::path dir = fs::temp_directory_path() / ("surfaced-trim-" + std::to_string(rd()));
    fs::create_directories(dir);
    const std::string cli = SURFACED_CLI_PATH;
    const fs::path json = dir / "plane.json", obj = dir / "plane.obj", out = dir / "out.obj";
    std::ofstream(json) << kTrimmedPlaneJson;
    std::ofstream(obj) << kTrimmedPlaneObj;
    const auto area_of = [&](const fs::path& path) {
        std::ifstream in(path);
        return obj_area(std::string((std::istreambuf_iterator<char>(in)), {}));
    };
    EXPECT_EQ(run(cli + " tessellate " + json.string() + " -o " + out.string() + " > /dev/null"), 0);
    EXPECT_NEAR(area_of(out), 3.0, 1e-12);
    EXPECT_EQ(run(cli + " tessellate " + obj.string() + " -o " + out.string() + " --tolerance 0.01 > /dev/null"), 0);
    EXPECT_NEAR(area_of(out), 3.0, 1e-12);
    // segments do not apply to a trimmed surface: a usage error
    EXPECT_EQ(run(cli + " tessellate " + obj.string() + " -o " + out.string() + " --segments 4 2> /dev/null"), 2);
    std::error_code ec;
    fs::remove_all(dir, ec);
}

TEST(SurfacesCli, ObjBsplineAndSurfaceQueries) {
    std::random_device rd;
    const fs::path dir = fs::temp_directory_path() / ("surfaced-surf-" + std::to_string(rd()));
    fs::create_directories(dir);
    const std::string cli = SURFACED_CLI_PATH;
    const fs::path obj = dir / "plane.obj", out = dir / "plane-mesh.obj", request = dir / "request.json",
                   answer = dir / "answer.json";
    std::ofstream(obj) << "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\ncstype bspline\ndeg 1 1\n"
                          "surf 0 2 0 1 1 2 3 4 5 6\nparm u 0 0 1 2 2\nparm v 0 0 1 1\nend\n";
    EXPECT_EQ(run(cli + " tessellate " + obj.string() + " -o " + out.string() + " --segments 2 > /dev/null"), 0);
    EXPECT_GT(fs::file_size(out), 100u);
    std::ofstream(request) << R"({"surface":{"degree":[1,1],"knots_u":[0,0,1,1],"knots_v":[0,0,1,1],)"
                              R"("points":[[0,0,0],[1,0,0],[0,1,0],[1,1,1]]},"evaluate":[[0.5,0.5]]})";
    EXPECT_EQ(run(cli + " surfaces " + request.string() + " -o " + answer.string() + " > /dev/null"), 0);
    std::ifstream in(answer);
    const auto json = nlohmann::json::parse(in, nullptr, false);
    ASSERT_FALSE(json.is_discarded());
    EXPECT_EQ(json["evaluate"][0]["position"], nlohmann::json::parse("[0.5, 0.5, 0.25]"));  // z = u v
    // a parameter outside the domain is the operation's failure (exit 1), --format a usage error (exit 2)
    std::ofstream(request) << R"({"surface":{"degree":[1,1],"knots_u":[0,0,1,1],"knots_v":[0,0,1,1],)"
                              R"("points":[[0,0,0],[1,0,0],[0,1,0],[1,1,1]]},"evaluate":[[2,0.5]]})";
    EXPECT_EQ(run(cli + " surfaces " + request.string() + " -o " + answer.string() + " 2> /dev/null"), 1);
    EXPECT_EQ(run(cli + " surfaces " + request.string() + " -o - --format glb 2> /dev/null"), 2);
    std::error_code ec;
    fs::remove_all(dir, ec);
}

TEST_F(PatchesHttp, OpenApiDocumentOverHttp) {
    auto res = client().Get("/openapi.json");
    ASSERT_TRUE(res) << httplib::to_string(res.error());
    ASSERT_EQ(res->status, 200);
    EXPECT_EQ(res->get_header_value("Content-Type").rfind("application/json", 0), 0u);
    EXPECT_EQ(res->body, api::openapi_document());
    EXPECT_EQ(nlohmann::json::parse(res->body).value("openapi", ""), "3.1.0");
}

}  // namespace
}  // namespace surfaced::server
