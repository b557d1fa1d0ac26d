// POST /implicit/query through dispatch (no sockets), and the scene codec's error paths: every bad scene names its
// field path, budgets are checked before work, refs share nodes and cycles are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "api/routes.h"
#include "api/scene_codec.h"
#include "tests/support/api_request.h"

namespace surfaced::api {
namespace {

using Json = nlohmann::json;

using namespace fixtures;

ApiResponse post(const std::string& body, const ApiContext& context = {}) {
    return dispatch(make_request("POST", "/implicit/query", "application/json", body), context);
}

//! A query of one point at the origin against `scene`.
std::string at_origin(const std::string& scene) { return R"({"scene": )" + scene + R"(, "points": [[0, 0, 0]]})"; }

TEST(ImplicitQueryOperation, BoxMinusSphereAnswersPointsAndRays) {
    const ApiResponse response = post(R"({
        "scene": {"op": "difference", "args": [{"op": "box", "half_size": [1, 1, 1]},
                  {"op": "translate", "offset": [0, 0, 1], "arg": {"op": "sphere", "radius": 0.5}}]},
        "points": [[0, 0, 0], [0, 0, 0.75], [2, 0, 0], [1, 0.5, 0]],
        "tolerance": 1e-9,
        "rays": [{"origin": [-5, 0, 0], "direction": [2, 0, 0]}, {"origin": [0, 0, 5], "direction": [0, 0, -1]},
                 {"origin": [0, 5, 0], "direction": [0, 1, 0]}],
        "max_distance": 20, "max_steps": 500})");
    ASSERT_EQ(response.status, 200) << response.body;
    EXPECT_EQ(response.content_type, "application/json");
    const Json out = Json::parse(response.body);
    EXPECT_EQ(out["kind"], "distance_bound");
    EXPECT_EQ(out["lipschitz"], 1.0);
    const auto& points = out["points"];
    ASSERT_EQ(points.size(), 4u);
    EXPECT_EQ(points[0]["class"], "inside");
    EXPECT_NEAR(points[0]["value"].get<double>(), -0.5, 1e-12);  // 0.5 below the sphere's bottom
    EXPECT_EQ(points[1]["class"], "outside");                    // inside the removed ball
    EXPECT_EQ(points[2]["class"], "outside");
    EXPECT_NEAR(points[2]["value"].get<double>(), 1.0, 1e-12);
    EXPECT_EQ(points[3]["class"], "on");
    EXPECT_EQ(points[3]["gradient"], Json::array({1.0, 0.0, 0.0}));
    const auto& rays = out["rays"];
    ASSERT_EQ(rays.size(), 3u);
    EXPECT_TRUE(rays[0]["hit"].get<bool>());
    EXPECT_NEAR(rays[0]["t"].get<double>(), 4.0, 1e-6);  // directions are normalised
    EXPECT_NEAR(rays[0]["normal"][0].get<double>(), -1.0, 1e-9);
    EXPECT_TRUE(rays[1]["hit"].get<bool>());
    EXPECT_NEAR(rays[1]["t"].get<double>(), 4.5, 1e-6);  // through the dent to the ball's bottom at z = 0.5
    EXPECT_NEAR(rays[1]["point"][2].get<double>(), 0.5, 1e-6);
    EXPECT_NEAR(rays[1]["normal"][2].get<double>(), 1.0, 1e-6);
    EXPECT_FALSE(rays[2]["hit"].get<bool>());
    EXPECT_FALSE(rays[2].contains("t"));
    EXPECT_GE(rays[2]["steps"].get<int>(), 1);
}

TEST(ImplicitQueryOperation, RefsShareNodesAndExpressionsAreGeneral) {
    const ApiResponse shared = post(R"({"scene": {"op": "union", "args": [
        {"id": "ball", "op": "sphere", "radius": 1},
        {"op": "translate", "offset": [3, 0, 0], "arg": {"ref": "ball"}},
        {"op": "translate", "offset": [0, 3, 0], "arg": {"ref": "later"}},
        {"op": "translate", "offset": [0, 0, 9], "arg": {"id": "later", "op": "box", "half_size": [1, 1, 1]}}]},
        "points": [[3, 0, 0], [0, 3, 0], [0, 0, 9], [1.5, 0, 0]]})");
    ASSERT_EQ(shared.status, 200) << shared.body;
    const Json out = Json::parse(shared.body);
    EXPECT_EQ(out["points"][0]["class"], "inside");
    EXPECT_EQ(out["points"][1]["class"], "inside");  // a forward reference
    EXPECT_EQ(out["points"][2]["class"], "inside");
    EXPECT_EQ(out["points"][3]["class"], "outside");

    const ApiResponse algebraic = post(R"({"scene": {"op": "expression", "expr": "x^2 + y^2 + z^2 - 1"},
        "points": [[0, 0, 0], [2, 0, 0]], "rays": [{"origin": [-3, 0, 0], "direction": [1, 0, 0]}],
        "max_distance": 6, "max_steps": 3000})");
    ASSERT_EQ(algebraic.status, 200) << algebraic.body;
    const Json a = Json::parse(algebraic.body);
    EXPECT_EQ(a["kind"], "general");
    EXPECT_EQ(a["points"][0]["value"], -1.0);
    EXPECT_EQ(a["points"][1]["gradient"], Json::array({4.0, 0.0, 0.0}));
    EXPECT_NEAR(a["rays"][0]["t"].get<double>(), 2.0, 1e-6);

    const ApiResponse undefined = post(at_origin(R"J({"op": "expression", "expr": "sqrt(x - 1)"})J"));
    ASSERT_EQ(undefined.status, 200) << undefined.body;
    const Json u = Json::parse(undefined.body);
    EXPECT_EQ(u["points"][0]["class"], "undefined");
    EXPECT_TRUE(u["points"][0]["value"].is_null());
}

TEST(ImplicitQueryOperation, EveryOpParses) {
    const char* scenes[] = {
        R"({"op": "rounded_box", "half_size": [1, 1, 1], "radius": 0.2})",
        R"({"op": "torus", "major_radius": 0.2, "minor_radius": 0.5})",
        R"({"op": "cylinder", "radius": 1, "half_height": 1})",
        R"({"op": "cone", "radius": 1, "half_height": 1, "top_radius": 0.5})",
        R"({"op": "capsule", "a": [0, 0, -1], "b": [0, 0, 1], "radius": 0.5})",
        R"({"op": "plane", "normal": [0, 0, 1], "offset": 0.5})",
        R"({"op": "ellipsoid", "radii": [1, 2, 3]})",
        R"({"op": "rotate", "axis": [0, 0, 1], "angle": 45, "arg": {"op": "box", "half_size": [1, 1, 1]}})",
        R"({"op": "rotate", "euler": [10, 20, 30], "arg": {"op": "box", "half_size": [1, 1, 1]}})",
        R"({"op": "scale", "factor": 2, "arg": {"op": "sphere", "radius": 1}})",
        R"({"op": "scale", "factor": [1, 2, 3], "arg": {"op": "sphere", "radius": 1}})",
        R"({"op": "intersection", "args": [{"op": "sphere", "radius": 1}, {"op": "box", "half_size": [1, 1, 1]}]})",
        R"({"op": "blend", "t": 0.5, "args": [{"op": "sphere", "radius": 1}, {"op": "box", "half_size": [1, 1, 1]}]})",
        R"({"op": "smooth_union", "k": 0.3, "args": [{"op": "sphere", "radius": 1}, {"op": "sphere", "radius": 0.5}]})",
        R"({"op": "smooth_intersection", "k": 0.3, "args": [{"op": "sphere", "radius": 1}, {"op": "sphere", "radius": 2}]})",
        R"({"op": "smooth_difference", "k": 0.3, "args": [{"op": "sphere", "radius": 1}, {"op": "plane", "normal": [1, 0, 0], "offset": -0.5}]})",
        R"({"op": "offset", "distance": 0.1, "arg": {"op": "sphere", "radius": 1}})",
        R"({"op": "shell", "thickness": 4, "arg": {"op": "sphere", "radius": 1}})",
        R"({"op": "level_set", "dims": [2, 2, 2], "origin": [-1, -1, -1], "spacing": 2, "values": [-1, -1, -1, -1, -1, -1, -1, 1]})",
        R"({"op": "level_set", "dims": [2, 2, 2], "origin": [-1, -1, -1], "spacing": [2, 2, 2], "values": [-1, -1, -1, -1, -1, -1, -1, 1]})",
        R"({"op": "mandelbulb", "power": 8, "iterations": 10})",
        R"({"op": "menger", "iterations": 0, "half_size": 2})",
    };
    for (const char* scene : scenes) {
        const ApiResponse response = post(at_origin(scene));
        ASSERT_EQ(response.status, 200) << scene << ": " << response.body;
        EXPECT_EQ(Json::parse(response.body)["points"][0]["class"], "inside") << scene;
    }
}

TEST(ImplicitQueryOperation, SceneErrorsNameTheFieldPath) {
    struct Case {
        std::string scene;
        int status;
        std::string code, field;
    };
    const std::string ball = R"({"op": "sphere", "radius": 1})";
    const Case cases[] = {
        {R"({"op": "difference", "args": [)" + ball +
             R"(, {"op": "translate", "offset": [0, 0, 1], "arg": {"op": "sphere", "radius": -0.5}}]})",
         422, "invalid_argument", "scene.args[1].arg.radius"},
        {R"({"op": "union", "args": [)" + ball + R"(, {"op": "spehre", "radius": 1}]})", 400, "invalid_field",
         "scene.args[1].op"},
        {R"({"op": "sphere", "radius": 1, "center": [0, 0, 0]})", 400, "unknown_field", "scene.center"},
        {R"({"op": "sphere"})", 400, "invalid_field", "scene.radius"},
        {R"({"op": "sphere", "radius": "1"})", 400, "invalid_field", "scene.radius"},
        {R"({"radius": 1})", 400, "invalid_field", "scene.op"},
        {R"([1, 2])", 400, "invalid_field", "scene"},
        {R"({"op": "box", "half_size": [1, 0, 1]})", 422, "invalid_argument", "scene.half_size[1]"},
        {R"({"op": "box", "half_size": [1, 1]})", 400, "invalid_field", "scene.half_size"},
        {R"({"op": "union", "args": [{"ref": "nowhere"}]})", 400, "invalid_field", "scene.args[0].ref"},
        {R"({"op": "union", "args": [{"ref": "a", "op": "sphere"}]})", 400, "unknown_field", "scene.args[0].op"},
        {R"({"id": "a", "op": "translate", "offset": [1, 0, 0], "arg": {"ref": "a"}})", 400, "invalid_field",
         "scene.arg.ref"},
        {R"({"op": "union", "args": [{"id": "a", "op": "scale", "factor": 2, "arg": {"ref": "b"}}, {"id": "b", "op": "offset", "distance": 1, "arg": {"ref": "a"}}]})",
         400, "invalid_field", "scene.args[1].arg.ref"},
        {R"({"op": "union", "args": [{"id": "a", "op": "sphere", "radius": 1}, {"id": "a", "op": "sphere", "radius": 2}]})",
         400, "invalid_field", "scene.args[1].id"},
        {R"({"op": "union", "args": []})", 400, "invalid_field", "scene.args"},
        {R"({"op": "difference", "args": [)" + ball + "]}", 400, "invalid_field", "scene.args"},
        {R"({"op": "blend", "t": 1.5, "args": [)" + ball + "," + ball + "]}", 422, "invalid_argument", "scene.t"},
        {R"({"op": "rotate", "axis": [0, 0, 0], "angle": 3, "arg": )" + ball + "}", 422, "invalid_argument",
         "scene.axis"},
        {R"({"op": "rotate", "euler": [0, 0, 0], "angle": 3, "arg": )" + ball + "}", 400, "invalid_field", "scene"},
        {R"({"op": "rounded_box", "half_size": [1, 1, 1], "radius": 2})", 422, "invalid_argument", "scene.radius"},
        {R"({"op": "expression", "expr": "x^2 + * y"})", 400, "invalid_field", "scene.expr"},
        {R"({"op": "expression", "expr": 3})", 400, "invalid_field", "scene.expr"},
        {R"({"op": "mandelbulb", "iterations": 1000})", 422, "budget_exceeded", "scene.iterations"},
        {R"({"op": "menger", "iterations": 65})", 422, "budget_exceeded", "scene.iterations"},
        {R"({"op": "menger", "iterations": -1})", 422, "invalid_argument", "scene.iterations"},
        {R"({"op": "level_set", "dims": [100000, 100000, 100000], "origin": [0, 0, 0], "spacing": 1, "values": []})",
         422, "budget_exceeded", "scene.dims"},
        {R"({"op": "level_set", "dims": [2, 2, 2], "origin": [0, 0, 0], "spacing": 1, "values": [1, 2, 3]})", 400,
         "invalid_field", "scene.values"},
        {R"({"op": "level_set", "dims": [2, 2, 2], "origin": [0, 0, 0], "spacing": 1, "values": [1, 2, 3, 4, 5, 6, "7", 8]})",
         400, "invalid_field", "scene.values[6]"},
        {R"({"op": "level_set", "dims": [2, 2, 2], "origin": [0, 0, 0], "spacing": -1, "values": [1, 2, 3, 4, 5, 6, 7, 8]})",
         422, "invalid_argument", "scene.spacing"},
        {R"({"op": "sphere", "radius": 1e999})", 400, "number_out_of_range", "<none>"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.scene);
        expect_problem(post(at_origin(c.scene)), c.status, c.code, c.field);
    }
    // the expression's character offset is in the detail
    const ApiResponse bad = post(at_origin(R"({"op": "expression", "expr": "x^2 + * y"})"));
    EXPECT_NE(bad.error->detail.find("at character 6"), std::string::npos) << bad.error->detail;
}

TEST(ImplicitQueryOperation, BudgetsAreCheckedBeforeWork) {
    ApiContext small;
    small.limits.max_scene_nodes = 3;
    small.limits.max_expression_nodes = 5;
    small.limits.max_expression_depth = 4;
    small.limits.max_query_points = 2;
    small.limits.max_ray_steps = 50;
    small.limits.max_level_set_samples = 7;
    const std::string ball = R"({"op": "sphere", "radius": 1})";
    expect_problem(post(at_origin(R"({"op": "union", "args": [)" + ball + "," + ball + "," + ball + "]}"), small), 422,
                   "budget_exceeded", "scene.args[2]");
    EXPECT_EQ(post(at_origin(R"({"op": "union", "args": [)" + ball + "," + ball + "]}"), small).status, 200);
    expect_problem(post(at_origin(R"({"op": "expression", "expr": "x+y+z+1"})"), small), 422, "budget_exceeded",
                   "scene.expr");
    expect_problem(post(at_origin(R"J({"op": "expression", "expr": "(((((x)))))"})J"), small), 422, "budget_exceeded",
                   "scene.expr");
    expect_problem(
        post(at_origin(R"({"op": "level_set", "dims": [2, 2, 2], "origin": [0, 0, 0], "spacing": 1, "values": []})"),
             small),
        422, "budget_exceeded", "scene.dims");
    // the scene is never read when the request is over a budget: a broken scene still gets the budget error
    expect_problem(post(R"({"scene": 0, "points": [[0, 0, 0], [1, 1, 1], [2, 2, 2]]})", small), 422, "budget_exceeded",
                   "points");
    expect_problem(
        post(
            R"({"scene": 0, "points": [[0, 0, 0]], "rays": [{"origin": [0, 0, 0], "direction": [1, 0, 0]}], "max_steps": 51})",
            small),
        422, "budget_exceeded", "max_steps");
}

TEST(ImplicitQueryOperation, DeepScenesAreRefusedNotOverflowed) {
    auto nested = [](int depth) {
        std::string scene = R"({"op": "sphere", "radius": 1})";
        for (int i = 0; i < depth; ++i) scene = R"({"op": "translate", "offset": [0.001, 0, 0], "arg": )" + scene + "}";
        return scene;
    };
    const ApiResponse ok = post(at_origin(nested(99)));
    ASSERT_EQ(ok.status, 200) << ok.body;
    EXPECT_NEAR(Json::parse(ok.body)["points"][0]["value"].get<double>(), -0.901, 1e-9);
    const ApiResponse deep = post(at_origin(nested(101)));
    EXPECT_EQ(deep.status, 422);
    EXPECT_EQ(deep.error->code, "budget_exceeded");
}

TEST(ImplicitQueryOperation, OptionsAreReadByTheirTable) {
    const std::string head = R"({"scene": {"op": "sphere", "radius": 1}, "points": [[0, 0, 0]], )";
    // the range, the units and the value in the detail, as every operation words it
    const ApiResponse range = post(head + R"("max_distance": -2})");
    ASSERT_EQ(range.status, 400);
    EXPECT_EQ(range.error->field, "max_distance");
    EXPECT_EQ(range.error->detail, "max_distance must be > 0 (model units), got -2");
    const ApiResponse steps = post(head + R"("max_steps": 0})");
    ASSERT_EQ(steps.status, 400);
    EXPECT_EQ(steps.error->detail, "max_steps must be in [1, 10000], got 0");
    // a wrong type, and a whole number given as a fraction
    expect_problem(post(head + R"("tolerance": "small"})"), 400, "invalid_field", "tolerance");
    expect_problem(post(head + R"("max_steps": 2.5})"), 400, "invalid_field", "max_steps");
    // a misspelt option gets the table's suggestion
    const ApiResponse typo = post(head + R"("max_step": 10})");
    ASSERT_EQ(typo.status, 400);
    EXPECT_EQ(typo.error->code, "unknown_field");
    EXPECT_NE(typo.error->detail.find("max_steps"), std::string::npos) << typo.error->detail;
    // in range, the values take effect: a ray searched to 3 misses the sphere 4 away
    const ApiResponse short_ray = post(
        R"({"scene": {"op": "sphere", "radius": 1}, "rays": [{"origin": [-5, 0, 0], "direction": [1, 0, 0]}],
            "max_distance": 3})");
    ASSERT_EQ(short_ray.status, 200) << short_ray.body;
    EXPECT_FALSE(Json::parse(short_ray.body)["rays"][0]["hit"].get<bool>());
    const ApiResponse long_ray =
        post(R"({"scene": {"op": "sphere", "radius": 1}, "rays": [{"origin": [-5, 0, 0], "direction": [1, 0, 0]}]})");
    ASSERT_EQ(long_ray.status, 200) << long_ray.body;
    EXPECT_TRUE(Json::parse(long_ray.body)["rays"][0]["hit"].get<bool>());
}

TEST(ImplicitQueryOperation, RequestErrors) {
    const std::string scene = R"({"op": "sphere", "radius": 1})";
    expect_problem(post(R"({"scene": )" + scene + R"(, "points": [[0, 0]]})"), 400, "invalid_field", "points[0]");
    expect_problem(post(R"({"scene": )" + scene + R"(, "points": [[0, 0, "a"]]})"), 400, "invalid_field",
                   "points[0][2]");
    expect_problem(post(R"({"scene": )" + scene + R"(, "rays": [{"origin": [0, 0, 0], "direction": [0, 0, 0]}]})"), 422,
                   "invalid_argument", "rays[0].direction");
    expect_problem(post(R"({"scene": )" + scene + R"(, "rays": [{"origin": [0, 0, 0]}]})"), 400, "invalid_field",
                   "rays[0].direction");
    expect_problem(post(R"({"scene": )" + scene + R"(, "rays": [{"origin": [0, 0, 0], "dir": [1, 0, 0]}]})"), 400,
                   "unknown_field", "rays[0].dir");
    expect_problem(post(R"({"scene": )" + scene + R"(, "points": [[0, 0, 0]], "tolerance": -1})"), 400, "invalid_field",
                   "tolerance");
    expect_problem(post(R"({"scene": )" + scene + R"(, "points": [[0, 0, 0]], "max_distance": 0})"), 400,
                   "invalid_field", "max_distance");
    expect_problem(post(R"({"scene": )" + scene + R"(, "points": [[0, 0, 0]], "resolution": 3})"), 400, "unknown_field",
                   "resolution");
    expect_problem(post(R"({"scene": )" + scene + "}"), 400, "invalid_field", "points");
    expect_problem(post(R"({"points": [[0, 0, 0]]})"), 400, "invalid_field", "scene");
    const ApiResponse broken = post(R"({"scene": )");
    EXPECT_EQ(broken.status, 400);
    EXPECT_EQ(broken.error->code, "invalid_json");
    ApiRequest text;
    text.method = "POST";
    text.path = "/implicit/query";
    text.content_type = "text/plain";
    text.body = "{}";
    EXPECT_EQ(dispatch(text, ApiContext{}).status, 415);
}

TEST(SceneCodec, Bounds) {
    auto ok = parse_bounds(Json::parse("[[-1, -2, -3], [1, 2, 3]]"));
    ASSERT_TRUE(ok.ok());
    EXPECT_EQ(ok.value().min, (Vec3{-1, -2, -3}));
    EXPECT_EQ(ok.value().max, (Vec3{1, 2, 3}));
    auto flat = parse_bounds(Json::parse("[[-1, 2, -3], [1, 2, 3]]"));
    ASSERT_FALSE(flat.ok());
    EXPECT_EQ(flat.error().field.value_or(""), "bounds[1][1]");
    auto shape = parse_bounds(Json::parse("[[-1, 2, -3]]"));
    ASSERT_FALSE(shape.ok());
    EXPECT_EQ(shape.error().field.value_or(""), "bounds");
    auto type = parse_bounds(Json::parse(R"([[-1, 2, "x"], [1, 2, 3]])"), "mesh.bounds");
    ASSERT_FALSE(type.ok());
    EXPECT_EQ(type.error().field.value_or(""), "mesh.bounds[0][2]");
}

TEST(SceneCodec, ParseSceneDirectlyWithACustomPath) {
    auto field = parse_scene(Json::parse(R"({"op": "sphere", "radius": 2})"), Limits{}, "body.shape");
    ASSERT_TRUE(field.ok());
    EXPECT_NEAR(field.value()->value({3, 0, 0}), 1.0, 1e-15);
    auto bad = parse_scene(Json::parse(R"({"op": "sphere", "radius": 0})"), Limits{}, "body.shape");
    ASSERT_FALSE(bad.ok());
    EXPECT_EQ(bad.error().field.value_or(""), "body.shape.radius");
}

}  // namespace
}  // namespace surfaced::api
