// Trimmed surfaces in POST /tessellate, called through dispatch (no sockets): JSON "surfaces[i].trim" and OBJ
// curv2/trim/hole. Areas against analytic answers (a square hole in a plane; a rational circle trimming a rational
// patch, against a quadrature of the patch's own Jacobian written here), every trim rule as a 422 naming the loop and
// curve, shapes as 400 with the field path, budgets before work, and the options trimmed surfaces need.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/routes.h"
#include "api/trim_codec.h"
#include "geometry/io/mesh_io.h"
#include "tests/support/api_request.h"

namespace surfaced::api {
namespace {

using namespace fixtures;
using json = nlohmann::json;

ApiResponse post(const json& body, const Limits& limits = {}) {
    return dispatch(make_request("POST", "/tessellate", "application/json", body.dump()), context_with(limits));
}

//! The plane z = 0 over [0, 2]^2 as a bilinear B-spline surface on [0, 1]^2; weights make it rational.
json plane(const json& weights = nullptr) {
    json s = {{"degree", {1, 1}},
              {"knots_u", {0, 0, 1, 1}},
              {"knots_v", {0, 0, 1, 1}},
              {"points", {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {2, 2, 0}}}};
    if (!weights.is_null()) s["weights"] = weights;
    return s;
}

json line(double u0, double v0, double u1, double v1) {
    return {{"degree", 1}, {"points", {{u0, v0}, {u1, v1}}}};  // no knots: the Bézier segment
}

//! The square [a, b]^2 in (u, v), counter-clockwise, as four segments.
json square(double a, double b) { return {line(a, a, b, a), line(b, a, b, b), line(b, b, a, b), line(a, b, a, a)}; }

//! The circle about c of radius r as one rational quadratic curve (the 9-point circle, The NURBS Book ex. 7.2).
json circle(double cu, double cv, double r) {
    const double h = std::sqrt(0.5);
    const double x[] = {1, 1, 0, -1, -1, -1, 0, 1, 1}, y[] = {0, 1, 1, 1, 0, -1, -1, -1, 0};
    json points = json::array();
    for (int i = 0; i < 9; ++i) points.push_back({cu + r * x[i], cv + r * y[i]});
    return {{"degree", 2},
            {"knots", {0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1}},
            {"points", points},
            {"weights", {1, h, 1, h, 1, h, 1, h, 1}}};
}

json request(const std::vector<json>& surfaces, double tolerance = 1e-3) {
    return {{"surfaces", surfaces}, {"tolerance", tolerance}, {"output", {{"format", "obj"}}}};
}

PolygonMesh read_obj_mesh(const ApiResponse& response) {
    auto mesh = read_mesh(response.body, MeshFormat::Obj);
    EXPECT_TRUE(mesh.ok()) << (mesh.ok() ? "" : mesh.error().message);
    return mesh.ok() ? std::move(mesh.value()) : PolygonMesh{};
}

double area(const PolygonMesh& mesh) {
    double sum = 0;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const auto face = mesh.face(f);
        for (std::size_t k = 1; k + 1 < face.size(); ++k)
            sum += 0.5 * norm(cross(mesh.positions[face[k]] - mesh.positions[face[0]],
                                    mesh.positions[face[k + 1]] - mesh.positions[face[0]]));
    }
    return sum;
}

TEST(TessellateTrim, SquareHoleInAPlaneHasTheExactArea) {
    json surface = plane();
    surface["trim"] = {{"holes", {square(0.25, 0.75)}}};
    const ApiResponse response = post(request({surface}, 1e-2));
    ASSERT_EQ(response.status, 200) << response.body;
    EXPECT_EQ(header(response, "X-Patches"), "1");
    EXPECT_LE(std::stod(header(response, "X-Error-Bound")), 1e-2);
    const PolygonMesh mesh = read_obj_mesh(response);
    ASSERT_GT(mesh.face_count(), 0u);
    // the square [0, 2]^2 less [0.5, 1.5]^2: the trims are straight and the surface flat, so the area is exact
    EXPECT_NEAR(area(mesh), 3.0, 1e-12);
    for (const Vec3& p : mesh.positions) {
        EXPECT_EQ(p.z, 0.0);
        EXPECT_FALSE(p.x > 0.5 + 1e-12 && p.x < 1.5 - 1e-12 && p.y > 0.5 + 1e-12 && p.y < 1.5 - 1e-12)
            << "vertex inside the hole: " << p.x << " " << p.y;
    }
    // the same with the hole given clockwise and as an explicit outer loop over the whole domain
    json reversed = plane();
    json hole = json::array();
    for (const json& segment : square(0.25, 0.75)) {
        json r = segment;
        r["points"] = {segment["points"][1], segment["points"][0]};
        hole.insert(hole.begin(), r);
    }
    reversed["trim"] = {{"outer", square(0, 1)}, {"holes", {hole}}};
    const ApiResponse same = post(request({reversed}, 1e-2));
    ASSERT_EQ(same.status, 200) << same.body;
    EXPECT_NEAR(area(read_obj_mesh(same)), 3.0, 1e-12);
    // an empty trim is the whole domain
    json whole = plane();
    whole["trim"] = json::object();
    const ApiResponse all = post(request({whole}, 1e-2));
    ASSERT_EQ(all.status, 200) << all.body;
    EXPECT_NEAR(area(read_obj_mesh(all)), 4.0, 1e-12);
}

TEST(TessellateTrim, DiscTrimOnARationalPatch) {
    // weights 1 and 3 along u: x(u) = 6u / (1 + 2u), y(v) = 2v, z = 0, so the Jacobian is 12 / (1 + 2u)^2 and the
    // disc |(u, v) - (0.5, 0.5)| <= 0.3 has area  int_{-pi/2}^{pi/2} 12 / (1 + 2 (0.5 + r sin t))^2 2 r^2 cos^2 t dt
    const double r = 0.3;
    const auto jacobian = [](double u) { return 12.0 / ((1 + 2 * u) * (1 + 2 * u)); };
    double reference = 0, perimeter = 0;
    const int n = 20000;  // Simpson on a smooth periodic-free integrand: far below the tolerances checked
    for (int i = 0; i <= n; ++i) {
        const double t = -std::numbers::pi / 2 + std::numbers::pi * i / n;
        const double weight = (i == 0 || i == n ? 1 : i % 2 ? 4 : 2) * std::numbers::pi / n / 3;
        reference += weight * jacobian(0.5 + r * std::sin(t)) * 2 * r * r * std::cos(t) * std::cos(t);
    }
    for (int i = 0; i < 4000; ++i) {  // the image of the circle: length, for the area's bound
        const auto at = [&](int k) {
            const double a = 2 * std::numbers::pi * k / 4000, u = 0.5 + r * std::cos(a), v = 0.5 + r * std::sin(a);
            return Vec3{6 * u / (1 + 2 * u), 2 * v, 0};
        };
        perimeter += norm(at(i + 1) - at(i));
    }
    for (double tolerance : {1e-2, 1e-3}) {
        json surface = plane({1, 3, 1, 3});
        surface["trim"] = {{"outer", {circle(0.5, 0.5, r)}}};
        const ApiResponse response = post(request({surface}, tolerance));
        ASSERT_EQ(response.status, 200) << response.body;
        EXPECT_LE(std::stod(header(response, "X-Error-Bound")), tolerance);
        const PolygonMesh mesh = read_obj_mesh(response);
        // the boundary is a polygon within the tolerance of the trim's image: the area is within perimeter x e
        EXPECT_NEAR(area(mesh), reference, perimeter * tolerance) << "tolerance " << tolerance;
        // every vertex is the surface's point at its (u, v), inside the disc; the boundary's are on the circle
        ASSERT_EQ(mesh.uv_indices.size(), mesh.face_indices.size());
        std::size_t on_circle = 0;
        for (std::size_t k = 0; k < mesh.face_indices.size(); ++k) {
            const Vec2 uv = mesh.uvs[mesh.uv_indices[k]];
            const Vec3& p = mesh.positions[mesh.face_indices[k]];
            EXPECT_NEAR(p.x, 6 * uv.x / (1 + 2 * uv.x), 1e-6);  // OBJ prints positions and uvs in full
            EXPECT_NEAR(p.y, 2 * uv.y, 1e-6);
            const double d = std::hypot(uv.x - 0.5, uv.y - 0.5);
            EXPECT_LE(d, r + 1e-9);
            if (std::fabs(d - r) < 1e-9) ++on_circle;
        }
        EXPECT_GT(on_circle, 24u);
    }
}

TEST(TessellateTrim, TrimmedAndUntrimmedSurfacesTogether) {
    json trimmed = plane();
    trimmed["trim"] = {{"holes", {{circle(0.5, 0.5, 0.25)}}}};
    const ApiResponse alone = post(request({trimmed}));
    const ApiResponse untrimmed = post(request({plane()}));
    const ApiResponse both = post(request({plane(), trimmed}));
    ASSERT_EQ(both.status, 200) << both.body;
    ASSERT_EQ(alone.status, 200) << alone.body;
    EXPECT_EQ(header(both, "X-Patches"), "2");
    EXPECT_EQ(std::stoul(header(both, "X-Output-Faces")),
              std::stoul(header(alone, "X-Output-Faces")) + std::stoul(header(untrimmed, "X-Output-Faces")));
    EXPECT_NEAR(area(read_obj_mesh(both)), 4 + 4 - 4 * std::numbers::pi * 0.25 * 0.25, 4 * 2 * 0.5 * 3.2e-3);
    // GLB too
    json glb = request({trimmed});
    glb["output"] = {{"format", "glb"}};
    const ApiResponse binary = post(glb);
    ASSERT_EQ(binary.status, 200) << binary.body;
    EXPECT_EQ(binary.content_type, "model/gltf-binary");
}

//! The request of three planes whose third has `trim`.
json third_trimmed(const json& trim) {
    json surface = plane();
    surface["trim"] = trim;
    return request({plane(), plane(), surface}, 1e-2);
}

TEST(TessellateTrim, EveryBrokenRuleIs422NamingTheLoopAndCurve) {
    struct Case {
        const char* what;
        json trim;
        std::string field;
    };
    const Case cases[] = {
        {"open loop",
         {{"holes", {{line(0.2, 0.2, 0.8, 0.2), line(0.8, 0.2, 0.8, 0.8), line(0.8, 0.8, 0.2, 0.7)}}}},
         "surfaces[2].trim.holes[0][2]"},
        {"self-intersecting",
         {{"holes",
           {{line(0.2, 0.2, 0.8, 0.8), line(0.8, 0.8, 0.8, 0.2), line(0.8, 0.2, 0.2, 0.8), line(0.2, 0.8, 0.2, 0.2)}}}},
         "surfaces[2].trim.holes[0][0]"},
        {"hole outside the outer loop",
         {{"outer", square(0.1, 0.4)}, {"holes", {square(0.6, 0.9)}}},
         "surfaces[2].trim.holes[0]"},
        {"loops crossing", {{"holes", {square(0.2, 0.6), square(0.4, 0.8)}}}, "surfaces[2].trim.holes[0][1]"},
        {"outside the domain", {{"outer", square(0.5, 1.5)}}, "surfaces[2].trim.outer[1]"},
        {"invalid curve",
         {{"holes",
           {{line(0.2, 0.2, 0.8, 0.2),
             {{"degree", 1}, {"points", {{0.8, 0.2}, {0.2, 0.8}}}, {"knots", {0, 1, 0.5, 1}}},
             line(0.2, 0.8, 0.2, 0.2)}}}},
         "surfaces[2].trim.holes[0][1]"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.what);
        const ApiResponse response = post(third_trimmed(c.trim));
        expect_problem(response, 422, "invalid_argument", c.field);
        // the detail names the loops by the same paths
        const json problem = expect_problem(response, 422, "invalid_argument");
        EXPECT_EQ(problem.value("detail", "").rfind(c.field + ": ", 0), 0u) << response.body;
    }
}

TEST(TessellateTrim, MalformedTrimsAre400WithTheFieldPath) {
    const auto with_outer_curve = [](const json& curve) { return post(third_trimmed({{"outer", {curve}}})); };
    expect_problem(with_outer_curve({{"degree", 1}, {"points", {{0.1, 0.1}, {0.5}}}}), 400, "invalid_field",
                   "surfaces[2].trim.outer[0].points[1]");
    expect_problem(with_outer_curve({{"degree", 1}, {"points", {{0.1, "x"}, {0.5, 0.5}}}}), 400, "invalid_field",
                   "surfaces[2].trim.outer[0].points[0][1]");
    expect_problem(with_outer_curve({{"degree", 0}, {"points", {{0.1, 0.1}, {0.5, 0.5}}}}), 400, "invalid_field",
                   "surfaces[2].trim.outer[0].degree");
    expect_problem(with_outer_curve({{"degree", 16}, {"points", {{0.1, 0.1}, {0.5, 0.5}}}}), 400, "invalid_field",
                   "surfaces[2].trim.outer[0].degree");
    expect_problem(with_outer_curve({{"degree", 2}, {"points", {{0.1, 0.1}, {0.5, 0.5}}}}), 400, "invalid_field",
                   "surfaces[2].trim.outer[0].points");
    expect_problem(with_outer_curve({{"degree", 1}, {"points", {{0.1, 0.1}, {0.5, 0.5}}}, {"weights", {1, -1}}}), 400,
                   "invalid_field", "surfaces[2].trim.outer[0].weights[1]");
    expect_problem(with_outer_curve({{"degree", 1}, {"points", {{0.1, 0.1}, {0.5, 0.5}}}, {"knots", {0, 1}}}), 400,
                   "invalid_field", "surfaces[2].trim.outer[0].knots");
    expect_problem(with_outer_curve({{"degree", 1}, {"points", {{0.1, 0.1}, {0.5, 0.5}}}, {"span", 1}}), 400,
                   "unknown_field", "surfaces[2].trim.outer[0].span");
    expect_problem(post(third_trimmed({{"holes", {json::array()}}})), 400, "invalid_field",
                   "surfaces[2].trim.holes[0]");
    expect_problem(post(third_trimmed({{"holes", square(0.2, 0.4)}})), 400, "invalid_field",
                   "surfaces[2].trim.holes[0]");  // a loop, not a list of loops: holes[0] is a curve object
    expect_problem(post(third_trimmed({{"inner", json::array()}})), 400, "unknown_field", "surfaces[2].trim.inner");
    expect_problem(post(third_trimmed(json::array())), 400, "invalid_field", "surfaces[2].trim");
}

TEST(TessellateTrim, OptionsAndBudgets) {
    json surface = plane();
    surface["trim"] = {{"holes", {square(0.25, 0.75)}}};
    json segments = {{"surfaces", {plane(), surface}}, {"segments", 4}};
    expect_problem(post(segments), 400, "invalid_field", "segments");
    json neither = {{"surfaces", {surface}}};
    expect_problem(post(neither), 400, "invalid_field", "tolerance");
    json patches = {{"surfaces", {surface}}, {"output", {{"format", "patches"}}}};
    expect_problem(post(patches), 422, "unsupported", "format");
    // loop count from the array sizes, before anything is decoded
    json many = plane();
    many["trim"] = {{"holes", json::array()}};
    for (std::size_t i = 0; i <= kMaxTrimLoops; ++i) many["trim"]["holes"].push_back(json::array());
    expect_problem(post(request({plane(), many})), 422, "budget_exceeded", "surfaces[1].trim");
    // the output budget: the surface's grid (2 triangles for the flat patch) counted before tessellating, then the
    // trimmed tessellator's own count (12 triangles around the hole) as it works
    Limits small;
    small.max_output_faces = 1;
    expect_problem(post(request({surface}, 1e-2), small), 422, "budget_exceeded", "tolerance");
    small.max_output_faces = 11;
    expect_problem(post(request({surface}, 1e-2), small), 422, "budget_exceeded", "tolerance");
    small.max_output_faces = 12;
    EXPECT_EQ(post(request({surface}, 1e-2), small).status, 200);
}

TEST(TessellateTrim, BoundAboveTheToleranceIs422NamingTheSurface) {
    // The plane scaled to 1e6 units with a square hole whose last side stops 5e-8 short of its start (within the
    // closure tolerance, 1e-7 of the domain): that gap alone puts the trim 5e-8 x |dS| ~ 0.07 units from its polygon,
    // far above the tolerance, so the guaranteed bound cannot reach it. Never a 200 with X-Error-Bound above the
    // tolerance: 422 naming the surface.
    constexpr double kSize = 1e6;
    json big = plane();
    big["points"] = {{0, 0, 0}, {kSize, 0, 0}, {0, kSize, 0}, {kSize, kSize, 0}};
    json hole = square(0.25, 0.75);
    hole[3] = line(0.25, 0.75, 0.25, 0.25 + 5e-8);
    big["trim"] = {{"holes", {hole}}};
    const ApiResponse response = post(request({plane(), big}, 1e-3));
    expect_problem(response, 422, "budget_exceeded", "surfaces[1]");
    EXPECT_NE(response.body.find("above the tolerance 0.001"), std::string::npos) << response.body;
    EXPECT_NE(response.body.find("gaps between its trim curves"), std::string::npos) << response.body;
    // closed exactly, the same surface is within the tolerance
    big["trim"] = {{"holes", {square(0.25, 0.75)}}};
    const ApiResponse closed = post(request({plane(), big}, 1e-3));
    ASSERT_EQ(closed.status, 200) << closed.body;
    EXPECT_LE(std::stod(header(closed, "X-Error-Bound")), 1e-3);
}

constexpr const char* kPlaneObjWithHole = R"(# the plane z = 0 over [0, 2]^2 less a square hole
v 0 0 0
v 2 0 0
v 0 2 0
v 2 2 0
vp 0.25 0.25
vp 0.75 0.25
vp 0.75 0.75
vp 0.25 0.75
cstype bspline
deg 1
curv2 1 2 3 4 1
parm u 0 0 1 2 3 4 4
end
deg 1 1
surf 0 1 0 1 1 2 3 4
parm u 0 0 1 1
parm v 0 0 1 1
hole 0 4 1
end
)";

TEST(TessellateTrim, ObjCurv2Hole) {
    const ApiResponse response = dispatch(
        make_request("POST", "/tessellate", "model/obj", kPlaneObjWithHole, {{"tolerance", "0.01"}, {"format", "obj"}}),
        ApiContext{});
    ASSERT_EQ(response.status, 200) << response.body;
    EXPECT_NEAR(area(read_obj_mesh(response)), 3.0, 1e-12);
    // a trimmed surface needs a tolerance; its errors name the line
    expect_problem(dispatch(make_request("POST", "/tessellate", "model/obj", kPlaneObjWithHole, {{"segments", "4"}}),
                            ApiContext{}),
                   400, "invalid_field", "segments");
    std::string open = kPlaneObjWithHole;
    open.replace(open.find("curv2 1 2 3 4 1"), 15, "curv2 1 2 3 4 2");
    const ApiResponse error =
        dispatch(make_request("POST", "/tessellate", "model/obj", open, {{"tolerance", "0.01"}}), ApiContext{});
    const json problem = expect_problem(error, 422, "invalid_argument");
    EXPECT_EQ(problem.value("line", 0), 19) << error.body;  // the hole statement
}

}  // namespace
}  // namespace surfaced::api
