// OFF reader: header variants, where the counts go, skipped per-vertex and per-face data.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "geometry/io/mesh_io.h"
#include "geometry/io/number_text.h"
#include "tests/io/format_test_helpers.h"

namespace surfaced {
namespace {

using format_test::fails_with;

// A cube: 8 vertices, 6 quads.
const char* kCubeBody =
    "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
    "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n";

TEST(OffRead, CountsOnTheNextLine) {
    auto mesh = read_off(std::string("OFF\n8 6 12\n") + kCubeBody);
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    EXPECT_EQ(mesh->vertex_count(), 8u);
    EXPECT_EQ(mesh->face_count(), 6u);
    EXPECT_EQ(mesh->face_indices, format_test::cube().face_indices);
    EXPECT_EQ(mesh->positions[6], (Vec3{1, 1, 1}));
    EXPECT_EQ(format_test::euler(*mesh), 2);
    EXPECT_TRUE(validate(*mesh).ok());
}

TEST(OffRead, CountsOnTheHeaderLineWithCommentsAndCrlf) {
    const std::string text =
        "OFF 4 2 0 # counts here\r\n"
        "# a comment line\r\n"
        "\r\n"
        "0 0 0\r\n1 0 0 # trailing comment\r\n1 1 0\r\n0 1 0.5e1\r\n"
        "3 0 1 2\r\n3 0 2 3\r\n";
    auto mesh = read_off(text);
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    EXPECT_EQ(mesh->face_count(), 2u);
    EXPECT_EQ(mesh->positions[3].z, 5.0);
    EXPECT_EQ(mesh->face_indices, (std::vector<Index>{0, 1, 2, 0, 2, 3}));
}

TEST(OffRead, ColorsNormalsAndFaceColorsAreSkipped) {
    const std::string coff =
        "COFF\n4 2 0\n"
        "0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n1 1 0 0 0 255 255\n0 1 0 9 9 9 255\n"
        "3 0 1 2 1.0 0.0 0.0\n4 0 1 2 3 0 0 255 255\n";
    auto mesh = read_off(coff);
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    EXPECT_EQ(mesh->face_indices, (std::vector<Index>{0, 1, 2, 0, 1, 2, 3}));
    EXPECT_EQ(mesh->positions[3], (Vec3{0, 1, 0}));

    auto noff = read_off("NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n");
    ASSERT_TRUE(noff.ok()) << noff.error().message;
    EXPECT_EQ(noff->positions[1], (Vec3{1, 0, 0}));
    auto cnoff = read_off("CNOFF\n3 1 0\n0 0 0 0 0 1 1 1 1\n1 0 0 0 0 1 1 1 1\n0 1 0 0 0 1 1 1 1\n3 0 1 2\n");
    ASSERT_TRUE(cnoff.ok()) << cnoff.error().message;
    auto stoff = read_off("STOFF\n3 1 0\n0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n3 2 1 0\n");
    ASSERT_TRUE(stoff.ok()) << stoff.error().message;
    EXPECT_EQ(stoff->face_indices, (std::vector<Index>{2, 1, 0}));
}

TEST(OffRead, HeaderKeywordIsOptional) {
    auto mesh = read_off("3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    EXPECT_EQ(mesh->face_count(), 1u);
}

TEST(OffRead, UnsupportedVariants) {
    EXPECT_TRUE(fails_with(read_off("4OFF\n1 1 0\n0 0 0 1\n"), ErrorCode::Unsupported, "line 1:"));
    EXPECT_TRUE(fails_with(read_off("nOFF\n3\n1 1 0\n"), ErrorCode::Unsupported, "line 1:"));
    EXPECT_TRUE(fails_with(read_off("OFF BINARY\n"), ErrorCode::Unsupported, "binary OFF"));
}

TEST(OffRead, RepeatedVertexAllowedOnRequest) {
    const std::string text = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2 2\n";
    EXPECT_TRUE(fails_with(read_off(text), ErrorCode::DegenerateFace, "line 6: face uses vertex 2 more than once"));
    ReadOptions lenient;
    lenient.allow_repeated_vertices = true;
    EXPECT_TRUE(read_off(text, lenient).ok());
}

TEST(OffRead, Limits) {
    const std::string text = std::string("OFF\n8 6 0\n") + kCubeBody;
    ReadOptions options;
    options.max_vertices = 7;
    EXPECT_TRUE(fails_with(read_off(text, options), ErrorCode::BudgetExceeded,
                           "line 2: header declares 8 vertices, more than max_vertices (7)"));
    options = {};
    options.max_faces = 5;
    EXPECT_TRUE(fails_with(read_off(text, options), ErrorCode::BudgetExceeded, "max_faces (5)"));
    options = {};
    options.max_face_size = 3;
    EXPECT_TRUE(fails_with(read_off(text, options), ErrorCode::BudgetExceeded,
                           "line 11: face has 4 vertices, more than max_face_size (3)"));
}

TEST(OffRead, SameMeshAsObj) {
    const std::string obj =
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
        "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
    auto a = read_obj(obj);
    auto b = read_off(std::string("OFF\n8 6 12\n") + kCubeBody);
    ASSERT_TRUE(a.ok() && b.ok());
    format_test::expect_same_mesh(*a, *b);
}

// ---- write_off --------------------------------------------------------------------------------------------------

TEST(OffWrite, PolygonsKeptAndDoublesRoundTripExactly) {
    PolygonMesh mesh = format_test::big_grid(5);  // quads with coordinates such as 1/7 and 1/3
    mesh.add_face({0, 1, 2});                     // and a triangle: faces keep their sizes
    mesh.positions[3] = {0.1, -1e-300, 12345678.901234567};
    const std::string text = write_off(mesh);
    EXPECT_EQ(text.substr(0, 4), "OFF\n");
    auto read = read_off(text);
    ASSERT_TRUE(read.ok()) << read.error().message;
    format_test::expect_same_mesh(mesh, *read);
}

TEST(OffWrite, ShortestNumbersAndNoNegativeZero) {
    PolygonMesh mesh;
    mesh.positions = {{-0.0, 0.1, 1}, {1, -0.0, 2.5}, {0, 1, -0.0}};
    mesh.add_face({0, 1, 2});
    EXPECT_EQ(write_off(mesh), "OFF\n3 1 0\n0 0.1 1\n1 0 2.5\n0 1 0\n3 0 1 2\n");
}

TEST(NumberText, ShortestRoundTripIntegralWithoutFractionNoNegativeZero) {
    EXPECT_EQ(number_text(-0.0), "0");
    EXPECT_EQ(number_text(0.0), "0");
    EXPECT_EQ(number_text(1.0), "1");
    EXPECT_EQ(number_text(-2.0), "-2");
    EXPECT_EQ(number_text(0.1), "0.1");
    EXPECT_EQ(number_text(1e300), "1e+300");
    EXPECT_EQ(number_text(1.0 / 3.0), "0.3333333333333333");
    for (double v : {1.0 / 3.0, 0.1 + 0.2, 5e-324, 1.7976931348623157e308, -123.456, 2.0 / 7.0 * 1e-20}) {
        const std::string text = number_text(v);
        EXPECT_EQ(std::strtod(text.c_str(), nullptr), v) << text;
    }
}

}  // namespace
}  // namespace surfaced
