// The `surfaced` binary as a user runs it: exit codes that mean the same in every command, suggestions for
// misspelt options and values, standard input and output.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "geometry/io/mesh_io.h"
#include "geometry/mesh/shapes.h"
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

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

class SurfacedCli : public ::testing::Test {
protected:
    void SetUp() override {
        std::random_device rd;
        dir_ = fs::temp_directory_path() / ("surfaced-cli-" + std::to_string(rd()));
        fs::create_directories(dir_);
        std::ofstream(dir_ / "cube.obj", std::ios::binary) << write_obj(shapes::cube());
        std::ofstream(dir_ / "torus.obj", std::ios::binary) << write_obj(shapes::torus(24, 12));
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(dir_, ec);
    }

    //! Runs `surfaced ARGS` (with standard input from `stdin_file` in dir_, if given); stdout and stderr captured.
    CliRun run(const std::string& args, const std::string& stdin_file = "") const {
        const fs::path out = dir_ / "stdout.bin", err = dir_ / "stderr.txt";
        std::string command =
            std::string("'") + SURFACED_CLI_PATH + "' " + args + " >'" + out.string() + "' 2>'" + err.string() + "'";
        if (!stdin_file.empty()) command += " <'" + (dir_ / stdin_file).string() + "'";
        const int status = std::system(command.c_str());
        return CliRun{WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
    }
    std::string path(const std::string& name) const { return "'" + (dir_ / name).string() + "'"; }

    fs::path dir_;
};

TEST_F(SurfacedCli, AGeometricFailureExits1WithTheProblem) {
    // Loop subdivision needs triangles: the operation refuses the cube's quads
    const CliRun r = run("subdivide " + path("cube.obj") + " -o " + path("x.obj") + " --scheme loop");
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_TRUE(contains(r.err, "not_triangle_mesh")) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "x.obj"));
    // and a budget: more levels than the limit
    EXPECT_EQ(run("subdivide " + path("cube.obj") + " -o " + path("x.obj") + " --levels 12").exit_code, 1);
}

TEST_F(SurfacedCli, TheSameMistakeExitsTheSameInEveryCommand) {
    // an out-of-range Draco quantization, whichever command: usage (2)
    const CliRun subdivide = run("subdivide " + path("cube.obj") + " -o " + path("x.glb") + " --quantize-position 25");
    const CliRun tessellate = run("tessellate sample:teapot -o " + path("x.glb") + " --quantize-position 25");
    const CliRun simplify =
        run("simplify " + path("torus.obj") + " -o " + path("x.glb") + " --ratio 0.5 --quantize-position 25");
    for (const CliRun* r : {&subdivide, &tessellate, &simplify}) {
        EXPECT_EQ(r->exit_code, 2) << r->err;
        EXPECT_TRUE(contains(r->err, "--quantize-position")) << r->err;
    }
    // a value only the operation checks (simplify's ratio, remesh's feature angle, repair's weld tolerance, the
    // implicit cell size): the same usage error, naming the option
    const CliRun ratio = run("simplify " + path("torus.obj") + " -o " + path("x.obj") + " --ratio 2");
    EXPECT_EQ(ratio.exit_code, 2);
    EXPECT_TRUE(contains(ratio.err, "simplify --ratio: ")) << ratio.err;
    const CliRun angle = run("remesh " + path("torus.obj") + " -o " + path("x.obj") + " --feature-angle 200");
    EXPECT_EQ(angle.exit_code, 2);
    EXPECT_TRUE(contains(angle.err, "remesh --feature-angle: ")) << angle.err;
    EXPECT_EQ(run("repair " + path("torus.obj") + " -o " + path("x.obj") + " --weld-tolerance -1").exit_code, 2);
    // an unknown value of --repair, in both commands that take it
    EXPECT_EQ(run("simplify " + path("torus.obj") + " -o " + path("x.obj") + " --ratio 0.5 --repair maybe").exit_code,
              2);
    EXPECT_EQ(run("remesh " + path("torus.obj") + " -o " + path("x.obj") + " --repair maybe").exit_code, 2);
    // an option that does not apply to the output format
    EXPECT_EQ(run("subdivide " + path("cube.obj") + " -o " + path("x.obj") + " --quantize-position 12").exit_code, 2);
    EXPECT_EQ(run("remesh " + path("torus.obj") + " -o " + path("x.obj") + " --quantize-position 12").exit_code, 2);
}

TEST_F(SurfacedCli, MisspeltOptionsAndValuesGetASuggestion) {
    const CliRun option = run("subdivide " + path("cube.obj") + " -o " + path("x.obj") + " --levle 2");
    EXPECT_EQ(option.exit_code, 2);
    EXPECT_TRUE(contains(option.err, "unknown option \"--levle\" (did you mean --levels?)")) << option.err;
    const CliRun value = run("subdivide " + path("cube.obj") + " -o " + path("x.obj") + " --scheme catmul-clark");
    EXPECT_EQ(value.exit_code, 2);
    EXPECT_TRUE(contains(value.err, "--scheme: unknown value \"catmul-clark\" (did you mean \"catmull-clark\"?"))
        << value.err;
    EXPECT_FALSE(fs::exists(dir_ / "x.obj"));
    // the same in the commands with their own option loops, and for the command itself
    const CliRun serve = run("serve --prot 8080");
    EXPECT_EQ(serve.exit_code, 2);
    EXPECT_TRUE(contains(serve.err, "did you mean --port?")) << serve.err;
    const CliRun command = run("simplfy " + path("torus.obj"));
    EXPECT_EQ(command.exit_code, 2);
    EXPECT_TRUE(contains(command.err, "did you mean simplify?")) << command.err;
    // nothing close: no suggestion, the allowed values
    const CliRun far = run("subdivide " + path("cube.obj") + " -o " + path("x.obj") + " --scheme sqrt3");
    EXPECT_EQ(far.exit_code, 2);
    EXPECT_FALSE(contains(far.err, "did you mean")) << far.err;
    EXPECT_TRUE(contains(far.err, "allowed: \"catmull-clark\", \"loop\"")) << far.err;
}

TEST_F(SurfacedCli, StandardInputToStandardOutput) {
    // PLY in (sniffed: no extension to go by), OBJ out; stdout carries only the file, the summary goes to stderr
    std::ofstream(dir_ / "torus.ply", std::ios::binary) << write_ply(shapes::torus(24, 12));
    const CliRun r = run("simplify - -o - --format obj --ratio 0.5", "torus.ply");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(contains(r.err, "wrote standard output: ")) << r.err;
    auto mesh = read_mesh(r.out, MeshFormat::Obj);
    ASSERT_TRUE(mesh.ok()) << mesh.error().message << "\n" << r.out.substr(0, 200);
    EXPECT_LE(mesh->face_count(), 24u * 12u * 2u / 2u);
    EXPECT_TRUE(testing::is_watertight(mesh.value()));
    // binary output to stdout, read back as a file; --input-format instead of sniffing
    const CliRun glb = run("subdivide - --input-format obj -o - --format glb --levels 1", "cube.obj");
    ASSERT_EQ(glb.exit_code, 0) << glb.err;
    EXPECT_EQ(glb.out.substr(0, 4), "glTF");
    auto back = read_mesh(glb.out, MeshFormat::Glb);
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(back->face_count(), 24u * 2u);  // 24 quads, triangulated in glTF
    // a problem names standard input; nothing is written to stdout
    std::ofstream(dir_ / "quads.obj", std::ios::binary) << write_obj(shapes::cube());
    const CliRun loop = run("subdivide - -o - --format obj --scheme loop", "quads.obj");
    EXPECT_EQ(loop.exit_code, 1);
    EXPECT_TRUE(contains(loop.err, "surfaced: standard input: ")) << loop.err;
    EXPECT_EQ(loop.out, "");
}

TEST_F(SurfacedCli, FormatOverridesTheExtensionAndIsNeededForStandardOutput) {
    const CliRun r = run("remesh " + path("torus.obj") + " -o " + path("out.mesh") + " --format ply --iterations 1");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(contains(r.out, "wrote ")) << r.out;  // a file: the summary stays on stdout
    EXPECT_EQ(slurp(dir_ / "out.mesh").substr(0, 4), "ply\n");
    const CliRun missing = run("remesh " + path("torus.obj") + " -o -");
    EXPECT_EQ(missing.exit_code, 2);
    EXPECT_TRUE(contains(missing.err, "-o - (standard output) needs --format")) << missing.err;
    const CliRun wrong = run("remesh " + path("torus.obj") + " -o - --format stl");
    EXPECT_EQ(wrong.exit_code, 2);
    EXPECT_TRUE(contains(wrong.err, "--format: unknown value \"stl\"")) << wrong.err;
}

TEST_F(SurfacedCli, HelpListsTheExitCodes) {
    const CliRun help = run("--help");
    EXPECT_EQ(help.exit_code, 0);
    EXPECT_TRUE(contains(help.out, "Exit codes")) << help.out;
    EXPECT_TRUE(contains(help.out, "  2  bad usage")) << help.out;
}

}  // namespace
}  // namespace surfaced
