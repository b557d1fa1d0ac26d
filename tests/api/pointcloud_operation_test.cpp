// POST /pointcloud called directly: JSON points, uploads (PLY, XYZ sniffed), mesh and scene sampling, normal
// estimation (outward on a sphere), GLB output through the Khronos validator, and every error naming its field,
// line or budget.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <string>

#include <nlohmann/json.hpp>

#include "api/operations/pointcloud.h"
#include "geometry/io/gltf.h"
#include "geometry/io/pointcloud_glb.h"
#include "geometry/io/pointcloud_io.h"
#include "tests/support/api_request.h"
#include "tests/support/gltf_validator.h"

namespace surfaced::api {
namespace {

using nlohmann::json;
using namespace fixtures;

ApiResponse post(const std::string& body, const std::string& content_type = "application/json",
                 std::multimap<std::string, std::string> query = {}, const ApiContext& context = {}) {
    return operations::pointcloud(make_request("POST", "/pointcloud", content_type, body, std::move(query)), context);
}

const char* kCubeMesh =
    R"({"positions": [[-1,-1,-1],[1,-1,-1],[1,1,-1],[-1,1,-1],[-1,-1,1],[1,-1,1],[1,1,1],[-1,1,1]],
        "faces": [[0,3,2,1],[4,5,6,7],[0,1,5,4],[2,3,7,6],[1,2,6,5],[0,4,7,3]]})";

TEST(PointcloudOperation, JsonPointsToJsonAndDracoGlb) {
    const std::string body =
        R"({"points": [[0,0,0],[1,0,0],[0,1,0],[1,1,0.5]], "colors": [[1,0,0],[0,1,0],[0,0,1],[0.5,0.5,0.5]],
            "output": {"format": "json"}})";
    const ApiResponse r = post(body);
    ASSERT_EQ(r.status, 200) << r.body;
    EXPECT_EQ(r.content_type, "application/json");
    const json out = json::parse(r.body);
    ASSERT_EQ(out["points"].size(), 4u);
    EXPECT_EQ(out["points"][3], json::array({1, 1, 0.5}));
    EXPECT_EQ(out["colors"][1], json::array({0, 1, 0}));
    EXPECT_FALSE(out.contains("normals"));
    EXPECT_EQ(header(r, "X-Output-Points"), "4");

    json glb_request = json::parse(body);
    glb_request.erase("output");
    const ApiResponse glb = post(glb_request.dump());
    ASSERT_EQ(glb.status, 200) << glb.body;
    EXPECT_EQ(glb.content_type, "model/gltf-binary");
    const auto v = testing::run_gltf_validator(glb.body);
    ASSERT_TRUE(v.ran) << v.report;
    EXPECT_EQ(v.errors, 0) << v.report;
    EXPECT_EQ(v.warnings, 0) << v.report;
}

TEST(PointcloudOperation, SampledSceneGetsOutwardNormals) {
    const std::string body =
        R"({"sample": {"scene": {"op": "sphere", "radius": 1}, "bounds": [[-2,-2,-2],[2,2,2]], "count": 800, "seed": 3},
            "estimate_normals": {"k": 12}, "output": {"format": "json"}})";
    const ApiResponse r = post(body);
    ASSERT_EQ(r.status, 200) << r.body;
    const json out = json::parse(r.body);
    ASSERT_EQ(out["points"].size(), 800u);
    ASSERT_EQ(out["normals"].size(), 800u);
    for (std::size_t i = 0; i < 800; ++i) {
        const auto& p = out["points"][i];
        const auto& n = out["normals"][i];
        const double x = p[0], y = p[1], z = p[2];
        EXPECT_NEAR(std::sqrt(x * x + y * y + z * z), 1.0, 1e-5);
        const double d = x * n[0].get<double>() + y * n[1].get<double>() + z * n[2].get<double>();
        EXPECT_GT(d, 0.9) << "point " << i;  // outward and within ~25 degrees of radial
    }
}

TEST(PointcloudOperation, MeshSamplingIsReproducibleAndOnTheFaces) {
    const std::string body = std::string(R"({"sample": {"mesh": )") + kCubeMesh +
                             R"(, "count": 600, "seed": 11}, "output": {"format": "json"}})";
    const ApiResponse a = post(body), b = post(body);
    ASSERT_EQ(a.status, 200) << a.body;
    const json pa = json::parse(a.body), pb = json::parse(b.body);
    EXPECT_EQ(pa["points"], pb["points"]);
    for (std::size_t i = 0; i < 600; ++i) {
        double largest = 0;
        for (int k = 0; k < 3; ++k) largest = std::max(largest, std::fabs(pa["points"][i][k].get<double>()));
        EXPECT_NEAR(largest, 1.0, 1e-12);  // on the cube's surface
        const auto& n = pa["normals"][i];
        EXPECT_NEAR(std::fabs(n[0].get<double>()) + std::fabs(n[1].get<double>()) + std::fabs(n[2].get<double>()), 1.0,
                    1e-12);  // an axis direction
    }
    // the cube in the document's own example shape: a GLB with Draco by default
    const ApiResponse glb = post(std::string(R"({"sample": {"mesh": )") + kCubeMesh + R"(, "count": 300}})");
    ASSERT_EQ(glb.status, 200) << glb.body;
    const auto v = testing::run_gltf_validator(glb.body);
    ASSERT_TRUE(v.ran) << v.report;
    EXPECT_EQ(v.errors, 0) << v.report;
    EXPECT_EQ(v.warnings, 0) << v.report;
}

TEST(PointcloudOperation, UploadsPlyAndSniffedXyz) {
    PointCloud cloud;
    for (int i = 0; i < 10; ++i)
        for (int j = 0; j < 10; ++j) cloud.positions.push_back({i * 0.1, j * 0.1, 0.0});
    const std::string ply = write_ply_points(cloud);
    const ApiResponse r = post(ply, "application/ply", {{"estimate_normals", "true"}, {"k", "8"}, {"format", "ply"}});
    ASSERT_EQ(r.status, 200) << r.body;
    EXPECT_EQ(r.content_type, "application/ply");
    EXPECT_EQ(header(r, "X-Input-Points"), "100");
    auto back = read_ply_points(r.body);
    ASSERT_TRUE(back.ok()) << back.error().message;
    ASSERT_EQ(back->normals.size(), 100u);
    for (const Vec3& n : back->normals) EXPECT_NEAR(n.z, 1.0, 1e-12);  // plane, oriented +z

    const ApiResponse xyz = post("# scan\n0 0 0\n1 0 0\n0 1 0\n", "application/octet-stream", {{"format", "json"}});
    ASSERT_EQ(xyz.status, 200) << xyz.body;
    EXPECT_EQ(json::parse(xyz.body)["points"].size(), 3u);
}

//! A GLB with its JSON chunk changed by `change` (the BIN chunk kept as it is).
template <class Change>
std::string edit_glb_json(const std::string& glb, Change&& change) {
    auto u32 = [&](std::size_t at) {
        std::uint32_t v = 0;
        std::memcpy(&v, glb.data() + at, 4);
        return v;
    };
    const std::uint32_t json_length = u32(12);
    json gltf = json::parse(glb.substr(20, json_length));
    change(gltf);
    std::string text = gltf.dump();
    text.resize((text.size() + 3) & ~std::size_t{3}, ' ');
    const std::string rest = glb.substr(20 + json_length);
    std::string out = glb.substr(0, 20) + text + rest;
    const auto total = static_cast<std::uint32_t>(out.size()), length = static_cast<std::uint32_t>(text.size());
    std::memcpy(out.data() + 8, &total, 4);
    std::memcpy(out.data() + 12, &length, 4);
    return out;
}

TEST(PointcloudOperation, UploadsGlbAndGltfPoints) {
    PointCloud cloud;
    for (int i = 0; i < 10; ++i)
        for (int j = 0; j < 5; ++j) {
            cloud.positions.push_back({i * 0.1, j * 0.1, 0.0});
            cloud.normals.push_back({0, 0, 1});
            cloud.colors.push_back({i / 9.0f, j / 4.0f, 0.5f, 1.0f});
        }
    for (bool draco : {false, true}) {
        SCOPED_TRACE(draco ? "draco" : "plain");
        auto glb = write_points_glb(cloud, {.draco = draco});
        ASSERT_TRUE(glb.ok()) << glb.error().message;
        for (const char* type : {"model/gltf-binary", "application/octet-stream"}) {
            const ApiResponse r = post(*glb, type, {{"format", "ply"}});
            ASSERT_EQ(r.status, 200) << r.body;
            EXPECT_EQ(header(r, "X-Input-Points"), "50");
            auto back = read_ply_points(r.body);
            ASSERT_TRUE(back.ok()) << back.error().message;
            ASSERT_EQ(back->size(), 50u);
            ASSERT_EQ(back->normals.size(), 50u);
            ASSERT_EQ(back->colors.size(), 50u);
            for (std::size_t p = 0; p < back->size(); ++p) {
                EXPECT_NEAR(back->normals[p].z, 1.0, 1e-6);
                // the colour is the one of the point there (Draco may reorder the points; 8 bits a channel)
                const Vec3& q = back->positions[p];
                EXPECT_NEAR(back->colors[p].r, q.x / 0.9, 1.0 / 255 + 1e-3);
                EXPECT_NEAR(back->colors[p].g, q.y / 0.4, 1.0 / 255 + 1e-3);
            }
        }
    }
    auto plain = write_points_glb(cloud, {.draco = false});
    ASSERT_TRUE(plain.ok());
    auto gltf = gltf_from_glb(*plain);
    ASSERT_TRUE(gltf.ok());
    const ApiResponse text = post(*gltf, "model/gltf+json", {{"format", "json"}});
    ASSERT_EQ(text.status, 200) << text.body;
    EXPECT_EQ(json::parse(text.body)["points"].size(), 50u);

    // a form's file part: by the file name's extension, the part's type being the generic one curl sends
    const std::string form =
        "--b1\r\nContent-Disposition: form-data; name=\"file\"; filename=\"scan.glb\"\r\n"
        "Content-Type: application/octet-stream\r\n\r\n" +
        *plain + "\r\n--b1\r\nContent-Disposition: form-data; name=\"format\"\r\n\r\njson\r\n--b1--\r\n";
    const ApiResponse multipart = post(form, "multipart/form-data; boundary=b1");
    ASSERT_EQ(multipart.status, 200) << multipart.body;
    EXPECT_EQ(json::parse(multipart.body)["colors"].size(), 50u);

    // a COLOR_0 accessor shorter than POSITION: 400 naming both accessors
    const std::string short_colors = edit_glb_json(*plain, [](json& g) {
        g["accessors"][g["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"].get<int>()]["count"] = 49;
    });
    const json problem = expect_problem(post(short_colors, "model/gltf-binary"), 400, "parse_error");
    EXPECT_NE(problem["detail"].get<std::string>().find("COLOR_0 (accessors[2]) has 49 elements, POSITION "
                                                        "(accessors[0]) has 50"),
              std::string::npos)
        << problem.dump();
    // the point limit, from the announced count
    ApiContext context;
    context.limits.max_points = 49;
    expect_problem(post(*plain, "model/gltf-binary", {}, context), 422, "budget_exceeded");
    // a GLB of lines only has no points
    const std::string lines = edit_glb_json(*plain, [](json& g) { g["meshes"][0]["primitives"][0]["mode"] = 1; });
    expect_problem(post(lines, "model/gltf-binary"), 422, "unsupported");
}

struct BadCase {
    const char* name;
    std::string body;
    std::string content_type;
    std::multimap<std::string, std::string> query;
    int status;
    std::string code;
    std::string field;       // "" = not checked
    std::int64_t line = -1;  // -1 = not checked
};

TEST(PointcloudOperation, ErrorsNameTheFieldLineOrBudget) {
    const std::vector<BadCase> cases = {
        {"bad coordinate",
         R"({"points": [[0,0,0],[1,0,"x"]]})",
         "application/json",
         {},
         400,
         "invalid_field",
         "points[1][2]"},
        {"not an array", R"({"points": 3})", "application/json", {}, 400, "invalid_field", "points"},
        {"colors count",
         R"({"points": [[0,0,0]], "colors": [[1,0,0],[0,1,0]]})",
         "application/json",
         {},
         400,
         "invalid_field",
         "colors"},
        {"colour range",
         R"({"points": [[0,0,0]], "colors": [[1,2,0]]})",
         "application/json",
         {},
         400,
         "invalid_field",
         "colors[0][1]"},
        {"zero normal",
         R"({"points": [[0,0,0]], "normals": [[0,0,0]]})",
         "application/json",
         {},
         400,
         "invalid_field",
         "normals[0]"},
        {"both forms",
         std::string(R"({"points": [[0,0,0]], "sample": {"mesh": )") + kCubeMesh + R"(, "count": 3}})",
         "application/json",
         {},
         400,
         "invalid_field",
         "points"},
        {"neither form", R"({"output": {"format": "json"}})", "application/json", {}, 400, "invalid_field", "points"},
        {"unknown member", R"({"points": [[0,0,0]], "radius": 3})", "application/json", {}, 400, "unknown_field", ""},
        {"obj output",
         R"({"points": [[0,0,0]], "output": {"format": "obj"}})",
         "application/json",
         {},
         400,
         "invalid_field",
         "output.format"},
        {"k too small",
         R"({"points": [[0,0,0]], "estimate_normals": {"k": 2}})",
         "application/json",
         {},
         400,
         "invalid_field",
         "estimate_normals.k"},
        {"too few for normals",
         R"({"points": [[0,0,0],[1,0,0]], "estimate_normals": true})",
         "application/json",
         {},
         422,
         "invalid_argument",
         "estimate_normals"},
        {"sample count",
         std::string(R"({"sample": {"mesh": )") + kCubeMesh + R"(, "count": 0}})",
         "application/json",
         {},
         400,
         "invalid_field",
         "sample.count"},
        {"mesh and bounds",
         std::string(R"({"sample": {"mesh": )") + kCubeMesh + R"(, "count": 5, "bounds": [[0,0,0],[1,1,1]]}})",
         "application/json",
         {},
         400,
         "invalid_field",
         "sample.bounds"},
        {"bad mesh index",
         R"({"sample": {"mesh": {"positions": [[0,0,0],[1,0,0],[0,1,0]], "faces": [[0,1,7]]}, "count": 5}})",
         "application/json",
         {},
         422,
         "index_out_of_range",
         "sample.mesh.faces[0][2]"},
        {"scene without bounds",
         R"({"sample": {"scene": {"op": "sphere", "radius": 1}, "count": 5}})",
         "application/json",
         {},
         400,
         "invalid_field",
         "sample.bounds"},
        {"no surface in bounds",
         R"({"sample": {"scene": {"op": "sphere", "radius": 1}, "bounds": [[5,5,5],[6,6,6]], "count": 5}})",
         "application/json",
         {},
         422,
         "invalid_argument",
         "sample.scene"},
        {"bad scene",
         R"({"sample": {"scene": {"op": "sphere", "radius": "big"}, "bounds": [[-1,-1,-1],[1,1,1]], "count": 5}})",
         "application/json",
         {},
         400,
         "invalid_field",
         "sample.scene.radius"},
        {"query with json",
         R"({"points": [[0,0,0]]})",
         "application/json",
         {{"k", "5"}},
         400,
         "unknown_parameter",
         "k"},
        {"ply line",
         "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
         "end_header\n0 0 0\n1 q 0\n",
         "application/ply",
         {},
         400,
         "parse_error",
         "",
         9},
        {"xyz columns", "0 0 0\n1 1 1 1\n", "text/x-xyz", {}, 400, "parse_error", "", 2},
        {"k without estimate", "0 0 0\n", "text/x-xyz", {{"k", "5"}}, 400, "invalid_field", "k"},
        {"unknown parameter", "0 0 0\n", "text/x-xyz", {{"levels", "5"}}, 400, "unknown_parameter", ""},
        {"media type", "solid x\n", "model/stl", {}, 415, "unsupported_media_type", ""},
        {"unsniffable", "hello world\n", "application/octet-stream", {}, 415, "unsupported_media_type", ""},
    };
    for (const BadCase& c : cases) {
        const ApiResponse r = post(c.body, c.content_type, c.query);
        EXPECT_EQ(r.status, c.status) << c.name << ": " << r.body;
        ASSERT_TRUE(r.error.has_value()) << c.name;
        EXPECT_EQ(r.content_type, "application/problem+json") << c.name;
        EXPECT_EQ(r.error->code, c.code) << c.name << ": " << r.body;
        if (!c.field.empty()) {
            EXPECT_EQ(r.error->field.value_or(""), c.field) << c.name << ": " << r.body;
        }
        if (c.line >= 0) {
            EXPECT_EQ(r.error->line.value_or(-1), c.line) << c.name << ": " << r.body;
        }
    }
}

TEST(PointcloudOperation, AllowedFormatsListedAreTheOnesThatWork) {
    const auto problem = expect_problem(
        post("ply\nformat ascii 1.0\nelement vertex 0\nend_header\n", "application/ply", {{"format", "obj"}}), 400,
        "invalid_field");
    EXPECT_EQ(problem.value("field", ""), "format");
    const std::string detail = problem.value("detail", "");
    EXPECT_NE(detail.find("(allowed: \"glb\", \"gltf\", \"ply\", \"json\")"), std::string::npos) << detail;
    // and each one listed answers
    for (const char* format : {"glb", "gltf", "ply", "json"}) {
        const ApiResponse response =
            post(R"({"points": [[0,0,0],[1,0,0]], "output": {"format": ")" + std::string(format) + R"("}})");
        EXPECT_EQ(response.status, 200) << format << ": " << response.body;
    }
    expect_problem(post(R"({"points": [[0,0,0]], "estimate_normals": {"k": 300}})"), 400, "invalid_field",
                   "estimate_normals.k");
    expect_problem(post("ply\nformat ascii 1.0\nelement vertex 0\nend_header\n", "application/ply",
                        {{"estimate_normals", "true"}, {"k", "300"}}),
                   400, "invalid_field", "k");
}

TEST(PointcloudOperation, BudgetsAreCheckedBeforeWork) {
    ApiContext context;
    context.limits.max_points = 3;
    const ApiResponse points =
        post(R"({"points": [[0,0,0],[1,0,0],[0,1,0],[1,1,1]]})", "application/json", {}, context);
    EXPECT_EQ(points.status, 422) << points.body;
    EXPECT_EQ(points.error->code, "budget_exceeded");
    EXPECT_EQ(points.error->field.value_or(""), "points");
    const ApiResponse sample =
        post(std::string(R"({"sample": {"mesh": )") + kCubeMesh + R"(, "count": 4}})", "application/json", {}, context);
    EXPECT_EQ(sample.status, 422) << sample.body;
    EXPECT_EQ(sample.error->field.value_or(""), "sample.count");
    const ApiResponse upload = post("0 0 0\n1 1 1\n2 2 2\n3 3 3\n", "text/x-xyz", {}, context);
    EXPECT_EQ(upload.status, 422) << upload.body;
    EXPECT_EQ(upload.error->code, "budget_exceeded");
    EXPECT_EQ(upload.error->line.value_or(-1), 4);
    context.limits.max_body_bytes = 10;
    const ApiResponse big = post("0 0 0\n1 1 1\n2 2 2\n", "text/x-xyz", {}, context);
    EXPECT_EQ(big.status, 413);
}

TEST(PointcloudOperation, NormalEstimationBudgetIsPointsTimesK) {
    // 3 points x k = 16 fits max_points x 16 = 48 links; x k = 17 does not, and is refused before any kNN work.
    ApiContext context;
    context.limits.max_points = 3;
    const std::string points = R"("points": [[0,0,0],[1,0,0],[0,1,0]])";
    const ApiResponse over =
        post("{" + points + R"(, "estimate_normals": {"k": 17}})", "application/json", {}, context);
    EXPECT_EQ(over.status, 422) << over.body;
    EXPECT_EQ(over.error->code, "budget_exceeded");
    EXPECT_EQ(over.error->field.value_or(""), "estimate_normals.k");
    const ApiResponse file =
        post("0 0 0\n1 0 0\n0 1 0\n", "text/x-xyz", {{"estimate_normals", "true"}, {"k", "17"}}, context);
    EXPECT_EQ(file.status, 422) << file.body;
    EXPECT_EQ(file.error->field.value_or(""), "k");
    const ApiResponse within = post("{" + points + R"(, "estimate_normals": {"k": 16}, "output": {"format": "json"}})",
                                    "application/json", {}, context);
    EXPECT_NE(within.status, 422) << within.body;
}

TEST(PointcloudOperation, ExpiredDeadlineGives503) {
    ApiContext context;
    context.cancel.deadline = Cancel::Clock::now() - std::chrono::seconds(1);
    const ApiResponse r = post(std::string(R"({"sample": {"mesh": )") + kCubeMesh + R"(, "count": 5000}})",
                               "application/json", {}, context);
    EXPECT_EQ(r.status, 503) << r.body;
    EXPECT_EQ(r.error->code, "cancelled");
}

}  // namespace
}  // namespace surfaced::api
