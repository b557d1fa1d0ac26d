// The real server on an ephemeral loopback port, driven by httplib::Client; and the `surfaced` binary itself.
#include <gtest/gtest.h>

#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "geometry/io/mesh_io.h"
#include "server/http_server.h"
#include "tests/support/gltf_validator.h"
#include "tests/support/http_test_server.h"

namespace surfaced::server {
namespace {

namespace fs = std::filesystem;

constexpr const char* kCubeObj =
    "v -0.5 -0.5 -0.5\nv 0.5 -0.5 -0.5\nv 0.5 0.5 -0.5\nv -0.5 0.5 -0.5\n"
    "v -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv 0.5 0.5 0.5\nv -0.5 0.5 0.5\n"
    "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

constexpr const char* kCubeJson = R"({"positions":[[-0.5,-0.5,-0.5],[0.5,-0.5,-0.5],[0.5,0.5,-0.5],[-0.5,0.5,-0.5],)"
                                  R"([-0.5,-0.5,0.5],[0.5,-0.5,0.5],[0.5,0.5,0.5],[-0.5,0.5,0.5]],)"
                                  R"("faces":[[0,3,2,1],[4,5,6,7],[0,1,5,4],[1,2,6,5],[2,3,7,6],[3,0,4,7]]})";

constexpr std::size_t kTestBodyLimit = 64 * 1024;

fs::path make_temp_dir(const std::string& tag) {
    std::random_device rd;
    const fs::path dir = fs::temp_directory_path() / ("surfaced-" + tag + "-" + std::to_string(rd()));
    fs::create_directories(dir);
    return dir;
}

void write_text(const fs::path& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

std::string read_bytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

class HttpRoundTrip : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        web_root_ = new fs::path(make_temp_dir("web"));
        write_text(*web_root_ / "index.html", "<!doctype html><title>surfaced test page</title>");
        ServerConfig config;
        config.host = "127.0.0.1";
        config.port = 0;
        config.threads = 4;
        config.web_root = web_root_->string();
        config.limits.max_body_bytes = kTestBodyLimit;
        server_ = new testing::LoopbackServer(config);
    }
    static void TearDownTestSuite() {
        delete server_;  // stops and joins
        server_ = nullptr;
        std::error_code ec;
        fs::remove_all(*web_root_, ec);
        delete web_root_;
    }

    httplib::Client client() const { return server_->client(30); }

    //! The property every failure test ends with: the server still answers.
    void expect_healthy() const {
        auto res = client().Get("/healthz");
        ASSERT_TRUE(res) << httplib::to_string(res.error());
        EXPECT_EQ(res->status, 200);
    }

    //! The shared envelope checks (tests/support/http_test_server.h), and the members every problem has.
    static nlohmann::json expect_problem(const httplib::Result& res, int status, const std::string& code) {
        auto json = testing::expect_http_problem(res, status, code);
        EXPECT_TRUE(json.contains("type") && json.contains("title") && json.contains("detail")) << json.dump();
        return json;
    }

    static testing::LoopbackServer* server_;
    static fs::path* web_root_;
};

testing::LoopbackServer* HttpRoundTrip::server_ = nullptr;
fs::path* HttpRoundTrip::web_root_ = nullptr;

TEST_F(HttpRoundTrip, Healthz) {
    auto res = client().Get("/healthz");
    ASSERT_TRUE(res) << httplib::to_string(res.error());
    EXPECT_EQ(res->status, 200);
    EXPECT_EQ(res->get_header_value("Content-Type"), "application/json");
    EXPECT_EQ(nlohmann::json::parse(res->body)["status"], "ok");
}

TEST_F(HttpRoundTrip, ServesWebRoot) {
    EXPECT_TRUE(server_->server().serves_web_root());
    auto res = client().Get("/");
    ASSERT_TRUE(res) << httplib::to_string(res.error());
    EXPECT_EQ(res->status, 200);
    EXPECT_NE(res->body.find("surfaced test page"), std::string::npos);
    EXPECT_NE(res->get_header_value("Content-Type").find("text/html"), std::string::npos);
}

TEST_F(HttpRoundTrip, JsonToValidGlb) {
    const std::string body = std::string(R"({"mesh":)") + kCubeJson + R"(,"levels":2})";
    auto res = client().Post("/subdivide", body, "application/json");
    ASSERT_TRUE(res) << httplib::to_string(res.error());
    ASSERT_EQ(res->status, 200) << res->body;
    EXPECT_EQ(res->get_header_value("Content-Type"), "model/gltf-binary");
    EXPECT_EQ(res->get_header_value("X-Input-Faces"), "6");
    EXPECT_EQ(res->get_header_value("X-Output-Faces"), "96");
    EXPECT_EQ(res->get_header_value("X-Output-Vertices"), "98");
    EXPECT_FALSE(res->get_header_value("Server-Timing").empty());
    const auto validation = testing::run_gltf_validator(res->body);
    ASSERT_TRUE(validation.ran) << validation.report;
    EXPECT_EQ(validation.errors, 0) << validation.report;
    EXPECT_EQ(validation.warnings, 0) << validation.report;
}

TEST_F(HttpRoundTrip, RawObjWithQueryToObj) {
    auto res = client().Post("/subdivide?scheme=catmull-clark&levels=1&format=obj", kCubeObj, "model/obj");
    ASSERT_TRUE(res) << httplib::to_string(res.error());
    ASSERT_EQ(res->status, 200) << res->body;
    EXPECT_EQ(res->get_header_value("Content-Type"), "model/obj");
    auto mesh = read_obj(res->body);
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    EXPECT_EQ(mesh->face_count(), 24u);
    EXPECT_EQ(mesh->vertex_count(), 26u);
}

TEST_F(HttpRoundTrip, MalformedJsonIs400) {
    expect_problem(client().Post("/subdivide", R"({"mesh": [}})", "application/json"), 400, "invalid_json");
    expect_healthy();
}

TEST_F(HttpRoundTrip, UnknownMediaTypeIs415) {
    expect_problem(client().Post("/subdivide", kCubeObj, "text/plain"), 415, "unsupported_media_type");
    expect_healthy();
}

TEST_F(HttpRoundTrip, BodyOverLimitIs413) {
    // Rejected by the HTTP layer from Content-Length, before the operation runs.
    const std::string big(kTestBodyLimit + 1024, '#');
    expect_problem(client().Post("/subdivide", big, "model/obj"), 413, "payload_too_large");
    expect_healthy();
}

TEST_F(HttpRoundTrip, IndexOutOfRangeIs422WithField) {
    const std::string body = R"({"mesh":{"positions":[[0,0,0],[1,0,0],[0,1,0]],"faces":[[0,1,2],[0,2,3]]}})";
    const auto json = expect_problem(client().Post("/subdivide", body, "application/json"), 422, "index_out_of_range");
    EXPECT_EQ(json.value("field", ""), "mesh.faces[1][2]");
    expect_healthy();
}

TEST_F(HttpRoundTrip, LoopOnQuadsIs422) {
    const std::string body = std::string(R"({"mesh":)") + kCubeJson + R"(,"scheme":"loop"})";
    const auto json = expect_problem(client().Post("/subdivide", body, "application/json"), 422, "not_triangle_mesh");
    EXPECT_EQ(json.value("field", ""), "mesh.faces[0]");
    expect_healthy();
}

TEST_F(HttpRoundTrip, ObjParseErrorCarriesLine) {
    const auto json =
        expect_problem(client().Post("/subdivide?format=obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 zz\n", "model/obj"),
                       400, "parse_error");
    EXPECT_EQ(json.value("line", 0), 4);
    expect_healthy();
}

TEST_F(HttpRoundTrip, UnknownQueryParameterIs400) {
    const auto json = expect_problem(client().Post("/subdivide?levels=1&smooth=yes", kCubeObj, "model/obj"), 400,
                                     "unknown_parameter");
    EXPECT_NE(json.value("detail", "").find("\"smooth\""), std::string::npos);
    expect_healthy();
}

TEST_F(HttpRoundTrip, UnknownRouteIs404Json) {
    expect_problem(client().Get("/no/such/thing"), 404, "not_found");
    expect_problem(client().Post("/nope", "{}", "application/json"), 404, "not_found");
    expect_healthy();
}

TEST_F(HttpRoundTrip, WrongMethodIs405WithAllow) {
    auto res = client().Get("/subdivide");
    expect_problem(res, 405, "method_not_allowed");
    ASSERT_TRUE(res);
    EXPECT_EQ(res->get_header_value("Allow"), "POST");
    expect_problem(client().Post("/healthz", "{}", "application/json"), 405, "method_not_allowed");
    expect_healthy();
}

TEST_F(HttpRoundTrip, ConcurrentRequests) {
    std::atomic<int> ok{0};
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([&] {
            for (int i = 0; i < 5; ++i) {
                auto res = client().Post("/subdivide?levels=2&format=json", kCubeObj, "model/obj");
                if (res && res->status == 200 && res->get_header_value("X-Output-Faces") == "96") ++ok;
            }
        });
    for (auto& t : threads) t.join();
    EXPECT_EQ(ok.load(), 20);
}

TEST(HttpServerLifecycle, StopIsIdempotentAndPortIsReleased) {
    ServerConfig config;
    config.port = 0;
    config.web_root = "/definitely/not/a/dir";
    HttpServer server(config);
    EXPECT_EQ(server.port(), -1);
    server.stop();  // before start: no-op
    ASSERT_TRUE(server.start());
    EXPECT_FALSE(server.serves_web_root());
    const int port = server.port();
    server.stop();
    server.stop();
    httplib::Client c("127.0.0.1", port);
    c.set_connection_timeout(1, 0);
    EXPECT_FALSE(c.Get("/healthz"));
}

// ---- the CLI binary ------------------------------------------------------------------------------------------

struct CliRun {
    int exit_code = -1;
    std::string out, err;
};

//! Runs `surfaced ARGS`, capturing stdout/stderr in files under `dir`.
CliRun run_cli(const std::string& args, const fs::path& dir) {
    static int counter = 0;
    const fs::path out = dir / ("out" + std::to_string(counter) + ".txt");
    const fs::path err = dir / ("err" + std::to_string(counter++) + ".txt");
    const std::string command =
        std::string("'") + SURFACED_CLI_PATH + "' " + args + " >'" + out.string() + "' 2>'" + err.string() + "'";
    const int status = std::system(command.c_str());
    CliRun run;
    run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    run.out = read_bytes(out);
    run.err = read_bytes(err);
    return run;
}

class Cli : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = make_temp_dir("cli");
        write_text(dir_ / "cube.obj", kCubeObj);
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(dir_, ec);
    }
    std::string path(const std::string& name) const { return "'" + (dir_ / name).string() + "'"; }
    CliRun run_cli(const std::string& args) const { return server::run_cli(args, dir_); }
    fs::path dir_;
};

TEST_F(Cli, ObjToObj) {
    const auto run = run_cli("subdivide " + path("cube.obj") + " -o " + path("out.obj") + " --levels 1");
    ASSERT_EQ(run.exit_code, 0) << run.err;
    EXPECT_NE(run.out.find("24 faces"), std::string::npos) << run.out;
    auto mesh = read_obj(read_bytes(dir_ / "out.obj"));
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    EXPECT_EQ(mesh->face_count(), 24u);
    EXPECT_EQ(mesh->vertex_count(), 26u);
}

TEST_F(Cli, ObjToValidGlb) {
    const auto run = run_cli("subdivide " + path("cube.obj") + " -o " + path("out.glb") +
                             " --scheme catmull-clark --levels=2 --boundary edge-only");
    ASSERT_EQ(run.exit_code, 0) << run.err;
    const std::string glb = read_bytes(dir_ / "out.glb");
    EXPECT_NE(glb.find("KHR_draco_mesh_compression"), std::string::npos);
    const auto validation = testing::run_gltf_validator(glb);
    ASSERT_TRUE(validation.ran) << validation.report;
    EXPECT_EQ(validation.errors, 0) << validation.report;
    EXPECT_EQ(validation.warnings, 0) << validation.report;

    const auto plain = run_cli("subdivide " + path("cube.obj") + " -o " + path("plain.glb") + " --no-draco");
    ASSERT_EQ(plain.exit_code, 0) << plain.err;
    EXPECT_EQ(read_bytes(dir_ / "plain.glb").find("KHR_draco_mesh_compression"), std::string::npos);
}

TEST_F(Cli, ObjToValidTextGltf) {
    const auto run = run_cli("subdivide " + path("cube.obj") + " -o " + path("out.gltf") + " --levels 2 --normals");
    ASSERT_EQ(run.exit_code, 0) << run.err;
    const std::string gltf = read_bytes(dir_ / "out.gltf");
    EXPECT_NE(gltf.find("\"uri\":\"data:application/octet-stream;base64,"), std::string::npos);
    const auto validation = testing::run_gltf_validator(gltf);
    ASSERT_TRUE(validation.ran) << validation.report;
    EXPECT_EQ(validation.errors, 0) << validation.report;
    EXPECT_EQ(validation.warnings, 0) << validation.report;

    // .gltf is an input format too (the buffer is embedded): the level-2 mesh subdivided once more.
    const auto back = run_cli("subdivide " + path("out.gltf") + " -o " + path("back.obj") + " --levels 1");
    ASSERT_EQ(back.exit_code, 0) << back.err;
    EXPECT_NE(back.out.find("(from 98 vertices, "), std::string::npos) << back.out;
}

TEST_F(Cli, BadUsageExits2) {
    EXPECT_EQ(run_cli("").exit_code, 2);
    EXPECT_EQ(run_cli("frobnicate").exit_code, 2);
    EXPECT_EQ(run_cli("subdivide " + path("cube.obj")).exit_code, 2) << "missing -o";
    EXPECT_EQ(run_cli("subdivide -o " + path("x.obj")).exit_code, 2) << "missing input";
    EXPECT_EQ(run_cli("subdivide " + path("cube.obj") + " -o " + path("x.obj") + " --bogus").exit_code, 2);
    EXPECT_EQ(run_cli("subdivide " + path("cube.obj") + " -o " + path("x.obj") + " --levels two").exit_code, 2);
    EXPECT_EQ(run_cli("subdivide " + path("cube.obj") + " -o " + path("x.obj") + " --scheme sqrt3").exit_code, 2);
    EXPECT_EQ(run_cli("subdivide " + path("cube.obj") + " -o " + path("x.fbx")).exit_code, 2);
    const auto fbx = run_cli("subdivide " + path("x.fbx") + " -o " + path("y.obj"));
    EXPECT_EQ(fbx.exit_code, 2);
    EXPECT_NE(fbx.err.find("(use .obj .off .ply .stl .glb .gltf, or --input-format)"), std::string::npos) << fbx.err;
    EXPECT_EQ(run_cli("serve --port 70000").exit_code, 2);
}

TEST_F(Cli, OperationErrorExits1WithDetail) {
    const auto loop = run_cli("subdivide " + path("cube.obj") + " -o " + path("x.obj") + " --scheme loop");
    EXPECT_EQ(loop.exit_code, 1);
    EXPECT_NE(loop.err.find("not_triangle_mesh"), std::string::npos) << loop.err;

    write_text(dir_ / "broken.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 q\n");
    const auto broken = run_cli("subdivide " + path("broken.obj") + " -o " + path("x.obj"));
    EXPECT_EQ(broken.exit_code, 1);
    EXPECT_NE(broken.err.find("line 4"), std::string::npos) << broken.err;

    const auto missing = run_cli("subdivide " + path("missing.obj") + " -o " + path("x.obj"));
    EXPECT_EQ(missing.exit_code, 1);

    const auto budget =
        run_cli("subdivide " + path("cube.obj") + " -o " + path("x.obj") + " --levels 3 --max-output-faces 100");
    EXPECT_EQ(budget.exit_code, 1);
    EXPECT_NE(budget.err.find("budget_exceeded"), std::string::npos) << budget.err;
}

TEST_F(Cli, HelpAndVersion) {
    const auto help = run_cli("--help");
    EXPECT_EQ(help.exit_code, 0);
    EXPECT_NE(help.out.find("surfaced subdivide IN -o OUT"), std::string::npos) << help.out;
    const auto sub = run_cli("subdivide --help");
    EXPECT_EQ(sub.exit_code, 0);
    EXPECT_NE(sub.out.find("--levels"), std::string::npos);
    EXPECT_NE(sub.out.find("--compression NAME"), std::string::npos) << sub.out;  // from the option table
    const auto serve = run_cli("serve --help");
    EXPECT_EQ(serve.exit_code, 0);
    EXPECT_NE(serve.out.find("POST /subdivide"), std::string::npos) << serve.out;
    const auto version = run_cli("--version");
    EXPECT_EQ(version.exit_code, 0);
    EXPECT_EQ(version.out.rfind("surfaced ", 0), 0u) << version.out;
}

TEST_F(Cli, ServeAnswersAndStopsOnSigterm) {
    int out_pipe[2];
    ASSERT_EQ(pipe(out_pipe), 0);
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        dup2(out_pipe[1], STDOUT_FILENO);
        close(out_pipe[0]);
        close(out_pipe[1]);
        execl(SURFACED_CLI_PATH, SURFACED_CLI_PATH, "serve", "--port", "0", "--threads", "2",
              static_cast<char*>(nullptr));
        _exit(127);
    }
    close(out_pipe[1]);
    // First line: "surfaced X listening on http://127.0.0.1:PORT/ (...)".
    std::string line;
    char c = 0;
    pollfd pfd{out_pipe[0], POLLIN, 0};
    while (line.find('\n') == std::string::npos && poll(&pfd, 1, 10'000) > 0 && read(out_pipe[0], &c, 1) == 1)
        line += c;
    const auto at = line.find("http://127.0.0.1:");
    int port = 0;
    if (at != std::string::npos) port = std::atoi(line.c_str() + at + std::string("http://127.0.0.1:").size());
    EXPECT_GT(port, 0) << line;
    if (port > 0) {
        httplib::Client client("127.0.0.1", port);
        auto res = client.Get("/healthz");
        ASSERT_TRUE(res) << httplib::to_string(res.error());
        EXPECT_EQ(res->status, 200);
    }
    kill(pid, SIGTERM);
    int status = 0;
    ASSERT_EQ(waitpid(pid, &status, 0), pid);
    close(out_pipe[0]);
    EXPECT_TRUE(WIFEXITED(status)) << "killed by a signal instead of stopping cleanly";
    EXPECT_EQ(WEXITSTATUS(status), 0);
}

}  // namespace
}  // namespace surfaced::server
