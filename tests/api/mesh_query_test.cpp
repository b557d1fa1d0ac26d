// POST /mesh/query through dispatch (no sockets): inside tests and signed distances on the unit cube against the
// analytic answer, closest points and faces against a brute-force loop over every triangle, rays against analytic
// hits, the winding number of an open box, and every 4xx with the field it names.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/routes.h"
#include "geometry/io/base64.h"
#include "geometry/io/mesh_io.h"
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

// ---- packed batches and answers ------------------------------------------------------------------------------

//! base64 of the little-endian float32 (or float64) values.
template <class T>
std::string pack(const std::vector<double>& values) {
    std::string bytes;
    for (const double v : values) {
        const auto bits = std::bit_cast<std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>(T(v));
        for (std::size_t b = 0; b < sizeof(T); ++b) bytes += static_cast<char>((bits >> (8 * b)) & 0xff);
    }
    return encode_base64(bytes);
}

//! The little-endian values of type T in base64 `text`.
template <class T>
std::vector<T> unpack(const Json& text) {
    EXPECT_TRUE(text.is_string()) << text.dump();
    if (!text.is_string()) return {};
    auto bytes = decode_base64(text.get<std::string>());
    EXPECT_TRUE(bytes) << bytes.error().message;
    if (!bytes) return {};
    EXPECT_EQ(bytes->size() % sizeof(T), 0u);
    std::vector<T> out(bytes->size() / sizeof(T));
    for (std::size_t i = 0; i < out.size(); ++i) {
        std::conditional_t<sizeof(T) == 1, std::uint8_t,
                           std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>
            bits = 0;
        for (std::size_t b = 0; b < sizeof(T); ++b)
            bits |= static_cast<decltype(bits)>(static_cast<decltype(bits)>((*bytes)[i * sizeof(T) + b]) << (8 * b));
        out[i] = std::bit_cast<T>(bits);
    }
    return out;
}

// The same questions asked as JSON arrays and as packed float64 batches with packed answers: the same answers, to
// the last bit for float64, and to float32 rounding for float32; misses are NaN and -1.
TEST(MeshQueryOperation, PackedBatchesAndAnswersAgreeWithJson) {
    const PolygonMesh torus = shapes::torus(24, 12);
    const std::vector<Vec3> points = {{0, 0, 0}, {1, 0, 0}, {1.2, 0.1, 0.05}, {0, 2, 0.3}, {3, -1, 2}};
    std::vector<double> flat_points;
    for (const Vec3& p : points) flat_points.insert(flat_points.end(), {p.x, p.y, p.z});
    const std::vector<double> flat_rays = {-3, 0, 0, 1, 0, 0, 0, 0, 5, 0, 0, -1, 5, 5, 5, 1, 1, 1};
    Json rays_json = Json::array();
    for (std::size_t i = 0; i < flat_rays.size(); i += 6)
        rays_json.push_back(std::vector<double>(flat_rays.begin() + i, flat_rays.begin() + i + 6));

    const ApiResponse plain =
        post(json_request(torus, R"(,"points":)" + points_json(points) + R"(,"rays":)" + rays_json.dump()));
    ASSERT_EQ(plain.status, 200) << plain.body;
    const Json a = Json::parse(plain.body);
    for (const std::string encoding : {"float64", "float32"}) {
        SCOPED_TRACE(encoding);
        const bool single = encoding == "float32";
        const std::string batches = single ? R"(,"points":{"float32":")" + pack<float>(flat_points) +
                                                 R"("},"rays":{"float32":")" + pack<float>(flat_rays) + R"("})"
                                           : R"(,"points":{"float64":")" + pack<double>(flat_points) +
                                                 R"("},"rays":{"float64":")" + pack<double>(flat_rays) + R"("})";
        const ApiResponse packed = post(json_request(torus, batches + R"(,"encoding":")" + encoding + "\""));
        ASSERT_EQ(packed.status, 200) << packed.body;
        const Json b = Json::parse(packed.body);
        EXPECT_EQ(b["encoding"], encoding);
        auto reals = [&](const Json& text) {
            std::vector<double> out;
            if (single)
                for (float x : unpack<float>(text)) out.push_back(x);
            else
                out = unpack<double>(text);
            return out;
        };
        const double tolerance = single ? 1e-6 : 0;  // the float32 inputs are exact in these points and rays
        const auto inside = unpack<std::uint8_t>(b["points"]["inside"]);
        const auto distance = reals(b["points"]["distance"]);
        const auto winding = reals(b["points"]["winding_number"]);
        const auto closest = reals(b["points"]["closest"]);
        const auto face = unpack<std::int32_t>(b["points"]["face"]);
        ASSERT_EQ(inside.size(), points.size());
        ASSERT_EQ(distance.size(), points.size());
        ASSERT_EQ(closest.size(), 3 * points.size());
        ASSERT_EQ(face.size(), points.size());
        for (std::size_t i = 0; i < points.size(); ++i) {
            EXPECT_EQ(inside[i] == 1, a["points"]["inside"][i].get<bool>()) << i;
            EXPECT_NEAR(distance[i], a["points"]["distance"][i].get<double>(), tolerance) << i;
            EXPECT_NEAR(winding[i], a["points"]["winding_number"][i].get<double>(), tolerance) << i;
            for (int k = 0; k < 3; ++k)
                EXPECT_NEAR(closest[3 * i + k], a["points"]["closest"][i][k].get<double>(), tolerance) << i;
            EXPECT_EQ(face[i], a["points"]["face"][i].get<int>()) << i;
        }
        const auto hit = unpack<std::uint8_t>(b["rays"]["hit"]);
        const auto t = reals(b["rays"]["t"]);
        const auto ray_face = unpack<std::int32_t>(b["rays"]["face"]);
        const auto hit_point = reals(b["rays"]["point"]);
        ASSERT_EQ(hit.size(), 3u);
        ASSERT_EQ(hit_point.size(), 9u);
        for (std::size_t i = 0; i < 3; ++i) {
            EXPECT_EQ(hit[i] == 1, a["rays"]["hit"][i].get<bool>()) << i;
            if (hit[i]) {
                EXPECT_NEAR(t[i], a["rays"]["t"][i].get<double>(), tolerance) << i;
                EXPECT_EQ(ray_face[i], a["rays"]["face"][i].get<int>()) << i;
            } else {
                EXPECT_TRUE(std::isnan(t[i]) && std::isnan(hit_point[3 * i])) << i;
                EXPECT_EQ(ray_face[i], -1) << i;
            }
        }
        EXPECT_FALSE(hit[2]);  // the ray from (5, 5, 5) away from the torus
    }
}

TEST(MeshQueryOperation, BadPackedBatchesNameTheirField) {
    const PolygonMesh cube = shapes::cube();
    // 8 bytes: not a whole [x, y, z] of float32 (12 bytes)
    expect_problem(post(json_request(cube, R"(,"points":{"float32":")" + pack<float>({1, 2}) + R"("})")), 400,
                   "invalid_field", "points.float32");
    // rays: 6 numbers each
    expect_problem(post(json_request(cube, R"(,"rays":{"float64":")" + pack<double>({0, 0, 0}) + R"("})")), 400,
                   "invalid_field", "rays.float64");
    expect_problem(post(json_request(cube, R"(,"points":{"float32":"AAAA*AAA"})")), 400, "invalid_field",
                   "points.float32");
    expect_problem(post(json_request(cube, R"(,"points":{"int32":"AAAA"})")), 400, "invalid_field", "points");
    expect_problem(post(json_request(cube, R"(,"points":{"float32":")" +
                                               pack<float>({0, std::numeric_limits<double>::infinity(), 0}) + R"("})")),
                   400, "invalid_field", "points.float32");
    expect_problem(post(json_request(cube, R"(,"points":[[0,0,0]],"encoding":"float16")")), 400, "invalid_field",
                   "encoding");
    // the budget counts packed items before decoding them
    Limits limits;
    limits.max_mesh_queries = 2;
    expect_problem(
        post(json_request(cube, R"(,"points":{"float32":")" + pack<float>(std::vector<double>(9, 0.0)) + R"("})"),
             context_with(limits)),
        422, "budget_exceeded", "points");
}

// ---- multipart: the mesh as a file, the rest as a JSON part ---------------------------------------------------

std::string form(const std::vector<std::array<std::string, 4>>& parts) {  // name, filename, content type, body
    std::string body;
    for (const auto& [name, filename, type, content] : parts) {
        body += "--B0undary\r\nContent-Disposition: form-data; name=\"" + name + "\"";
        if (!filename.empty()) body += "; filename=\"" + filename + "\"";
        body += "\r\n";
        if (!type.empty()) body += "Content-Type: " + type + "\r\n";
        body += "\r\n" + content + "\r\n";
    }
    return body + "--B0undary--\r\n";
}

ApiResponse post_form(const std::string& body) {
    return dispatch(make_request("POST", "/mesh/query", "multipart/form-data; boundary=B0undary", body), {});
}

TEST(MeshQueryOperation, MultipartMeshFileGivesTheSameAnswersAsJson) {
    const PolygonMesh cube = shapes::cube();
    const std::string query = R"({"points":[[0,0,0],[1,0.2,0.1]],"rays":[[-2,0.1,0.2,1,0,0]]})";
    const ApiResponse plain =
        post(json_request(cube, R"(,"points":[[0,0,0],[1,0.2,0.1]],"rays":[[-2,0.1,0.2,1,0,0]])"));
    ASSERT_EQ(plain.status, 200) << plain.body;
    const std::string obj = write_obj(cube);
    for (const auto& [filename, type] : std::vector<std::pair<std::string, std::string>>{
             {"cube.obj", ""}, {"cube.bin", "model/obj"}, {"cube.obj", "application/octet-stream"}}) {
        SCOPED_TRACE(filename + " " + type);
        const std::string body =
            form({{"file", filename, type, obj}, {"request", "q.json", "application/json", query}});
        const ApiResponse packed = post_form(body);
        ASSERT_EQ(packed.status, 200) << packed.body;
        EXPECT_EQ(Json::parse(packed.body), Json::parse(plain.body));
    }
    // a JSON mesh file too
    const std::string json_mesh = mesh_json(cube);
    const std::string body = form({{"file", "cube.json", "", json_mesh}, {"request", "", "", query}});
    const ApiResponse from_json = post_form(body);
    ASSERT_EQ(from_json.status, 200) << from_json.body;
    EXPECT_EQ(Json::parse(from_json.body), Json::parse(plain.body));
}

TEST(MeshQueryOperation, MultipartMistakesAreNamed) {
    const std::string obj = write_obj(shapes::cube());
    const std::string query = R"({"points":[[0,0,0]]})";
    const std::string no_request = form({{"file", "cube.obj", "", obj}});
    expect_problem(post_form(no_request), 400, "malformed_multipart");
    const std::string no_file = form({{"request", "", "", query}});
    expect_problem(post_form(no_file), 400, "malformed_multipart");
    const std::string stray = form({{"file", "cube.obj", "", obj}, {"request", "", "", query}, {"extra", "", "", "1"}});
    expect_problem(post_form(stray), 400, "malformed_multipart");
    const std::string twice =
        form({{"file", "cube.obj", "", obj}, {"request", "", "", query}, {"request", "", "", query}});
    expect_problem(post_form(twice), 400, "malformed_multipart");
    const std::string mesh_too =
        form({{"file", "cube.obj", "", obj},
              {"request", "", "", R"({"mesh":{"positions":[],"faces":[]},"points":[[0,0,0]]})"}});
    expect_problem(post_form(mesh_too), 400, "invalid_field", "mesh");
    const std::string bad_point = form({{"file", "cube.obj", "", obj}, {"request", "", "", R"({"points":[[0,0]]})"}});
    expect_problem(post_form(bad_point), 400, "invalid_field", "points[0]");
    // a broken OBJ names its line
    const std::string broken =
        form({{"file", "cube.obj", "", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n"}, {"request", "", "", query}});
    const Json problem = expect_problem(post_form(broken), 422, "index_out_of_range");
    EXPECT_EQ(problem.value("line", 0), 4) << problem.dump();
    // another media type entirely
    expect_problem(dispatch(make_request("POST", "/mesh/query", "model/obj", obj), {}), 415, "unsupported_media_type");
}

}  // namespace
}  // namespace surfaced::api
