// Mesh repair through the real server on an ephemeral loopback port, with files of the repair corpus
// (tests/data/repair-corpus, its expected.json): POST /repair answers with the repaired mesh and its report in
// X-Repairs; /simplify and /remesh repair a broken upload by default and report it, and refuse it with repair=none
// (422 naming the problem). And `surfaced repair IN -o OUT` on a corpus file.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "geometry/io/mesh_io.h"
#include "tests/support/http_test_server.h"
#include "tests/support/mesh_asserts.h"
#include "tests/support/repair_asserts.h"

namespace surfaced::server {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using testing::expect_http_problem;

const fs::path kCorpus = fs::path(SURFACED_TEST_DATA_DIR) / "repair-corpus";

std::string corpus_file(const std::string& name) { return testing::read_file((kCorpus / name).string()); }

//! expected.json's repair counts for `name`, as X-Repairs writes them ("welded=18; degenerate=0; ...", in
//! RepairReport order).
std::string expected_x_repairs(const std::string& name) {
    const Json files = Json::parse(corpus_file("expected.json"))["files"];
    const Json& counts = files.at(name).at("repairs");
    std::string out;
    for (const char* key : {"welded", "degenerate", "duplicate", "flipped", "nonmanifold_split", "small_components",
                            "removed_faces", "holes_filled", "fill_faces", "unreferenced", "components"})
        out += std::string(out.empty() ? "" : "; ") + key + "=" + std::to_string(counts.at(key).get<std::size_t>());
    return out;
}

//! The mesh of a {"mesh": {"positions", "faces"}, ...} response.
PolygonMesh json_mesh(const Json& body) {
    PolygonMesh mesh;
    for (const auto& p : body.at("mesh").at("positions")) mesh.positions.push_back({p[0], p[1], p[2]});
    for (const auto& f : body.at("mesh").at("faces")) mesh.add_face(f.get<std::vector<Index>>());
    return mesh;
}

class RepairHttp : public testing::SharedServerTest<RepairHttp> {
protected:
    static httplib::Client client() { return SharedServerTest::client(60); }
};

TEST_F(RepairHttp, BinaryStlSoupComesBackManifoldWithItsReport) {
    // The STL reader welds the corners it stores per triangle (26 distinct of 144), so repair itself welds nothing.
    auto res = client().Post("/repair?format=json", corpus_file("soup_binary.stl"), "model/stl");
    ASSERT_TRUE(res) << httplib::to_string(res.error());
    ASSERT_EQ(res->status, 200) << res->body;
    EXPECT_EQ(res->get_header_value("Content-Type"), "application/json");
    EXPECT_EQ(res->get_header_value("X-Repairs"), expected_x_repairs("soup_binary.stl"));
    EXPECT_EQ(res->get_header_value("X-Input-Vertices"), "26");
    EXPECT_EQ(res->get_header_value("X-Input-Faces"), "48");
    EXPECT_EQ(res->get_header_value("X-Output-Faces"), "48");
    const Json body = Json::parse(res->body);
    const PolygonMesh mesh = json_mesh(body);
    testing::expect_repaired(mesh);
    EXPECT_TRUE(testing::is_watertight(mesh));
    EXPECT_NEAR(testing::signed_volume(mesh), 8000.0, 1e-9);  // a 20 mm cube
    EXPECT_EQ(body["stats"]["repairs"]["components"], 1);
}

TEST_F(RepairHttp, BrokenFilesReportWhatWasRepairedAndComeBackManifold) {
    const std::map<std::string, std::string> files = {{"soup_octahedron.obj", "model/obj"},
                                                      {"flipped_components.obj", "model/obj"},
                                                      {"boxes_sharing_edge.obj", "model/obj"},
                                                      {"pinched_pyramids.off", "model/off"},
                                                      {"blender249_flat_cube.ply", "application/ply"},
                                                      {"soup_flipped_facets_ascii.stl", "model/stl"}};
    for (const auto& [name, type] : files) {
        SCOPED_TRACE(name);
        auto res = client().Post("/repair?format=obj", corpus_file(name), type);
        ASSERT_TRUE(res) << httplib::to_string(res.error());
        ASSERT_EQ(res->status, 200) << res->body;
        EXPECT_EQ(res->get_header_value("X-Repairs"), expected_x_repairs(name));
        auto mesh = read_obj(res->body);
        ASSERT_TRUE(mesh.ok()) << mesh.error().message;
        testing::expect_repaired(mesh.value());
    }
}

TEST_F(RepairHttp, SimplifyAndRemeshRepairABrokenUploadByDefault) {
    // two cubes sharing an edge: four faces around it
    const std::string body = corpus_file("boxes_sharing_edge.obj");
    for (const std::string target : {"/simplify?ratio=0.5&format=obj", "/remesh?format=obj"}) {
        SCOPED_TRACE(target);
        auto res = client().Post(target, body, "model/obj");
        ASSERT_TRUE(res) << httplib::to_string(res.error());
        ASSERT_EQ(res->status, 200) << res->body;
        EXPECT_EQ(res->get_header_value("X-Repairs"), expected_x_repairs("boxes_sharing_edge.obj"));
        auto mesh = read_obj(res->body);
        ASSERT_TRUE(mesh.ok()) << mesh.error().message;
        const auto edges = testing::edge_stats(mesh.value());
        EXPECT_EQ(edges.non_manifold_edges, 0u);
        EXPECT_EQ(edges.inconsistent_edges, 0u);
    }
}

TEST_F(RepairHttp, SimplifyAndRemeshWithRepairNoneRefuseNamingTheProblem) {
    for (const std::string op : {"/simplify?ratio=0.5&repair=none", "/remesh?repair=none"}) {
        SCOPED_TRACE(op);
        // four faces on the edge the two cubes share
        const Json shared = expect_http_problem(client().Post(op, corpus_file("boxes_sharing_edge.obj"), "model/obj"),
                                                422, "non_manifold");
        const std::string detail = shared.value("detail", "");
        EXPECT_NE(detail.find("edge"), std::string::npos) << detail;
        // a face that repeats a vertex (f 1 2 2) is refused when the file is read, with its line
        const Json degenerate = expect_http_problem(client().Post(op, corpus_file("degenerate_faces.obj"), "model/obj"),
                                                    422, "degenerate_face");
        EXPECT_NE(degenerate.value("detail", "").find("line 26"), std::string::npos) << degenerate.dump();
        // and the same files are processed with the default, repair=auto
        const std::string auto_op = op.substr(0, op.find("repair=none")) + "repair=auto";
        for (const char* name : {"boxes_sharing_edge.obj", "degenerate_faces.obj"}) {
            auto res = client().Post(auto_op, corpus_file(name), "model/obj");
            ASSERT_TRUE(res) << httplib::to_string(res.error());
            EXPECT_EQ(res->status, 200) << name << ": " << res->body;
            EXPECT_EQ(res->get_header_value("X-Repairs"), expected_x_repairs(name));
        }
    }
}

TEST_F(RepairHttp, NonManifoldUploadsAreRefusedAtAFacesLineByBothOperations) {
    struct Case {
        const char* file;
        const char* type;
        int line;            // of the face the problem is located at
        const char* detail;  // after "line N: "
    };
    // boxes: faces 6, 9, 17 and 22 (0-based; lines 22, 25, 33, 38) share the edge between vertices 2 and 6: the
    // third, f 3 12 7 on line 33, makes it non-manifold (its half-edge there runs from 6 to 2);
    // the bow-tie and the pyramids meet at vertex 0, first used by the face on line 11 and line 13
    const Case cases[] = {
        {"boxes_sharing_edge.obj", "model/obj", 33, "edge (6, 2) is shared by more than two faces (face 17 is one)"},
        {"bowtie.obj", "model/obj", 11, "vertex 0 joins several fans of faces"},
        {"pinched_pyramids.off", "model/off", 13, "vertex 0 joins several fans of faces"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.file);
        std::vector<Json> problems;
        for (const std::string op : {"/simplify?ratio=0.5&repair=none", "/remesh?repair=none"}) {
            SCOPED_TRACE(op);
            const Json problem =
                expect_http_problem(client().Post(op, corpus_file(c.file), c.type), 422, "non_manifold");
            EXPECT_EQ(problem.value("line", 0), c.line) << problem.dump();
            EXPECT_EQ(
                problem.value("detail", ""),
                "line " + std::to_string(c.line) + ": " + c.detail +
                    (std::string(c.detail).rfind("vertex", 0) == 0 ? " (a non-manifold vertex; face 0 uses it)" : ""))
                << problem.dump();
            EXPECT_EQ(problem.value("hint", ""), "repair=auto repairs it");
            problems.push_back(problem);
        }
        EXPECT_EQ(problems[0], problems[1]);  // the same rules, the same words
        // repair=auto: both cut the vertex or edge apart
        for (const std::string op : {"/simplify?ratio=0.5&format=obj", "/remesh?format=obj"}) {
            auto res = client().Post(op, corpus_file(c.file), c.type);
            ASSERT_TRUE(res) << httplib::to_string(res.error());
            ASSERT_EQ(res->status, 200) << op << ": " << res->body;
            EXPECT_EQ(res->get_header_value("X-Repairs"), expected_x_repairs(c.file)) << op;
        }
    }
}

TEST_F(RepairHttp, LoopOnAQuadUploadNamesTheFacesLineWithAHint) {
    const std::string obj =
        "# a triangle and a quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\nf 1 2 3\n\nf 2 5 6 3\n";
    const Json problem =
        expect_http_problem(client().Post("/subdivide?scheme=loop", obj, "model/obj"), 422, "not_triangle_mesh");
    EXPECT_EQ(problem.value("line", 0), 10) << problem.dump();
    EXPECT_EQ(problem.value("detail", ""), "line 10: face 1 has 4 vertices; Loop subdivision needs triangles");
    EXPECT_EQ(problem.value("hint", ""), "scheme catmull-clark takes any polygons");
    auto res = client().Post("/subdivide?scheme=catmull-clark&format=obj", obj, "model/obj");
    ASSERT_TRUE(res) << httplib::to_string(res.error());
    EXPECT_EQ(res->status, 200) << res->body;
}

// ---- the CLI ----

struct CliResult {
    int exit_code = -1;
    std::string out, err;
};

class RepairCli : public ::testing::Test {
protected:
    void SetUp() override {
        std::random_device rd;
        dir_ = fs::temp_directory_path() / ("surfaced-repair-" + std::to_string(rd()));
        fs::create_directories(dir_);
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(dir_, ec);
    }
    CliResult run_cli(const std::string& args) const {
        const fs::path out = dir_ / "stdout.txt", err = dir_ / "stderr.txt";
        const std::string command =
            std::string("'") + SURFACED_CLI_PATH + "' " + args + " >'" + out.string() + "' 2>'" + err.string() + "'";
        const int status = std::system(command.c_str());
        CliResult r;
        r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        r.out = testing::read_file(out.string());
        r.err = testing::read_file(err.string());
        return r;
    }
    fs::path dir_;
};

TEST_F(RepairCli, RepairsACorpusFileAndPrintsTheReport) {
    for (const char* name : {"flipped_components.obj", "nested_transforms.gltf"}) {
        SCOPED_TRACE(name);
        const fs::path output = dir_ / "out.obj";
        const auto r = run_cli("repair '" + (kCorpus / name).string() + "' -o '" + output.string() + "'");
        ASSERT_EQ(r.exit_code, 0) << r.err;
        // the report goes to standard error, like simplify's and remesh's; the summary of what was written to
        // standard output
        EXPECT_NE(r.err.find("repaired " + (kCorpus / name).string() + ": " + expected_x_repairs(name)),
                  std::string::npos)
            << r.err;
        EXPECT_NE(r.out.find("wrote " + output.string()), std::string::npos) << r.out;
        EXPECT_EQ(r.out.find(expected_x_repairs(name)), std::string::npos) << r.out;
        auto mesh = read_obj(testing::read_file(output.string()));
        ASSERT_TRUE(mesh.ok()) << mesh.error().message;
        testing::expect_repaired(mesh.value());
    }
    // a file that is no mesh: exit status non-zero, the reader's error on standard error
    const auto refused = run_cli("repair '" + (kCorpus / "not_a_mesh_point_cloud.ply").string() + "' -o '" +
                                 (dir_ / "x.obj").string() + "'");
    EXPECT_NE(refused.exit_code, 0);
    EXPECT_NE(refused.err.find("no faces"), std::string::npos) << refused.err;
}

}  // namespace
}  // namespace surfaced::server
