// The scene's "mesh" node (a triangle mesh's signed distance, geometry/implicit/triangle_mesh_field.h) through
// POST /implicit/mesh and /implicit/query in process: CSG with primitives against analytic volumes with the output
// closed, manifold and consistently oriented and the cube's sharp edges kept; offset; a smooth union; a mesh with a
// hole; errors with the node's field paths; the triangle and vertex budgets over all mesh nodes, before any is built.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/routes.h"
#include "tests/support/api_request.h"
#include "tests/support/mesh_asserts.h"
#include "tests/support/simplify_meshes.h"

namespace surfaced::api {
namespace {

using Json = nlohmann::json;
using namespace fixtures;

ApiResponse post(const std::string& path, const std::string& body, const ApiContext& context = {}) {
    return dispatch(make_request("POST", path, "application/json", body), context);
}

void expect_problem(const ApiResponse& response, int status, const std::string& code, const std::string& field) {
    EXPECT_EQ(response.status, status) << response.body;
    EXPECT_EQ(response.content_type, "application/problem+json");
    ASSERT_TRUE(response.error.has_value()) << response.body;
    EXPECT_EQ(response.error->code, code) << response.body;
    EXPECT_EQ(response.error->field.value_or("<none>"), field) << response.body;
}

//! {"op": "mesh", "mesh": ...} of `mesh`, with `extra` members.
std::string mesh_node(const PolygonMesh& mesh, const std::string& extra = "") {
    return R"({"op": "mesh", "mesh": )" + mesh_json(mesh) + extra + "}";
}

//! POST /implicit/mesh of `scene` in the cube [-h, h]^3 at `resolution` in `mode`, JSON out; the mesh decoded.
PolygonMesh mesh_scene(const std::string& scene, double h, int resolution, const std::string& mode = "uniform") {
    const std::string bounds = "[[" + std::to_string(-h) + "," + std::to_string(-h) + "," + std::to_string(-h) + "],[" +
                               std::to_string(h) + "," + std::to_string(h) + "," + std::to_string(h) + "]]";
    const ApiResponse response =
        post("/implicit/mesh", R"({"scene": )" + scene + R"(, "bounds": )" + bounds + R"(, "resolution": )" +
                                   std::to_string(resolution) + R"(, "mode": ")" + mode +
                                   R"(", "output": {"format": "json"}})");
    EXPECT_EQ(response.status, 200) << response.body;
    PolygonMesh mesh;
    if (response.status != 200) return mesh;
    const Json doc = Json::parse(response.body);
    for (const auto& p : doc["mesh"]["positions"]) mesh.positions.push_back({p[0], p[1], p[2]});
    for (const auto& f : doc["mesh"]["faces"]) mesh.add_face({f[0].get<Index>(), f[1].get<Index>(), f[2].get<Index>()});
    return mesh;
}

//! Closed, every edge shared by two faces in opposite directions, every vertex one fan.
void expect_closed_manifold(const PolygonMesh& mesh) {
    ASSERT_GT(mesh.face_count(), 0u);
    ASSERT_TRUE(validate(mesh).ok());
    const testing::EdgeStats edges = testing::edge_stats(mesh);
    EXPECT_EQ(edges.boundary_edges, 0u);
    EXPECT_EQ(edges.non_manifold_edges, 0u);
    EXPECT_EQ(edges.inconsistent_edges, 0u);
    EXPECT_EQ(testing::non_manifold_vertices(mesh), 0u);
    EXPECT_GT(testing::signed_volume(mesh), 0);  // outward
}

const std::string kSphereOnTop = R"({"op": "translate", "offset": [0, 0, 1], "arg": {"op": "sphere", "radius": 0.5}})";

// (a) the cube mesh minus a ball centred on its top face: the analytic volume, the cube's edges sharp.
TEST(ImplicitMeshNode, CubeMeshMinusSphere) {
    const double h = 1.25;
    const int resolution = 64;
    const PolygonMesh mesh = mesh_scene(
        R"({"op": "difference", "args": [)" + mesh_node(testing::triangle_cube()) + ", " + kSphereOnTop + "]}", h,
        resolution);
    expect_closed_manifold(mesh);
    const double volume = 8.0 - 2.0 / 3.0 * std::numbers::pi * 0.125;
    EXPECT_NEAR(testing::signed_volume(mesh) / volume, 1.0, 0.005);
    // the closed mesh is an exact distance: the adaptive mode culls by it and gives the same mesh
    const PolygonMesh adaptive = mesh_scene(
        R"({"op": "difference", "args": [)" + mesh_node(testing::triangle_cube()) + ", " + kSphereOnTop + "]}", h,
        resolution, "adaptive");
    EXPECT_EQ(adaptive.face_count(), mesh.face_count());
    const auto sorted = [](std::vector<Vec3> points) {
        std::sort(points.begin(), points.end(), [](const Vec3& a, const Vec3& b) {
            return a.x != b.x ? a.x < b.x : (a.y != b.y ? a.y < b.y : a.z < b.z);
        });
        return points;
    };
    EXPECT_TRUE(sorted(adaptive.positions) == sorted(mesh.positions));  // the same vertices, in another order
    // vertices within half a cell of one of the cube's 12 edge lines lie on it (the edges are not rounded off)
    const double cell = 2 * h / resolution;
    double worst_edge = 0;
    std::size_t near_edge = 0;
    for (const Vec3& p : mesh.positions) {
        const Vec3 q{std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)};
        for (int a = 0; a < 3; ++a) {
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            const double distance = std::hypot(q[b] - 1, q[c] - 1);
            if (distance < 0.5 * cell) {
                ++near_edge;
                worst_edge = std::max(worst_edge, distance);
            }
        }
    }
    EXPECT_GT(near_edge, 12u * 40);  // about 2 / cell = 51 cells along each edge
    EXPECT_LT(worst_edge, 1e-3 * cell);
    // and the 8 corners
    for (int corner = 0; corner < 8; ++corner) {
        const Vec3 c{corner & 1 ? 1.0 : -1.0, corner & 2 ? 1.0 : -1.0, corner & 4 ? 1.0 : -1.0};
        double best = 1e9;
        for (const Vec3& p : mesh.positions) best = std::min(best, norm(p - c));
        EXPECT_LT(best, 1e-3 * cell) << "corner " << corner;
    }
}

// (b) offset by r: the cube with rounded edges and corners, a^3 + 6 a^2 r + 3 pi a r^2 + 4/3 pi r^3.
TEST(ImplicitMeshNode, OffsetCubeMesh) {
    const double a = 2, r = 0.2;
    const PolygonMesh mesh =
        mesh_scene(R"({"op": "offset", "distance": 0.2, "arg": )" + mesh_node(testing::triangle_cube()) + "}", 1.5, 64);
    expect_closed_manifold(mesh);
    const double volume =
        a * a * a + 6 * a * a * r + 3 * std::numbers::pi * a * r * r + 4.0 / 3 * std::numbers::pi * r * r * r;
    EXPECT_NEAR(testing::signed_volume(mesh) / volume, 1.0, 0.005);
}

// (c) a mesh sphere smoothly joined to a box primitive.
TEST(ImplicitMeshNode, SmoothUnionOfMeshSphereAndBox) {
    const PolygonMesh sphere = testing::icosphere(3);  // 1280 triangles on the unit sphere
    const PolygonMesh mesh = mesh_scene(
        R"({"op": "smooth_union", "k": 0.3, "args": [)" + mesh_node(sphere) +
            R"(, {"op": "translate", "offset": [1.2, 0, 0], "arg": {"op": "box", "half_size": [0.6, 0.4, 0.4]}}]})",
        2, 48);
    expect_closed_manifold(mesh);
    // more than the ball alone, less than the ball and the box together plus the blend's fillet margin
    const double volume = testing::signed_volume(mesh);
    EXPECT_GT(volume, testing::signed_volume(sphere) + 0.5 * 1.2 * 0.8 * 0.8);
    EXPECT_LT(volume, 4.0 / 3 * std::numbers::pi + 1.2 * 0.8 * 0.8 + 0.5);
}

// (d) the cube mesh without its top face: the winding number closes the hole (its w = 1/2 sheet is the missing face's
// square), so the output is closed and holds about the cube's volume.
TEST(ImplicitMeshNode, MeshWithAHoleGivesAClosedSolid) {
    PolygonMesh open = testing::triangle_cube();
    PolygonMesh without_top;
    without_top.positions = open.positions;
    for (std::size_t f = 0; f < open.face_count(); ++f) {
        const auto t = open.face(f);
        if (open.positions[t[0]].z > 0 && open.positions[t[1]].z > 0 && open.positions[t[2]].z > 0) continue;
        without_top.add_face(t);
    }
    ASSERT_EQ(without_top.face_count(), 10u);
    const double h = 1.25;
    const int resolution = 48;
    for (const char* mode : {"uniform", "adaptive"}) {
        SCOPED_TRACE(mode);
        const PolygonMesh mesh = mesh_scene(mesh_node(without_top), h, resolution, mode);
        expect_closed_manifold(mesh);
        // the cap lies on the jump of the field across z = 1 (within its row of cells; measured 7.9993 at 48), the
        // rest on the cube
        EXPECT_NEAR(testing::signed_volume(mesh), 8.0, 0.01 * 8.0);
        for (const Vec3& p : mesh.positions) ASSERT_LT(p.z, 1 + 2 * h / resolution);
    }
    // the field is not a distance bound across the cap: it says so
    const ApiResponse query =
        post("/implicit/query", R"({"scene": )" + mesh_node(without_top) + R"(, "points": [[0, 0, 0.5]]})");
    ASSERT_EQ(query.status, 200) << query.body;
    const Json out = Json::parse(query.body);
    EXPECT_EQ(out["kind"], "general");
    EXPECT_TRUE(out["lipschitz"].is_null());
    EXPECT_EQ(out["points"][0]["class"], "inside");
}

TEST(ImplicitMeshNode, QueryGivesTheSignedDistance) {
    const ApiResponse response =
        post("/implicit/query", R"({"scene": )" + mesh_node(testing::triangle_cube()) +
                                    R"(, "points": [[0, 0, 0], [0, 0, 3], [2, 2, 2], [1, 0.5, 0.25]],
                                   "rays": [{"origin": [0, 0, 5], "direction": [0, 0, -1]}]})");
    ASSERT_EQ(response.status, 200) << response.body;
    const Json out = Json::parse(response.body);
    EXPECT_EQ(out["kind"], "exact_distance");
    const auto& points = out["points"];
    ASSERT_EQ(points.size(), 4u);
    EXPECT_NEAR(points[0]["value"].get<double>(), -1.0, 1e-12);
    EXPECT_EQ(points[0]["class"], "inside");
    EXPECT_NEAR(points[1]["value"].get<double>(), 2.0, 1e-12);
    EXPECT_NEAR(points[2]["value"].get<double>(), std::sqrt(3.0), 1e-12);
    EXPECT_EQ(points[3]["class"], "on");
    EXPECT_EQ(points[3]["gradient"], Json::array({1.0, 0.0, 0.0}));
    ASSERT_TRUE(out["rays"][0]["hit"].get<bool>());
    EXPECT_NEAR(out["rays"][0]["t"].get<double>(), 4.0, 1e-6);
}

TEST(ImplicitMeshNode, WindingAccuracyIsAccepted) {
    const ApiResponse response = post(
        "/implicit/query", R"({"scene": )" + mesh_node(testing::triangle_cube(), R"(, "winding": {"accuracy": 3})") +
                               R"(, "points": [[0, 0, 0]]})");
    ASSERT_EQ(response.status, 200) << response.body;
    EXPECT_NEAR(Json::parse(response.body)["points"][0]["value"].get<double>(), -1.0, 1e-12);
}

TEST(ImplicitMeshNode, ErrorsNameTheNodesFieldPath) {
    const auto query = [](const std::string& scene) {
        return post("/implicit/query", R"({"scene": )" + scene + R"(, "points": [[0, 0, 0]]})");
    };
    const std::string tri = R"("positions": [[0, 0, 0], [1, 0, 0], [0, 1, 0]])";
    const auto in_union = [](const std::string& node) {
        return R"({"op": "union", "args": [{"op": "sphere", "radius": 1}, )" + node + "]}";
    };
    expect_problem(query(in_union(R"({"op": "mesh"})")), 400, "invalid_field", "scene.args[1].mesh");
    expect_problem(query(in_union(R"({"op": "mesh", "mesh": [1, 2]})")), 400, "invalid_field", "scene.args[1].mesh");
    expect_problem(query(in_union(R"({"op": "mesh", "mesh": {)" + tri + R"(, "faces": [[0, 1, 2]]}, "radius": 1})")),
                   400, "unknown_field", "scene.args[1].radius");
    expect_problem(query(in_union(R"({"op": "mesh", "mesh": {)" + tri + R"(, "face": [[0, 1, 2]]}})")), 400,
                   "unknown_field", "scene.args[1].mesh.face");
    expect_problem(
        query(in_union(R"({"op": "mesh", "mesh": {)" + tri + R"(, "faces": [[0, 1, 2], [0, 1, 2], [3, 1, 2]]}})")), 422,
        "index_out_of_range", "scene.args[1].mesh.faces[2][0]");
    expect_problem(
        query(in_union(
            R"({"op": "mesh", "mesh": {"positions": [[0, 0, 0], [1, 0, "x"], [0, 1, 0]], "faces": [[0, 1, 2]]}})")),
        400, "invalid_field", "scene.args[1].mesh.positions[1][2]");
    expect_problem(query(in_union(R"({"op": "mesh", "mesh": {)" + tri + R"(, "faces": [[0, 1]]}})")), 422,
                   "degenerate_face", "scene.args[1].mesh.faces[0]");
    expect_problem(query(in_union(R"({"op": "mesh", "mesh": {)" + tri + R"(, "faces": [[0, 1, 2], [0, 1, 1]]}})")), 422,
                   "degenerate_face", "scene.args[1].mesh.faces[1]");
    expect_problem(query(in_union(R"({"op": "mesh", "mesh": {)" + tri + R"(, "faces": []}})")), 422, "invalid_argument",
                   "scene.args[1].mesh.faces");
    const std::string ok_mesh = R"({"op": "mesh", "mesh": {)" + tri + R"(, "faces": [[0, 1, 2]]})";
    expect_problem(query(ok_mesh + R"(, "winding": 2})"), 400, "invalid_field", "scene.winding");
    expect_problem(query(ok_mesh + R"(, "winding": {"exact": true}})"), 400, "unknown_field", "scene.winding.exact");
    expect_problem(query(ok_mesh + R"(, "winding": {"accuracy": 1}})"), 422, "invalid_argument",
                   "scene.winding.accuracy");
    expect_problem(query(ok_mesh + R"(, "winding": {"accuracy": 11}})"), 422, "invalid_argument",
                   "scene.winding.accuracy");
    expect_problem(query(ok_mesh + R"(, "winding": {"accuracy": "high"}})"), 400, "invalid_field",
                   "scene.winding.accuracy");
    // the op's name is listed among the known ones
    const ApiResponse unknown = query(R"({"op": "meshes"})");
    EXPECT_EQ(unknown.status, 400);
    EXPECT_NE(unknown.body.find("mesh)"), std::string::npos) << unknown.body;
}

// Indexing a mesh node's triangles watches the request's deadline: a passed one is 503 naming the node, before any
// field is evaluated (icosphere(6): 81,920 triangles, enough hierarchy nodes for the build to look at it).
TEST(ImplicitMeshNode, APassedDeadlineStopsTheMeshNodesBuild) {
    Cancel cancel;
    cancel.deadline = Cancel::Clock::now() - std::chrono::seconds(1);
    const std::string scene = mesh_node(testing::icosphere(6));
    expect_problem(
        post("/implicit/query", R"({"scene": )" + scene + R"(, "points": [[0, 0, 0]]})", context_with({}, cancel)), 503,
        "cancelled", "scene.mesh");
    // the same scene without a deadline is answered
    EXPECT_EQ(post("/implicit/query", R"({"scene": )" + scene + R"(, "points": [[0, 0, 0]]})").status, 200);
}

TEST(ImplicitMeshNode, BudgetsCountEveryMeshNodeOnceBeforeAnyIsBuilt) {
    const std::string cube = mesh_node(testing::triangle_cube());  // 12 triangles, 8 vertices
    const std::string quads = mesh_node(shapes::cube());           // 6 quads: 12 triangles, 8 vertices
    const auto query = [](const std::string& scene, const ApiContext& context) {
        return post("/implicit/query", R"({"scene": )" + scene + R"(, "points": [[0, 0, 0]]})", context);
    };
    ApiContext faces;
    faces.limits.max_input_faces = 23;
    expect_problem(query(R"({"op": "union", "args": [)" + cube + ", " + quads + "]}", faces), 422, "budget_exceeded",
                   "scene.args[1]");
    faces.limits.max_input_faces = 11;
    expect_problem(query(quads, faces), 422, "budget_exceeded", "scene");
    faces.limits.max_input_faces = 24;
    EXPECT_EQ(query(R"({"op": "union", "args": [)" + cube + ", " + quads + "]}", faces).status, 200);
    // a node reused by ref is built once and counted once
    faces.limits.max_input_faces = 12;
    const std::string reused = R"({"op": "union", "args": [{"id": "part", )" + cube.substr(1) +
                               R"(, {"op": "translate", "offset": [3, 0, 0], "arg": {"ref": "part"}}]})";
    EXPECT_EQ(query(reused, faces).status, 200) << query(reused, faces).body;
    ApiContext vertices;
    vertices.limits.max_input_vertices = 15;
    expect_problem(query(R"({"op": "union", "args": [)" + cube + ", " + cube + "]}", vertices), 422, "budget_exceeded",
                   "scene.args[1]");
    // over budget before anything is decoded: the first node's bad index is not reached
    const std::string bad = R"({"op": "mesh", "mesh": {"positions": [[0, 0, 0]], "faces": [[0, 1, 2]]}})";
    faces.limits.max_input_faces = 12;
    expect_problem(query(R"({"op": "union", "args": [)" + bad + ", " + cube + "]}", faces), 422, "budget_exceeded",
                   "scene.args[1]");
}

}  // namespace
}  // namespace surfaced::api
