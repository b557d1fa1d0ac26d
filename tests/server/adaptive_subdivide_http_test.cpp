// POST /subdivide with `tolerance` (the limit surface tessellated adaptively) through the real server on an ephemeral
// loopback port: the raw-file and JSON forms, the headers, the invariants of the decoded mesh, and the problems.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <httplib.h>

#include "geometry/io/mesh_io.h"
#include "geometry/mesh/shapes.h"
#include "geometry/subdivision/subdivide.h"
#include "tests/support/http_test_server.h"
#include "tests/support/mesh_asserts.h"

namespace surfaced::server {
namespace {

using testing::expect_http_problem;

constexpr const char* kCubeObj =
    "v -0.5 -0.5 -0.5\nv 0.5 -0.5 -0.5\nv 0.5 0.5 -0.5\nv -0.5 0.5 -0.5\n"
    "v -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv 0.5 0.5 0.5\nv -0.5 0.5 0.5\n"
    "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

class AdaptiveSubdivideHttp : public testing::SharedServerTest<AdaptiveSubdivideHttp> {
protected:
    static httplib::Client client() { return SharedServerTest::client(60); }
};

// The cube's limit surface to 1e-3: a closed triangle mesh whose volume is that of the dense uniform limit mesh
// (level 6, limit positions) within the tolerance times the area, and whose achieved tolerance is reported.
TEST_F(AdaptiveSubdivideHttp, ObjToleranceToClosedObj) {
    auto res = client().Post("/subdivide?tolerance=0.001&format=obj", kCubeObj, "model/obj");
    ASSERT_TRUE(res) << httplib::to_string(res.error());
    ASSERT_EQ(res->status, 200) << res->body;
    EXPECT_EQ(res->get_header_value("Content-Type"), "model/obj");
    EXPECT_EQ(res->get_header_value("X-Tolerance"), "0.001");
    const double achieved = std::stod(res->get_header_value("X-Achieved-Tolerance"));
    EXPECT_GT(achieved, 0);
    EXPECT_LE(achieved, 0.001);
    auto mesh = read_obj(res->body);
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    EXPECT_TRUE(mesh->is_triangle_mesh());
    EXPECT_EQ(std::to_string(mesh->face_count()), res->get_header_value("X-Output-Faces"));
    EXPECT_TRUE(testing::is_watertight(mesh.value()));

    SubdivisionOptions dense;
    dense.levels = 6;
    dense.limit_surface = true;
    auto reference = subdivide(shapes::cube(), dense);
    ASSERT_TRUE(reference.ok());
    const double area = 4.0;  // the limit surface of the unit cube is smaller than the cube (6)
    EXPECT_NEAR(testing::signed_volume(mesh.value()), testing::signed_volume(reference.value()), 2 * 0.001 * area);
}

TEST_F(AdaptiveSubdivideHttp, JsonToleranceAndItsProblems) {
    const std::string mesh = R"({"mesh": {"positions": [[-0.5,-0.5,-0.5],[0.5,-0.5,-0.5],[0.5,0.5,-0.5],)"
                             R"([-0.5,0.5,-0.5],[-0.5,-0.5,0.5],[0.5,-0.5,0.5],[0.5,0.5,0.5],[-0.5,0.5,0.5]],)"
                             R"( "faces": [[0,3,2,1],[4,5,6,7],[0,1,5,4],[1,2,6,5],[2,3,7,6],[3,0,4,7]]})";
    auto res =
        client().Post("/subdivide", mesh + R"(, "tolerance": 0.01, "output": {"format": "json"}})", "application/json");
    ASSERT_TRUE(res) << httplib::to_string(res.error());
    ASSERT_EQ(res->status, 200) << res->body;
    EXPECT_LE(std::stod(res->get_header_value("X-Achieved-Tolerance")), 0.01);

    expect_http_problem(client().Post("/subdivide", mesh + R"(, "tolerance": 0.01, "levels": 2})", "application/json"),
                        400, "invalid_field", "tolerance");
    expect_http_problem(client().Post("/subdivide", mesh + R"(, "tolerance": 0})", "application/json"), 400,
                        "invalid_field", "tolerance");
    expect_http_problem(client().Post("/subdivide?tolerance=1e-9", kCubeObj, "model/obj"), 422, "budget_exceeded",
                        "tolerance");
}

}  // namespace
}  // namespace surfaced::server
