// `surfaced implicit SCENE.json -o OUT`: the real binary, run as a user would, through the same operation as
// POST /implicit/mesh (options laid over the file's request, output format from OUT's extension).
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "geometry/io/mesh_io.h"
#include "tests/support/mesh_asserts.h"

namespace surfaced {
namespace {

namespace fs = std::filesystem;

struct CliRun {
    int exit_code = -1;
    std::string out, err;
};

std::string slurp(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

class ImplicitCli : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("surfaced-implicit-cli-" + std::to_string(::getpid()));
        fs::create_directories(dir_);
        std::ofstream(dir_ / "scene.json")
            << R"({"scene": {"op": "difference", "args": [{"op": "box", "half_size": [1, 1, 1]},
                  {"op": "translate", "offset": [0, 0, 1], "arg": {"op": "sphere", "radius": 0.5}}]},
                  "bounds": [[-1.25, -1.25, -1.25], [1.25, 1.25, 1.25]], "resolution": 16})";
    }
    void TearDown() override { fs::remove_all(dir_); }

    CliRun run(const std::string& args) {
        const fs::path out = dir_ / "stdout.txt", err = dir_ / "stderr.txt";
        const std::string command =
            std::string("'") + SURFACED_CLI_PATH + "' " + args + " >'" + out.string() + "' 2>'" + err.string() + "'";
        const int status = std::system(command.c_str());
        return CliRun{WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
    }
    std::string path(const std::string& name) const { return "'" + (dir_ / name).string() + "'"; }

    fs::path dir_;
};

TEST_F(ImplicitCli, MeshesTheFileAtTheGivenResolution) {
    const CliRun r = run("implicit " + path("scene.json") + " -o " + path("part.obj") + " --resolution 40");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("grid 40x40x40"), std::string::npos) << r.out;
    auto mesh = read_mesh(slurp(dir_ / "part.obj"), MeshFormat::Obj);
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    EXPECT_TRUE(testing::is_watertight(mesh.value()));
    EXPECT_NEAR(testing::signed_volume(mesh.value()) / (8.0 - 2.0 / 3.0 * 3.14159265358979 * 0.125), 1.0, 0.01);
    // adaptive mode, GLB out
    const CliRun adaptive = run("implicit " + path("scene.json") + " -o " + path("part.glb") + " --mode adaptive");
    ASSERT_EQ(adaptive.exit_code, 0) << adaptive.err;
    EXPECT_NE(adaptive.out.find("grid 16x16x16"), std::string::npos) << adaptive.out;  // the file's resolution
    EXPECT_GT(fs::file_size(dir_ / "part.glb"), 100u);
}

TEST_F(ImplicitCli, MeshesASceneAloneWithBounds) {
    // the scene object without the request around it: --bounds gives the box, the resolution its default or flag
    std::ofstream(dir_ / "sphere.json") << R"({"op": "sphere", "radius": 1})";
    const CliRun r = run("implicit " + path("sphere.json") + " -o " + path("sphere.obj") +
                         " --bounds -1.5,-1.5,-1.5,1.5,1.5,1.5 --resolution 24");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("grid 24x24x24"), std::string::npos) << r.out;
    auto mesh = read_mesh(slurp(dir_ / "sphere.obj"), MeshFormat::Obj);
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    EXPECT_TRUE(testing::is_watertight(mesh.value()));
    EXPECT_NEAR(testing::signed_volume(mesh.value()) / (4.0 / 3.0 * 3.14159265358979), 1.0, 0.05);
    // --bounds over a whole request replaces its bounds: a box cutting the sphere in half meshes a capped half
    const CliRun half =
        run("implicit " + path("scene.json") + " -o " + path("half.obj") + " --bounds -1.25,-1.25,0,1.25,1.25,1.25");
    ASSERT_EQ(half.exit_code, 0) << half.err;
    auto cut = read_mesh(slurp(dir_ / "half.obj"), MeshFormat::Obj);
    ASSERT_TRUE(cut.ok()) << cut.error().message;
    EXPECT_NEAR(testing::signed_volume(cut.value()) / (4.0 - 2.0 / 3.0 * 3.14159265358979 * 0.125), 1.0, 0.02);
    // a scene alone needs bounds; bounds need six numbers, min below max: usage errors
    const CliRun missing = run("implicit " + path("sphere.json") + " -o " + path("x.obj"));
    EXPECT_EQ(missing.exit_code, 2);
    EXPECT_NE(missing.err.find("--bounds"), std::string::npos) << missing.err;
    EXPECT_EQ(run("implicit " + path("sphere.json") + " -o " + path("x.obj") + " --bounds 0,0,0,1,1").exit_code, 2);
    EXPECT_EQ(run("implicit " + path("sphere.json") + " -o " + path("x.obj") + " --bounds 1,1,1,0,0,0").exit_code, 2);
}

TEST_F(ImplicitCli, ErrorsNameTheProblem) {
    const CliRun budget = run("implicit " + path("scene.json") + " -o " + path("x.ply") + " --resolution 300");
    EXPECT_EQ(budget.exit_code, 1);
    EXPECT_NE(budget.err.find("budget_exceeded"), std::string::npos) << budget.err;
    std::ofstream(dir_ / "bad.json") << R"({"scene": {"op": "sphere"}, "bounds": [[0, 0, 0], [1, 1, 1]]})";
    const CliRun bad = run("implicit " + path("bad.json") + " -o " + path("x.ply"));
    EXPECT_EQ(bad.exit_code, 1);
    EXPECT_NE(bad.err.find("scene.radius"), std::string::npos) << bad.err;
    std::ofstream(dir_ / "broken.json") << R"({"scene": )";
    EXPECT_EQ(run("implicit " + path("broken.json") + " -o " + path("x.ply")).exit_code, 1);
    EXPECT_EQ(run("implicit " + path("scene.json") + " -o " + path("x.dae")).exit_code, 2);
    EXPECT_EQ(run("implicit " + path("scene.json")).exit_code, 2);
    EXPECT_EQ(run("implicit " + path("scene.json") + " -o " + path("x.obj") + " --mode octree").exit_code, 2);
    const CliRun help = run("implicit --help");
    EXPECT_EQ(help.exit_code, 0);
    EXPECT_NE(help.out.find("--resolution"), std::string::npos);
}

}  // namespace
}  // namespace surfaced
