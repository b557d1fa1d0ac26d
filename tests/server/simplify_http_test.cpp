// POST /simplify through the real server on an ephemeral loopback port, and `surfaced simplify` as a process.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "geometry/io/gltf.h"
#include "geometry/io/mesh_io.h"
#include "geometry/mesh/shapes.h"
#include "server/http_server.h"
#include "tests/support/gltf_validator.h"
#include "tests/support/http_test_server.h"
#include "tests/support/mesh_asserts.h"
#include "tests/support/simplify_meshes.h"

namespace surfaced::server {
namespace {

namespace fs = std::filesystem;

std::string header_of(const httplib::Result& res, const char* name) {
    return res && res->has_header(name) ? res->get_header_value(name) : std::string();
}

class SimplifyHttp : public testing::SharedServerTest<SimplifyHttp> {
public:
    static ServerConfig suite_config() {
        ServerConfig config = SharedServerTest::suite_config();
        config.limits.max_body_bytes = 4 << 20;
        return config;
    }

protected:
    static httplib::Client client() { return SharedServerTest::client(60); }
};

TEST_F(SimplifyHttp, ObjUploadToValidGlbWithErrorHeaders) {
    const PolygonMesh sphere = testing::icosphere(4);
    auto res = client().Post("/simplify?target_faces=500&report_error=true", write_obj(sphere), "model/obj");
    ASSERT_TRUE(res) << httplib::to_string(res.error());
    ASSERT_EQ(res->status, 200) << res->body;
    EXPECT_EQ(res->get_header_value("Content-Type"), "model/gltf-binary");
    EXPECT_EQ(header_of(res, "X-Input-Faces"), "5120");
    EXPECT_LE(std::stoi(header_of(res, "X-Output-Faces")), 500);
    EXPECT_EQ(header_of(res, "X-Triangulated"), "false");
    const double hausdorff = std::stod(header_of(res, "X-Hausdorff"));
    EXPECT_GT(hausdorff, 0);
    EXPECT_LT(hausdorff, 0.05);
    EXPECT_LE(std::stod(header_of(res, "X-RMS")), hausdorff);
    EXPECT_GT(std::stod(header_of(res, "X-Relative-Error")), 0);
    const auto validation = testing::run_gltf_validator(res->body);
    ASSERT_TRUE(validation.ran) << validation.report;
    EXPECT_EQ(validation.errors, 0) << validation.report;
    EXPECT_EQ(validation.warnings, 0) << validation.report;
    auto back = read_glb(res->body);
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(back->face_count(), static_cast<std::size_t>(std::stoi(header_of(res, "X-Output-Faces"))));
    EXPECT_TRUE(testing::is_watertight(back.value()));
}

TEST_F(SimplifyHttp, JsonWithMaxErrorToJson) {
    const PolygonMesh sphere = testing::icosphere(3);
    nlohmann::json positions = nlohmann::json::array(), faces = nlohmann::json::array();
    for (const Vec3& p : sphere.positions) positions.push_back({p.x, p.y, p.z});
    for (std::size_t f = 0; f < sphere.face_count(); ++f) {
        auto t = sphere.face(f);
        faces.push_back({t[0], t[1], t[2]});
    }
    const nlohmann::json body = {
        {"mesh", {{"positions", positions}, {"faces", faces}}}, {"max_error", 0.02}, {"output", {{"format", "json"}}}};
    auto res = client().Post("/simplify", body.dump(), "application/json");
    ASSERT_TRUE(res) << httplib::to_string(res.error());
    ASSERT_EQ(res->status, 200) << res->body;
    const auto json = nlohmann::json::parse(res->body);
    EXPECT_LE(json["stats"]["achieved_error"].get<double>(), 0.02);
    EXPECT_LT(json["mesh"]["faces"].size(), sphere.face_count());
}

// X-Target-Faces / X-Achieved-Faces / X-Target-Met, and the same in the JSON stats: a target that cannot be met is
// still 200, saying so.
struct Reached {
    int status = 0;
    std::string target, achieved, met;  // the headers ("" when absent)
    std::string body;
};

TEST_F(SimplifyHttp, ReportsTheTargetAndWhatItReached) {
    const auto post = [&](const std::string& query, const PolygonMesh& mesh) {
        auto res = client().Post("/simplify?" + query + "&format=obj", write_obj(mesh), "model/obj");
        EXPECT_TRUE(res) << httplib::to_string(res.error());
        if (!res) return Reached{};
        Reached r{res->status, header_of(res, "X-Target-Faces"), header_of(res, "X-Achieved-Faces"),
                  header_of(res, "X-Target-Met"), res->body};
        if (res->status == 200) {
            EXPECT_EQ(r.achieved, header_of(res, "X-Output-Faces")) << query;
            auto back = read_obj(res->body);
            EXPECT_TRUE(back.ok()) << query;
            if (back.ok()) {
                EXPECT_EQ(std::to_string(back->face_count()), r.achieved) << query;
            }
        }
        return r;
    };
    const PolygonMesh sphere = testing::icosphere(3);  // 1280 triangles, closed
    // a target it reaches
    Reached r = post("target_faces=500", sphere);
    ASSERT_EQ(r.status, 200) << r.body;
    EXPECT_EQ(r.target, "500");
    EXPECT_LE(std::stoi(r.achieved), 500);
    EXPECT_GE(std::stoi(r.achieved), 490);  // a collapse removes two faces; it stops at the target
    EXPECT_EQ(r.met, "true");
    // ratio: of the input's triangles, floor(0.25 x 1280)
    r = post("ratio=0.25", sphere);
    ASSERT_EQ(r.status, 200) << r.body;
    EXPECT_EQ(r.target, "320");
    EXPECT_LE(std::stoi(r.achieved), 320);
    EXPECT_EQ(r.met, "true");
    // both: the smaller
    r = post("ratio=0.5&target_faces=600", sphere);
    EXPECT_EQ(r.target, "600");
    r = post("ratio=0.25&target_faces=600", sphere);
    EXPECT_EQ(r.target, "320");
    // ratio counts triangles, not polygons: the cube's 6 quads are 12 triangles
    r = post("ratio=0.5", shapes::cube());
    ASSERT_EQ(r.status, 200) << r.body;
    EXPECT_EQ(r.target, "6");
    EXPECT_EQ(r.met, std::stoi(r.achieved) <= 6 ? "true" : "false");
    // target 0 on a closed mesh: a tetrahedron cannot lose a face and stay a closed surface
    r = post("target_faces=0", shapes::tetrahedron());
    ASSERT_EQ(r.status, 200) << r.body;
    EXPECT_EQ(r.target, "0");
    EXPECT_EQ(r.achieved, "4");
    EXPECT_EQ(r.met, "false");
    // a target above the input's count: simplification never adds faces
    r = post("target_faces=5000", sphere);
    ASSERT_EQ(r.status, 200) << r.body;
    EXPECT_EQ(r.target, "5000");
    EXPECT_EQ(r.achieved, "1280");
    EXPECT_EQ(r.met, "false");
    // max_error stops it before the target: nothing may move off the sphere
    r = post("target_faces=10&max_error=0", sphere);
    ASSERT_EQ(r.status, 200) << r.body;
    EXPECT_EQ(r.target, "10");
    EXPECT_GT(std::stoi(r.achieved), 10);
    EXPECT_EQ(r.met, "false");
    // max_error alone: no face target, and the bound always holds
    r = post("max_error=0.01", sphere);
    ASSERT_EQ(r.status, 200) << r.body;
    EXPECT_EQ(r.target, "");
    EXPECT_LT(std::stoi(r.achieved), 1280);
    EXPECT_EQ(r.met, "true");

    // the JSON output's stats say the same
    nlohmann::json positions = nlohmann::json::array(), faces = nlohmann::json::array();
    const PolygonMesh tetra = shapes::tetrahedron();
    for (const Vec3& p : tetra.positions) positions.push_back({p.x, p.y, p.z});
    for (std::size_t f = 0; f < tetra.face_count(); ++f) {
        auto t = tetra.face(f);
        faces.push_back({t[0], t[1], t[2]});
    }
    nlohmann::json body = {
        {"mesh", {{"positions", positions}, {"faces", faces}}}, {"target_faces", 0}, {"output", {{"format", "json"}}}};
    auto res = client().Post("/simplify", body.dump(), "application/json");
    ASSERT_TRUE(res) << httplib::to_string(res.error());
    ASSERT_EQ(res->status, 200) << res->body;
    auto stats = nlohmann::json::parse(res->body)["stats"];
    EXPECT_EQ(stats["target_faces"], 0);
    EXPECT_EQ(stats["achieved_faces"], 4);
    EXPECT_EQ(stats["target_met"], false);
    EXPECT_EQ(header_of(res, "X-Target-Met"), "false");
    body.erase("target_faces");
    body["max_error"] = 0.5;
    res = client().Post("/simplify", body.dump(), "application/json");
    ASSERT_TRUE(res) << httplib::to_string(res.error());
    ASSERT_EQ(res->status, 200) << res->body;
    stats = nlohmann::json::parse(res->body)["stats"];
    EXPECT_FALSE(stats.contains("target_faces"));
    EXPECT_EQ(stats["achieved_faces"], stats["output_faces"]);
    EXPECT_EQ(stats["target_met"], true);
    EXPECT_FALSE(res->has_header("X-Target-Faces"));
}

TEST_F(SimplifyHttp, ErrorsAreProblemJson) {
    auto res = client().Post("/simplify?format=obj", write_obj(testing::icosphere(1)), "model/obj");
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 400);
    EXPECT_EQ(res->get_header_value("Content-Type"), "application/problem+json");
    auto get = client().Get("/simplify");
    ASSERT_TRUE(get);
    EXPECT_EQ(get->status, 405);
    EXPECT_EQ(get->get_header_value("Allow"), "POST");
    // the server still answers
    auto health = client().Get("/healthz");
    ASSERT_TRUE(health);
    EXPECT_EQ(health->status, 200);
}

// ---- the CLI -------------------------------------------------------------------------------------------------

struct CliResult {
    int exit_code = -1;
    std::string out, err;
};

std::string slurp(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

class SimplifyCli : public ::testing::Test {
protected:
    void SetUp() override {
        std::random_device rd;
        dir_ = fs::temp_directory_path() / ("surfaced-simplify-" + std::to_string(rd()));
        fs::create_directories(dir_);
        std::ofstream(dir_ / "torus.obj", std::ios::binary) << write_obj(shapes::torus(32, 16));
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(dir_, ec);
    }
    std::string path(const std::string& name) const { return "'" + (dir_ / name).string() + "'"; }
    CliResult run_cli(const std::string& args) const {
        const fs::path out = dir_ / "stdout.txt", err = dir_ / "stderr.txt";
        const std::string command =
            std::string("'") + SURFACED_CLI_PATH + "' " + args + " >'" + out.string() + "' 2>'" + err.string() + "'";
        const int status = std::system(command.c_str());
        CliResult r;
        r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        r.out = slurp(out);
        r.err = slurp(err);
        return r;
    }
    fs::path dir_;
};

TEST_F(SimplifyCli, TargetFacesToObjWithReport) {
    const auto r =
        run_cli("simplify " + path("torus.obj") + " -o " + path("out.obj") + " --target-faces 300 --report-error");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("triangulated first"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("Hausdorff"), std::string::npos) << r.out;
    auto mesh = read_obj(slurp(dir_ / "out.obj"));
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    EXPECT_LE(mesh->face_count(), 300u);
    EXPECT_TRUE(testing::is_watertight(mesh.value()));
}

TEST_F(SimplifyCli, RatioAndLockBorderToGlb) {
    std::ofstream(dir_ / "grid.obj", std::ios::binary) << write_obj(shapes::grid(12, 12, true));
    const auto r = run_cli("simplify " + path("grid.obj") + " -o " + path("out.glb") + " --ratio 0.3 --lock-border");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string glb = slurp(dir_ / "out.glb");
    const auto validation = testing::run_gltf_validator(glb);
    ASSERT_TRUE(validation.ran) << validation.report;
    EXPECT_EQ(validation.errors, 0) << validation.report;
}

TEST_F(SimplifyCli, UsageErrors) {
    EXPECT_EQ(run_cli("simplify " + path("torus.obj") + " -o " + path("out.obj")).exit_code, 2);
    EXPECT_EQ(run_cli("simplify " + path("torus.obj") + " -o " + path("out.obj") + " --ratio x").exit_code, 2);
    EXPECT_EQ(run_cli("simplify " + path("torus.obj") + " -o " + path("out.xyz") + " --ratio 0.5").exit_code, 2);
    // a range the operation checks: a usage error like the ranges the command line checks, with the problem's detail
    const auto r = run_cli("simplify " + path("torus.obj") + " -o " + path("out.obj") + " --ratio 2");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("--ratio: ratio must be"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace surfaced::server
