// POST /curves called directly: the single Bézier curve form (byte-identical to before), chains (continuity per joint,
// C1/G1 enforcement, evaluation, length, tessellation), SVG path data, B-splines/NURBS (de Boor evaluation, knot
// insertion, Bézier extraction), LINE_STRIP glTF output through the Khronos validator, the CLI's file form, the
// OpenAPI examples, and errors with field paths and budgets.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/openapi.h"
#include "api/operations/curves.h"
#include "geometry/io/polyline_gltf.h"
#include "tests/support/api_request.h"
#include "tests/support/gltf_validator.h"

namespace surfaced::api {
namespace {

using nlohmann::json;
using namespace fixtures;
using operations::kMaxCurveQueries;

ApiResponse post(const std::string& body, const ApiContext& context = {}) {
    return operations::curves(make_request("POST", "/curves", "application/json", body), context);
}

json ok_json(const ApiResponse& r) {
    EXPECT_EQ(r.status, 200) << r.body;
    EXPECT_EQ(r.content_type, "application/json");
    return json::parse(r.body, nullptr, false);
}

//! The JSON chunk of a GLB (its structure is checked by the validator separately).
json glb_json(const std::string& glb) {
    if (glb.size() < 20 || glb.compare(0, 4, "glTF") != 0) return {};
    std::uint32_t length = 0;
    std::memcpy(&length, glb.data() + 12, 4);
    return json::parse(glb.substr(20, length), nullptr, false);
}

void expect_valid_gltf(const std::string& bytes) {
    const auto v = testing::run_gltf_validator(bytes);
    ASSERT_TRUE(v.ran) << v.report;
    EXPECT_EQ(v.errors, 0) << v.report;
    EXPECT_EQ(v.warnings, 0) << v.report;
}

double dist(const json& a, const json& b) {
    double s = 0;
    for (std::size_t i = 0; i < a.size(); ++i)
        s += (a[i].get<double>() - b[i].get<double>()) * (a[i].get<double>() - b[i].get<double>());
    return std::sqrt(s);
}

// Responses of the single-curve form recorded from the service before chains, SVG paths and B-splines were added
// (commit 9803d60, `POST /curves` on a running server), with numbers as every output prints them (shortest round
// trip, integral values without ".0"; the same doubles as recorded): the form must answer byte for byte the same.
const char* kGoldenRequest1 =
    R"({"points":[[0,0],[1,2],[3,2],[4,0]],"evaluate":[0,0.5,1],"length":{"tolerance":1e-6},"closest":[2,3],"tessellate":{"tolerance":0.01}})";
const char* kGoldenResponse1 =
    R"({"closest":{"distance":1.5,"point":[2,1.5],"t":0.5},"degree":3,"evaluate":[[0,0],[2,1.5],[4,0]],"length":{"error_bound":2.530535923635918e-07,"guaranteed":true,"length":5.268365543018511},"rational":false,"tessellate":{"bound":0.00992337859837185,"max_deviation":0.008875739644970349,"params":[0,0.07692307692307693,0.15384615384615385,0.23076923076923078,0.3076923076923077,0.38461538461538464,0.46153846153846156,0.5384615384615384,0.6153846153846154,0.6923076923076923,0.7692307692307693,0.8461538461538461,0.9230769230769231,1],"points":[[0,0],[0.24761037778789258,0.42603550295857995],[0.5252617205279928,0.7810650887573964],[0.8274920345926262,1.0650887573964496],[1.1488393263541195,1.2781065088757397],[1.483841602184798,1.4201183431952664],[1.8270368684569869,1.4911242603550297],[2.172963131543013,1.4911242603550297],[2.516158397815203,1.4201183431952662],[2.8511606736458805,1.2781065088757397],[3.172507965407374,1.0650887573964496],[3.474738279472007,0.7810650887573964],[3.752389622212108,0.42603550295857967],[4,0]],"segments":13}})";
const char* kGoldenRequest2 =
    R"({"points":[[1,0,0],[1,1,0],[0,1,0.5]],"weights":[1,0.7071067811865476,1],"evaluate":[0.25,0.75],"derivatives":{"t":[0,0.3,1],"order":2},"curvature":[0,0.5],"split":0.4,"elevate":2,"bounding_box":true,"length":{"tolerance":1e-4},"closest":[0.2,0.3,0.1],"tessellate":{"tolerance":0.001}})";
const char* kGoldenResponse2 =
    R"({"bounding_box":{"max":[1,1,0.5],"min":[0,0,0]},"closest":{"distance":0.6475083549684735,"point":[0.6290219127597764,0.7773875695353202,0.18548904362011182],"t":0.5634941952727408},"curvature":[1.1180339887498947,0.9369711585684087],"degree":2,"derivatives":[[-2,0.8284271247461898,1],[-2.52368787629422,-0.7608488877219749,1.26184393814711],[0.8284271247461898,-2,-0.4142135623730949]],"elevate":{"points":[[1,0,0],[1,0.41421356237309515,0],[0.7928932188134523,0.7928932188134524,0.10355339059327376],[0.41421356237309503,1,0.2928932188134525],[0,1,0.5]],"weights":[1,0.8535533905932737,0.804737854124365,0.8535533905932737,1]},"evaluate":[[0.9297883010624304,0.36809470956187285,0.03510584946878485],[0.36809470956187285,0.9297883010624304,0.3159526452190637]],"length":{"error_bound":2.791405352709983e-05,"guaranteed":false,"length":1.664791805695889},"rational":true,"split":[{"points":[[1,0,0],[1,0.3203772410170408,0],[0.8138260360510752,0.581108581114919,0.0930869819744625]],"weights":[1,0.882842712474619,0.8594112549695427]},{"points":[[0.8138260360510752,0.581108581114919,0.0930869819744625],[0.5147186257614298,1,0.2426406871192852],[0,1,0.5]],"weights":[0.8594112549695427,0.8242640687119285,1]}],"tessellate":{"bound":0.0007107450003596631,"max_deviation":0.00035531320530968376,"params":[0,0.03125,0.0625,0.09375,0.125,0.15625,0.1875,0.21875,0.25,0.28125,0.3125,0.34375,0.375,0.40625,0.4375,0.46875,0.5,0.53125,0.5625,0.59375,0.625,0.65625,0.6875,0.71875,0.75,0.78125,0.8125,0.84375,0.875,0.90625,0.9375,0.96875,1],"points":[[1,0,0],[0.9990058067056695,0.044580244148657945,0.0004970966471651102],[0.9959549086128785,0.08985443789770466,0.0020225456935606557],[0.9907506046682437,0.13569539177698584,0.004624697665878197],[0.9833053684165747,0.18196305241214475,0.00834731579171281],[0.9735427010427451,0.22850516240644608,0.013228649478627468],[0.9613989581870315,0.27515821484536934,0.019300520906484247],[0.9468250988416779,0.321748709715279,0.02658745057916106],[0.9297883010624306,0.3680947095618728,0.03510584946878485],[0.9102733877567537,0.41400768053484627,0.04486330612162331],[0.8882840068297528,0.45929459305600345,0.05585799658512362],[0.8638435137474316,0.5037602443191515,0.06807824312628423],[0.836995511218651,0.5472097533851425,0.0815022443906743],[0.8078040101090123,0.5894511695228015,0.09609799494549379],[0.7763531875748432,0.6302981263992306,0.11182340621257846],[0.7427467322257565,0.669572469392194,0.12862663388712178],[0.7071067811865475,0.7071067811865475,0.14644660940672624],[0.669572469392194,0.7427467322257565,0.16521376530390308],[0.6302981263992306,0.7763531875748432,0.18485093680038475],[0.5894511695228015,0.8078040101090123,0.20527441523859918],[0.5472097533851425,0.836995511218651,0.22639512330742864],[0.5037602443191515,0.8638435137474316,0.24811987784042436],[0.45929459305600345,0.8882840068297528,0.27035270347199836],[0.41400768053484627,0.9102733877567537,0.292996159732577],[0.3680947095618728,0.9297883010624306,0.3159526452190638],[0.321748709715279,0.9468250988416779,0.33912564514236054],[0.27515821484536934,0.9613989581870315,0.3624208925773153],[0.22850516240644608,0.9735427010427451,0.385747418796777],[0.18196305241214475,0.9833053684165747,0.40901847379392764],[0.13569539177698584,0.9907506046682437,0.43215230411150707],[0.08985443789770466,0.9959549086128785,0.45507278105114757],[0.044580244148657945,0.9990058067056695,0.477709877925671],[0,1,0.5]],"segments":32}})";

// ---- one Bézier curve ----------------------------------------------------------------------------------------------

TEST(CurvesOperation, SingleCurveAnswersAsBefore) {
    const ApiResponse r1 = post(kGoldenRequest1);
    ASSERT_EQ(r1.status, 200) << r1.body;
    EXPECT_EQ(r1.content_type, "application/json");
    EXPECT_EQ(r1.body, kGoldenResponse1);
    const ApiResponse r2 = post(kGoldenRequest2);
    ASSERT_EQ(r2.status, 200) << r2.body;
    EXPECT_EQ(r2.body, kGoldenResponse2);
    EXPECT_TRUE(r1.headers.empty());
}

TEST(CurvesOperation, AcceptPicksTheFormatTheBodyDoesNotName) {
    const std::string body = R"({"points": [[0,0],[1,2],[3,2],[4,0]], "tessellate": {"tolerance": 0.01}})";
    const auto with_accept = [&](const std::string& accept, const std::string& request_body) {
        ApiRequest request = make_request("POST", "/curves", "application/json", request_body);
        request.headers.emplace("accept", accept);
        return operations::curves(request, ApiContext{});
    };
    // the same bytes as output.format glb
    const ApiResponse named = post(R"({"points": [[0,0],[1,2],[3,2],[4,0]], "tessellate": {"tolerance": 0.01},)"
                                   R"( "output": {"format": "glb"}})");
    const ApiResponse glb = with_accept("model/gltf-binary", body);
    ASSERT_EQ(glb.status, 200) << glb.body;
    EXPECT_EQ(glb.content_type, "model/gltf-binary");
    EXPECT_EQ(glb.body, named.body);
    EXPECT_EQ(with_accept("model/gltf+json;q=0.9, application/json;q=0.5", body).content_type, "model/gltf+json");
    // a tie, or anything: json, the default
    EXPECT_EQ(with_accept("*/*", body).content_type, "application/json");
    EXPECT_EQ(with_accept("application/json, model/gltf-binary", body).content_type, "application/json");
    // a format named in the body wins over Accept
    const ApiResponse body_wins = with_accept(
        "model/gltf-binary", R"({"points": [[0,0],[1,2]], "output": {"format": "json"}, "evaluate": [0.5]})");
    EXPECT_EQ(body_wins.status, 200) << body_wins.body;
    EXPECT_EQ(body_wins.content_type, "application/json");
    // nothing acceptable: 406 naming the media types /curves answers with
    const ApiResponse none = with_accept("image/png", body);
    EXPECT_EQ(none.status, 406) << none.body;
    EXPECT_NE(none.body.find("model/gltf-binary"), std::string::npos) << none.body;
    EXPECT_NE(none.body.find("application/json"), std::string::npos) << none.body;
    // glb chosen by Accept still needs the tessellation: the same 400 as output.format glb without it
    const ApiResponse no_tessellation =
        with_accept("model/gltf-binary", R"({"points": [[0,0],[1,2]], "evaluate": [0.5]})");
    EXPECT_EQ(no_tessellation.status, 400) << no_tessellation.body;
    EXPECT_NE(no_tessellation.body.find("\"field\":\"tessellate\""), std::string::npos) << no_tessellation.body;
}

TEST(CurvesOperation, SingleCurveTessellationAsGlbLineStrip) {
    const std::string base = R"({"points": [[0,0],[1,2],[3,2],[4,0]], "tessellate": {"tolerance": 0.01})";
    const json reference = ok_json(post(base + "}"));
    const std::size_t segments = reference["tessellate"]["segments"];

    const ApiResponse glb = post(base + R"(, "output": {"format": "glb"}})");
    ASSERT_EQ(glb.status, 200) << glb.body;
    EXPECT_EQ(glb.content_type, "model/gltf-binary");
    EXPECT_EQ(header(glb, "X-Segments"), std::to_string(segments));
    EXPECT_EQ(header(glb, "X-Polylines"), "1");
    expect_valid_gltf(glb.body);
    const json doc = glb_json(glb.body);
    ASSERT_EQ(doc["meshes"][0]["primitives"].size(), 1u);
    const json& primitive = doc["meshes"][0]["primitives"][0];
    EXPECT_EQ(primitive["mode"], 3);  // LINE_STRIP
    EXPECT_FALSE(primitive.contains("indices"));
    EXPECT_FALSE(doc.contains("extensionsUsed"));  // no Draco for lines
    const json& accessor = doc["accessors"][primitive["attributes"]["POSITION"].get<int>()];
    EXPECT_EQ(accessor["count"], segments + 1);
    // min/max are those of the JSON polyline's points as floats; the curve's top (1.5, at t = 1/2) is within the
    // tolerance above the polyline's
    double max_y = 0;
    for (const json& p : reference["tessellate"]["points"]) max_y = std::max(max_y, p[1].get<double>());
    EXPECT_EQ(accessor["min"], json::array({0.0, 0.0, 0.0}));
    EXPECT_EQ(accessor["max"][0].get<double>(), 4.0);
    EXPECT_EQ(accessor["max"][1].get<double>(), static_cast<double>(static_cast<float>(max_y)));
    EXPECT_GE(accessor["max"][1].get<double>(), 1.5 - 0.01);
    EXPECT_EQ(accessor["max"][2].get<double>(), 0.0);

    const ApiResponse gltf = post(base + R"(, "output": {"format": "gltf", "compression": "none"}})");
    ASSERT_EQ(gltf.status, 200) << gltf.body;
    EXPECT_EQ(gltf.content_type, "model/gltf+json");
    expect_valid_gltf(gltf.body);
    const json text = json::parse(gltf.body);
    EXPECT_TRUE(text["buffers"][0]["uri"].get<std::string>().starts_with("data:application/octet-stream;base64,"));
}

TEST(CurvesOperation, GltfOutputErrorsNameTheirField) {
    const std::string curve = R"("points": [[0,0],[1,2],[3,2]])";
    expect_problem(post("{" + curve + R"(, "output": {"format": "glb"}})"), 400, "invalid_field", "tessellate");
    expect_problem(
        post("{" + curve + R"(, "tessellate": {"tolerance": 0.1}, "evaluate": [0.5], "output": {"format": "glb"}})"),
        400, "invalid_field", "evaluate");
    expect_problem(post("{" + curve +
                        R"(, "tessellate": {"tolerance": 0.1}, "output": {"format": "glb", "compression": "draco"}})"),
                   400, "invalid_field", "output.compression");
    expect_problem(post("{" + curve + R"(, "tessellate": {"tolerance": 0.1}, "output": {"format": "obj"}})"), 400,
                   "invalid_field", "output.format");
    expect_problem(post("{" + curve + R"(, "output": {"format": "stl"}})"), 400, "invalid_field", "output.format");
    expect_problem(
        post("{" + curve + R"(, "tessellate": {"tolerance": 0.1}, "output": {"format": "glb", "normals": true}})"), 400,
        "unknown_field", "output.normals");
}

TEST(CurvesOperation, SingleCurveQueryMembersAreChecked) {
    const std::string curve = R"("points": [[0,0],[1,2],[3,2]])";
    // a switch that is not a boolean is refused, not taken as false
    expect_problem(post("{" + curve + R"(, "bounding_box": "true"})"), 400, "invalid_field", "bounding_box");
    // an unknown member beside a tolerance is named itself
    expect_problem(post("{" + curve + R"(, "length": {"tolerance": 0.1, "toleranse": 1}})"), 400, "unknown_field",
                   "length.toleranse");
    expect_problem(post("{" + curve + R"(, "tessellate": {"tolerance": 0.1, "segments": 4}})"), 400, "unknown_field",
                   "tessellate.segments");
    expect_problem(post("{" + curve + R"(, "length": {}})"), 400, "invalid_field", "length.tolerance");
    EXPECT_TRUE(ok_json(post("{" + curve + R"(, "bounding_box": true})")).contains("bounding_box"));
    EXPECT_FALSE(ok_json(post("{" + curve + R"(, "bounding_box": false})")).contains("bounding_box"));
}

TEST(CurvesOperation, PolylineWriterChecksItsInput) {
    EXPECT_FALSE(write_polylines_glb({}));
    EXPECT_FALSE(write_polylines_glb({{Vec3{0, 0, 0}}}));                    // one point is no line strip
    EXPECT_FALSE(write_polylines_glb({{Vec3{0, 0, 0}, Vec3{1e39, 0, 0}}}));  // beyond float range
    auto glb = write_polylines_glb({{Vec3{0, 0, 0}, Vec3{1, 0, 0}}, {Vec3{0, 1, 0}, Vec3{0, 1, 1}, Vec3{2, 2, 2}}});
    ASSERT_TRUE(glb);
    expect_valid_gltf(*glb);
    const json doc = glb_json(*glb);
    ASSERT_EQ(doc["meshes"][0]["primitives"].size(), 2u);
    EXPECT_EQ(doc["accessors"][1]["count"], 3);
    EXPECT_EQ(doc["accessors"][1]["byteOffset"], 24);  // after the first strip's 2 points
    EXPECT_EQ(doc["accessors"][1]["max"], json::array({2.0, 2.0, 2.0}));
}

// ---- chains ----------------------------------------------------------------------------------------------------------

// Piece 0 ends at (3, 0) with derivative 3 ((3,0) - (2,1)) = (3, -3). Piece 1 starts with (3, -3): C1. Piece 2 starts
// with 3 ((5,-2) - (3,0)) ... at the next joint: see the test.
const char* kChain =
    R"({"chain": {"pieces": [{"points": [[0,0],[1,1],[2,1],[3,0]]},
                             {"points": [[3,0],[4,-1],[5,-1],[6,0]]},
                             {"points": [[6,0],[8,2],[9,2],[10,0]]},
                             {"points": [[10,0],[10,1],[11,1]]},
                             {"points": [[12,1],[13,1]]}]}})";

TEST(CurvesOperation, ChainContinuityPerJoint) {
    const json out = ok_json(post(std::string(kChain).insert(1, R"("continuity": true, )")));
    EXPECT_EQ(out["piece_count"], 5);
    EXPECT_EQ(out["closed"], false);
    const json& report = out["continuity"];
    ASSERT_EQ(report["joints"].size(), 4u);
    // joint 0: derivatives (3,-3) and (3,-3): C1
    EXPECT_EQ(report["joints"][0]["continuity"], "C1");
    EXPECT_NEAR(report["joints"][0]["derivative_mismatch"].get<double>(), 0.0, 1e-12);
    // joint 1: (3,3) and 3 (2,2) = (6,6): same direction, mismatch |(3,3)| = 3 sqrt 2: G1
    EXPECT_EQ(report["joints"][1]["continuity"], "G1");
    EXPECT_NEAR(report["joints"][1]["derivative_mismatch"].get<double>(), 3 * std::sqrt(2.0), 1e-12);
    EXPECT_NEAR(report["joints"][1]["angle"].get<double>(), 0.0, 1e-12);
    // joint 2: (3,-6) and 2 (0,1) = (0,2): a corner of angle acos(-6 / (sqrt 45 * 1))
    EXPECT_EQ(report["joints"][2]["continuity"], "C0");
    EXPECT_NEAR(report["joints"][2]["angle"].get<double>(), std::acos(-6.0 / std::sqrt(45.0)), 1e-12);
    // joint 3: (11,1) to (12,1): a gap of 1
    EXPECT_EQ(report["joints"][3]["continuity"], "none");
    EXPECT_NEAR(report["joints"][3]["gap"].get<double>(), 1.0, 1e-15);
    EXPECT_EQ(report["weakest"], "none");
    EXPECT_NEAR(report["max_gap"].get<double>(), 1.0, 1e-15);
}

TEST(CurvesOperation, ChainEvaluateAtGlobalParameters) {
    const json out = ok_json(post(std::string(kChain).insert(1, R"("evaluate": [0, 0.5, 1, 2, 3.5, 5], )")));
    const json& p = out["evaluate"];
    ASSERT_EQ(p.size(), 6u);
    EXPECT_EQ(p[0], json::array({0.0, 0.0}));
    // piece 0 at t = 1/2: (0 + 3 + 6 + 3) / 8, (0 + 3 + 3 + 0) / 8
    EXPECT_NEAR(dist(p[1], json::array({1.5, 0.75})), 0.0, 1e-15);
    EXPECT_NEAR(dist(p[2], json::array({3.0, 0.0})), 0.0, 1e-15);
    EXPECT_NEAR(dist(p[3], json::array({6.0, 0.0})), 0.0, 1e-15);
    // piece 3 (quadratic) at t = 1/2: (10 + 20 + 11) / 4, (0 + 2 + 1) / 4
    EXPECT_NEAR(dist(p[4], json::array({10.25, 0.75})), 0.0, 1e-15);
    EXPECT_NEAR(dist(p[5], json::array({13.0, 1.0})), 0.0, 1e-15);
    expect_problem(post(std::string(kChain).insert(1, R"("evaluate": [0, 5.5], )")), 400, "invalid_field",
                   "evaluate[1]");
}

TEST(CurvesOperation, ChainLengthOfLines) {
    // (0,0)-(3,4) and the closing (3,4)-(3,10): 5 + 6; a degree-elevated line has the same length
    const json out = ok_json(post(R"({"chain": {"pieces": [{"points": [[0,0,0],[1.5,2,0],[3,4,0]]},
                                                         {"points": [[3,4,0],[3,10,0]]}]},
                                      "length": {"tolerance": 1e-9}})"));
    EXPECT_NEAR(out["length"]["length"].get<double>(), 11.0, 1e-9);
    EXPECT_LE(out["length"]["error_bound"].get<double>(), 1e-9);
    EXPECT_EQ(out["length"]["guaranteed"], true);
}

TEST(CurvesOperation, EnforceC1GivesAChainThatReportsC1) {
    // joints 1 (G1) and 2 (a corner) of kChain's first four pieces
    const std::string chain = R"({"chain": {"pieces": [{"points": [[0,0],[1,1],[2,1],[3,0]]},
                                                      {"points": [[3,0],[4,-1],[5,-1],[6,0]]},
                                                      {"points": [[6,0],[8,2],[9,2],[10,0]]},
                                                      {"points": [[10,0],[10,1],[11,1]]}]}})";
    for (const char* side : {"left", "right", "both"}) {
        const json out = ok_json(post(std::string(chain).insert(
            1, std::string(R"("enforce_c1": {"mode": "C1", "side": ")") + side + R"("}, "continuity": true, )")));
        EXPECT_EQ(out["continuity"]["weakest"], "C0") << side;  // the input's report
        const json& result = out["enforce_c1"];
        EXPECT_LE(result["max_derivative_mismatch"].get<double>(), 1e-12) << side;
        EXPECT_TRUE(result["skipped_joints"].empty());
        // the modified chain, sent back, is C1 at every joint; piece ends did not move
        json again = {{"chain", result["chain"]}, {"continuity", true}};
        const json check = ok_json(post(again.dump()));
        EXPECT_EQ(check["continuity"]["weakest"], "C1") << side << check.dump();
        for (std::size_t i = 0; i < 4; ++i)
            EXPECT_EQ(result["chain"]["pieces"][i]["points"][0], json::parse(chain)["chain"]["pieces"][i]["points"][0]);
    }
    // G1 keeps each side's length: joint 1's sides stay 3 sqrt 2 and 6 sqrt 2 long, now parallel
    const json g1 = ok_json(post(std::string(chain).insert(1, R"("enforce_c1": {"mode": "G1", "joints": [2]}, )")));
    EXPECT_LE(g1["enforce_c1"]["max_angle"].get<double>(), 1e-12);
    // tessellation and evaluation describe the modified chain
    const json t =
        ok_json(post(std::string(chain).insert(1, R"("enforce_c1": {}, "tessellate": {"tolerance": 0.001}, )")));
    EXPECT_LE(t["tessellate"]["bound"].get<double>(), 0.001);
    EXPECT_EQ(t["tessellate"]["piece_start"].size(), 4u);
    EXPECT_EQ(t["tessellate"]["points"].size(), t["tessellate"]["segments"].get<std::size_t>() + 1);
    EXPECT_EQ(t["tessellate"]["points"].back(), json::array({11.0, 1.0}));

    expect_problem(post(std::string(chain).insert(1, R"("enforce_c1": {"mode": "C2"}, )")), 400, "invalid_field",
                   "enforce_c1.mode");
    expect_problem(post(std::string(chain).insert(1, R"("enforce_c1": {"joints": [3]}, )")), 400, "invalid_field",
                   "enforce_c1.joints[0]");
    // the mirror rule needs polynomial pieces
    expect_problem(post(R"({"chain": {"pieces": [{"points": [[0,0],[1,1],[2,0]], "weights": [1,2,1]},
                                                {"points": [[2,0],[3,-1],[4,0]]}]}, "enforce_c1": {}})"),
                   422, "invalid_argument", "enforce_c1");
}

TEST(CurvesOperation, ClosedChainTessellatesToALoopAsGlb) {
    const std::string body =
        R"({"chain": {"closed": true, "pieces": [{"points": [[1,0,0],[1,1,0],[0,1,0]], "weights": [1,0.7071067811865476,1]},
                                                                      {"points": [[0,1,0],[-1,1,0],[-1,0,0]], "weights": [1,0.7071067811865476,1]},
                                                                      {"points": [[-1,0,0],[-1,-1,0],[0,-1,0]], "weights": [1,0.7071067811865476,1]},
                                                                      {"points": [[0,-1,0],[1,-1,0],[1,0,0]], "weights": [1,0.7071067811865476,1]}]},
                                  "tessellate": {"tolerance": 1e-4}, "continuity": true})";
    const json out = ok_json(post(body));
    // a circle of four rational quadratics: every joint G1 (C1 too: equal weights give equal end speeds)
    EXPECT_EQ(out["continuity"]["joints"].size(), 4u);
    EXPECT_NE(out["continuity"]["weakest"], "none");
    EXPECT_NE(out["continuity"]["weakest"], "C0");
    const json& points = out["tessellate"]["points"];
    EXPECT_EQ(points.front(), points.back());
    for (const json& p : points) EXPECT_NEAR(dist(p, json::array({0, 0, 0})), 1.0, 1e-12);
    // polyline within 1e-4 of the circle: each chord's sagitta 1 - cos(theta/2) <= 1e-4
    for (std::size_t i = 1; i < points.size(); ++i)
        EXPECT_LE(1 - std::sqrt(1 - dist(points[i], points[i - 1]) * dist(points[i], points[i - 1]) / 4), 1e-4 + 1e-12);

    json glb_request = json::parse(body);
    glb_request.erase("continuity");
    glb_request["output"] = {{"format", "glb"}};
    const ApiResponse glb = post(glb_request.dump());
    ASSERT_EQ(glb.status, 200) << glb.body;
    expect_valid_gltf(glb.body);
    EXPECT_EQ(glb_json(glb.body)["accessors"][0]["count"], points.size());
}

// ---- SVG path data -------------------------------------------------------------------------------------------------

TEST(CurvesOperation, SvgSubpathsAndSmoothJoints) {
    // S reflects the previous control point: the joint is C1 (same degree, mirrored point)
    const json out = ok_json(post(R"({"svg": "M 0 0 C 1 1 2 1 3 0 S 5 -1 6 0 M 10 10 l 1 0 0 1 z",
                                      "continuity": true, "to_bezier": true, "evaluate": [0, 1]})"));
    ASSERT_EQ(out["subpaths"].size(), 2u);
    const json& first = out["subpaths"][0];
    EXPECT_EQ(first["piece_count"], 2);
    EXPECT_EQ(first["continuity"]["weakest"], "C1");
    EXPECT_EQ(first["to_bezier"]["pieces"][1]["points"][1], json::array({4.0, -1.0}));
    EXPECT_EQ(first["evaluate"][1], json::array({3.0, 0.0}));
    const json& second = out["subpaths"][1];
    EXPECT_EQ(second["closed"], true);
    EXPECT_EQ(second["piece_count"], 3);  // two lines and the closing one
    EXPECT_EQ(second["continuity"]["joints"].size(), 3u);
    EXPECT_EQ(second["continuity"]["weakest"], "C0");  // a triangle's corners
    EXPECT_EQ(second["to_bezier"]["pieces"][2]["points"], json::parse("[[11.0, 11.0], [10.0, 10.0]]"));

    const ApiResponse glb = post(R"({"svg": "M 0 0 C 1 1 2 1 3 0 S 5 -1 6 0 M 10 10 l 1 0 0 1 z",
                                     "tessellate": {"tolerance": 0.01}, "output": {"format": "glb"}})");
    ASSERT_EQ(glb.status, 200) << glb.body;
    EXPECT_EQ(header(glb, "X-Polylines"), "2");
    expect_valid_gltf(glb.body);
    const json doc = glb_json(glb.body);
    ASSERT_EQ(doc["meshes"][0]["primitives"].size(), 2u);
    EXPECT_EQ(doc["accessors"][1]["count"], 4);  // the triangle: 3 corners and back to the first
}

TEST(CurvesOperation, SvgErrorsNameTheOffset) {
    // an unknown command letter at byte 6 of the path data
    const ApiResponse r = post(R"({"svg": "M 0 0 X 1 1"})");
    expect_problem(r, 422, "parse_error", "svg");
    ASSERT_TRUE(r.error && r.error->offset);
    EXPECT_EQ(*r.error->offset, 6);
    const json body = json::parse(r.body);
    EXPECT_EQ(body["offset"], 6);
    // a missing number: the offset is where it was expected (the end)
    const ApiResponse missing = post(R"({"svg": "M 0 0 C 1 1 2"})");
    expect_problem(missing, 422, "parse_error", "svg");
    ASSERT_TRUE(missing.error && missing.error->offset);
    EXPECT_GE(*missing.error->offset, 10);
    EXPECT_LE(*missing.error->offset, 14);
    expect_problem(post(R"({"svg": "M 1 2"})"), 400, "invalid_field", "svg");  // nothing drawn
    expect_problem(post(R"({"svg": 12})"), 400, "invalid_field", "svg");
    expect_problem(post(R"({"svg": "M0 0 L1 1", "split": 0.5})"), 400, "invalid_field", "split");
}

// ---- B-splines -----------------------------------------------------------------------------------------------------

TEST(CurvesOperation, ClampedBsplineWithOneSpanIsTheBezierCurve) {
    const json bspline = ok_json(post(R"({"bspline": {"degree": 3, "points": [[0,0],[1,2],[3,2],[4,0]]},
                                          "evaluate": [0, 0.25, 0.5, 1], "derivatives": {"t": [0, 0.5], "order": 1}})"));
    const json bezier = ok_json(post(R"({"points": [[0,0],[1,2],[3,2],[4,0]], "evaluate": [0, 0.25, 0.5, 1],
                                         "derivatives": {"t": [0, 0.5], "order": 1}})"));
    EXPECT_EQ(bspline["domain"], json::array({0.0, 1.0}));
    for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(dist(bspline["evaluate"][i], bezier["evaluate"][i]), 0.0, 1e-14);
    for (std::size_t i = 0; i < 2; ++i)
        EXPECT_NEAR(dist(bspline["derivatives"][i], bezier["derivatives"][i]), 0.0, 1e-13);
    // C'(0) = 3 (P1 - P0)
    EXPECT_NEAR(dist(bspline["derivatives"][0], json::array({3.0, 6.0})), 0.0, 1e-13);
}

TEST(CurvesOperation, NurbsQuarterCirclesStayOnTheCircle) {
    // a full circle as a clamped quadratic NURBS with double knots: 9 points, weights 1, sqrt(2)/2, ...
    const double h = std::sqrt(0.5);
    json request = {{"bspline",
                     {{"degree", 2},
                      {"points", json::parse("[[1,0],[1,1],[0,1],[-1,1],[-1,0],[-1,-1],[0,-1],[1,-1],[1,0]]")},
                      {"weights", {1, h, 1, h, 1, h, 1, h, 1}},
                      {"knots", {0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1}}}},
                    {"evaluate", json::array()},
                    {"to_bezier", true},
                    {"tessellate", {{"tolerance", 1e-5}}}};
    for (int i = 0; i <= 40; ++i) request["evaluate"].push_back(i / 40.0);
    const json out = ok_json(post(request.dump()));
    for (const json& p : out["evaluate"]) EXPECT_NEAR(dist(p, json::array({0, 0})), 1.0, 1e-14);
    EXPECT_EQ(out["rational"], true);
    ASSERT_EQ(out["to_bezier"]["pieces"].size(), 4u);
    EXPECT_EQ(out["to_bezier"]["breaks"], json::parse("[0.0, 0.25, 0.5, 0.75, 1.0]"));
    for (const json& p : out["tessellate"]["points"]) EXPECT_NEAR(dist(p, json::array({0, 0})), 1.0, 1e-12);
    EXPECT_LE(out["tessellate"]["bound"].get<double>(), 1e-5);

    request.erase("evaluate");
    request.erase("to_bezier");
    request["output"] = {{"format", "glb"}};
    const ApiResponse glb = post(request.dump());
    ASSERT_EQ(glb.status, 200) << glb.body;
    expect_valid_gltf(glb.body);
}

TEST(CurvesOperation, KnotInsertionKeepsTheCurve) {
    const std::string curve =
        R"("bspline": {"degree": 3, "points": [[0,0,0],[1,2,0],[3,3,1],[5,1,2],[6,0,0],[8,2,1]]})";
    const json out = ok_json(
        post("{" + curve + R"(, "insert_knot": {"u": 0.3, "times": 2}, "evaluate": [0, 0.1, 0.3, 0.62, 0.9, 1]})"));
    const json& inserted = out["insert_knot"];
    EXPECT_EQ(inserted["points"].size(), 8u);
    EXPECT_EQ(inserted["knots"].size(), 12u);
    json again = {{"bspline", inserted}, {"evaluate", {0, 0.1, 0.3, 0.62, 0.9, 1}}};
    const json check = ok_json(post(again.dump()));
    for (std::size_t i = 0; i < 6; ++i) EXPECT_NEAR(dist(check["evaluate"][i], out["evaluate"][i]), 0.0, 1e-13) << i;

    // clamped uniform: interior knots 1/3, 2/3; to_bezier gives 3 cubic pieces meeting exactly
    const json bezier = ok_json(post("{" + curve + R"(, "to_bezier": true})"));
    const json& pieces = bezier["to_bezier"]["pieces"];
    ASSERT_EQ(pieces.size(), 3u);
    for (std::size_t i = 0; i + 1 < pieces.size(); ++i) EXPECT_EQ(pieces[i]["points"][3], pieces[i + 1]["points"][0]);
}

TEST(CurvesOperation, UniformAndClosedKnotVectors) {
    const json uniform =
        ok_json(post(R"({"bspline": {"degree": 2, "points": [[0,0],[1,1],[2,0],[3,1]], "knot_vector": "uniform"},
                                          "evaluate": [0, 1]})"));
    EXPECT_EQ(uniform["domain"], json::array({0.0, 1.0}));
    // a uniform quadratic starts at the midpoint of its first two control points
    EXPECT_NEAR(dist(uniform["evaluate"][0], json::array({0.5, 0.5})), 0.0, 1e-14);
    const json closed =
        ok_json(post(R"({"bspline": {"degree": 3, "points": [[1,0],[0,1],[-1,0],[0,-1]], "knot_vector": "closed"},
                                         "evaluate": [0, 1]})"));
    EXPECT_NEAR(dist(closed["evaluate"][0], closed["evaluate"][1]), 0.0, 1e-14);
}

TEST(CurvesOperation, BsplineErrorsNameTheirField) {
    expect_problem(post(R"({"bspline": {"degree": 0, "points": [[0,0],[1,1]]}})"), 400, "invalid_field",
                   "bspline.degree");
    expect_problem(post(R"({"bspline": {"degree": 3, "points": [[0,0],[1,1]]}})"), 400, "invalid_field",
                   "bspline.points");
    expect_problem(post(R"({"bspline": {"degree": 1, "points": [[0,0],[1,1]], "knots": [0, 0, 1]}})"), 400,
                   "invalid_field", "bspline.knots");
    expect_problem(post(R"({"bspline": {"degree": 1, "points": [[0,0],[1,1],[2,0]], "knots": [0, 0, 2, 1, 1]}})"), 422,
                   "invalid_argument", "bspline.knots[3]");
    expect_problem(
        post(R"({"bspline": {"degree": 1, "points": [[0,0],[1,1]], "knots": [0, 0, 1, 1], "knot_vector": "clamped"}})"),
        400, "invalid_field", "bspline.knot_vector");
    expect_problem(post(R"({"bspline": {"degree": 1, "points": [[0,0],[1,"a"]]}})"), 400, "invalid_field",
                   "bspline.points[1][1]");
    expect_problem(post(R"({"bspline": {"degree": 1, "points": [[0,0],[1,1]], "weights": [1, -1]}})"), 400,
                   "invalid_field", "bspline.weights[1]");
    const std::string line = R"("bspline": {"degree": 1, "points": [[0,0],[1,1]], "knots": [0, 0, 2, 2]})";
    expect_problem(post("{" + line + R"(, "evaluate": [1, 2.5]})"), 400, "invalid_field", "evaluate[1]");
    expect_problem(post("{" + line + R"(, "insert_knot": {"u": 1, "times": 2}})"), 400, "invalid_field",
                   "insert_knot.times");
    expect_problem(post("{" + line + R"(, "insert_knot": {"u": -1}})"), 400, "invalid_field", "insert_knot.u");
    expect_problem(post("{" + line + R"(, "continuity": true})"), 400, "invalid_field", "continuity");
}

// ---- request shape and budgets -------------------------------------------------------------------------------------

TEST(CurvesOperation, ExactlyOneForm) {
    expect_problem(post(R"({"points": [[0,0],[1,1]], "chain": {"pieces": [{"points": [[0,0],[1,1]]}]}})"), 400,
                   "invalid_field", "chain");
    expect_problem(post(R"({"svg": "M0 0 L1 1", "bspline": {}})"), 400, "invalid_field", "bspline");
    expect_problem(post(R"({"evaluate": [0.5]})"), 400, "invalid_field", "points");
    expect_problem(post(R"({"points": [[0,0],[1,1]], "continuity": true})"), 400, "invalid_field", "continuity");
    expect_problem(post(R"({"chain": {"pieces": [{"points": [[0,0],[1,1]]}]}, "closest": [0, 0]})"), 400,
                   "invalid_field", "closest");
    expect_problem(post(R"({"chain": {"pieces": [{"points": [[0,0],[1,1]]}]}, "frob": 1})"), 400, "unknown_field",
                   "frob");
}

TEST(CurvesOperation, ChainErrorsNameTheirPath) {
    expect_problem(post(R"({"chain": {"pieces": []}})"), 400, "invalid_field", "chain.pieces");
    expect_problem(post(R"({"chain": {"pieces": [{"points": [[0,0],[1,1]]}, {"points": [[1,1],[2,2,2]]}]}})"), 400,
                   "invalid_field", "chain.pieces[1].points[1]");
    expect_problem(post(R"({"chain": {"pieces": [{"points": [[0,0],[1,1]], "weights": [1]}]}})"), 400, "invalid_field",
                   "chain.pieces[0].weights");
    expect_problem(post(R"({"chain": {"pieces": [{"points": [[0,0],[1,1]], "degree": 1}]}})"), 400, "unknown_field",
                   "chain.pieces[0].degree");
    expect_problem(post(R"({"chain": {"pieces": [{"points": [[0,0],[1,1]]}], "closed": 1}})"), 400, "invalid_field",
                   "chain.closed");
    expect_problem(post(R"({"chain": {"pieces": [{"points": [[0,0],[1,1]]}]}, "continuity": {"angle_tolerance": -1}})"),
                   400, "invalid_field", "continuity.angle_tolerance");
}

TEST(CurvesOperation, BudgetsAreCheckedBeforeWork) {
    // a piece of degree 65
    json piece = {{"points", json::array()}};
    for (int i = 0; i < 66; ++i) piece["points"].push_back({i, 0});
    expect_problem(post(json{{"chain", {{"pieces", {piece}}}}}.dump()), 422, "budget_exceeded",
                   "chain.pieces[0].points");
    // too many parameters: per subpath, times the subpaths
    json evaluate = json::array();
    for (std::size_t i = 0; i < kMaxCurveQueries / 2 + 1; ++i) evaluate.push_back(0.5);
    expect_problem(post(json{{"svg", "M0 0 L1 1 M2 2 L3 3"}, {"evaluate", evaluate}}.dump()), 422, "budget_exceeded",
                   "evaluate");
    // SVG data length
    expect_problem(post(json{{"svg", "M0 0" + std::string(operations::kMaxSvgBytes, ' ')}}.dump()), 422,
                   "budget_exceeded", "svg");
    // B-spline control points
    json bspline = {{"degree", 1}, {"points", json::array()}};
    for (std::size_t i = 0; i <= operations::kMaxBsplinePoints; ++i) bspline["points"].push_back({0, 0});
    expect_problem(post(json{{"bspline", bspline}}.dump()), 422, "budget_exceeded", "bspline.points");
    // tessellation over the output budget
    Limits limits;
    limits.max_output_faces = 10;
    expect_problem(
        post(R"({"svg": "M0 0 C 0 10 10 10 10 0", "tessellate": {"tolerance": 1e-6}})", context_with(limits)), 422,
        "budget_exceeded", "tessellate.tolerance");
    expect_problem(
        post(R"({"bspline": {"degree": 2, "points": [[0,0],[5,9],[10,0]]}, "tessellate": {"tolerance": 1e-6}})",
             context_with(limits)),
        422, "budget_exceeded", "tessellate.tolerance");
}

TEST(CurvesOperation, PastDeadlineIsCancelled) {
    Cancel cancel;
    cancel.deadline = Cancel::Clock::now() - std::chrono::seconds(1);
    const ApiResponse r =
        post(R"({"chain": {"pieces": [{"points": [[0,0],[1,1],[2,0]]}]}, "tessellate": {"tolerance": 0.001}})",
             context_with(Limits{}, cancel));
    expect_problem(r, 503, "cancelled", "tessellate.tolerance");
}

// ---- the CLI's file form and the OpenAPI examples --------------------------------------------------------------

TEST(CurvesOperation, SvgFileWithPathElements) {
    const std::string svg =
        "<svg xmlns=\"http://www.w3.org/2000/svg\">\n"
        "  <path id=\"a\" d=\"M 0 0 L 1 0\"/>\n"
        "  <path d='M 5 5 Q 6 6 7 5'/>\n"
        "</svg>\n";
    operations::CurveFileOverrides overrides;
    overrides.svg = true;
    overrides.continuity = true;
    const json out = ok_json(operations::curves_from_file(svg, overrides, ApiContext{}));
    ASSERT_EQ(out["subpaths"].size(), 2u);
    EXPECT_EQ(out["subpaths"][1]["continuity"]["joints"].size(), 0u);

    overrides.continuity = false;          // glTF output holds the tessellation only
    overrides.format = OutputFormat::Glb;  // no tolerance given: the default one
    const ApiResponse glb = operations::curves_from_file(svg, overrides, ApiContext{});
    ASSERT_EQ(glb.status, 200) << glb.body;
    EXPECT_EQ(header(glb, "X-Polylines"), "2");
    expect_valid_gltf(glb.body);

    // an error in the second path: the offset and line are the file's
    const std::string bad = "<svg>\n<path d=\"M0 0 L1 1\"/>\n<path d=\"M0 0 L1 x\"/>\n</svg>";
    operations::CurveFileOverrides svg_only;
    svg_only.svg = true;
    const ApiResponse r = operations::curves_from_file(bad, svg_only, ApiContext{});
    expect_problem(r, 422, "parse_error", "svg");
    ASSERT_TRUE(r.error && r.error->offset && r.error->line);
    EXPECT_EQ(*r.error->line, 3);
    EXPECT_EQ(bad[static_cast<std::size_t>(*r.error->offset)], 'x');
}

TEST(CurvesOperation, JsonFileWithOverrides) {
    const std::string file =
        R"({"chain": {"pieces": [{"points": [[0,0],[1,1],[2,0]]}, {"points": [[2,0],[4,-2],[5,0]]}]}})";
    operations::CurveFileOverrides overrides;
    overrides.enforce_c1 = "C1";
    overrides.tolerance = 0.01;
    overrides.continuity = true;
    const json out = ok_json(operations::curves_from_file(file, overrides, ApiContext{}));
    EXPECT_EQ(out["continuity"]["weakest"], "G1");
    EXPECT_LE(out["enforce_c1"]["max_derivative_mismatch"].get<double>(), 1e-12);
    EXPECT_LE(out["tessellate"]["bound"].get<double>(), 0.01);
    expect_problem(operations::curves_from_file("[1]", {}, ApiContext{}), 400, "invalid_field", "");
    overrides.enforce_c1 = "C7";
    expect_problem(operations::curves_from_file(file, overrides, ApiContext{}), 400, "invalid_field",
                   "enforce_c1.mode");
}

TEST(CurvesOperation, OpenApiExamplesAreAccepted) {
    const json doc = json::parse(openapi_document());
    const json& content = doc["paths"]["/curves"]["post"]["requestBody"]["content"]["application/json"];
    int examples = 0;
    if (content.contains("example")) {
        EXPECT_EQ(post(content["example"].dump()).status, 200);
        ++examples;
    }
    const json named = content.contains("examples") ? content["examples"] : json::object();
    for (const auto& [name, example] : named.items()) {
        const ApiResponse r = post(example["value"].dump());
        EXPECT_EQ(r.status, 200) << name << ": " << r.body;
        ++examples;
    }
    EXPECT_GE(examples, 5);  // one curve, chain, svg, bspline, glb output
}

}  // namespace
}  // namespace surfaced::api
