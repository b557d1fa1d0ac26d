// POST /subdivide with format "patches": the limit surface as bicubic Bézier patches, the same bytes as the library's
// limit_patches() encoded, a body POST /tessellate takes and welds watertight, and every option that does not apply
// refused by name.
#include <gtest/gtest.h>

#include <string>

#include <nlohmann/json.hpp>

#include "api/operations/request_forms.h"
#include "api/operations/subdivide.h"
#include "api/operations/tessellate.h"
#include "api/patch_codec.h"
#include "geometry/io/mesh_io.h"
#include "geometry/mesh/shapes.h"
#include "geometry/subdivision/limit_patches.h"
#include "tests/support/api_request.h"
#include "tests/support/mesh_asserts.h"

namespace surfaced::api {
namespace {

using namespace fixtures;

ApiResponse call(const std::string& content_type, const std::string& body,
                 std::multimap<std::string, std::string> query = {}, const Limits& limits = {}) {
    return operations::subdivide(make_request("POST", "/subdivide", content_type, body, std::move(query)),
                                 context_with(limits));
}

constexpr const char* kCubeObj =
    "v -0.5 -0.5 -0.5\nv 0.5 -0.5 -0.5\nv 0.5 0.5 -0.5\nv -0.5 0.5 -0.5\n"
    "v -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv 0.5 0.5 0.5\nv -0.5 0.5 0.5\n"
    "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

TEST(SubdividePatches, UploadAnswersTheLibrarysPatchesAsTessellateInput) {
    const ApiResponse response = call("model/obj", kCubeObj, {{"format", "patches"}});
    ASSERT_EQ(response.status, 200) << response.body;
    EXPECT_EQ(response.content_type, "application/json");

    // the library's answer for the same mesh and the documented default tolerance (1e-3 of the diagonal)
    auto mesh = read_obj(kCubeObj);
    ASSERT_TRUE(mesh.ok());
    auto evaluator = LimitSurfaceEvaluator::create(*mesh, SubdivisionOptions{});
    ASSERT_TRUE(evaluator.ok());
    LimitPatchOptions options;
    options.tolerance = 1e-3 * std::sqrt(3.0);
    options.max_levels = 8;
    auto expected = limit_patches(*evaluator, *mesh, options);
    ASSERT_TRUE(expected.ok());
    PatchSet set;
    set.patches = expected->patches;
    EXPECT_EQ(response.body, patch_set_json(set));
    EXPECT_EQ(header(response, "X-Patches"), std::to_string(expected->patches.size()));
    EXPECT_EQ(header(response, "X-Isolation-Level"), std::to_string(expected->levels));
    EXPECT_EQ(header(response, "X-Approximate-Patches"), std::to_string(expected->approximate_count));
    EXPECT_LE(std::stod(header(response, "X-Max-Error")), 1e-3 * std::sqrt(3.0));
    EXPECT_EQ(header(response, "X-Input-Faces"), "6");

    // POST /tessellate takes the body as it is and welds the patches into a closed sphere-like surface
    const ApiResponse tessellated =
        operations::tessellate(make_request("POST", "/tessellate", "application/json",
                                            R"({"patches": )" + nlohmann::json::parse(response.body)["patches"].dump() +
                                                R"(, "segments": 3, "output": {"format": "obj"}})"),
                               context_with());
    ASSERT_EQ(tessellated.status, 200) << tessellated.body;
    auto surface = read_obj(tessellated.body);
    ASSERT_TRUE(surface.ok());
    EXPECT_TRUE(testing::is_watertight(*surface));
    EXPECT_EQ(testing::euler_characteristic(*surface), 2);
}

TEST(SubdividePatches, JsonLevelsIsTheIsolationLevel) {
    const ApiResponse response =
        call("application/json", json_request(shapes::cube(), R"(,"levels":1,"output":{"format":"patches"})"));
    ASSERT_EQ(response.status, 200) << response.body;
    const auto json = nlohmann::json::parse(response.body);
    EXPECT_EQ(json["patches"].size(), 24u);
    EXPECT_EQ(header(response, "X-Isolation-Level"), "1");
    EXPECT_EQ(header(response, "X-Approximate-Patches"), "24");  // every square touches one of the 8 corners
    for (const auto& patch : json["patches"]) {
        EXPECT_EQ(patch["degree"], nlohmann::json::array({3, 3}));
        EXPECT_EQ(patch["points"].size(), 16u);
    }
}

TEST(SubdividePatches, ToleranceBoundsTheApproximatedPatches) {
    const ApiResponse at_two = call("model/obj", kCubeObj, {{"format", "patches"}, {"levels", "2"}});
    ASSERT_EQ(at_two.status, 200) << at_two.body;
    const double error = std::stod(header(at_two, "X-Max-Error"));
    const ApiResponse loose =
        call("model/obj", kCubeObj, {{"format", "patches"}, {"tolerance", operations::format_double(error * 1.0001)}});
    ASSERT_EQ(loose.status, 200) << loose.body;
    EXPECT_EQ(header(loose, "X-Isolation-Level"), "2");
    EXPECT_EQ(loose.body, at_two.body);
    const ApiResponse tight =
        call("model/obj", kCubeObj, {{"format", "patches"}, {"tolerance", operations::format_double(error * 0.9)}});
    ASSERT_EQ(tight.status, 200) << tight.body;
    EXPECT_EQ(header(tight, "X-Isolation-Level"), "3");
    EXPECT_LE(std::stod(header(tight, "X-Max-Error")), error * 0.9);
}

TEST(SubdividePatches, OptionsThatDoNotApplyAreRefusedByName) {
    expect_problem(call("model/obj", kCubeObj, {{"format", "patches"}, {"compression", "none"}}), 400, "invalid_field",
                   "compression");
    expect_problem(call("model/obj", kCubeObj, {{"format", "patches"}, {"normals", "false"}}), 400, "invalid_field",
                   "normals");
    expect_problem(call("model/obj", kCubeObj, {{"format", "patches"}, {"target_faces", "100"}}), 400, "invalid_field",
                   "target_faces");
    expect_problem(call("model/obj", kCubeObj, {{"format", "patches"}, {"limit_surface", "true"}}), 400,
                   "invalid_field", "limit_surface");
    expect_problem(call("application/json",
                        json_request(shapes::cube(), R"(,"output":{"format":"patches","quantize_position":12})")),
                   400, "invalid_field", "output.quantize_position");
    expect_problem(call("application/json",
                        json_request(shapes::octahedron(), R"(,"scheme":"loop","output":{"format":"patches"})")),
                   400, "invalid_field", "scheme");
    // N-gons' patches lie in their quad sub-faces: level 0 cannot hold them
    expect_problem(call("application/json",
                        json_request(shapes::mixed_polygons(), R"(,"levels":0,"output":{"format":"patches"})")),
                   400, "invalid_field", "levels");
}

TEST(SubdividePatches, PatchBudgetIsCheckedBeforeWork) {
    Limits limits;
    limits.max_patches = 95;  // level 2 of the cube makes 96
    expect_problem(call("model/obj", kCubeObj, {{"format", "patches"}, {"levels", "2"}}, limits), 422,
                   "budget_exceeded", "levels");
    // without levels: the tolerance needs level 2, which the budget does not allow
    expect_problem(call("model/obj", kCubeObj, {{"format", "patches"}}, limits), 422, "budget_exceeded", "levels");
}

}  // namespace
}  // namespace surfaced::api
