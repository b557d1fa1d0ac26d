// POST /reconstruct called directly: a sampled sphere comes back closed, outward and near the sphere (with its own
// normals, with estimated ones, from JSON and from an upload); options, formats and Accept; the budgets answered
// before any work (a request whose deadline has already passed still gets its 422); bad input named by field.
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <string>

#include <nlohmann/json.hpp>

#include "api/json_codec.h"
#include "api/operations/reconstruct.h"
#include "geometry/io/gltf_points.h"
#include "geometry/io/pointcloud_glb.h"
#include "geometry/io/pointcloud_io.h"
#include "tests/support/api_request.h"
#include "tests/support/gltf_validator.h"
#include "tests/support/mesh_asserts.h"

namespace surfaced::api {
namespace {

using nlohmann::json;
using namespace fixtures;

constexpr double kPi = 3.14159265358979323846;

ApiResponse post(const std::string& body, const std::string& content_type = "application/json",
                 std::multimap<std::string, std::string> query = {}, const ApiContext& context = {}) {
    return operations::reconstruct(make_request("POST", "/reconstruct", content_type, body, std::move(query)), context);
}

//! n points evenly over the sphere of radius r (a Fibonacci lattice), with outward unit normals.
struct Sphere {
    json points = json::array(), normals = json::array();
    std::string xyz;  //!< "x y z" per line (no normals)
};
Sphere sphere_cloud(std::size_t n, double r = 1) {
    Sphere s;
    const double golden = kPi * (3 - std::sqrt(5.0));
    for (std::size_t i = 0; i < n; ++i) {
        const double z = 1 - (2 * static_cast<double>(i) + 1) / static_cast<double>(n);
        const double rho = std::sqrt(1 - z * z), t = golden * static_cast<double>(i);
        const double x = rho * std::cos(t), y = rho * std::sin(t);
        s.points.push_back({r * x, r * y, r * z});
        s.normals.push_back({x, y, z});
        s.xyz += std::to_string(r * x) + " " + std::to_string(r * y) + " " + std::to_string(r * z) + "\n";
    }
    return s;
}

//! The mesh of a JSON answer.
PolygonMesh answer_mesh(const ApiResponse& r) {
    const json out = json::parse(r.body);
    auto mesh = decode_mesh(out.at("mesh").dump(), Limits{}, "mesh");
    EXPECT_TRUE(mesh.ok());
    return mesh.ok() ? std::move(mesh.value()) : PolygonMesh{};
}

//! Closed, manifold, outward, every vertex within `tolerance` of the sphere of radius r, the volume within 3%.
void expect_sphere(const PolygonMesh& mesh, double r, double tolerance) {
    ASSERT_GT(mesh.face_count(), 100u);
    EXPECT_TRUE(testing::is_watertight(mesh));
    EXPECT_EQ(testing::non_manifold_vertices(mesh), 0u);
    EXPECT_EQ(testing::euler_characteristic(mesh), 2);
    double worst = 0;
    for (const Vec3& p : mesh.positions) worst = std::max(worst, std::abs(norm(p) - r));
    EXPECT_LT(worst, tolerance);
    const double volume = testing::signed_volume(mesh), exact = 4.0 / 3.0 * kPi * r * r * r;
    EXPECT_NEAR(volume / exact, 1.0, 0.03);
}

TEST(ReconstructOperation, SphereWithNormalsRoundTripsClosedAndNearTheSphere) {
    const Sphere s = sphere_cloud(3000, 2);
    const json body = {{"points", s.points}, {"normals", s.normals}, {"depth", 6}, {"output", {{"format", "json"}}}};
    const ApiResponse r = post(body.dump());
    ASSERT_EQ(r.status, 200) << r.body;
    EXPECT_EQ(r.content_type, "application/json");
    // the finest cell: the cube (the bounding box's side 4 times scale 1.1) over 2^6
    const double h = 4 * 1.1 / 64;
    expect_sphere(answer_mesh(r), 2, 0.5 * h);
    EXPECT_EQ(header(r, "X-Input-Points"), "3000");
    EXPECT_EQ(header(r, "X-Normals-Estimated"), "false");
    EXPECT_EQ(header(r, "X-Depth"), "6");
    EXPECT_FALSE(header(r, "X-Iso-Value").empty());
    EXPECT_GT(std::stoll(header(r, "X-Octree-Cells")), 64);
    const json stats = json::parse(r.body)["stats"];
    EXPECT_EQ(stats["output_faces"].get<std::size_t>(), answer_mesh(r).face_count());
    EXPECT_EQ(std::to_string(stats["output_faces"].get<std::size_t>()), header(r, "X-Output-Faces"));
    EXPECT_EQ(stats["cells_per_level"].size(), 5u);  // levels 2..6
}

TEST(ReconstructOperation, NormalsAreEstimatedAndOrientedWhenMissing) {
    const Sphere s = sphere_cloud(3000);
    const ApiResponse r = post(s.xyz, "text/x-xyz", {{"depth", "6"}, {"k", "12"}, {"format", "json"}});
    ASSERT_EQ(r.status, 200) << r.body;
    EXPECT_EQ(header(r, "X-Normals-Estimated"), "true");
    expect_sphere(answer_mesh(r), 1, 0.5 * 2.2 / 64);  // outward: the volume is positive

    // never: the same cloud is refused, naming what is missing
    const json body = {{"points", s.points}, {"estimate_normals", "never"}};
    const ApiResponse refused = post(body.dump());
    expect_problem(refused, 422, "invalid_argument", "normals");
    EXPECT_TRUE(refused.error->hint.has_value());
    // always: the cloud's own normals, inward here, are replaced by outward estimates
    json inward = json::array();
    for (const auto& n : s.normals) inward.push_back({-n[0].get<double>(), -n[1].get<double>(), -n[2].get<double>()});
    const json always = {{"points", s.points},
                         {"normals", inward},
                         {"estimate_normals", "always"},
                         {"depth", 5},
                         {"output", {{"format", "json"}}}};
    const ApiResponse replaced = post(always.dump());
    ASSERT_EQ(replaced.status, 200) << replaced.body;
    EXPECT_EQ(header(replaced, "X-Normals-Estimated"), "true");
    EXPECT_GT(testing::signed_volume(answer_mesh(replaced)), 0);
}

TEST(ReconstructOperation, OptionsReachTheReconstruction) {
    const Sphere s = sphere_cloud(1500);
    const auto run = [&](json extra) {
        json body = {{"points", s.points}, {"normals", s.normals}, {"depth", 5}, {"output", {{"format", "json"}}}};
        if (extra.is_object()) body.update(extra);
        const ApiResponse r = post(body.dump());
        EXPECT_EQ(r.status, 200) << r.body;
        return r;
    };
    const ApiResponse base = run(json::object());
    // depth: about 4x the triangles per level
    const double ratio =
        std::stod(header(run({{"depth", 6}}), "X-Output-Faces")) / std::stod(header(base, "X-Output-Faces"));
    EXPECT_GT(ratio, 3.0);
    EXPECT_LT(ratio, 5.0);
    // scale: a larger cube, coarser cells, fewer triangles
    EXPECT_LT(std::stoll(header(run({{"scale", 2}}), "X-Output-Faces")), std::stoll(header(base, "X-Output-Faces")));
    // the other options change the result, and the defaults given explicitly do not
    const json defaults = {
        {"point_weight", 4},      {"samples_per_node", 1.5}, {"boundary", "neumann"},      {"scale", 1.1},
        {"fit_to_samples", true}, {"confidence", false},     {"estimate_normals", "auto"}, {"k", 16}};
    const auto mesh_of = [](const ApiResponse& r) { return json::parse(r.body)["mesh"]; };
    EXPECT_TRUE(mesh_of(run(defaults)) == mesh_of(base));
    for (const json& extra : {json{{"point_weight", 0}}, json{{"samples_per_node", 4}}, json{{"boundary", "dirichlet"}},
                              json{{"fit_to_samples", false}}})
        EXPECT_FALSE(mesh_of(run(extra)) == mesh_of(base)) << extra.dump();
}

// threads 2 gives the same mesh as 1 (on a cloud large enough for the second thread), and only 1 or 2 are taken.
TEST(ReconstructOperation, TwoThreadsGiveTheSameMesh) {
    const Sphere s = sphere_cloud(70'000);
    const auto run = [&](int threads) {
        const json body = {{"points", s.points},
                           {"normals", s.normals},
                           {"depth", 7},
                           {"threads", threads},
                           {"output", {{"format", "json"}}}};
        return post(body.dump());
    };
    const ApiResponse one = run(1), two = run(2);
    ASSERT_EQ(one.status, 200) << one.body;
    ASSERT_EQ(two.status, 200) << two.body;
    EXPECT_TRUE(json::parse(one.body)["mesh"] == json::parse(two.body)["mesh"]);
    expect_problem(run(3), 400, "invalid_field", "threads");
    expect_problem(post(s.xyz, "text/x-xyz", {{"depth", "5"}, {"threads", "0"}}), 400, "invalid_field", "threads");
}

TEST(ReconstructOperation, ConfidenceWeighsPointsByTheirNormalsLength) {
    Sphere s = sphere_cloud(1500);
    // points of zero weight far off the sphere: ignored with confidence, an error without it
    json normals = s.normals;
    for (int i = 0; i < 20; ++i) {
        s.points.push_back({3.0 + 0.01 * i, 0.0, 0.0});
        normals.push_back({0.0, 0.0, 0.0});
    }
    json body = {{"points", s.points}, {"normals", normals}, {"depth", 5}, {"output", {{"format", "json"}}}};
    expect_problem(post(body.dump()), 400, "invalid_field", "normals[1500]");
    body["confidence"] = true;
    const ApiResponse r = post(body.dump());
    ASSERT_EQ(r.status, 200) << r.body;
    const PolygonMesh mesh = answer_mesh(r);
    EXPECT_TRUE(testing::is_watertight(mesh));
    // the cube spans the outliers too (side 4 x 1.1), so its cells are larger; the surface stays on the sphere
    double worst = 0;
    for (const Vec3& p : mesh.positions) worst = std::max(worst, std::abs(norm(p) - 1));
    EXPECT_LT(worst, 4 * 1.1 / 32);
}

TEST(ReconstructOperation, TrimOpensTheSurfaceWhereTheScanEnds) {
    // the unit sphere scanned below z = 0.3 only: Poisson closes it with an invented cap
    const Sphere all = sphere_cloud(8000);
    json points = json::array(), normals = json::array();
    for (std::size_t i = 0; i < all.points.size(); ++i)
        if (all.points[i][2].get<double>() < 0.3) {
            points.push_back(all.points[i]);
            normals.push_back(all.normals[i]);
        }
    const auto run = [&](double trim) {
        json body = {{"points", points}, {"normals", normals}, {"depth", 6}, {"output", {{"format", "json"}}}};
        if (trim > 0) body["trim"] = trim;
        return post(body.dump());
    };
    const double h = 2.2 / 64;
    const ApiResponse closed = run(0);
    ASSERT_EQ(closed.status, 200) << closed.body;
    EXPECT_EQ(header(closed, "X-Sample-Density"), "");  // reported only when trimming
    const PolygonMesh capped = answer_mesh(closed);
    EXPECT_TRUE(testing::is_watertight(capped));
    double top = -1;
    for (const Vec3& p : capped.positions) top = std::max(top, p.z);
    EXPECT_GT(top, 0.6);  // the cap

    // a first trim reports the typical density; half a level below it cuts where the samples end
    const ApiResponse probe = run(1);
    ASSERT_EQ(probe.status, 200) << probe.body;
    const double typical = std::stod(header(probe, "X-Sample-Density"));
    EXPECT_GT(typical, 4);
    EXPECT_LT(typical, 7);
    const ApiResponse cut = run(typical - 0.5);
    ASSERT_EQ(cut.status, 200) << cut.body;
    const PolygonMesh open = answer_mesh(cut);
    EXPECT_EQ(testing::boundary_loop_count(open), 1u);
    EXPECT_EQ(testing::edge_stats(open).non_manifold_edges, 0u);
    EXPECT_EQ(testing::edge_stats(open).inconsistent_edges, 0u);
    top = -1;
    for (const Vec3& p : open.positions) top = std::max(top, p.z);
    EXPECT_LT(top, 0.3 + 3 * h);
    EXPECT_GT(std::stoll(header(cut, "X-Trimmed-Faces")), 0);
    EXPECT_EQ(json::parse(cut.body)["stats"]["trim"]["faces_removed"].get<std::int64_t>(),
              std::stoll(header(cut, "X-Trimmed-Faces")));

    // a level above every vertex removes everything: refused, naming trim; a negative one is out of range
    json body = {{"points", points}, {"normals", normals}, {"depth", 5}, {"trim", 30}};
    expect_problem(post(body.dump()), 422, "invalid_argument", "trim");
    body["trim"] = -1;
    expect_problem(post(body.dump()), 400, "invalid_field", "trim");
    body["trim"] = 5;
    body["island_area"] = 2;
    expect_problem(post(body.dump()), 400, "invalid_field", "island_area");
}

TEST(ReconstructOperation, ConfidenceFromAPlyPropertyWeighsThePoints) {
    // a unit sphere at confidence 1 and outliers 0.15 outside it at confidence 0
    const Sphere inner = sphere_cloud(3000), outer = sphere_cloud(1000, 1.15);
    std::string ply =
        "ply\nformat ascii 1.0\nelement vertex 4000\nproperty double x\nproperty double y\n"
        "property double z\nproperty double nx\nproperty double ny\nproperty double nz\n"
        "property float confidence\nend_header\n";
    for (const Sphere* s : {&inner, &outer})
        for (std::size_t i = 0; i < s->points.size(); ++i) {
            for (int k = 0; k < 3; ++k) ply += std::to_string(s->points[i][k].get<double>()) + " ";
            for (int k = 0; k < 3; ++k) ply += std::to_string(s->normals[i][k].get<double>()) + " ";
            ply += s == &inner ? "1\n" : "0\n";
        }
    const auto worst_distance = [](const ApiResponse& r) {
        double worst = 0;
        for (const Vec3& p : answer_mesh(r).positions) worst = std::max(worst, std::abs(norm(p) - 1));
        return worst;
    };
    const ApiResponse weighted =
        post(ply, "application/ply", {{"depth", "5"}, {"confidence", "true"}, {"format", "json"}});
    ASSERT_EQ(weighted.status, 200) << weighted.body;
    EXPECT_EQ(header(weighted, "X-Confidence"), "property");
    const ApiResponse unweighted = post(ply, "application/ply", {{"depth", "5"}, {"format", "json"}});
    ASSERT_EQ(unweighted.status, 200) << unweighted.body;
    EXPECT_EQ(header(unweighted, "X-Confidence"), "none");
    // points of weight 0 do not count, not even for the bounding cube
    EXPECT_LT(worst_distance(weighted), 0.5 * 2.2 / 32);
    EXPECT_GT(worst_distance(unweighted), worst_distance(weighted));
}

TEST(ReconstructOperation, PointColoursAreCarriedToTheVertices) {
    // the unit sphere coloured by position: (p + 1) / 2
    const Sphere s = sphere_cloud(3000);
    json colors = json::array();
    for (const auto& p : s.points)
        colors.push_back({(p[0].get<double>() + 1) / 2, (p[1].get<double>() + 1) / 2, (p[2].get<double>() + 1) / 2});
    json body = {{"points", s.points},
                 {"normals", s.normals},
                 {"colors", colors},
                 {"depth", 5},
                 {"output", {{"format", "json"}}}};
    const ApiResponse r = post(body.dump());
    ASSERT_EQ(r.status, 200) << r.body.substr(0, 400);
    EXPECT_EQ(header(r, "X-Colors"), "true");
    const json out = json::parse(r.body);
    const PolygonMesh mesh = answer_mesh(r);
    ASSERT_EQ(out["colors"].size(), mesh.vertex_count());
    double worst = 0;
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
        // the colour at the nearest point of the sphere
        const Vec3 q = mesh.positions[v] * (1.0 / norm(mesh.positions[v]));
        const double expected[3] = {(q.x + 1) / 2, (q.y + 1) / 2, (q.z + 1) / 2};
        for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(out["colors"][v][k].get<double>() - expected[k]));
    }
    EXPECT_LT(worst, 0.03);

    // PLY carries them as uchar red green blue, read back by the point reader
    body["output"] = {{"format", "ply"}};
    const ApiResponse ply = post(body.dump());
    ASSERT_EQ(ply.status, 200) << ply.body.substr(0, 400);
    auto cloud = read_ply_points(ply.body);
    ASSERT_TRUE(cloud.ok()) << cloud.error().message;
    ASSERT_EQ(cloud->colors.size(), mesh.vertex_count());
    EXPECT_NEAR(cloud->colors[0].r, out["colors"][0][0].get<double>(), 1.0 / 255);
    // OBJ as `v x y z r g b`
    body["output"] = {{"format", "obj"}};
    const ApiResponse obj = post(body.dump());
    ASSERT_EQ(obj.status, 200);
    auto obj_cloud = read_obj_points(obj.body);
    ASSERT_TRUE(obj_cloud.ok()) << obj_cloud.error().message;
    EXPECT_EQ(obj_cloud->colors.size(), mesh.vertex_count());

    // glTF as COLOR_0 (Draco: normalised bytes; none: floats), valid, read back as the mesh's vertices
    for (const char* compression : {"draco", "none"}) {
        SCOPED_TRACE(compression);
        body["output"] = {{"format", "glb"}, {"compression", compression}};
        const ApiResponse glb = post(body.dump());
        ASSERT_EQ(glb.status, 200) << glb.body.substr(0, 400);
        EXPECT_EQ(header(glb, "X-Colors"), "true");
        const auto v = testing::run_gltf_validator(glb.body);
        ASSERT_TRUE(v.ran) << v.report;
        EXPECT_EQ(v.errors, 0) << v.report;
        EXPECT_EQ(v.warnings, 0) << v.report;
        auto vertices = read_glb_points(glb.body);
        ASSERT_TRUE(vertices.ok()) << vertices.error().message;
        ASSERT_EQ(vertices->colors.size(), mesh.vertex_count());
        double worst_glb = 0;
        for (std::size_t p = 0; p < vertices->size(); ++p) {
            const Vec3 q = vertices->positions[p] * (1.0 / norm(vertices->positions[p]));
            worst_glb = std::max({worst_glb, std::abs(vertices->colors[p].r - (q.x + 1) / 2),
                                  std::abs(vertices->colors[p].g - (q.y + 1) / 2),
                                  std::abs(vertices->colors[p].b - (q.z + 1) / 2)});
        }
        EXPECT_LT(worst_glb, 0.03 + 1.0 / 255);
    }

    // off by request; by default not in a format without them; asked for where they cannot go or do not exist
    body["vertex_colors"] = false;
    EXPECT_EQ(header(post(body.dump()), "X-Colors"), "false");
    body.erase("vertex_colors");
    body["output"] = {{"format", "stl"}};
    const ApiResponse stl = post(body.dump());
    ASSERT_EQ(stl.status, 200);
    EXPECT_EQ(header(stl, "X-Colors"), "false");
    body["vertex_colors"] = true;
    expect_problem(post(body.dump()), 400, "invalid_field", "vertex_colors");
    body.erase("colors");
    body["output"] = {{"format", "ply"}};
    expect_problem(post(body.dump()), 422, "invalid_argument", "vertex_colors");
}

TEST(ReconstructOperation, GlbPointsAndGlbMeshVerticesAreInput) {
    // the sphere's points with normals and colours as a Draco POINTS GLB
    const Sphere s = sphere_cloud(3000);
    PointCloud cloud;
    for (std::size_t i = 0; i < s.points.size(); ++i) {
        cloud.positions.push_back({s.points[i][0], s.points[i][1], s.points[i][2]});
        cloud.normals.push_back({s.normals[i][0], s.normals[i][1], s.normals[i][2]});
        cloud.colors.push_back({0.25f, 0.5f, 0.75f, 1.0f});
    }
    auto glb = write_points_glb(cloud);
    ASSERT_TRUE(glb.ok()) << glb.error().message;
    const ApiResponse r = post(*glb, "model/gltf-binary", {{"depth", "6"}, {"format", "json"}});
    ASSERT_EQ(r.status, 200) << r.body.substr(0, 400);
    EXPECT_EQ(header(r, "X-Input-Points"), "3000");
    EXPECT_EQ(header(r, "X-Normals-Estimated"), "false");  // the GLB's NORMAL
    EXPECT_EQ(header(r, "X-Colors"), "true");
    expect_sphere(answer_mesh(r), 1, 0.5 * 2.2 / 64);
    const json answer = json::parse(r.body);  // held: a range-for over a temporary's member would dangle
    for (const auto& c : answer["colors"]) EXPECT_NEAR(c[1].get<double>(), 0.5, 1.0 / 255);

    // a triangle GLB (that answer as a GLB with vertex normals): its vertices are the points, its normals theirs
    const ApiResponse mesh_glb =
        post(*glb, "model/gltf-binary", {{"depth", "6"}, {"format", "glb"}, {"normals", "true"}});
    ASSERT_EQ(mesh_glb.status, 200) << mesh_glb.body.substr(0, 400);
    const ApiResponse again = post(mesh_glb.body, "model/gltf-binary", {{"depth", "6"}, {"format", "json"}});
    ASSERT_EQ(again.status, 200) << again.body.substr(0, 400);
    EXPECT_EQ(header(again, "X-Input-Points"), header(mesh_glb, "X-Output-Vertices"));
    EXPECT_EQ(header(again, "X-Normals-Estimated"), "false");
    expect_sphere(answer_mesh(again), 1, 2.2 / 64);
}

TEST(ReconstructOperation, EveryMeshFormatAndAccept) {
    const Sphere s = sphere_cloud(500);
    const struct {
        const char* format;
        const char* media_type;
    } formats[] = {{"glb", "model/gltf-binary"}, {"gltf", "model/gltf+json"}, {"obj", "model/obj"},
                   {"ply", "application/ply"},   {"stl", "model/stl"},        {"off", "model/off"},
                   {"json", "application/json"}};
    for (const auto& f : formats) {
        const ApiResponse r = post(s.xyz, "text/x-xyz", {{"depth", "4"}, {"format", f.format}});
        ASSERT_EQ(r.status, 200) << f.format << ": " << r.body;
        EXPECT_EQ(r.content_type, f.media_type);
        EXPECT_FALSE(r.body.empty());
    }
    ApiRequest request = make_request("POST", "/reconstruct", "text/x-xyz", s.xyz, {{"depth", "4"}});
    request.headers.emplace("accept", "model/obj");
    const ApiResponse obj = operations::reconstruct(request, {});
    ASSERT_EQ(obj.status, 200) << obj.body;
    EXPECT_EQ(obj.content_type, "model/obj");
    request.headers.clear();
    request.headers.emplace("accept", "image/png");
    expect_problem(operations::reconstruct(request, {}), 406, "not_acceptable");
}

TEST(ReconstructOperation, BudgetsAreCheckedBeforeAnyWork) {
    const Sphere s = sphere_cloud(400);
    const std::string body = json{{"points", s.points}, {"normals", s.normals}}.dump();
    // the deadline has passed: work would stop with 503, so a 422 means the budget was checked first
    Cancel expired;
    expired.deadline = Cancel::Clock::now() - std::chrono::seconds(1);
    const auto with = [&](auto change) {
        Limits limits;
        change(limits);
        return context_with(limits, expired);
    };
    // the mesher's grid: depth 9 is 512^3 cells, over the default grid-cell limit
    expect_problem(post(s.xyz, "text/x-xyz", {{"depth", "9"}}, with([](Limits&) {})), 422, "budget_exceeded", "depth");
    // the configured depth limit
    expect_problem(post(s.xyz, "text/x-xyz", {{"depth", "7"}}, with([](Limits& l) { l.max_reconstruct_depth = 6; })),
                   422, "budget_exceeded", "depth");
    // the predicted memory (estimate_poisson)
    const ApiResponse memory =
        post(body, "application/json", {}, with([](Limits& l) { l.max_reconstruct_bytes = 1000; }));
    expect_problem(memory, 422, "budget_exceeded", "depth");
    EXPECT_NE(memory.error->detail.find("bytes"), std::string::npos) << memory.error->detail;
    // points, from JSON and from a file
    expect_problem(post(body, "application/json", {}, with([](Limits& l) { l.max_points = 100; })), 422,
                   "budget_exceeded", "points");
    EXPECT_EQ(post(s.xyz, "text/x-xyz", {}, with([](Limits& l) { l.max_points = 100; })).status, 422);
    // points x k for the normal estimate
    expect_problem(post(s.xyz, "text/x-xyz", {{"k", "64"}}, with([](Limits& l) { l.max_points = 1000; })), 422,
                   "budget_exceeded", "k");
    // the body itself
    expect_problem(post(body, "application/json", {}, with([](Limits& l) { l.max_body_bytes = 100; })), 413,
                   "payload_too_large");
    // within every budget, the expired deadline stops the work
    expect_problem(post(body, "application/json", {}, context_with(Limits{}, expired)), 503, "cancelled");
}

TEST(ReconstructOperation, BadInputNamesTheField) {
    const Sphere s = sphere_cloud(50);
    const auto json_body = [&](json extra) {
        json body = {{"points", s.points}, {"normals", s.normals}};
        if (extra.is_object()) body.update(extra);
        return body.dump();
    };
    // options out of range, of the wrong type or unknown, in both transports
    expect_problem(post(s.xyz, "text/x-xyz", {{"depth", "1"}}), 400, "invalid_field", "depth");
    expect_problem(post(s.xyz, "text/x-xyz", {{"depth", "11"}}), 422, "budget_exceeded", "depth");
    expect_problem(post(s.xyz, "text/x-xyz", {{"boundary", "open"}}), 400, "invalid_field", "boundary");
    expect_problem(post(s.xyz, "text/x-xyz", {{"scale", "0.5"}}), 400, "invalid_field", "scale");
    expect_problem(post(s.xyz, "text/x-xyz", {{"dpeth", "5"}}), 400, "unknown_parameter", "dpeth");
    expect_problem(post(json_body({{"point_weight", -1}})), 400, "invalid_field", "point_weight");
    expect_problem(post(json_body({{"samples_per_node", 0}})), 400, "invalid_field", "samples_per_node");
    expect_problem(post(json_body({{"estimate_normals", true}})), 400, "invalid_field", "estimate_normals");
    expect_problem(post(json_body({{"output", {{"format", "obj"}, {"compression", "none"}}}})), 400, "invalid_field",
                   "output.compression");
    expect_problem(post(json_body({{"depht", 5}})), 400, "unknown_field", "depht");
    // k means nothing without estimation
    expect_problem(post(s.xyz, "text/x-xyz", {{"estimate_normals", "never"}, {"k", "8"}}), 400, "invalid_field", "k");
    // the cloud
    json points = s.points;
    points[3] = {1, 2};
    expect_problem(post(json{{"points", points}}.dump()), 400, "invalid_field", "points[3]");
    expect_problem(post(json{{"points", s.points}, {"normals", json::array({{0, 0, 1}})}}.dump()), 400, "invalid_field",
                   "normals");
    expect_problem(post(R"({"depth": 5})"), 400, "invalid_field", "points");
    expect_problem(post("0 0 0\n1 0 0\nnot a point\n", "text/x-xyz"), 400, "parse_error");
    expect_problem(post(s.xyz, "application/pdf"), 415, "unsupported_media_type");
    expect_problem(post(json_body({}), "application/json", {{"depth", "5"}}), 400, "unknown_parameter", "depth");
    // too few points to reconstruct, and all points equal
    expect_problem(post(R"({"points": [[0,0,0],[1,0,0],[0,1,0]], "normals": [[0,0,1],[0,0,1],[0,0,1]]})"), 422,
                   "invalid_argument", "points");
    expect_problem(
        post(R"({"points": [[1,1,1],[1,1,1],[1,1,1],[1,1,1]], "normals": [[0,0,1],[0,0,1],[0,0,1],[0,0,1]]})"), 422,
        "invalid_argument", "points");
}

TEST(ReconstructOperation, MultipartFormTakesTheFileAndFields) {
    const Sphere s = sphere_cloud(500);
    const std::string boundary = "reconstructBoundary";
    const std::string body = "--" + boundary + "\r\nContent-Disposition: form-data; name=\"depth\"\r\n\r\n4\r\n--" +
                             boundary + "\r\nContent-Disposition: form-data; name=\"format\"\r\n\r\nobj\r\n--" +
                             boundary +
                             "\r\nContent-Disposition: form-data; name=\"file\"; filename=\"cloud.xyz\"\r\n"
                             "Content-Type: application/octet-stream\r\n\r\n" +
                             s.xyz + "\r\n--" + boundary + "--\r\n";
    const ApiResponse r = post(body, "multipart/form-data; boundary=" + boundary);
    ASSERT_EQ(r.status, 200) << r.body;
    EXPECT_EQ(r.content_type, "model/obj");
    EXPECT_EQ(header(r, "X-Depth"), "4");
    EXPECT_EQ(header(r, "X-Input-Points"), "500");
}

}  // namespace
}  // namespace surfaced::api
