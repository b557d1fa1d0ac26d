// POST /surfaces and the "surfaces" input of POST /tessellate, called through dispatch (no sockets): the answers on the
// exact NURBS sphere against its analytic answers (positions on the sphere, radial normals, the closest point as the
// radial projection, the tight box), knot insertion and degree elevation returning the same surface, the Bézier
// decomposition feeding POST /tessellate, crack-free welding of two surfaces sharing a boundary, format=patches, OBJ
// bspline uploads, and every error with its field path.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include <nlohmann/json.hpp>

#include "api/operations/surfaces.h"
#include "api/routes.h"
#include "api/surface_codec.h"
#include "geometry/io/mesh_io.h"
#include "tests/support/api_request.h"
#include "tests/support/mesh_asserts.h"
#include "tests/support/nurbs_surfaces.h"

namespace surfaced::api {
namespace {

using namespace fixtures;
using nlohmann::json;

ApiResponse post(const std::string& path, const std::string& body, const ApiContext& context = {}) {
    return dispatch(make_request("POST", path, "application/json", body), context);
}

ApiResponse post_surfaces(const json& body, const ApiContext& context = {}) {
    return post("/surfaces", body.dump(), context);
}

Vec3 vec(const json& a) { return {a[0].get<double>(), a[1].get<double>(), a[2].get<double>()}; }

const Vec3 kCentre{1, -2, 0.5};
constexpr double kRadius = 2.0;

json sphere_json() { return surface_json(testing::sphere(kCentre, kRadius)); }

TEST(SurfacesOperation, SpherePointsNormalsAndDerivatives) {
    json uvs = json::array();
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> any(0.0, 1.0);
    for (int k = 0; k < 20; ++k) uvs.push_back({any(rng), any(rng)});
    uvs.push_back({0.3, 0.0});  // the south pole: the normal is the limit, pointing down
    const ApiResponse response = post_surfaces({{"surface", sphere_json()}, {"evaluate", uvs}, {"derivatives", uvs}});
    ASSERT_EQ(response.status, 200) << response.body;
    const json out = json::parse(response.body);
    EXPECT_EQ(out["degree"], json::array({2, 2}));
    EXPECT_EQ(out["rational"], true);
    EXPECT_EQ(out["domain"]["u"], json::array({0, 1}));
    ASSERT_EQ(out["evaluate"].size(), uvs.size());
    for (std::size_t k = 0; k < uvs.size(); ++k) {
        const json& e = out["evaluate"][k];
        const Vec3 p = vec(e["position"]), n = vec(e["normal"]);
        EXPECT_NEAR(norm(p - kCentre), kRadius, 1e-12) << k;
        EXPECT_NEAR(dot(n, (p - kCentre) * (1.0 / kRadius)), 1.0, 1e-9) << k;  // outward radial
        EXPECT_NEAR(dot(vec(e["du"]), p - kCentre), 0.0, 1e-9) << k;           // tangent
        const json& d = out["derivatives"][k];
        EXPECT_EQ(d["position"], e["position"]);
        EXPECT_EQ(d["du"], e["du"]);
        for (const char* name : {"duu", "duv", "dvv"}) EXPECT_TRUE(d.contains(name));
    }
    EXPECT_NEAR(vec(out["evaluate"].back()["normal"]).z, -1.0, 1e-12);
}

TEST(SurfacesOperation, ClosestPointsAreRadialProjections) {
    json points = json::array();
    std::mt19937 rng(2);
    std::uniform_real_distribution<double> c(-5, 5);
    std::vector<Vec3> queries;
    while (queries.size() < 20) {
        const Vec3 q = kCentre + Vec3{c(rng), c(rng), c(rng)};
        if (norm(q - kCentre) < 0.3) continue;
        queries.push_back(q);
        points.push_back({q.x, q.y, q.z});
    }
    const ApiResponse response = post_surfaces({{"surface", sphere_json()}, {"closest", points}});
    ASSERT_EQ(response.status, 200) << response.body;
    const json out = json::parse(response.body);
    for (std::size_t k = 0; k < queries.size(); ++k) {
        const json& a = out["closest"][k];
        const Vec3 q = queries[k];
        const Vec3 expected = kCentre + (q - kCentre) * (kRadius / norm(q - kCentre));
        EXPECT_LE(norm(vec(a["point"]) - expected), 1e-6) << k;
        EXPECT_NEAR(a["distance"].get<double>(), std::abs(norm(q - kCentre) - kRadius), 1e-9) << k;
        EXPECT_TRUE(a["converged"].get<bool>());
        EXPECT_EQ(a["uv"].size(), 2u);
    }
    // the centre: every point is closest, which no finite budget proves to 1e-9
    const ApiResponse centre =
        post_surfaces({{"surface", sphere_json()}, {"closest", {{kCentre.x, kCentre.y, kCentre.z}}}});
    expect_problem(centre, 422, "budget_exceeded", "closest[0]");
}

TEST(SurfacesOperation, InsertKnotAndElevateReturnTheSameSurface) {
    const json uvs = {{0.1, 0.2}, {0.5, 0.5}, {0.77, 0.9}, {1.0, 1.0}, {0.25, 0.5}};
    const ApiResponse response = post_surfaces({{"surface", sphere_json()},
                                                {"evaluate", uvs},
                                                {"insert_knot", {{"direction", "v"}, {"value", 0.3}, {"times", 2}}},
                                                {"elevate", {{"direction", "u"}, {"times", 2}}}});
    ASSERT_EQ(response.status, 200) << response.body;
    const json out = json::parse(response.body);
    EXPECT_EQ(out["elevate"]["degree"], json::array({4, 2}));
    EXPECT_EQ(out["insert_knot"]["knots_v"].size(), 10u);
    for (const char* query : {"insert_knot", "elevate"}) {
        const ApiResponse again = post_surfaces({{"surface", out[query]}, {"evaluate", uvs}});
        ASSERT_EQ(again.status, 200) << query << ": " << again.body;
        const json answers = json::parse(again.body)["evaluate"];
        for (std::size_t k = 0; k < uvs.size(); ++k)
            EXPECT_LE(norm(vec(answers[k]["position"]) - vec(out["evaluate"][k]["position"])), 1e-12)
                << query << " at " << uvs[k].dump();
    }
}

TEST(SurfacesOperation, ToBezierFeedsTessellateAndTheTightBoxIsTheSpheres) {
    const ApiResponse response =
        post_surfaces({{"surface", sphere_json()}, {"to_bezier", true}, {"bounding_box", true}});
    ASSERT_EQ(response.status, 200) << response.body;
    const json out = json::parse(response.body);
    EXPECT_EQ(out["to_bezier"]["patches"].size(), 8u);  // 4 spans along u, 2 along v
    EXPECT_EQ(out["to_bezier"]["breaks_u"], json::array({0, 0.25, 0.5, 0.75, 1}));
    const json& tight = out["bounding_box"]["tight"];
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(tight["min"][c].get<double>(), kCentre[c] - kRadius, 1e-8);
        EXPECT_NEAR(tight["max"][c].get<double>(), kCentre[c] + kRadius, 1e-8);
        EXPECT_LE(out["bounding_box"]["control_hull"]["min"][c].get<double>(), tight["min"][c].get<double>());
    }
    // the patches are POST /tessellate's body: a closed mesh, the same as tessellating the surface itself
    const json body = {{"patches", out["to_bezier"]["patches"]}, {"tolerance", 1e-3}, {"output", {{"format", "obj"}}}};
    const ApiResponse from_patches = post("/tessellate", body.dump());
    ASSERT_EQ(from_patches.status, 200) << from_patches.body;
    const json direct = {{"surfaces", {sphere_json()}}, {"tolerance", 1e-3}, {"output", {{"format", "obj"}}}};
    const ApiResponse from_surface = post("/tessellate", direct.dump());
    ASSERT_EQ(from_surface.status, 200) << from_surface.body;
    EXPECT_EQ(header(from_surface, "X-Patches"), "8");
    EXPECT_EQ(header(from_surface, "X-Output-Faces"), header(from_patches, "X-Output-Faces"));
    auto mesh = read_mesh(from_surface.body, MeshFormat::Obj);
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    EXPECT_TRUE(testing::is_watertight(*mesh));
    for (const Vec3& p : mesh->positions) EXPECT_NEAR(norm(p - kCentre), kRadius, 1e-9);
}

TEST(TessellateSurfaces, TwoSurfacesSharingABoundaryWeldCrackFree) {
    // the sphere cut at u = 1/2 into two NURBS surfaces whose nets share the cut's column exactly
    const BSplineSurface sphere = testing::sphere(kCentre, kRadius);
    auto halves = to_bezier(sphere);
    ASSERT_TRUE(halves.ok());
    const auto half = [&](int first) {
        BSplineSurface s;
        s.degree_u = 2;
        s.degree_v = 2;
        s.count_u = 5;
        s.count_v = 5;
        s.knots_u = {0, 0, 0, 0.5, 0.5, 1, 1, 1};
        s.knots_v = sphere.knots_v;
        for (int j = 0; j < 5; ++j)
            for (int i = first; i < first + 5; ++i) {
                s.points.push_back(sphere.at(i, j));
                s.weights.push_back(sphere.weight(i, j));
            }
        return s;
    };
    const json body = {{"surfaces", {surface_json(half(0)), surface_json(half(4))}},
                       {"tolerance", 1e-3},
                       {"output", {{"format", "obj"}}}};
    const ApiResponse response = post("/tessellate", body.dump());
    ASSERT_EQ(response.status, 200) << response.body;
    auto mesh = read_mesh(response.body, MeshFormat::Obj);
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    EXPECT_TRUE(testing::is_watertight(*mesh)) << "boundary edges " << testing::edge_stats(*mesh).boundary_edges;
    // and it is the whole sphere's tessellation
    const json whole = {{"surfaces", {sphere_json()}}, {"tolerance", 1e-3}, {"output", {{"format", "obj"}}}};
    const ApiResponse reference = post("/tessellate", whole.dump());
    EXPECT_EQ(header(response, "X-Output-Vertices"), header(reference, "X-Output-Vertices"));
}

TEST(TessellateSurfaces, FormatPatchesIsTheDecomposition) {
    const json body = {{"surfaces", {sphere_json()}},
                       {"patches", {{{"degree", {1, 1}}, {"points", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 1}}}}}},
                       {"output", {{"format", "patches"}}}};
    const ApiResponse response = post("/tessellate", body.dump());
    ASSERT_EQ(response.status, 200) << response.body;
    EXPECT_EQ(response.content_type, "application/json");
    const json out = json::parse(response.body);
    ASSERT_EQ(out["patches"].size(), 9u);  // the given patch first, then the sphere's 8
    auto expected = to_bezier(testing::sphere(kCentre, kRadius));
    ASSERT_TRUE(expected.ok());
    for (std::size_t k = 0; k < 8; ++k) {
        const json& patch = out["patches"][k + 1];
        ASSERT_EQ(patch["points"].size(), expected->patches[k].points.size());
        for (std::size_t i = 0; i < patch["points"].size(); ++i)
            EXPECT_EQ(vec(patch["points"][i]), expected->patches[k].points[i]);
        EXPECT_EQ(patch["weights"].get<std::vector<double>>(), expected->patches[k].weights);
    }
    // the same as a query parameter with an OBJ upload
    const std::string obj =
        "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 1\nv 2 1 0\ncstype bspline\ndeg 1 1\n"
        "surf 0 2 0 1 1 2 3 4 5 6\nparm u 0 0 1 2 2\nparm v 0 0 1 1\nend\n";
    const ApiResponse upload =
        dispatch(make_request("POST", "/tessellate", "model/obj", obj, {{"format", "patches"}}), ApiContext{});
    ASSERT_EQ(upload.status, 200) << upload.body;
    EXPECT_EQ(json::parse(upload.body)["patches"].size(), 2u);
}

TEST(TessellateSurfaces, ObjBsplineUploadTessellates) {
    // a bilinear B-spline of 2 x 1 spans: the two bilinear patches, 2 x 8 x 8 x 2 triangles at the default segments
    const std::string obj =
        "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 1\nv 2 1 0\ncstype bspline\ndeg 1 1\n"
        "surf 0 2 0 1 1 2 3 4 5 6\nparm u 0 0 1 2 2\nparm v 0 0 1 1\nend\n";
    const ApiResponse response =
        dispatch(make_request("POST", "/tessellate", "model/obj", obj, {{"format", "obj"}}), ApiContext{});
    ASSERT_EQ(response.status, 200) << response.body;
    EXPECT_EQ(header(response, "X-Patches"), "2");
    EXPECT_EQ(header(response, "X-Output-Faces"), "256");
    std::string bad = obj;
    bad.replace(bad.find("parm u 0 0 1 2 2"), 16, "parm u 0 0 0 2 2");  // 0 three times: one more than deg + 1
    const ApiResponse refused =
        dispatch(make_request("POST", "/tessellate", "model/obj", bad, {{"format", "obj"}}), ApiContext{});
    expect_problem(refused, 422, "invalid_argument", "");
    EXPECT_EQ(refused.error->line.value_or(-1), 10);
    EXPECT_NE(refused.body.find("parm u"), std::string::npos) << refused.body;
}

TEST(TessellateSurfaces, ErrorsNameTheField) {
    const auto tessellate = [](json surface, const Limits& limits = {}) {
        return post("/tessellate", json{{"surfaces", {sphere_json(), std::move(surface)}}}.dump(),
                    context_with(limits));
    };
    json decreasing = sphere_json();
    decreasing["knots_u"][5] = 0.1;
    expect_problem(tessellate(decreasing), 422, "invalid_argument", "surfaces[1].knots_u[5]");
    json trimmed = sphere_json();
    trimmed["trim"] = json::array();  // a trim is an object {"outer", "holes"} (tessellate_trim_test.cpp)
    expect_problem(tessellate(trimmed), 400, "invalid_field", "surfaces[1].trim");
    json degree = sphere_json();
    degree["degree"][1] = 16;
    expect_problem(tessellate(degree), 422, "invalid_argument", "surfaces[1].degree[1]");
    json weights = sphere_json();
    weights["weights"][7] = -1;
    expect_problem(tessellate(weights), 422, "invalid_argument", "surfaces[1].weights[7]");
    json points = sphere_json();
    points["points"].erase(points["points"].begin());
    expect_problem(tessellate(points), 422, "invalid_argument", "surfaces[1].points");
    Limits few;
    few.max_patches = 12;  // 8 + 8 Bézier patches predicted
    expect_problem(tessellate(sphere_json(), few), 422, "budget_exceeded", "surfaces[1]");
    expect_problem(post("/tessellate", R"({"tolerance": 0.1})"), 400, "invalid_field", "patches");
}

TEST(SurfacesOperation, ErrorsNameTheField) {
    const auto ask = [](json body, const Limits& limits = {}) { return post_surfaces(body, context_with(limits)); };
    json decreasing = sphere_json();
    decreasing["knots_v"][3] = -1;
    expect_problem(ask({{"surface", decreasing}, {"to_bezier", true}}), 422, "invalid_argument", "surface.knots_v[3]");
    expect_problem(ask({{"surface", sphere_json()}, {"evaluate", {{0.5, 0.5}, {1.5, 0.5}}}}), 422, "invalid_argument",
                   "evaluate[1][0]");
    expect_problem(ask({{"surface", sphere_json()}, {"derivatives", {{0.5, -0.1}}}}), 422, "invalid_argument",
                   "derivatives[0][1]");
    expect_problem(ask({{"surface", sphere_json()}, {"evaluate", {{0.5}}}}), 400, "invalid_field", "evaluate[0]");
    expect_problem(ask({{"surface", sphere_json()}, {"insert_knot", {{"direction", "u"}, {"value", 2}}}}), 422,
                   "invalid_argument", "insert_knot.value");
    // 0.25 already has multiplicity 2 = the degree along u
    expect_problem(ask({{"surface", sphere_json()}, {"insert_knot", {{"direction", "u"}, {"value", 0.25}}}}), 422,
                   "invalid_argument", "insert_knot.times");
    expect_problem(ask({{"surface", sphere_json()}, {"insert_knot", {{"direction", "w"}, {"value", 0.5}}}}), 400,
                   "invalid_field", "insert_knot.direction");
    expect_problem(ask({{"surface", sphere_json()}, {"elevate", {{"direction", "v"}, {"times", 14}}}}), 422,
                   "invalid_argument", "elevate.times");  // degree 2 + 14
    expect_problem(ask({{"surface", sphere_json()}, {"elevate", {{"direction", "v"}, {"times", 15}}}}), 400,
                   "invalid_field", "elevate.times");  // outside the documented 1..14
    expect_problem(ask({{"surface", sphere_json()}}), 400, "invalid_field", "surface");
    expect_problem(ask({{"evaluate", {{0, 0}}}}), 400, "invalid_field", "surface");
    expect_problem(ask({{"surface", sphere_json()}, {"trim", true}}), 400, "unknown_field", "trim");
    Limits small;
    small.max_input_vertices = 44;  // the sphere's net has 45 points
    expect_problem(ask({{"surface", sphere_json()}, {"to_bezier", true}}, small), 422, "budget_exceeded",
                   "surface.points");
    Limits few;
    few.max_patches = 7;
    expect_problem(ask({{"surface", sphere_json()}, {"bounding_box", true}}, few), 422, "budget_exceeded",
                   "bounding_box");
    json many = json::array();
    for (std::size_t k = 0; k <= operations::kMaxSurfaceClosest; ++k) many.push_back({0, 0, 5});
    expect_problem(ask({{"surface", sphere_json()}, {"closest", many}}), 422, "budget_exceeded", "closest");
}

}  // namespace
}  // namespace surfaced::api
