// POST /mesh/query through dispatch (no sockets): inside tests and signed distances on the unit cube against the
// analytic answer, closest points and faces against a brute-force loop over every triangle, rays against analytic
// hits, the winding number of an open box, and every 4xx with the field it names.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/routes.h"
#include "geometry/mesh/shapes.h"
#include "geometry/spatial/closest_point.h"
#include "tests/support/api_request.h"

namespace surfaced::api {
namespace {

using Json = nlohmann::json;

using namespace fixtures;

ApiResponse post(const std::string& body, const ApiContext& context = {}) {
    return dispatch(make_request("POST", "/mesh/query", "application/json", body), context);
}

//! Signed distance to the box [-0.5, 0.5]^3 (negative inside).
double cube_distance(const Vec3& p) {
    const Vec3 q{std::abs(p.x) - 0.5, std::abs(p.y) - 0.5, std::abs(p.z) - 0.5};
    const Vec3 outside{std::max(q.x, 0.0), std::max(q.y, 0.0), std::max(q.z, 0.0)};
    return norm(outside) + std::min(std::max({q.x, q.y, q.z}), 0.0);
}

//! Distance from p to face f of `mesh` (a fan of triangles), by trying every triangle.
double face_distance(const PolygonMesh& mesh, std::size_t f, const Vec3& p) {
    const auto face = mesh.face(f);
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t k = 1; k + 1 < face.size(); ++k) {
        const auto c =
            triangle_closest_point(p, mesh.positions[face[0]], mesh.positions[face[k]], mesh.positions[face[k + 1]]);
        best = std::min(best, norm(c.point - p));
    }
    return best;
}

double brute_distance(const PolygonMesh& mesh, const Vec3& p) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t f = 0; f < mesh.face_count(); ++f) best = std::min(best, face_distance(mesh, f, p));
    return best;
}

Vec3 point_of(const Json& v) { return {v[0].get<double>(), v[1].get<double>(), v[2].get<double>()}; }

//! Points on a lattice through, around and far from the cube (some on its faces, edges and corners).
std::vector<Vec3> lattice() {
    std::vector<Vec3> out;
    for (double x = -1.25; x <= 1.25; x += 0.25)
        for (double y = -1.0; y <= 1.0; y += 0.5)
            for (double z = -0.8; z <= 0.8; z += 0.4) out.push_back({x, y, z});
    out.push_back({0.1, -0.2, 0.3});
    out.push_back({3, -4, 12});
    return out;
}

std::string points_json(const std::vector<Vec3>& points) {
    Json list = Json::array();
    for (const Vec3& p : points) list.push_back({p.x, p.y, p.z});
    return list.dump();
}

TEST(MeshQueryOperation, CubeInsideDistanceAndClosestMatchAnalyticAndBruteForce) {
    const PolygonMesh cube = shapes::cube();
    const std::vector<Vec3> points = lattice();
    for (const bool exact : {false, true}) {
        SCOPED_TRACE(exact ? "exact winding" : "hierarchical winding");
        const ApiResponse response =
            post(json_request(cube, R"(, "points": )" + points_json(points) + R"(, "winding": {"exact": )" +
                                        (exact ? "true" : "false") + "}"));
        ASSERT_EQ(response.status, 200) << response.body;
        EXPECT_EQ(response.content_type, "application/json");
        const Json out = Json::parse(response.body);
        EXPECT_FALSE(out.contains("rays"));
        const Json& answers = out["points"];
        for (const char* member : {"inside", "winding_number", "distance", "closest", "face"})
            ASSERT_EQ(answers[member].size(), points.size()) << member;
        for (std::size_t i = 0; i < points.size(); ++i) {
            const Vec3& p = points[i];
            SCOPED_TRACE(i);
            const double expected = cube_distance(p);
            EXPECT_NEAR(answers["distance"][i].get<double>(), expected, 1e-12);
            const double w = answers["winding_number"][i].get<double>();
            if (expected < -1e-9) {
                EXPECT_TRUE(answers["inside"][i].get<bool>());
                EXPECT_NEAR(w, 1.0, 1e-2);
            } else if (expected > 1e-9) {
                EXPECT_FALSE(answers["inside"][i].get<bool>());
                EXPECT_NEAR(w, 0.0, 1e-2);
            }
            // The closest point is as near as the nearest of all triangles, lies on the face named, and its
            // distance is the unsigned one.
            const Vec3 c = point_of(answers["closest"][i]);
            EXPECT_NEAR(norm(c - p), brute_distance(cube, p), 1e-12);
            EXPECT_NEAR(norm(c - p), std::abs(expected), 1e-12);
            const auto f = answers["face"][i].get<std::size_t>();
            ASSERT_LT(f, cube.face_count());
            EXPECT_NEAR(face_distance(cube, f, c), 0.0, 1e-12);
        }
    }
}

TEST(MeshQueryOperation, WantSelectsMembersAndRaysHitWhereTheCubeIs) {
    const ApiResponse response = post(json_request(shapes::cube(), R"(, "points": [[0, 0, 0], [2, 0, 0]],
        "want": ["closest", "inside"],
        "rays": [[-5, 0.1, 0.2, 2, 0, 0], [0, 0, 0, 0, 0, 1], [0, 5, 0, 0, 1, 0], [0.25, 3, -0.25, 0, -1, 0]])"));
    ASSERT_EQ(response.status, 200) << response.body;
    const Json out = Json::parse(response.body);
    const Json& points = out["points"];
    EXPECT_EQ(points.size(), 3u);  // inside, closest, face
    EXPECT_FALSE(points.contains("distance"));
    EXPECT_FALSE(points.contains("winding_number"));
    EXPECT_EQ(points["inside"], Json::array({true, false}));
    EXPECT_EQ(points["closest"][1], Json::array({0.5, 0, 0}));
    EXPECT_EQ(points["face"][1], 4);  // +x

    const Json& rays = out["rays"];
    EXPECT_EQ(rays["hit"], Json::array({true, true, false, true}));
    // t is in units of the direction's length: 4.5 / 2.
    EXPECT_DOUBLE_EQ(rays["t"][0].get<double>(), 2.25);
    EXPECT_EQ(rays["face"][0], 5);  // -x
    EXPECT_NEAR(norm(point_of(rays["point"][0]) - Vec3{-0.5, 0.1, 0.2}), 0.0, 1e-12);
    EXPECT_NEAR(norm(point_of(rays["normal"][0]) - Vec3{-1, 0, 0}), 0.0, 1e-12);
    // From inside: the first hit is the face in front, its normal still outward.
    EXPECT_DOUBLE_EQ(rays["t"][1].get<double>(), 0.5);
    EXPECT_EQ(rays["face"][1], 1);  // +z
    EXPECT_NEAR(norm(point_of(rays["normal"][1]) - Vec3{0, 0, 1}), 0.0, 1e-12);
    // A miss: hit false and null for the rest.
    for (const char* member : {"t", "face", "point", "normal"}) EXPECT_TRUE(rays[member][2].is_null()) << member;
    EXPECT_DOUBLE_EQ(rays["t"][3].get<double>(), 2.5);
    EXPECT_EQ(rays["face"][3], 3);  // +y
}

TEST(MeshQueryOperation, TorusAgreesWithBruteForceAndTheAnalyticInside) {
    // A deeper hierarchy (1152 triangles): the closest point against every triangle, and inside against the smooth
    // torus (sqrt(x^2 + y^2) - R)^2 + z^2 < r^2 away from its surface, where the polygonal one may differ.
    const double R = 1.0, r = 0.35;
    const PolygonMesh torus = shapes::torus(24, 12, R, r);
    std::vector<Vec3> points;
    for (double x = -1.6; x <= 1.6; x += 0.2)
        for (double y = -1.5; y <= 1.5; y += 0.3)
            for (double z = -0.5; z <= 0.5; z += 0.25) points.push_back({x, y, z});
    const ApiResponse response = post(json_request(torus, R"(, "points": )" + points_json(points)));
    ASSERT_EQ(response.status, 200) << response.body;
    const Json answers = Json::parse(response.body)["points"];
    int checked_inside = 0, checked_outside = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const Vec3& p = points[i];
        SCOPED_TRACE(i);
        const double brute = brute_distance(torus, p);
        const Vec3 c = point_of(answers["closest"][i]);
        EXPECT_NEAR(norm(c - p), brute, 1e-12);
        EXPECT_NEAR(std::abs(answers["distance"][i].get<double>()), brute, 1e-12);
        EXPECT_NEAR(face_distance(torus, answers["face"][i].get<std::size_t>(), c), 0.0, 1e-12);
        const double smooth = std::hypot(std::hypot(p.x, p.y) - R, p.z) - r;
        if (std::abs(smooth) < 0.05) continue;
        const bool inside = smooth < 0;
        EXPECT_EQ(answers["inside"][i].get<bool>(), inside);
        EXPECT_EQ(answers["distance"][i].get<double>() < 0, inside);
        (inside ? checked_inside : checked_outside)++;
    }
    EXPECT_GT(checked_inside, 20);
    EXPECT_GT(checked_outside, 200);
}

TEST(MeshQueryOperation, OpenBoxWindingNumberIsTheSolidAngleOfItsFaces) {
    // Without its +z face, the box still covers 5/6 of the view from its centre: inside (w >= 1/2), where ray
    // parity would depend on the direction.
    PolygonMesh open;
    const PolygonMesh cube = shapes::cube();
    open.positions = cube.positions;
    for (std::size_t f = 0; f < cube.face_count(); ++f)
        if (f != 1) {
            const auto face = cube.face(f);
            open.add_face(std::vector<Index>(face.begin(), face.end()));
        }
    const ApiResponse response = post(json_request(open, R"(, "points": [[0, 0, 0], [0, 0, 3]],
        "want": ["winding_number", "inside", "distance"], "winding": {"exact": true})"));
    ASSERT_EQ(response.status, 200) << response.body;
    const Json points = Json::parse(response.body)["points"];
    EXPECT_NEAR(points["winding_number"][0].get<double>(), 5.0 / 6.0, 1e-12);
    EXPECT_EQ(points["inside"], Json::array({true, false}));
    EXPECT_NEAR(points["distance"][0].get<double>(), -0.5, 1e-12);
    EXPECT_NEAR(points["distance"][1].get<double>(), std::sqrt(2.5 * 2.5 + 0.5 * 0.5), 1e-12);  // to the rim
}

TEST(MeshQueryOperation, PolygonsAreTriangulatedAndFacesNameTheInputPolygon) {
    // mixed_polygons has triangles, quads and a pentagon: every closest face is a face of the input.
    const PolygonMesh house = shapes::mixed_polygons();
    const std::vector<Vec3> points = lattice();
    const ApiResponse response =
        post(json_request(house, R"(, "points": )" + points_json(points) + R"(, "want": ["closest"])"));
    ASSERT_EQ(response.status, 200) << response.body;
    const Json answers = Json::parse(response.body)["points"];
    for (std::size_t i = 0; i < points.size(); ++i) {
        const Vec3 c = point_of(answers["closest"][i]);
        EXPECT_NEAR(norm(c - points[i]), brute_distance(house, points[i]), 1e-12) << i;
        const auto f = answers["face"][i].get<std::size_t>();
        ASSERT_LT(f, house.face_count());
        EXPECT_NEAR(face_distance(house, f, c), 0.0, 1e-9) << i;
    }
}

TEST(MeshQueryOperation, BadRequestsNameTheirField) {
    const PolygonMesh cube = shapes::cube();
    const auto with = [&](const std::string& extra) { return post(json_request(cube, extra)); };
    expect_problem(with(R"(, "points": [[0, 0, 0], [1, 2, 3], [0, 0, 0], [1, "2", 3]])"), 400, "invalid_field",
                   "points[3][1]");
    expect_problem(with(R"(, "points": [[0, 0]])"), 400, "invalid_field", "points[0]");
    expect_problem(with(R"(, "points": {"x": 1})"), 400, "invalid_field", "points");
    expect_problem(with(R"(, "rays": [[0, 0, 0, 0, 0, 0]])"), 422, "invalid_argument", "rays[0]");
    expect_problem(with(R"(, "rays": [[0, 0, 0, 1, 0]])"), 400, "invalid_field", "rays[0]");
    expect_problem(with(R"(, "rays": [[0, 0, 0, 1, 0, null]])"), 400, "invalid_field", "rays[0][5]");
    expect_problem(with(R"()"), 400, "invalid_field", "points");
    expect_problem(with(R"(, "points": [])"), 400, "invalid_field", "points");
    const Json typo =
        expect_problem(with(R"(, "points": [[0, 0, 0]], "want": ["inside", "distnce"])"), 400, "invalid_field");
    EXPECT_EQ(typo["field"], "want[1]");
    EXPECT_NE(typo["detail"].get<std::string>().find("did you mean \"distance\""), std::string::npos) << typo["detail"];
    expect_problem(with(R"(, "points": [[0, 0, 0]], "want": ["inside", "inside"])"), 400, "invalid_field", "want[1]");
    expect_problem(with(R"(, "points": [[0, 0, 0]], "want": [])"), 400, "invalid_field", "want");
    expect_problem(with(R"(, "points": [[0, 0, 0]], "winding": {"accuracy": 1})"), 400, "invalid_field",
                   "winding.accuracy");
    expect_problem(with(R"(, "points": [[0, 0, 0]], "winding": {"exact": 1})"), 400, "invalid_field", "winding.exact");
    expect_problem(with(R"(, "points": [[0, 0, 0]], "winding": {"exakt": true})"), 400, "unknown_field", "");
    expect_problem(with(R"(, "points": [[0, 0, 0]], "winding": 3)"), 400, "invalid_field", "winding");
    expect_problem(with(R"(, "points": [[0, 0, 0]], "point": [[0, 0, 0]])"), 400, "unknown_field", "");
    expect_problem(post(R"({"points": [[0, 0, 0]]})"), 400, "invalid_field", "mesh");
    expect_problem(post(R"({"mesh": {"positions": [[0, 0, 0]], "faces": []}, "points": [[0, 0, 0]]})"), 422,
                   "invalid_argument", "mesh.faces");
    expect_problem(
        post(
            R"({"mesh": {"positions": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "faces": [[0, 1, 7]]}, "points": [[0, 0, 0]]})"),
        422, "index_out_of_range", "mesh.faces[0][2]");
    expect_problem(dispatch(make_request("POST", "/mesh/query", "model/obj", "v 0 0 0\n"), {}), 415,
                   "unsupported_media_type", "");
}

TEST(MeshQueryOperation, BudgetsAreCheckedBeforeTheMeshIsRead) {
    Limits small;
    small.max_mesh_queries = 2;
    // The mesh is broken too: the budget is named first.
    expect_problem(post(R"({"mesh": {"positions": [], "faces": [[0, 1, 2]]}, "points": [[0, 0, 0], [1, 1, 1]],
                            "rays": [[0, 0, 0, 1, 0, 0]]})",
                        context_with(small)),
                   422, "budget_exceeded", "points");
    Limits exact_work;
    exact_work.max_exact_winding_work = 12 * 2 - 1;  // two points on the cube's 12 triangles
    const std::string body =
        json_request(shapes::cube(), R"(, "points": [[0, 0, 0], [1, 1, 1]], "winding": {"exact": true})");
    expect_problem(post(body, context_with(exact_work)), 422, "budget_exceeded", "winding.exact");
    exact_work.max_exact_winding_work = 12 * 2;
    EXPECT_EQ(post(body, context_with(exact_work)).status, 200);
    // Only closest points: no winding numbers, no exact work.
    exact_work.max_exact_winding_work = 0;
    EXPECT_EQ(post(json_request(shapes::cube(),
                                R"(, "points": [[0, 0, 0]], "want": ["closest"], "winding": {"exact": true})"),
                   context_with(exact_work))
                  .status,
              200);
    Limits faces;
    faces.max_input_faces = 5;
    expect_problem(post(json_request(shapes::cube(), R"(, "points": [[0, 0, 0]])"), context_with(faces)), 422,
                   "budget_exceeded", "mesh.faces");
}

TEST(MeshQueryOperation, APassedDeadlineIs503) {
    Cancel cancel;
    cancel.deadline = Cancel::Clock::now() - std::chrono::seconds(1);
    expect_problem(post(json_request(shapes::cube(), R"(, "points": [[0, 0, 0]])"), context_with({}, cancel)), 503,
                   "cancelled", "");
}

}  // namespace
}  // namespace surfaced::api
