// The manifold rules /simplify and /remesh share (api/operations/mesh_repair.h): with repair "none" both refuse the
// same meshes with the same 422, located at a face (its JSON field, or its line in an uploaded text file) with a
// hint; with repair "auto" both repair the same meshes (bow-tie vertices split). And /subdivide's scheme loop on a
// polygon, located the same way. Called in-process through the route table.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/routes.h"
#include "geometry/io/mesh_io.h"
#include "geometry/mesh/shapes.h"
#include "geometry/repair/repair.h"
#include "tests/support/api_request.h"
#include "tests/support/mesh_asserts.h"

namespace surfaced::api {
namespace {

using namespace fixtures;

ApiResponse post(const std::string& path, const std::string& content_type, const std::string& body,
                 std::multimap<std::string, std::string> query = {}) {
    return dispatch(make_request("POST", path, content_type, body, std::move(query)), context_with());
}

// The operations, each with the options it needs besides the mesh.
struct Operation {
    const char* path;
    const char* json_options;                       // members after "mesh"
    std::multimap<std::string, std::string> query;  // for a file upload
};
const std::vector<Operation>& manifold_operations() {
    static const std::vector<Operation> ops = {
        {"/simplify", R"(,"ratio":0.5)", {{"ratio", "0.5"}}},
        {"/remesh", R"(,"iterations":2)", {{"iterations", "2"}}},
    };
    return ops;
}

//! Two fans of triangles around vertex 0 that meet only there.
PolygonMesh bowtie() {
    PolygonMesh m;
    m.positions = {{0, 0, 0},  {2, 0, 0},   {2, 1, 0},   {1, 2, 0}, {0, 2, 0},
                   {-2, 0, 0}, {-2, -1, 0}, {-1, -2, 0}, {0, -2, 0}};
    for (const auto& f :
         std::vector<std::vector<Index>>{{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 5, 6}, {0, 6, 7}, {0, 7, 8}})
        m.add_face(f);
    return m;
}

//! Three triangles on the edge (0, 1).
PolygonMesh fin() {
    PolygonMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
    m.add_face({0, 1, 2});
    m.add_face({1, 0, 3});
    m.add_face({0, 1, 4});
    return m;
}

//! Two triangles that traverse their shared edge (1, 2) in the same direction.
PolygonMesh inconsistent() {
    PolygonMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
    m.add_face({0, 1, 2});
    m.add_face({3, 1, 2});
    return m;
}

//! Two square pyramids (quad bases) touching at their apex, vertex 0: a non-manifold vertex of a polygon mesh.
PolygonMesh pinched_pyramids() {
    PolygonMesh m;
    m.positions = {{0, 0, 0},  {1, 1, 1},   {-1, 1, 1},   {-1, -1, 1}, {1, -1, 1},
                   {1, 1, -1}, {-1, 1, -1}, {-1, -1, -1}, {1, -1, -1}};
    for (const auto& f : std::vector<std::vector<Index>>{{2, 1, 0},
                                                         {3, 2, 0},
                                                         {4, 3, 0},
                                                         {1, 4, 0},
                                                         {2, 3, 4, 1},
                                                         {0, 5, 6},
                                                         {0, 6, 7},
                                                         {0, 7, 8},
                                                         {0, 8, 5},
                                                         {5, 8, 7, 6}})
        m.add_face(f);
    return m;
}

struct Refusal {
    const char* name;
    PolygonMesh mesh;
    std::string field;   // the face the problem is located at
    std::string detail;  // what the detail says (a part of it)
};

std::vector<Refusal> refusals() {
    return {
        {"bowtie", bowtie(), "mesh.faces[0]", "vertex 0 joins several fans of faces"},
        {"fin", fin(), "mesh.faces[2]", "edge (0, 1) is shared by more than two faces (face 2 is one)"},
        {"inconsistent", inconsistent(), "mesh.faces[1]", "edge (1, 2) is traversed in the same direction by face 1"},
        {"pinched pyramids", pinched_pyramids(), "mesh.faces[0]", "vertex 0 joins several fans of faces"},
    };
}

TEST(ManifoldRules, RepairNoneRefusesTheSameMeshesWithTheSameProblem) {
    for (const auto& [name, mesh, field, detail] : refusals()) {
        SCOPED_TRACE(name);
        std::vector<nlohmann::json> problems;
        for (const Operation& op : manifold_operations()) {
            SCOPED_TRACE(op.path);
            const std::string body = json_request(mesh, std::string(op.json_options) + R"(,"repair":"none")");
            const auto problem = expect_problem(post(op.path, "application/json", body), 422, "non_manifold");
            EXPECT_EQ(problem.value("field", ""), field) << problem.dump();
            EXPECT_NE(problem.value("detail", "").find(detail), std::string::npos) << problem.dump();
            EXPECT_EQ(problem.value("hint", ""), R"("repair": "auto" repairs it)") << problem.dump();
            EXPECT_FALSE(problem.contains("line"));
            problems.push_back(problem);
        }
        EXPECT_EQ(problems[0], problems[1]);  // word for word
    }
}

TEST(ManifoldRules, RepairNoneNamesTheFacesLineInAnUploadedFile) {
    for (const auto& [name, mesh, field, detail] : refusals()) {
        SCOPED_TRACE(name);
        // write_obj: a header comment, then one line per vertex, then one per face
        const std::string obj = write_obj(mesh);
        std::size_t first_face_line = 1;
        for (std::size_t at = 0; obj.compare(at, 2, "f ") != 0; at = obj.find('\n', at) + 1) ++first_face_line;
        const std::size_t face = std::stoul(field.substr(field.find('[') + 1));
        const std::string line = std::to_string(first_face_line + face);
        for (const Operation& op : manifold_operations()) {
            SCOPED_TRACE(op.path);
            auto query = op.query;
            query.emplace("repair", "none");
            const auto problem = expect_problem(post(op.path, "model/obj", obj, query), 422, "non_manifold");
            EXPECT_EQ(problem.value("line", 0), std::stoi(line)) << problem.dump();
            EXPECT_EQ(problem.value("detail", "").rfind("line " + line + ": ", 0), 0u) << problem.dump();
            EXPECT_NE(problem.value("detail", "").find(detail), std::string::npos) << problem.dump();
            EXPECT_EQ(problem.value("hint", ""), "repair=auto repairs it") << problem.dump();
            EXPECT_FALSE(problem.contains("field"));
        }
        // a binary file has no lines: the detail's face index names the element
        const std::string ply = write_ply(mesh);
        auto query = manifold_operations()[0].query;
        query.emplace("repair", "none");
        const auto problem = expect_problem(post("/simplify", "application/ply", ply, query), 422, "non_manifold");
        EXPECT_FALSE(problem.contains("line")) << problem.dump();
        EXPECT_NE(problem.value("detail", "").find(detail), std::string::npos) << problem.dump();
    }
}

TEST(ManifoldRules, RepairAutoSplitsBowTieVerticesForBoth) {
    for (const PolygonMesh& mesh : {bowtie(), pinched_pyramids()}) {
        for (const Operation& op : manifold_operations()) {
            SCOPED_TRACE(op.path);
            const std::string body =
                json_request(mesh, std::string(op.json_options) + R"(,"output":{"format":"json"})");
            const auto response = post(op.path, "application/json", body);
            ASSERT_EQ(response.status, 200) << response.body;
            const auto json = nlohmann::json::parse(response.body);
            EXPECT_EQ(json["stats"]["repairs"]["nonmanifold_split"], 1) << json["stats"].dump();
            EXPECT_EQ(json["stats"]["repairs"]["components"], 2) << json["stats"].dump();
            EXPECT_NE(header(response, "X-Repairs").find("nonmanifold_split=1"), std::string::npos);
            // the output: two pieces that share no vertex, each manifold
            PolygonMesh out;
            for (const auto& p : json["mesh"]["positions"]) out.positions.push_back({p[0], p[1], p[2]});
            for (const auto& f : json["mesh"]["faces"]) out.add_face(f.get<std::vector<Index>>());
            ASSERT_TRUE(validate(out).ok());
            EXPECT_TRUE(check_manifold(out).ok()) << check_manifold(out).error().message;
        }
    }
}

TEST(ManifoldRules, AManifoldMeshPassesUntouched) {
    const PolygonMesh torus = shapes::torus(16, 8);
    ASSERT_TRUE(check_manifold(torus).ok());
    for (const Operation& op : manifold_operations()) {
        SCOPED_TRACE(op.path);
        for (const char* repair : {"none", "auto"}) {
            const std::string body = json_request(
                torus, std::string(op.json_options) + R"(,"repair":")" + repair + R"(","output":{"format":"json"})");
            const auto response = post(op.path, "application/json", body);
            ASSERT_EQ(response.status, 200) << response.body;
            if (std::string(repair) == "auto") {
                EXPECT_NE(header(response, "X-Repairs").find("nonmanifold_split=0"), std::string::npos);
                EXPECT_NE(header(response, "X-Repairs").find("flipped=0"), std::string::npos);
            }
        }
    }
}

// ---- /subdivide: scheme loop needs triangles -------------------------------------------------------------------

TEST(ManifoldRules, LoopOnAPolygonNamesTheFaceItsLineAndCatmullClark) {
    // a triangle, then a quad
    PolygonMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}, {2, 1, 0}};
    m.add_face({0, 1, 2});
    m.add_face({1, 4, 5, 2});
    const char* hint = "scheme catmull-clark takes any polygons";
    // JSON: the field of the face
    const auto json = expect_problem(post("/subdivide", "application/json", json_request(m, R"(,"scheme":"loop")")),
                                     422, "not_triangle_mesh");
    EXPECT_EQ(json.value("field", ""), "mesh.faces[1]");
    EXPECT_EQ(json.value("hint", ""), hint);
    // text files: its line
    const std::string obj =
        "# a triangle and a quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n\n"
        "f 1 2 3\n# the quad\nf 2 5 6 3\n";
    const std::string off = "OFF\n6 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 0 0\n2 1 0\n3 0 1 2\n4 1 4 5 2\n";
    const std::string ply = write_ply(m, PlyEncoding::Ascii);
    const std::size_t ply_quad_line = [&] {
        std::size_t line = 1;
        for (std::size_t at = 0; ply.compare(at, 2, "4 ") != 0; at = ply.find('\n', at) + 1) ++line;
        return line;
    }();
    struct Upload {
        const char* type;
        const std::string& body;
        std::int64_t line;
    };
    for (const Upload& upload : {Upload{"model/obj", obj, 11}, Upload{"model/off", off, 10},
                                 Upload{"application/ply", ply, static_cast<std::int64_t>(ply_quad_line)}}) {
        SCOPED_TRACE(upload.type);
        const auto problem = expect_problem(post("/subdivide", upload.type, upload.body, {{"scheme", "loop"}}), 422,
                                            "not_triangle_mesh");
        EXPECT_EQ(problem.value("line", std::int64_t{0}), upload.line) << problem.dump();
        EXPECT_EQ(
            problem.value("detail", "").rfind("line " + std::to_string(upload.line) + ": face 1 has 4 vertices", 0), 0u)
            << problem.dump();
        EXPECT_EQ(problem.value("hint", ""), hint);
    }
    // a binary file: the face's index
    const auto binary = expect_problem(post("/subdivide", "application/ply", write_ply(m), {{"scheme", "loop"}}), 422,
                                       "not_triangle_mesh");
    EXPECT_FALSE(binary.contains("line"));
    EXPECT_EQ(binary.value("detail", "").rfind("face 1 has 4 vertices", 0), 0u) << binary.dump();
    EXPECT_EQ(binary.value("hint", ""), hint);
    // and catmull-clark takes it
    EXPECT_EQ(post("/subdivide", "model/obj", obj, {{"scheme", "catmull-clark"}, {"format", "obj"}}).status, 200);
}

}  // namespace
}  // namespace surfaced::api
