// POST /repair called directly (no sockets), and the `repair` option of /simplify and /remesh: what is repaired, the
// report (X-Repairs and the JSON stats), the output's invariants, repair "none" keeping the old refusals, and errors.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/routes.h"
#include "geometry/io/mesh_io.h"
#include "geometry/mesh/shapes.h"
#include "tests/support/api_request.h"
#include "tests/support/mesh_asserts.h"

namespace surfaced::api {
namespace {

using namespace fixtures;

ApiResponse call(const std::string& path, const std::string& content_type, const std::string& body,
                 std::multimap<std::string, std::string> query = {}) {
    return dispatch(make_request("POST", path, content_type, body, std::move(query)), context_with());
}

//! Two triangles meeting only at vertex 0 (a bow-tie), a copy of the first, and a fourth triangle glued to the first
//! along edge (1, 2) but traversing it the same way (inconsistent orientation).
PolygonMesh broken_mesh() {
    PolygonMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}, {1, 1, 0}};
    m.add_face({0, 1, 2});
    m.add_face({0, 3, 4});
    m.add_face({0, 1, 2});
    m.add_face({2, 5, 1});
    return m;
}

//! Three triangles on edge (0, 1): a fin.
PolygonMesh fin() {
    PolygonMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
    m.add_face({0, 1, 2});
    m.add_face({1, 0, 3});
    m.add_face({0, 1, 4});
    return m;
}

//! The output guarantees of repair, on a decoded JSON mesh.
void expect_clean(const nlohmann::json& mesh) {
    PolygonMesh m;
    for (const auto& p : mesh["positions"]) m.positions.push_back({p[0], p[1], p[2]});
    for (const auto& f : mesh["faces"]) m.add_face(f.get<std::vector<Index>>());
    const auto edges = testing::edge_stats(m);
    EXPECT_EQ(edges.non_manifold_edges, 0u);
    EXPECT_EQ(edges.inconsistent_edges, 0u);
}

TEST(RepairOperation, JsonReportsEveryRepairAndReturnsAManifoldMesh) {
    const auto r = call("/repair", "application/json", json_request(broken_mesh(), R"(,"output":{"format":"json"})"));
    ASSERT_EQ(r.status, 200) << r.body;
    const auto json = nlohmann::json::parse(r.body);
    const auto& repairs = json["stats"]["repairs"];
    EXPECT_EQ(repairs["duplicate"], 1) << repairs.dump();
    EXPECT_EQ(repairs["flipped"], 1) << repairs.dump();
    EXPECT_EQ(repairs["nonmanifold_split"], 1) << repairs.dump();
    EXPECT_EQ(repairs["degenerate"], 0) << repairs.dump();
    EXPECT_EQ(json["stats"]["input_faces"], 4);
    EXPECT_EQ(json["stats"]["output_faces"], 3);
    EXPECT_EQ(json["mesh"]["faces"].size(), 3u);
    expect_clean(json["mesh"]);
    const std::string header_value = header(r, "X-Repairs");
    EXPECT_NE(header_value.find("duplicate=1"), std::string::npos) << header_value;
    EXPECT_NE(header_value.find("flipped=1"), std::string::npos) << header_value;
    EXPECT_NE(header_value.find("nonmanifold_split=1"), std::string::npos) << header_value;
    EXPECT_EQ(header(r, "X-Input-Faces"), "4");
    EXPECT_EQ(header(r, "X-Output-Faces"), "3");
}

TEST(RepairOperation, UploadedObjWithQueryOptionsAndRepeatedVertices) {
    // an OBJ whose second face repeats a vertex (read, then dropped as degenerate) and a third, tiny component
    const std::string obj =
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 5 5 5\nv 6 5 5\nv 5 6 5\n"
        "f 1 2 3\nf 2 4 4\nf 2 4 3\nf 5 6 7\n";
    const auto r = call("/repair", "model/obj", obj, {{"min_component_faces", "2"}, {"format", "obj"}});
    ASSERT_EQ(r.status, 200) << r.body;
    const std::string repairs = header(r, "X-Repairs");
    EXPECT_NE(repairs.find("degenerate=1"), std::string::npos) << repairs;
    EXPECT_NE(repairs.find("small_components=1"), std::string::npos) << repairs;
    EXPECT_NE(repairs.find("removed_faces=1"), std::string::npos) << repairs;
    auto out = read_obj(r.body);
    ASSERT_TRUE(out.ok()) << out.error().message;
    EXPECT_EQ(out->face_count(), 2u);
    EXPECT_EQ(out->vertex_count(), 4u);  // the dropped component's vertices go too
}

TEST(RepairOperation, CleanMeshComesBackUnchanged) {
    const PolygonMesh cube = shapes::cube();
    const auto r = call("/repair", "application/json", json_request(cube, R"(,"output":{"format":"json"})"));
    ASSERT_EQ(r.status, 200) << r.body;
    const auto json = nlohmann::json::parse(r.body);
    for (const auto& [name, count] : json["stats"]["repairs"].items()) {
        if (name == "components") continue;
        EXPECT_EQ(count, 0) << name;
    }
    EXPECT_EQ(json["stats"]["repairs"]["components"], 1);
    EXPECT_EQ(json["mesh"]["faces"].size(), cube.face_count());
    EXPECT_EQ(json["mesh"]["positions"].size(), cube.vertex_count());
}

TEST(RepairOperation, OptionErrorsName400Fields) {
    const std::string body = json_request(broken_mesh());
    expect_problem(call("/repair", "application/json", json_request(broken_mesh(), R"(,"weld_tolerance":-1)")), 400,
                   "invalid_field", "weld_tolerance");
    expect_problem(call("/repair", "application/json", json_request(broken_mesh(), R"(,"max_hole_edges":20000)")), 400,
                   "invalid_field", "max_hole_edges");
    expect_problem(call("/repair", "application/json", json_request(broken_mesh(), R"(,"orient":"yes")")), 400,
                   "invalid_field", "orient");
    expect_problem(call("/repair", "application/json", json_request(broken_mesh(), R"(,"welding":1)")), 400,
                   "unknown_field");
    expect_problem(
        call("/repair", "model/obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", {{"min_component_faces", "-2"}}), 400,
        "invalid_field", "min_component_faces");
    expect_problem(call("/repair", "model/obj", "v 0 0 0\nf 1 2 3\n"), 422, "index_out_of_range");
}

TEST(RepairOperation, GltfJsonUploadCountsSkippedPointPrimitives) {
    // one triangle and the same three vertices as a POINTS primitive, the buffer embedded as a data URI
    const std::string gltf =
        R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,)"
        R"(AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}],"bufferViews":[{"buffer":0,"byteLength":36}],)"
        R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}],)"
        R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"mode":4},{"attributes":{"POSITION":0},"mode":0}]}],)"
        R"("nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}],"scene":0})";
    for (const std::string type : {"model/gltf+json", "application/octet-stream"}) {
        const auto r = call("/repair", type, gltf, {{"format", "obj"}});
        ASSERT_EQ(r.status, 200) << type << ": " << r.body;
        EXPECT_EQ(header(r, "X-Skipped-Primitives"), "1") << type;
        EXPECT_EQ(header(r, "X-Output-Faces"), "1") << type;
    }
    // an external buffer is refused, naming it
    const auto external = call("/repair", "model/gltf+json",
                               R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":36,"uri":"mesh.bin"}]})");
    EXPECT_EQ(external.status / 100, 4) << external.body;
    EXPECT_NE(external.body.find("mesh.bin"), std::string::npos) << external.body;
}

// ---- the repair option of the operations that need a manifold mesh -------------------------------------------------

TEST(RepairOption, SimplifyRepairsANonManifoldMeshByDefaultAndSaysSo) {
    const auto r =
        call("/simplify", "application/json", json_request(fin(), R"(,"ratio":1,"output":{"format":"json"})"));
    ASSERT_EQ(r.status, 200) << r.body;
    const std::string repairs = header(r, "X-Repairs");
    EXPECT_EQ(repairs.find("nonmanifold_split=0"), std::string::npos) << repairs;
    const auto json = nlohmann::json::parse(r.body);
    EXPECT_GT(json["stats"]["repairs"]["nonmanifold_split"].get<int>(), 0) << json["stats"].dump();
    expect_clean(json["mesh"]);
    // a mesh that needs nothing: the header says so, and the output is the one without repair
    const PolygonMesh cube = shapes::cube();
    const auto plain =
        call("/simplify", "application/json", json_request(cube, R"(,"ratio":1,"output":{"format":"json"})"));
    const auto none = call("/simplify", "application/json",
                           json_request(cube, R"(,"ratio":1,"repair":"none","output":{"format":"json"})"));
    ASSERT_EQ(plain.status, 200);
    ASSERT_EQ(none.status, 200);
    EXPECT_EQ(nlohmann::json::parse(plain.body)["mesh"], nlohmann::json::parse(none.body)["mesh"]);
    EXPECT_NE(header(plain, "X-Repairs").find("welded=0; degenerate=0; duplicate=0; flipped=0"), std::string::npos);
    EXPECT_EQ(header(none, "X-Repairs"), "");
}

TEST(RepairOption, SimplifyUploadWithRepeatedVertexFaceIsRepairedOrRefused) {
    const std::string obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 3\nf 1 3 4\n";
    const auto repaired = call("/simplify", "model/obj", obj, {{"ratio", "1"}, {"format", "obj"}});
    ASSERT_EQ(repaired.status, 200) << repaired.body;
    EXPECT_NE(header(repaired, "X-Repairs").find("degenerate=1"), std::string::npos) << header(repaired, "X-Repairs");
    const auto refused = call("/simplify", "model/obj", obj, {{"ratio", "1"}, {"repair", "none"}});
    const auto problem = expect_problem(refused, 422, "degenerate_face");
    EXPECT_EQ(problem.value("line", -1), 5) << problem.dump();
    expect_problem(call("/simplify", "model/obj", obj, {{"ratio", "1"}, {"repair", "maybe"}}), 400, "invalid_field",
                   "repair");
}

TEST(RepairOption, LockedVerticesFollowTheirPositionsThroughRepair) {
    // a duplicate face makes the mesh need repair; vertex 2 is locked and must keep its position in the output
    PolygonMesh m = shapes::cube();
    const std::size_t last = m.face_count() - 1;
    const std::vector<Index> copy(m.face(last).begin(), m.face(last).end());
    m.add_face(copy);
    const Vec3 locked = m.positions[2];
    const auto r = call("/simplify", "application/json",
                        json_request(m, R"(,"target_faces":2,"locked_vertices":[2],"output":{"format":"json"})"));
    ASSERT_EQ(r.status, 200) << r.body;
    EXPECT_NE(header(r, "X-Repairs").find("duplicate=1"), std::string::npos) << header(r, "X-Repairs");
    bool kept = false;
    const auto json = nlohmann::json::parse(r.body);
    for (const auto& p : json["mesh"]["positions"])
        kept = kept || (p[0] == locked.x && p[1] == locked.y && p[2] == locked.z);
    EXPECT_TRUE(kept) << "the locked vertex moved or vanished: " << r.body;
}

TEST(RepairOption, RemeshRepairsByDefault) {
    const auto r =
        call("/remesh", "application/json", json_request(fin(), R"(,"iterations":1,"output":{"format":"json"})"));
    ASSERT_EQ(r.status, 200) << r.body;
    const auto json = nlohmann::json::parse(r.body);
    EXPECT_GT(json["stats"]["repairs"]["nonmanifold_split"].get<int>(), 0) << json["stats"].dump();
    EXPECT_FALSE(header(r, "X-Repairs").empty());
    expect_clean(json["mesh"]);
}

}  // namespace
}  // namespace surfaced::api
