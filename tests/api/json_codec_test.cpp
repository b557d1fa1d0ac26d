// JSON <-> mesh codec: every error names its field path and carries the right status and code.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "api/json_codec.h"

namespace surfaced::api {
namespace {

// A unit cube as the wire form, written out so these tests depend on nothing but the codec.
constexpr std::string_view kCubePositions = R"([[-0.5,-0.5,-0.5],[0.5,-0.5,-0.5],[0.5,0.5,-0.5],[-0.5,0.5,-0.5],)"
                                            R"([-0.5,-0.5,0.5],[0.5,-0.5,0.5],[0.5,0.5,0.5],[-0.5,0.5,0.5]])";
constexpr std::string_view kCubeFaces = R"([[0,3,2,1],[4,5,6,7],[0,1,5,4],[1,2,6,5],[2,3,7,6],[3,0,4,7]])";

std::string cube_request(std::string_view extra = "") {
    return std::string(R"({"mesh":{"positions":)") + std::string(kCubePositions) + R"(,"faces":)" +
           std::string(kCubeFaces) + "}" + std::string(extra) + "}";
}

std::string mesh_json(std::string_view positions, std::string_view faces) {
    return std::string(R"({"positions":)") + std::string(positions) + R"(,"faces":)" + std::string(faces) + "}";
}

void expect_error(const ApiError& e, int status, std::string_view code, std::optional<std::string> field) {
    EXPECT_EQ(e.status, status) << e.detail;
    EXPECT_EQ(e.code, code) << e.detail;
    EXPECT_EQ(e.field, field) << e.detail;
    EXPECT_FALSE(e.detail.empty());
    EXPECT_FALSE(e.title.empty());
}

TEST(JsonCodec, DecodesCubeAndDefaults) {
    auto r = decode_subdivide_request(cube_request(), Limits{});
    ASSERT_TRUE(r.ok()) << r.error().detail;
    EXPECT_EQ(r->mesh.vertex_count(), 8u);
    EXPECT_EQ(r->mesh.face_count(), 6u);
    EXPECT_EQ(r->mesh.face(5)[3], 7u);
    EXPECT_EQ(r->mesh.positions[6].z, 0.5);
    EXPECT_EQ(r->params.scheme, SubdivisionScheme::CatmullClark);
    EXPECT_EQ(r->params.levels, 1);
    EXPECT_FALSE(r->params.boundary.has_value());
    EXPECT_EQ(r->params.output.format, OutputFormat::Glb);
    EXPECT_FALSE(r->params.output.draco.has_value());
}

TEST(JsonCodec, DecodesAllOptions) {
    auto r = decode_subdivide_request(
        cube_request(R"(,"scheme":"loop","levels":3,"boundary":"edge-and-corner",)"
                     R"("output":{"format":"obj","compression":"none","quantize_position":11,"normals":true})"),
        Limits{});
    ASSERT_TRUE(r.ok()) << r.error().detail;
    EXPECT_EQ(r->params.scheme, SubdivisionScheme::Loop);
    EXPECT_EQ(r->params.levels, 3);
    EXPECT_EQ(r->params.boundary, BoundaryInterpolation::EdgeAndCorner);
    EXPECT_EQ(r->params.output.format, OutputFormat::Obj);
    EXPECT_EQ(r->params.output.draco, false);
    EXPECT_EQ(r->params.output.quantize_position, 11);
    EXPECT_EQ(r->params.output.normals, true);
}

TEST(JsonCodec, MalformedJsonIs400WithOffset) {
    auto r = decode_subdivide_request(R"({"mesh": {"positions": [[0,0,0]],, })", Limits{});
    ASSERT_FALSE(r.ok());
    expect_error(r.error(), 400, "invalid_json", std::nullopt);
    ASSERT_TRUE(r.error().offset.has_value());
    EXPECT_EQ(*r.error().offset, 33);  // the second ','
    EXPECT_EQ(r.error().detail.find("[json.exception"), std::string::npos) << r.error().detail;

    auto empty = decode_subdivide_request("", Limits{});
    ASSERT_FALSE(empty.ok());
    expect_error(empty.error(), 400, "invalid_json", std::nullopt);
}

TEST(JsonCodec, NonObjectBodyIs400) {
    auto r = decode_subdivide_request("[1,2,3]", Limits{});
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().status, 400);
    EXPECT_EQ(r.error().code, "invalid_field");
}

TEST(JsonCodec, UnknownTopLevelFieldsAreNamed) {
    auto r = decode_subdivide_request(cube_request(R"(,"levles":2,"colour":"red")"), Limits{});
    ASSERT_FALSE(r.ok());
    expect_error(r.error(), 400, "unknown_field", "colour");
    EXPECT_NE(r.error().detail.find("\"levles\""), std::string::npos) << r.error().detail;
    EXPECT_NE(r.error().detail.find("\"colour\""), std::string::npos) << r.error().detail;
    EXPECT_NE(r.error().detail.find("\"levels\""), std::string::npos) << "allowed names listed: " << r.error().detail;
}

TEST(JsonCodec, UnknownNestedFieldsAreNamedWithPath) {
    auto r = decode_subdivide_request(cube_request(R"(,"output":{"fromat":"obj"})"), Limits{});
    ASSERT_FALSE(r.ok());
    expect_error(r.error(), 400, "unknown_field", "output.fromat");

    auto m = decode_mesh(R"({"positions":[],"faces":[],"colors":[]})", Limits{});
    ASSERT_FALSE(m.ok());
    expect_error(m.error(), 400, "unknown_field", "mesh.colors");
}

TEST(JsonCodec, UnknownEnumValuesListAllowedOnes) {
    auto r = decode_subdivide_request(cube_request(R"(,"scheme":"doo-sabin")"), Limits{});
    ASSERT_FALSE(r.ok());
    expect_error(r.error(), 400, "invalid_field", "scheme");
    EXPECT_NE(r.error().detail.find("\"catmull-clark\", \"loop\""), std::string::npos) << r.error().detail;

    auto b = decode_subdivide_request(cube_request(R"(,"boundary":"smooth")"), Limits{});
    ASSERT_FALSE(b.ok());
    expect_error(b.error(), 400, "invalid_field", "boundary");
    EXPECT_NE(b.error().detail.find("edge-and-corner"), std::string::npos);

    auto f = decode_subdivide_request(cube_request(R"(,"output":{"format":"fbx"})"), Limits{});
    ASSERT_FALSE(f.ok());
    expect_error(f.error(), 400, "invalid_field", "output.format");
    EXPECT_NE(f.error().detail.find("\"glb\""), std::string::npos);
}

TEST(JsonCodec, WrongTypesAre400) {
    auto levels = decode_subdivide_request(cube_request(R"(,"levels":2.0)"), Limits{});
    ASSERT_FALSE(levels.ok());
    expect_error(levels.error(), 400, "invalid_field", "levels");

    auto levels_text = decode_subdivide_request(cube_request(R"(,"levels":"2")"), Limits{});
    ASSERT_FALSE(levels_text.ok());
    expect_error(levels_text.error(), 400, "invalid_field", "levels");

    auto normals = decode_subdivide_request(cube_request(R"(,"output":{"normals":1})"), Limits{});
    ASSERT_FALSE(normals.ok());
    expect_error(normals.error(), 400, "invalid_field", "output.normals");

    auto missing = decode_subdivide_request(R"({"levels":1})", Limits{});
    ASSERT_FALSE(missing.ok());
    expect_error(missing.error(), 400, "invalid_field", "mesh");
}

TEST(JsonCodec, PositionErrorsNameTheCoordinate) {
    auto text = decode_mesh(mesh_json(R"([[0,0,0],[1,0,0],[0,1,0],[0,"x",1]])", "[[0,1,2]]"), Limits{});
    ASSERT_FALSE(text.ok());
    expect_error(text.error(), 400, "invalid_field", "mesh.positions[3][1]");
    EXPECT_NE(text.error().detail.find("mesh.positions[3][1] must be a finite number"), std::string::npos);

    auto short_point = decode_mesh(mesh_json(R"([[0,0,0],[1,0]])", "[]"), Limits{});
    ASSERT_FALSE(short_point.ok());
    expect_error(short_point.error(), 400, "invalid_field", "mesh.positions[1]");

    // JSON has no Inf literal; a number that overflows a double is refused while parsing: 400 number_out_of_range
    // with the number, its line and column and its byte offset, and none of nlohmann's exception text.
    const std::string body = mesh_json(R"([[0,0,0],[1,0,0],[0,1e999,0]])", "[[0,1,2]]");
    auto inf = decode_mesh(body, Limits{});
    ASSERT_FALSE(inf.ok());
    expect_error(inf.error(), 400, "number_out_of_range", std::nullopt);
    const std::string& detail = inf.error().detail;
    EXPECT_NE(detail.find("1e999"), std::string::npos) << detail;
    EXPECT_NE(detail.find("line 1, column "), std::string::npos) << detail;
    EXPECT_EQ(detail.find("json.exception"), std::string::npos) << detail;
    ASSERT_TRUE(inf.error().offset.has_value());
    EXPECT_EQ(body.substr(static_cast<std::size_t>(*inf.error().offset), 5), "1e999") << body;
}

TEST(JsonCodec, FaceErrorsNameTheIndex) {
    const std::string_view positions = kCubePositions;
    auto out_of_range = decode_mesh(mesh_json(positions,
                                              "[[0,1,2],[0,1,2],[0,1,2],[0,1,2],[0,1,2],[0,1,2],"
                                              "[0,1,2],[0,1,2],[0,1,2],[0,1,2],[0,1,2],[0,1,2],"
                                              "[0,1,2,99]]"),
                                    Limits{});
    ASSERT_FALSE(out_of_range.ok());
    expect_error(out_of_range.error(), 422, "index_out_of_range", "mesh.faces[12][3]");
    EXPECT_NE(out_of_range.error().detail.find("mesh.faces[12][3]: vertex 99 out of range (8 vertices)"),
              std::string::npos)
        << out_of_range.error().detail;

    auto negative = decode_mesh(mesh_json(positions, "[[0,-1,2]]"), Limits{});
    ASSERT_FALSE(negative.ok());
    expect_error(negative.error(), 400, "invalid_field", "mesh.faces[0][1]");

    auto fraction = decode_mesh(mesh_json(positions, "[[0,1,2.5]]"), Limits{});
    ASSERT_FALSE(fraction.ok());
    expect_error(fraction.error(), 400, "invalid_field", "mesh.faces[0][2]");

    auto two = decode_mesh(mesh_json(positions, "[[0,1,2],[0,1]]"), Limits{});
    ASSERT_FALSE(two.ok());
    expect_error(two.error(), 422, "degenerate_face", "mesh.faces[1]");

    auto not_array = decode_mesh(mesh_json(positions, "[7]"), Limits{});
    ASSERT_FALSE(not_array.ok());
    expect_error(not_array.error(), 400, "invalid_field", "mesh.faces[0]");
}

TEST(JsonCodec, InputBudgetsCheckedBeforeDecoding) {
    Limits limits;
    limits.max_input_faces = 5;
    auto faces = decode_mesh(mesh_json(kCubePositions, kCubeFaces), limits);
    ASSERT_FALSE(faces.ok());
    expect_error(faces.error(), 422, "budget_exceeded", "mesh.faces");

    limits = Limits{};
    limits.max_input_vertices = 7;
    auto vertices = decode_mesh(mesh_json(kCubePositions, kCubeFaces), limits);
    ASSERT_FALSE(vertices.ok());
    expect_error(vertices.error(), 422, "budget_exceeded", "mesh.positions");
}

TEST(JsonCodec, EncodeRoundTripsExactly) {
    PolygonMesh mesh;
    mesh.positions = {{0.1, -2.5e-300, 3}, {1.0 / 3.0, 1e300, -0.0}, {7, 8, 9}, {1, 1, 1}};
    mesh.add_face({0, 1, 2});
    mesh.add_face({0, 2, 3, 1});
    SubdivideStats stats;
    stats.input_vertices = 1;
    stats.input_faces = 2;
    stats.output_vertices = 4;
    stats.output_faces = 2;
    stats.scheme = SubdivisionScheme::Loop;
    stats.levels = 2;
    stats.elapsed_ms = 1.5;
    const std::string text = encode_mesh_response(mesh, stats);

    const auto json = nlohmann::json::parse(text);
    EXPECT_EQ(json["stats"]["output_faces"], 2);
    EXPECT_EQ(json["stats"]["scheme"], "loop");
    EXPECT_EQ(json["stats"]["levels"], 2);
    EXPECT_EQ(json["stats"]["elapsed_ms"], 1.5);

    auto back = decode_mesh(json["mesh"].dump(), Limits{});
    ASSERT_TRUE(back.ok()) << back.error().detail;
    ASSERT_EQ(back->positions.size(), 4u);
    for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(back->positions[i], mesh.positions[i]) << i;
    EXPECT_EQ(back->face_offsets, mesh.face_offsets);
    EXPECT_EQ(back->face_indices, mesh.face_indices);
}

TEST(JsonCodec, NormalsAreWrittenAndReadBack) {
    PolygonMesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    mesh.normals = {{0, 0, 1}, {0, -0.0, 1}, {0.6, 0, 0.8}};
    mesh.add_face({0, 1, 2});
    const std::string text = encode_mesh_with_stats(mesh, "{}");
    // one normal per vertex, in the shared number form (integral values without a fraction, -0 as 0)
    EXPECT_NE(text.find(R"("normals":[[0,0,1],[0,0,1],[0.6,0,0.8]])"), std::string::npos) << text;
    auto back = decode_mesh(nlohmann::json::parse(text)["mesh"].dump(), Limits{});
    ASSERT_TRUE(back.ok()) << back.error().detail;
    ASSERT_EQ(back->normals.size(), 3u);
    for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(back->normals[i], mesh.normals[i]) << i;
}

TEST(JsonCodec, NormalErrorsNameTheField) {
    const std::string positions = "[[0,0,0],[1,0,0],[0,1,0]]";
    const auto with_normals = [&](std::string_view normals) {
        return std::string(R"({"positions":)") + positions + R"(,"faces":[[0,1,2]],"normals":)" + std::string(normals) +
               "}";
    };
    auto count = decode_mesh(with_normals("[[0,0,1],[0,0,1]]"), Limits{});
    ASSERT_FALSE(count.ok());
    expect_error(count.error(), 400, "invalid_field", "mesh.normals");
    EXPECT_NE(count.error().detail.find("one per position (3)"), std::string::npos) << count.error().detail;
    auto shape = decode_mesh(with_normals("[[0,0,1],[0,0],[0,0,1]]"), Limits{});
    ASSERT_FALSE(shape.ok());
    expect_error(shape.error(), 400, "invalid_field", "mesh.normals[1]");
    auto type = decode_mesh(with_normals(R"([[0,0,1],[0,0,1],[0,"z",1]])"), Limits{});
    ASSERT_FALSE(type.ok());
    expect_error(type.error(), 400, "invalid_field", "mesh.normals[2][1]");
    auto not_array = decode_mesh(with_normals("true"), Limits{});
    ASSERT_FALSE(not_array.ok());
    expect_error(not_array.error(), 400, "invalid_field", "mesh.normals");
}

}  // namespace
}  // namespace surfaced::api
