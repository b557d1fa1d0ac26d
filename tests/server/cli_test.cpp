// The `surfaced` binary as a user runs it: exit codes that mean the same in every command, suggestions for
// misspelt options and values, standard input and output, and each command's flags and help held to its
// operation's option table (api/options/catalog.cpp).
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <functional>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/options/option_spec.h"
#include "geometry/io/mesh_io.h"
#include "geometry/io/pointcloud_io.h"
#include "geometry/mesh/shapes.h"
#include "geometry/subdivision/limit_evaluation.h"
#include "geometry/subdivision/uv_limit.h"
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
        std::ofstream points(dir_ / "points.xyz");
        for (int i = 0; i < 64; ++i) points << (i % 4) << " " << (i / 4 % 4) << " " << (i / 16) << "\n";
        std::ofstream(dir_ / "scene.json") << R"({"scene": {"op": "sphere", "radius": 1},
            "bounds": [[-1.5, -1.5, -1.5], [1.5, 1.5, 1.5]], "resolution": 8})";
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

// Every `serve` flag in its --help is accepted with a valid value, refused (2) out of range, and documented in
// docs/operations.md; the budget flags cover api/limits.h (their effect on requests: production_test).
TEST_F(SurfacedCli, ServeFlagsAreDocumentedAndRangeChecked) {
    const CliRun help = run("serve --help");
    ASSERT_EQ(help.exit_code, 0) << help.err;
    std::ifstream docs_file(std::string(SURFACED_SOURCE_DIR) + "/docs/operations.md");
    std::stringstream docs;
    docs << docs_file.rdbuf();
    std::vector<std::string> budget_flags;
    std::istringstream lines(help.out);
    for (std::string line; std::getline(lines, line);) {
        if (!line.starts_with("  --")) continue;
        const std::string flag = line.substr(2, line.find(' ', 2) - 2);
        EXPECT_TRUE(contains(docs.str(), "`" + flag)) << flag << " is not in docs/operations.md";
        if (flag.starts_with("--max-")) budget_flags.push_back(flag);
    }
    EXPECT_EQ(budget_flags.size(), 21u);  // every budget of api/limits.h but the deadline (--deadline-ms)
    for (const std::string& flag : budget_flags) {
        EXPECT_EQ(run("serve " + flag + " 8 --help").exit_code, 0) << flag;
        const CliRun negative = run("serve " + flag + "=-1 --help");
        EXPECT_EQ(negative.exit_code, 2) << flag;
        EXPECT_TRUE(contains(negative.err, flag + " must be between")) << negative.err;
        EXPECT_EQ(run("serve " + flag + " many --help").exit_code, 2) << flag;
    }
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
    const CliRun wrong = run("remesh " + path("torus.obj") + " -o - --format dae");
    EXPECT_EQ(wrong.exit_code, 2);
    EXPECT_TRUE(contains(wrong.err, "--format: unknown value \"dae\"")) << wrong.err;
}

TEST_F(SurfacedCli, SubdividePatchesFeedTessellate) {
    // the limit surface as patches (JSON whatever the extension), then tessellated from the file and from stdin
    const CliRun patches =
        run("subdivide " + path("cube.obj") + " -o " + path("cube.patches") + " --format patches --levels 1");
    ASSERT_EQ(patches.exit_code, 0) << patches.err;
    EXPECT_TRUE(contains(patches.out, "24 patches at isolation level 1 (24 approximate")) << patches.out;
    const std::string text = slurp(dir_ / "cube.patches");
    EXPECT_EQ(text.substr(0, 12), "{\"patches\":[");
    const CliRun mesh = run("tessellate " + path("cube.patches") + " --input-format json -o " + path("cube.obj.out") +
                            " --format obj --segments 2");
    ASSERT_EQ(mesh.exit_code, 0) << mesh.err;
    auto read = read_mesh(slurp(dir_ / "cube.obj.out"), MeshFormat::Obj);
    ASSERT_TRUE(read.ok()) << read.error().message;
    EXPECT_EQ(read->face_count(), 24u * 2u * 2u * 2u);  // 24 patches, 2 x 2 segments, 2 triangles each
    EXPECT_TRUE(testing::is_watertight(read.value()));
    const CliRun piped = run("tessellate - -o - --format obj --segments 2", "cube.patches");
    ASSERT_EQ(piped.exit_code, 0) << piped.err;
    EXPECT_EQ(piped.out, slurp(dir_ / "cube.obj.out"));
    // options that do not apply to patches: the operation's 400, a usage error
    const CliRun compression =
        run("subdivide " + path("cube.obj") + " -o " + path("x.json") + " --format patches --compression none");
    EXPECT_EQ(compression.exit_code, 2) << compression.err;
    EXPECT_TRUE(contains(compression.err, "does not apply to format \"patches\"")) << compression.err;
}

TEST_F(SurfacedCli, HelpListsTheExitCodes) {
    const CliRun help = run("--help");
    EXPECT_EQ(help.exit_code, 0);
    EXPECT_TRUE(contains(help.out, "Exit codes")) << help.out;
    EXPECT_TRUE(contains(help.out, "  2  bad usage")) << help.out;
}

//! A file command and the operation whose option table gives its flags.
struct TableCommand {
    std::string command;
    std::string operation;
    unsigned transport;  //!< the options it takes: query parameters, or (implicit) the members of a JSON body
};

const std::vector<TableCommand>& table_commands() {
    using api::options::kJson;
    using api::options::kQuery;
    static const std::vector<TableCommand> commands = {
        {"subdivide", "subdivide", kQuery},     {"simplify", "simplify", kQuery},
        {"remesh", "remesh", kQuery},           {"repair", "repair", kQuery},
        {"tessellate", "tessellate", kQuery},   {"pointcloud", "pointcloud", kQuery},
        {"implicit", "implicit_mesh", kJson},   {"query", "mesh_query", kJson},
        {"grid", "implicit_grid", kJson},       {"limit", "limit_evaluate", kJson},
        {"reconstruct", "reconstruct", kQuery},
    };
    return commands;
}

std::string kebab(std::string_view name) {
    std::string out = "--";
    for (const char c : name) out += c == '_' ? '-' : c;
    return out;
}

//! `flag` in `help` as a whole word (not the start of a longer flag).
bool mentions(const std::string& help, const std::string& flag) {
    for (std::size_t at = help.find(flag); at != std::string::npos; at = help.find(flag, at + 1)) {
        const std::size_t end = at + flag.size();
        if ((at == 0 || help[at - 1] == ' ' || help[at - 1] == '\n') &&
            (end == help.size() || !(std::isalnum(static_cast<unsigned char>(help[end])) || help[end] == '-')))
            return true;
    }
    return false;
}

//! A value of `option` inside its range, as the command line spells it.
std::string valid_value(const api::options::OptionSpec& option) {
    using api::options::OptionType;
    if (option.type == OptionType::Enum) return std::string(option.values.back());
    const double low = option.min ? option.min->value : 1;
    double value = low;
    if (option.min && option.min->exclusive) value = option.max ? (low + option.max->value) / 2 : low + 1;
    if (option.type == OptionType::Number) return std::to_string(value);
    if (option.type == OptionType::List) return std::to_string(static_cast<long long>(value)) + ",3";
    return std::to_string(static_cast<long long>(value));
}

TEST_F(SurfacedCli, EveryTableOptionIsAFlagInTheHelp) {
    for (const TableCommand& command : table_commands()) {
        SCOPED_TRACE(command.command);
        const auto* operation = api::options::operation_options(command.operation);
        ASSERT_NE(operation, nullptr);
        const CliRun help = run(command.command + " --help");
        ASSERT_EQ(help.exit_code, 0) << help.err;
        std::string flat;  // the help with its line breaks and indentation as single spaces
        for (const char c : help.out)
            if (!(std::isspace(static_cast<unsigned char>(c)) && !flat.empty() && flat.back() == ' '))
                flat += std::isspace(static_cast<unsigned char>(c)) ? ' ' : c;
        for (const api::options::OptionSpec* option : api::options::all_options(*operation)) {
            if ((option->transports & command.transport) == 0) continue;
            const std::string flag = option->name == "format" ? "--format" : kebab(option->name);
            EXPECT_TRUE(mentions(help.out, flag)) << flag << " is not in the help:\n" << help.out;
            if (option->name == "format") continue;
            // the description and default of the row are what the help says
            EXPECT_TRUE(contains(flat, std::string(option->description))) << flag;
            if (!option->default_json.empty() && option->type != api::options::OptionType::Enum) {
                EXPECT_TRUE(contains(flat, "default " + std::string(option->default_json))) << flag;
            }
            // the flag is accepted (arguments are parsed in order, so --help after it ends the run with 0)
            if (option->type == api::options::OptionType::Bool) {
                EXPECT_TRUE(mentions(help.out, "--no-" + flag.substr(2))) << flag;
                EXPECT_EQ(run(command.command + " " + flag + " --help").exit_code, 0) << flag;
                EXPECT_EQ(run(command.command + " --no-" + flag.substr(2) + " --help").exit_code, 0) << flag;
            } else {
                const CliRun given = run(command.command + " " + flag + " " + valid_value(*option) + " --help");
                EXPECT_EQ(given.exit_code, 0) << flag << " " << valid_value(*option) << ": " << given.err;
            }
            // each old name is still accepted, and listed
            for (const std::string_view alias : option->aliases) {
                EXPECT_TRUE(mentions(help.out, kebab(alias))) << kebab(alias);
                const std::string value =
                    option->type == api::options::OptionType::Bool ? "" : " " + valid_value(*option);
                EXPECT_EQ(run(command.command + " " + kebab(alias) + value + " --help").exit_code, 0) << kebab(alias);
            }
            // out of the row's range: a usage error naming the flag (a limit's maximum is the operation's: exit 1)
            if (option->type == api::options::OptionType::Integer && option->max && !option->max_is_limit) {
                const CliRun over = run(command.command + " " + flag + " " +
                                        std::to_string(static_cast<long long>(option->max->value) + 1) + " --help");
                EXPECT_EQ(over.exit_code, 2) << flag;
                EXPECT_TRUE(contains(over.err, command.command + " " + flag + ": ")) << over.err;
            }
        }
        // and every flag of the Options section is a table option, or one of the hand-written ones
        const std::vector<std::string> hand_written = {
            "--output",         "--format", "--input-format", "--help", "--max-output-faces",      "--bounds",
            "--max-grid-cells", "--points", "--rays",         "--want", "--max-reconstruct-bytes", "--max-points"};
        const std::vector<std::pair<std::string, std::string>> deprecated = {{"--no-draco", "compression"},
                                                                             {"--free-boundary", "keep_boundary"}};
        const std::string options = help.out.substr(help.out.find("\nOptions:\n"));
        for (std::size_t at = options.find(" --"); at != std::string::npos; at = options.find(" --", at + 1)) {
            std::size_t end = at + 3;
            while (end < options.size() &&
                   (std::isalnum(static_cast<unsigned char>(options[end])) || options[end] == '-'))
                ++end;
            const std::string flag = options.substr(at + 1, end - at - 1);
            if (std::find(hand_written.begin(), hand_written.end(), flag) != hand_written.end()) continue;
            const auto old =
                std::find_if(deprecated.begin(), deprecated.end(), [&](const auto& d) { return d.first == flag; });
            std::string name = old != deprecated.end() ? old->second : flag.substr(2);
            if (old == deprecated.end()) {
                for (char& c : name) c = c == '-' ? '_' : c;
                if (!api::options::find_option(*operation, name) && name.starts_with("no_")) name = name.substr(3);
            }
            const api::options::OptionSpec* option = api::options::find_option(*operation, name);
            EXPECT_TRUE(option && (option->transports & command.transport) != 0)
                << flag << " in the help of " << command.command << " is no option of " << command.operation;
        }
    }
}

TEST_F(SurfacedCli, QueryAnswersPointsAndRaysOfAMeshFile) {
    std::ofstream(dir_ / "points.json") << "[[0, 0, 0], [2, 0, 0], [0.1, 0.2, -1]]";
    std::ofstream(dir_ / "rays.json") << R"({"rays": [[-5, 0, 0, 2, 0, 0], [0, 5, 0, 0, 1, 0]]})";
    // No -o: the answer goes to standard output, the summary to stderr.
    const CliRun r = run("query " + path("cube.obj") + " --points " + path("points.json") + " --rays " +
                         path("rays.json") + " --want inside,distance,closest --exact");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(contains(r.err, "3 points, 2 rays")) << r.err;
    const auto out = nlohmann::json::parse(r.out);
    EXPECT_EQ(out["points"]["inside"], nlohmann::json::array({true, false, false}));
    EXPECT_EQ(out["points"]["distance"], nlohmann::json::array({-0.5, 1.5, 0.5}));  // the cube is [-0.5, 0.5]^3
    EXPECT_NEAR(out["points"]["closest"][2][0].get<double>(), 0.1, 1e-12);
    EXPECT_NEAR(out["points"]["closest"][2][1].get<double>(), 0.2, 1e-12);
    EXPECT_EQ(out["points"]["closest"][2][2], -0.5);
    EXPECT_FALSE(out["points"].contains("winding_number"));
    EXPECT_EQ(out["rays"]["hit"], nlohmann::json::array({true, false}));
    EXPECT_EQ(out["rays"]["t"][0], 2.25);
    EXPECT_TRUE(out["rays"]["t"][1].is_null());

    // The points from standard input, the answer to a file.
    const CliRun piped = run("query " + path("cube.obj") + " --points - -o " + path("answer.json"), "points.json");
    ASSERT_EQ(piped.exit_code, 0) << piped.err;
    EXPECT_EQ(nlohmann::json::parse(slurp(dir_ / "answer.json"))["points"]["face"].size(), 3u);

    // The mesh from standard input, its format named.
    const CliRun mesh_in =
        run("query - --input-format obj --points " + path("points.json") + " --want inside", "cube.obj");
    ASSERT_EQ(mesh_in.exit_code, 0) << mesh_in.err;
    EXPECT_EQ(nlohmann::json::parse(mesh_in.out)["points"]["inside"], nlohmann::json::array({true, false, false}));

    // Usage errors exit 2 naming the flag; a mesh without faces is the operation's failure, exit 1.
    const CliRun want = run("query " + path("cube.obj") + " --points " + path("points.json") + " --want insde");
    EXPECT_EQ(want.exit_code, 2);
    EXPECT_TRUE(contains(want.err, "did you mean \"inside\"")) << want.err;
    EXPECT_EQ(run("query " + path("cube.obj")).exit_code, 2);
    EXPECT_EQ(run("query " + path("cube.obj") + " --points " + path("points.json") + " --accuracy 1").exit_code, 2);
    std::ofstream(dir_ / "zero.json") << "[[0, 0, 0, 0, 0, 0]]";
    const CliRun zero = run("query " + path("cube.obj") + " --rays " + path("zero.json"));
    EXPECT_EQ(zero.exit_code, 2);
    EXPECT_TRUE(contains(zero.err, "rays[0]")) << zero.err;
    std::ofstream(dir_ / "empty.json") << R"({"positions": [[0, 0, 0]], "faces": []})";
    const CliRun empty = run("query " + path("empty.json") + " --points " + path("points.json"));
    EXPECT_EQ(empty.exit_code, 1);
    EXPECT_TRUE(contains(empty.err, "mesh.faces")) << empty.err;
}

TEST_F(SurfacedCli, LimitEvaluatesPointsOfAMeshFile) {
    std::ofstream(dir_ / "points.json") << R"([{"face": 0, "uv": [0.5, 0.5]}, {"face": 2, "uv": [0.1, 0.7]}])";
    const PolygonMesh cube = shapes::cube();
    const auto evaluator = LimitSurfaceEvaluator::create(cube, {});
    ASSERT_TRUE(evaluator.ok());
    const auto expect_answers = [&](const nlohmann::json& out, bool second) {
        ASSERT_EQ(out["points"].size(), 2u) << out.dump();
        const double uv[2][2] = {{0.5, 0.5}, {0.1, 0.7}};
        for (std::size_t k = 0; k < 2; ++k) {
            const auto s = evaluator->evaluate(k == 0 ? 0 : 2, uv[k][0], uv[k][1], second);
            ASSERT_TRUE(s.ok());
            for (int c = 0; c < 3; ++c) {
                EXPECT_NEAR(out["points"][k]["position"][c].get<double>(), (&s->position.x)[c], 1e-12);
                EXPECT_NEAR(out["points"][k]["normal"][c].get<double>(), (&s->normal.x)[c], 1e-12);
            }
            EXPECT_EQ(out["points"][k].contains("duv"), second);
        }
    };
    // No -o: the answer goes to standard output, the summary to stderr.
    const CliRun r = run("limit " + path("cube.obj") + " --points " + path("points.json"));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(contains(r.err, "2 limit points")) << r.err;
    expect_answers(nlohmann::json::parse(r.out), false);

    // The points from standard input, the answer to a file, second derivatives.
    const CliRun piped =
        run("limit " + path("cube.obj") + " --points - --derivatives 2 -o " + path("answer.json"), "points.json");
    ASSERT_EQ(piped.exit_code, 0) << piped.err;
    expect_answers(nlohmann::json::parse(slurp(dir_ / "answer.json")), true);

    // The mesh from standard input (its format from the bytes).
    const CliRun mesh_in = run("limit - --points " + path("points.json"), "cube.obj");
    ASSERT_EQ(mesh_in.exit_code, 0) << mesh_in.err;
    expect_answers(nlohmann::json::parse(mesh_in.out), false);

    // An OBJ's texture coordinates reach the operation: their limit is answered, as the UV evaluator gives it.
    PolygonMesh quad;
    quad.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0.5}, {0, 1, 0}};
    quad.add_face({0, 1, 2, 3});
    quad.uvs = {{0, 0}, {1, 0}, {0.8, 0.9}, {0, 1}};
    quad.uv_indices = {0, 1, 2, 3};
    std::ofstream(dir_ / "quad.obj", std::ios::binary) << write_obj(quad);
    std::ofstream(dir_ / "quad_points.json") << R"([{"face": 0, "uv": [0.3, 0.6]}])";
    const CliRun uvs = run("limit " + path("quad.obj") + " --points " + path("quad_points.json") +
                           " --uv-interpolation none --boundary edge-and-corner");
    ASSERT_EQ(uvs.exit_code, 0) << uvs.err;
    SubdivisionOptions options;
    options.uv_interpolation = UvInterpolation::None;
    options.boundary = BoundaryInterpolation::EdgeAndCorner;
    const auto uv = UvLimitEvaluator::create(read_obj(write_obj(quad)).value(), options).value().evaluate(0, 0.3, 0.6);
    ASSERT_TRUE(uv.ok());
    const auto answer = nlohmann::json::parse(uvs.out)["points"][0];
    ASSERT_TRUE(answer.contains("uv")) << uvs.out;
    EXPECT_NEAR(answer["uv"][0].get<double>(), uv->uv.x, 1e-12);
    EXPECT_NEAR(answer["uv"][1].get<double>(), uv->uv.y, 1e-12);

    // Usage errors exit 2 naming the flag or the point; a mesh without faces is the operation's failure, exit 1.
    EXPECT_EQ(run("limit " + path("cube.obj")).exit_code, 2);
    const CliRun derivatives =
        run("limit " + path("cube.obj") + " --points " + path("points.json") + " --derivatives 3");
    EXPECT_EQ(derivatives.exit_code, 2);
    EXPECT_TRUE(contains(derivatives.err, "limit --derivatives")) << derivatives.err;
    std::ofstream(dir_ / "far.json") << R"([{"face": 6, "uv": [0.5, 0.5]}])";
    const CliRun far = run("limit " + path("cube.obj") + " --points " + path("far.json"));
    EXPECT_EQ(far.exit_code, 2);
    EXPECT_TRUE(contains(far.err, "points[0].face")) << far.err;
    std::ofstream(dir_ / "empty.json") << R"({"positions": [[0, 0, 0]], "faces": []})";
    const CliRun empty = run("limit " + path("empty.json") + " --points " + path("points.json"));
    EXPECT_EQ(empty.exit_code, 1);
    EXPECT_TRUE(contains(empty.err, "mesh.faces")) << empty.err;
    const CliRun help = run("limit --help");
    EXPECT_EQ(help.exit_code, 0);
    EXPECT_TRUE(contains(help.out, "Exit codes")) << help.out;
}

TEST_F(SurfacedCli, GridWritesTheLevelSetNodeOfAMeshOrScene) {
    // cube.obj is [-0.5, 0.5]^3: with h 0.25 and band 1 the default bounds are [-1, 1]^3, 9 nodes per axis
    const CliRun r = run("grid " + path("cube.obj") + " --voxel-size 0.25 --band 1");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(contains(r.err, "grid 9x9x9")) << r.err;
    const auto node = nlohmann::json::parse(r.out);
    EXPECT_EQ(node["op"], "level_set");
    EXPECT_EQ(node["dims"], nlohmann::json::array({9, 9, 9}));
    EXPECT_EQ(node["values"][4 + 9 * (4 + 9 * 4)], -0.25);  // the centre: 0.5 deep, clamped to the band
    EXPECT_EQ(node["values"][6 + 9 * (4 + 9 * 4)], 0);      // (0.5, 0, 0): on the surface

    // a scene alone needs bounds; with them, to a file
    std::ofstream(dir_ / "ball.json") << R"({"op": "sphere", "radius": 0.5})";
    EXPECT_EQ(run("grid " + path("ball.json") + " --voxel-size 0.25").exit_code, 2);
    const CliRun scene =
        run("grid " + path("ball.json") + " --voxel-size 0.5 --bounds -1,-1,-1,1,1,1 -o " + path("ball_grid.json"));
    ASSERT_EQ(scene.exit_code, 0) << scene.err;
    EXPECT_EQ(nlohmann::json::parse(slurp(dir_ / "ball_grid.json"))["values"].size(), 125u);

    // usage errors exit 2; a budget is the operation's failure, exit 1, naming voxel_size
    EXPECT_EQ(run("grid " + path("cube.obj")).exit_code, 2);
    EXPECT_EQ(run("grid " + path("cube.obj") + " --voxel-size 0").exit_code, 2);
    EXPECT_EQ(run("grid " + path("cube.obj") + " --voxel-size 0.1 --band 65").exit_code, 2);
    const CliRun budget = run("grid " + path("cube.obj") + " --voxel-size 1e-4");
    EXPECT_EQ(budget.exit_code, 1);
    EXPECT_TRUE(contains(budget.err, "voxel_size")) << budget.err;
}

TEST_F(SurfacedCli, ATableOfMistakesExitsAlikeInEveryCommand) {
    // each command's run, writing OUT with the extension given
    struct Command {
        std::string name;
        std::function<std::string(const std::string& ext)> args;
        std::string plain;  //!< an output format that is not glTF
    };
    const std::vector<Command> commands = {
        {"subdivide",
         [&](const std::string& ext) { return "subdivide " + path("cube.obj") + " -o " + path("x." + ext); }, "obj"},
        {"simplify",
         [&](const std::string& ext) {
             return "simplify " + path("torus.obj") + " -o " + path("x." + ext) + " --ratio 0.5";
         },
         "obj"},
        {"remesh",
         [&](const std::string& ext) {
             return "remesh " + path("torus.obj") + " -o " + path("x." + ext) + " --iterations 1";
         },
         "ply"},
        {"repair", [&](const std::string& ext) { return "repair " + path("torus.obj") + " -o " + path("x." + ext); },
         "obj"},
        {"tessellate",
         [&](const std::string& ext) { return "tessellate sample:teapot -o " + path("x." + ext) + " --segments 2"; },
         "obj"},
        {"pointcloud",
         [&](const std::string& ext) { return "pointcloud " + path("points.xyz") + " -o " + path("x." + ext); }, "ply"},
        {"implicit",
         [&](const std::string& ext) { return "implicit " + path("scene.json") + " -o " + path("x." + ext); }, "obj"},
        {"reconstruct",
         [&](const std::string& ext) {
             return "reconstruct " + path("points.xyz") + " -o " + path("x." + ext) + " --depth 4";
         },
         "off"},
    };
    struct Mistake {
        std::string what;
        bool plain;         //!< written to the command's non-glTF format, else to .glb
        std::string extra;  //!< the arguments that make the mistake
        int exit_code;
        std::string message;  //!< part of what stderr says
    };
    const std::vector<Mistake> mistakes = {
        {"none", false, "", 0, ""},
        {"none, plain output", true, "", 0, ""},
        {"out of range", false, "--quantize-position 25", 2,
         "--quantize-position: quantize_position must be in [1, 24]"},
        {"not a number", false, "--quantize-position twelve", 2, "--quantize-position needs an integer"},
        {"unknown value", false, "--compression zstd", 2, "--compression: unknown value \"zstd\""},
        {"unknown option", false, "--quantise-position 12", 2, "did you mean --quantize-position?"},
        {"not for this format", true, "--quantize-position 12", 2, "--quantize-position: "},
        {"compression not for this format", true, "--compression none", 2, "--compression: "},
        {"the old spelling, not for this format", true, "--no-draco", 2, "--no-draco: "},
        {"quantization without Draco", false, "--compression none --quantize-position 12", 2, "--quantize-position: "},
        {"an unknown output format", false, "--format dae", 2, "--format: unknown value \"dae\""},
    };
    for (const Command& command : commands)
        for (const Mistake& mistake : mistakes) {
            const CliRun r = run(command.args(mistake.plain ? command.plain : "glb") + " " + mistake.extra);
            EXPECT_EQ(r.exit_code, mistake.exit_code) << command.name << ", " << mistake.what << ": " << r.err;
            EXPECT_TRUE(contains(r.err, mistake.message)) << command.name << ", " << mistake.what << ": " << r.err;
            if (mistake.exit_code == 2) {
                EXPECT_TRUE(contains(r.err, "surfaced: " + command.name)) << r.err;
            }
        }
    // an operation's budget is a failure (1), whichever command
    EXPECT_EQ(run(commands[0].args("glb") + " --levels 12").exit_code, 1);
    EXPECT_EQ(run("tessellate sample:teapot -o " + path("x.glb") + " --segments 1000").exit_code, 1);
    EXPECT_EQ(run(commands[6].args("glb") + " --resolution 5000").exit_code, 1);
    // a rule only the operation knows is the same usage error, naming the flag
    const CliRun k = run(commands[5].args("ply") + " --k 8");
    EXPECT_EQ(k.exit_code, 2);
    EXPECT_TRUE(contains(k.err, "pointcloud --k: ")) << k.err;
    // a range the command line checks and one the operation checks read alike
    const CliRun cli = run(commands[1].args("obj") + " --ratio 2");
    EXPECT_EQ(cli.exit_code, 2);
    EXPECT_TRUE(contains(cli.err, "surfaced: simplify --ratio: ratio must be in (0, 1], got 2")) << cli.err;
}

TEST_F(SurfacedCli, ReconstructWritesTheClosedSurfaceOfAPointFile) {
    // a unit sphere sampled on a Fibonacci lattice, without normals
    {
        std::ofstream xyz(dir_ / "sphere.xyz");
        const double golden = 3.14159265358979323846 * (3 - std::sqrt(5.0));
        for (int i = 0; i < 2000; ++i) {
            const double z = 1 - (2.0 * i + 1) / 2000, rho = std::sqrt(1 - z * z);
            xyz << rho * std::cos(golden * i) << " " << rho * std::sin(golden * i) << " " << z << "\n";
        }
    }
    const CliRun r = run("reconstruct " + path("sphere.xyz") + " -o " + path("sphere.obj") + " --depth 5 --k 12");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(contains(r.err + r.out, "normals estimated")) << r.out << r.err;
    auto mesh = read_obj(slurp(dir_ / "sphere.obj"));
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    EXPECT_TRUE(testing::is_watertight(mesh.value()));
    EXPECT_NEAR(testing::signed_volume(mesh.value()), 4.0 / 3.0 * 3.14159265358979323846, 0.15);
    // the same through standard input and output
    const CliRun piped = run("reconstruct - -o - --input-format xyz --format off --depth 4", "sphere.xyz");
    ASSERT_EQ(piped.exit_code, 0) << piped.err;
    EXPECT_TRUE(piped.out.starts_with("OFF")) << piped.out.substr(0, 40);
    // a budget is a failure (1), a value out of range or a rule of the options bad usage (2), naming the flag
    EXPECT_EQ(run("reconstruct " + path("sphere.xyz") + " -o " + path("x.obj") + " --depth 9").exit_code, 1);
    // ... which the budget flags raise (depth 9's 512^3 grid), and lower (the point count)
    const CliRun raised = run("reconstruct " + path("sphere.xyz") + " -o " + path("x9.obj") +
                              " --depth 9 --max-grid-cells 200000000 --threads 2");
    EXPECT_EQ(raised.exit_code, 0) << raised.err;
    const CliRun few =
        run("reconstruct " + path("sphere.xyz") + " -o " + path("x.obj") + " --depth 4 --max-points 100");
    EXPECT_EQ(few.exit_code, 1);
    EXPECT_TRUE(contains(few.err, "points")) << few.err;
    const CliRun depth = run("reconstruct " + path("sphere.xyz") + " -o " + path("x.obj") + " --depth 1");
    EXPECT_EQ(depth.exit_code, 2);
    EXPECT_TRUE(contains(depth.err, "reconstruct --depth: ")) << depth.err;
    const CliRun k =
        run("reconstruct " + path("sphere.xyz") + " -o " + path("x.obj") + " --estimate-normals never --k 8");
    EXPECT_EQ(k.exit_code, 2);
    EXPECT_TRUE(contains(k.err, "reconstruct --k: ")) << k.err;
    // points without normals when asked not to estimate them: the input fails (1)
    const CliRun never =
        run("reconstruct " + path("sphere.xyz") + " -o " + path("x.obj") + " --estimate-normals never");
    EXPECT_EQ(never.exit_code, 1) << never.err;
    EXPECT_TRUE(contains(never.err, "no normals")) << never.err;
    // GLB points (as pointcloud writes them, with estimated normals) in: by extension, and sniffed from standard input
    ASSERT_EQ(
        run("pointcloud " + path("sphere.xyz") + " -o " + path("sphere.glb") + " --estimate-normals --k 12").exit_code,
        0);
    const CliRun glb = run("reconstruct " + path("sphere.glb") + " -o " + path("from_glb.obj") + " --depth 5");
    ASSERT_EQ(glb.exit_code, 0) << glb.err;
    EXPECT_FALSE(contains(glb.err + glb.out, "normals estimated")) << glb.err;
    auto from_glb = read_obj(slurp(dir_ / "from_glb.obj"));
    ASSERT_TRUE(from_glb.ok()) << from_glb.error().message;
    EXPECT_TRUE(testing::is_watertight(from_glb.value()));
    EXPECT_NEAR(testing::signed_volume(from_glb.value()), 4.0 / 3.0 * 3.14159265358979323846, 0.15);
    const CliRun piped_glb = run("reconstruct - -o - --format off --depth 4", "sphere.glb");
    ASSERT_EQ(piped_glb.exit_code, 0) << piped_glb.err;
    EXPECT_TRUE(piped_glb.out.starts_with("OFF")) << piped_glb.out.substr(0, 40);
    ASSERT_EQ(run("pointcloud " + path("sphere.glb") + " -o " + path("back.ply")).exit_code, 0);
    auto back = read_ply_points(slurp(dir_ / "back.ply"));
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(back->size(), 2000u);
    EXPECT_EQ(back->normals.size(), 2000u);
}

TEST_F(SurfacedCli, OldSpellingsSetTheirTableOptions) {
    // --no-draco is --compression none: a plain glTF is larger than a Draco one
    ASSERT_EQ(run("subdivide " + path("cube.obj") + " -o " + path("draco.glb") + " --levels 2").exit_code, 0);
    ASSERT_EQ(run("subdivide " + path("cube.obj") + " -o " + path("plain.glb") + " --levels 2 --no-draco").exit_code,
              0);
    ASSERT_EQ(
        run("subdivide " + path("cube.obj") + " -o " + path("none.glb") + " --levels 2 --compression none").exit_code,
        0);
    EXPECT_GT(fs::file_size(dir_ / "plain.glb"), fs::file_size(dir_ / "draco.glb"));
    EXPECT_EQ(slurp(dir_ / "plain.glb"), slurp(dir_ / "none.glb"));
    // --free-boundary is the boundary option set false, under whatever name the table gives it
    const auto* remesh = api::options::operation_options("remesh");
    const auto* boundary = api::options::find_option(*remesh, "keep_boundary");
    ASSERT_NE(boundary, nullptr);
    std::ofstream(dir_ / "sheet.obj", std::ios::binary) << write_obj(shapes::grid(6, 6, true));
    const std::string base = "remesh " + path("sheet.obj") + " --iterations 2 --edge-length 0.3 -o ";
    ASSERT_EQ(run(base + path("free.obj") + " --free-boundary").exit_code, 0);
    ASSERT_EQ(run(base + path("no.obj") + " --no-" + kebab(boundary->name).substr(2)).exit_code, 0);
    ASSERT_EQ(run(base + path("kept.obj")).exit_code, 0);
    EXPECT_EQ(slurp(dir_ / "free.obj"), slurp(dir_ / "no.obj"));
    EXPECT_NE(slurp(dir_ / "free.obj"), slurp(dir_ / "kept.obj"));
}

}  // namespace
}  // namespace surfaced
