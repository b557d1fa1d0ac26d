// OBJ reader/writer: statement forms, OpenSubdiv tags, round trips, and the whole OpenSubdiv shape corpus.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "geometry/io/mesh_io.h"
#include "tests/io/format_test_helpers.h"

namespace surfaced {
namespace {

using format_test::expect_same_mesh;
using format_test::fails_with;

TEST(ObjRead, CornerFormsAndExactCoordinates) {
    // One face per corner form; vt on every face, so uvs are kept.
    const std::string text =
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 -2.5e-3\n"
        "vt 0 0\nvt 1 0\nvt 1 1\nvt 0.25\n"
        "vn 0 0 1\n"
        "f 1/1 2/2 3/3\n"
        "f 1/1/1 3/3/1 4/4/1\n";
    auto mesh = read_obj(text);
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    ASSERT_EQ(mesh->vertex_count(), 4u);
    ASSERT_EQ(mesh->face_count(), 2u);
    EXPECT_EQ(mesh->positions[3].z, -2.5e-3);
    EXPECT_EQ(mesh->face_indices, (std::vector<Index>{0, 1, 2, 0, 2, 3}));
    ASSERT_EQ(mesh->uvs.size(), 4u);
    EXPECT_EQ(mesh->uvs[3].x, 0.25);
    EXPECT_EQ(mesh->uvs[3].y, 0.0);  // a missing v defaults to 0
    EXPECT_EQ(mesh->uv_indices, (std::vector<Index>{0, 1, 2, 0, 2, 3}));
    EXPECT_FALSE(mesh->has_normals());  // vn is ignored
    EXPECT_TRUE(validate(*mesh).ok());
}

TEST(ObjRead, NormalOnlyCornersHaveNoUvs) {
    auto mesh = read_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\n");
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    EXPECT_EQ(mesh->face_indices, (std::vector<Index>{0, 1, 2}));
    EXPECT_FALSE(mesh->has_uvs());
}

TEST(ObjRead, NegativeIndicesAreRelativeToVerticesSoFar) {
    auto mesh = read_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 5 5 5\nf -4 -1 -2\n");
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    EXPECT_EQ(mesh->face_indices, (std::vector<Index>{0, 1, 2, 0, 3, 2}));
}

TEST(ObjRead, PolygonsCommentsBlankLinesCrlfAndContinuations) {
    const std::string text =
        "# a hexagon and a triangle\r\n"
        "\r\n"
        "o thing\r\ng group\r\ns off\r\nusemtl red\r\nmtllib x.mtl\r\n"
        "v 0 0 0\r\nv 1 0 0\r\nv 2 1 0\r\nv 1 2 0\r\nv 0 2 0\r\nv -1 1 0\r\n"
        "   \t \r\n"
        "f 1 2 3 \\\r\n  4 5 6\r\n"
        "f 1 3 5 # trailing comment\r\n"
        "l 1 2\r\np 3\r\n";
    auto mesh = read_obj(text);
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    ASSERT_EQ(mesh->face_count(), 2u);
    EXPECT_EQ(mesh->face_size(0), 6u);
    EXPECT_EQ(mesh->face_size(1), 3u);
    EXPECT_EQ(mesh->positions[5].x, -1.0);
}

TEST(ObjRead, ContinuationKeepsLineNumbersRight) {
    // The error is on physical line 5; the joined line 2-3 must count as two lines.
    auto mesh = read_obj("v 0 0 0\nv 1 \\\n 0 0\nv 0 1 0\nf 1 2 7\n");
    EXPECT_TRUE(fails_with(mesh, ErrorCode::IndexOutOfRange, "line 5: face index 7 out of range (3 vertices)"));
    EXPECT_EQ(mesh.error().line, 5);
}

TEST(ObjRead, Utf8BomIsSkipped) {
    auto mesh = read_obj("\xef\xbb\xbfv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    EXPECT_EQ(mesh->face_count(), 1u);
}

TEST(ObjRead, UvsDroppedWhenSomeFacesHaveNone) {
    auto mesh = read_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nf 1/1 2/1 3/1\nf 2 4 3\n");
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    EXPECT_FALSE(mesh->has_uvs());
    EXPECT_TRUE(mesh->uvs.empty());
    EXPECT_TRUE(validate(*mesh).ok());
}

TEST(ObjRead, Tags) {
    const std::string text =
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n"
        "f 1 2 3 4\nf 2 5 6 3\n"
        "t crease 2/1/0 0 1 2.5\n"
        "t crease 4/1/0 1 2 2 3 7\n"     // several pairs, one sharpness for all
        "t crease 4/2/0 3 0 4 5 1 10\n"  // one sharpness per pair
        "t corner 1/1/0 5 3\n"
        "t corner 2/2/0 0 4 0.5 -2\n"  // negative sharpness clamps to 0 (OpenSubdiv)
        "t hole 1/0/0 1\n"
        "t interpolateboundary 1/0/0 1\n"
        "t creasemethod 0/0/1 chaikin\n"  // known to OpenSubdiv, ignored here
        "t vertexedit 4/2/3 1 2 3 4 0.5 0.25 add P value\n"
        "t facevaryinginterpolateboundary 1/0/0 1\n";
    auto mesh = read_obj(text);
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    const auto& t = mesh->tags;
    ASSERT_EQ(t.creases.size(), 5u);
    EXPECT_EQ(t.creases[0].v0, 0u);
    EXPECT_EQ(t.creases[0].v1, 1u);
    EXPECT_EQ(t.creases[0].sharpness, 2.5);
    EXPECT_EQ(t.creases[1].v0, 1u);
    EXPECT_EQ(t.creases[2].v1, 3u);
    EXPECT_EQ(t.creases[2].sharpness, 7.0);
    EXPECT_EQ(t.creases[3].sharpness, 1.0);
    EXPECT_EQ(t.creases[4].v0, 4u);
    EXPECT_EQ(t.creases[4].sharpness, 10.0);
    ASSERT_EQ(t.corners.size(), 3u);
    EXPECT_EQ(t.corners[0].vertex, 5u);
    EXPECT_EQ(t.corners[0].sharpness, 3.0);
    EXPECT_EQ(t.corners[2].vertex, 4u);
    EXPECT_EQ(t.corners[2].sharpness, 0.0);
    EXPECT_EQ(t.holes, (std::vector<Index>{1}));
    EXPECT_EQ(t.boundary, BoundaryInterpolation::EdgeAndCorner);
    EXPECT_TRUE(validate(*mesh).ok());
}

TEST(ObjRead, InterpolateBoundaryValues) {
    const std::string base = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    EXPECT_EQ(read_obj(base + "t interpolateboundary 1/0/0 0\n")->tags.boundary, BoundaryInterpolation::None);
    EXPECT_EQ(read_obj(base + "t interpolateboundary 1/0/0 1\n")->tags.boundary, BoundaryInterpolation::EdgeAndCorner);
    EXPECT_EQ(read_obj(base + "t interpolateboundary 1/0/0 2\n")->tags.boundary, BoundaryInterpolation::EdgeOnly);
    EXPECT_FALSE(read_obj(base)->tags.boundary.has_value());
}

TEST(ObjRead, TagsMayPrecedeGeometry) {
    auto mesh = read_obj("t crease 2/1/0 0 2 1\nt hole 1/0/0 0\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    EXPECT_EQ(mesh->tags.creases.size(), 1u);
}

TEST(ObjRead, RepeatedVertexIsAnErrorUnlessAllowed) {
    const std::string text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 4 3 2 2\n";
    EXPECT_TRUE(fails_with(read_obj(text), ErrorCode::DegenerateFace, "line 6: face uses vertex 2 more than once"));
    ReadOptions lenient;
    lenient.allow_repeated_vertices = true;
    auto mesh = read_obj(text, lenient);
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    EXPECT_EQ(mesh->face_count(), 2u);
}

TEST(ObjRead, LimitsGiveBudgetExceeded) {
    const std::string text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3 4\nf 1 2 3\n";
    ReadOptions few_vertices;
    few_vertices.max_vertices = 3;
    EXPECT_TRUE(
        fails_with(read_obj(text, few_vertices), ErrorCode::BudgetExceeded, "line 4: more than max_vertices (3)"));
    ReadOptions few_faces;
    few_faces.max_faces = 1;
    EXPECT_TRUE(fails_with(read_obj(text, few_faces), ErrorCode::BudgetExceeded, "line 6: more than max_faces (1)"));
    ReadOptions small_faces;
    small_faces.max_face_size = 3;
    EXPECT_TRUE(fails_with(read_obj(text, small_faces), ErrorCode::BudgetExceeded,
                           "line 5: face has more than max_face_size (3)"));
}

PolygonMesh tagged_mesh_with_uvs() {
    PolygonMesh m = format_test::cube();
    // awkward doubles: only an exact text form reads back bit-identical
    m.positions[0] = {0.1, 1.0 / 3.0, -2.0 / 7.0};
    m.positions[1] = {1e-300, 1.7976931348623157e308, -4.9e-324};
    m.positions[6] = {123456789.123456789, -0.0, 6.02214076e23};
    for (std::size_t i = 0; i < m.face_indices.size(); ++i) {
        m.uv_indices.push_back(static_cast<Index>(i % 5));
    }
    m.uvs = {{0, 0}, {0.125, 1.0 / 3.0}, {1, 1}, {0.7, 0.2}, {1e-9, 0.999999999999}};
    m.tags.creases = {{0, 1, 2.5}, {1, 2, 10}, {5, 6, 1.0 / 3.0}};
    m.tags.corners = {{7, 4.25}};
    m.tags.holes = {2, 4};
    m.tags.boundary = BoundaryInterpolation::EdgeOnly;
    return m;
}

TEST(ObjWrite, RoundTripIsExact) {
    const PolygonMesh original = tagged_mesh_with_uvs();
    ASSERT_TRUE(validate(original).ok());
    const std::string text = write_obj(original);
    auto back = read_obj(text);
    ASSERT_TRUE(back.ok()) << back.error().message << "\n" << text;
    expect_same_mesh(original, *back);
    EXPECT_NE(text.find("t crease 2/1/0 0 1 2.5\n"), std::string::npos) << text;
    EXPECT_NE(text.find("t hole 2/0/0 2 4\n"), std::string::npos) << text;
    EXPECT_NE(text.find("t interpolateboundary 1/0/0 2\n"), std::string::npos) << text;
    EXPECT_NE(text.find("v 0.1 "), std::string::npos) << "shortest exact form expected";
}

TEST(ObjWrite, NormalsAndOptions) {
    PolygonMesh m = tagged_mesh_with_uvs();
    m.normals.assign(m.positions.size(), Vec3{0, 0, 1});
    const std::string with_all = write_obj(m);
    EXPECT_NE(with_all.find("vn 0 0 1\n"), std::string::npos);
    EXPECT_NE(with_all.find("f 1/1/1 4/2/4 3/3/3 2/4/2\n"), std::string::npos) << with_all;
    auto back = read_obj(with_all);
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(back->face_indices, m.face_indices);
    EXPECT_EQ(back->uv_indices, m.uv_indices);

    ObjWriteOptions bare;
    bare.write_tags = false;
    bare.write_uvs = false;
    bare.write_normals = false;
    const std::string plain = write_obj(m, bare);
    EXPECT_EQ(plain.find("vt "), std::string::npos);
    EXPECT_EQ(plain.find("vn "), std::string::npos);
    EXPECT_EQ(plain.find("t "), std::string::npos);
    EXPECT_NE(plain.find("f 1 4 3 2\n"), std::string::npos);
    auto plain_back = read_obj(plain);
    ASSERT_TRUE(plain_back.ok());
    EXPECT_TRUE(plain_back->tags.empty());
    EXPECT_FALSE(plain_back->has_uvs());

    ObjWriteOptions normals_only = bare;
    normals_only.write_normals = true;
    EXPECT_NE(write_obj(m, normals_only).find("f 1//1 4//4 3//3 2//2\n"), std::string::npos);

    ObjWriteOptions short_numbers;
    short_numbers.precision = 3;
    EXPECT_NE(write_obj(m, short_numbers).find("v 0.1 0.333 -0.286\n"), std::string::npos)
        << write_obj(m, short_numbers);
}

TEST(ObjLarge, QuarterMillionFacesRoundTrip) {
    const PolygonMesh grid = format_test::big_grid(500);  // 250,000 quads, ~20 MB of text
    const std::string text = write_obj(grid);
    auto back = read_obj(text);
    ASSERT_TRUE(back.ok()) << back.error().message;
    expect_same_mesh(grid, *back);
}

// ---- the OpenSubdiv regression shapes

struct ShapeCounts {
    std::size_t v = 0, f = 0, crease_pairs = 0, corners = 0, holes = 0, faces_with_vt = 0;
    bool has_boundary_tag = false;
};

//! Counts what the reader should find, by looking at the file line by line independently of the reader.
ShapeCounts count_by_hand(const std::string& text) {
    ShapeCounts c;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream words(line);
        std::string kw;
        words >> kw;
        if (kw == "v") ++c.v;
        if (kw == "f") {
            ++c.f;
            if (line.find('/') != std::string::npos && line.find("//") == std::string::npos) ++c.faces_with_vt;
        }
        if (kw == "t") {
            std::string name, counts;
            words >> name >> counts;
            const int nints = std::stoi(counts.substr(0, counts.find('/')));
            if (name == "crease") c.crease_pairs += static_cast<std::size_t>(nints / 2);
            if (name == "corner") c.corners += static_cast<std::size_t>(nints);
            if (name == "hole") c.holes += static_cast<std::size_t>(nints);
            if (name == "interpolateboundary") c.has_boundary_tag = true;
        }
    }
    return c;
}

std::vector<std::filesystem::path> shape_files() {
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::directory_iterator(format_test::shapes_dir()))
        if (entry.path().extension() == ".obj") files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    return files;
}

TEST(ObjCorpus, EveryOpenSubdivShapeParses) {
    const auto files = shape_files();
    ASSERT_EQ(files.size(), 122u);
    ReadOptions lenient;
    lenient.allow_repeated_vertices = true;  // five shapes repeat a vertex in a face on purpose
    std::size_t total_v = 0, total_f = 0, total_creases = 0;
    for (const auto& path : files) {
        SCOPED_TRACE(path.filename().string());
        const std::string text = format_test::slurp(path.string());
        auto mesh = read_obj(text, lenient);
        ASSERT_TRUE(mesh.ok()) << mesh.error().message;
        const ShapeCounts expected = count_by_hand(text);
        EXPECT_EQ(mesh->vertex_count(), expected.v);
        EXPECT_EQ(mesh->face_count(), expected.f);
        EXPECT_EQ(mesh->tags.creases.size(), expected.crease_pairs);
        EXPECT_EQ(mesh->tags.corners.size(), expected.corners);
        EXPECT_EQ(mesh->tags.holes.size(), expected.holes);
        EXPECT_EQ(mesh->tags.boundary.has_value(), expected.has_boundary_tag);
        EXPECT_EQ(mesh->has_uvs(), expected.faces_with_vt == expected.f);
        total_v += mesh->vertex_count();
        total_f += mesh->face_count();
        total_creases += mesh->tags.creases.size();

        // Writing and reading back gives the same mesh (tags included).
        auto back = read_obj(write_obj(*mesh), lenient);
        ASSERT_TRUE(back.ok()) << back.error().message;
        expect_same_mesh(*mesh, *back);
    }
    // Totals from the corpus README.
    EXPECT_EQ(total_v, 10702u);
    EXPECT_EQ(total_f, 10509u);
    EXPECT_EQ(total_creases, 1379u);
}

TEST(ObjCorpus, RepeatedVerticesRejectedByDefaultWithLine) {
    // The README lists these as the shapes with faces that repeat a vertex; everything else validates.
    const std::map<std::string, int> expected_line = {
        {"catmark_nonman_edges.obj", 161},      {"catmark_nonman_quadpole360.obj", 723},
        {"catmark_nonman_quadpole64.obj", 131}, {"catmark_nonman_quadpole8.obj", 19},
        {"loop_nonman_edges.obj", 192},
    };
    for (const auto& path : shape_files()) {
        SCOPED_TRACE(path.filename().string());
        auto mesh = read_obj(format_test::slurp(path.string()));
        auto it = expected_line.find(path.filename().string());
        if (it == expected_line.end()) {
            ASSERT_TRUE(mesh.ok()) << mesh.error().message;
            EXPECT_TRUE(validate(*mesh).ok()) << validate(*mesh).error().message;
        } else {
            EXPECT_TRUE(fails_with(mesh, ErrorCode::DegenerateFace, "line " + std::to_string(it->second) + ": "));
            EXPECT_EQ(mesh.error().line, it->second);
        }
    }
}

TEST(ObjCorpus, HandCheckedShapes) {
    auto read = [](const char* name) {
        auto mesh = read_obj(format_test::slurp(format_test::shapes_dir() + "/" + name));
        EXPECT_TRUE(mesh.ok()) << name << ": " << mesh.error().message;
        return mesh.ok() ? std::move(mesh).value() : PolygonMesh{};
    };
    const PolygonMesh bishop = read("catmark_bishop.obj");
    EXPECT_EQ(bishop.vertex_count(), 917u);
    EXPECT_EQ(bishop.face_count(), 968u);
    EXPECT_EQ(bishop.tags.creases.size(), 224u);
    EXPECT_TRUE(bishop.has_uvs());

    const PolygonMesh cube = read("catmark_cube_corner0.obj");
    ASSERT_EQ(cube.tags.corners.size(), 1u);
    EXPECT_EQ(cube.tags.corners[0].vertex, 0u);
    EXPECT_EQ(cube.tags.corners[0].sharpness, 0.7);
    EXPECT_EQ(format_test::euler(cube), 2);

    const PolygonMesh holes = read("catmark_hole_test3.obj");
    EXPECT_EQ(holes.tags.holes, (std::vector<Index>{15, 2, 7, 8, 9, 5, 13, 14}));
    EXPECT_EQ(holes.tags.boundary, BoundaryInterpolation::EdgeAndCorner);

    const PolygonMesh edgenone = read("catmark_edgenone.obj");
    EXPECT_EQ(edgenone.tags.boundary, BoundaryInterpolation::None);  // and its `#t` lines stay comments

    const PolygonMesh hedit = read("catmark_square_hedit0.obj");  // vertexedit 16/24/3 ... add P value: ignored
    EXPECT_EQ(hedit.vertex_count(), 16u);
    EXPECT_EQ(hedit.face_count(), 9u);
    EXPECT_EQ(hedit.tags.boundary, BoundaryInterpolation::EdgeOnly);

    const PolygonMesh tet = read("catmark_toroidal_tet.obj");
    EXPECT_EQ(format_test::euler(tet), -4);

    const PolygonMesh pole = read("catmark_pole8.obj");
    EXPECT_FALSE(pole.has_uvs());
}

// ReadReport::face_lines: the line each face starts on, for text formats, so that an error found after reading can
// name it; none for binary formats and STL.
TEST(ReadReport, KeepsTheLineOfEachFaceOfATextFile) {
    const auto lines_of = [](std::string_view bytes, MeshFormat format) {
        ReadReport report;
        report.face_lines = {99};  // read_mesh starts afresh
        auto mesh = read_mesh(bytes, format, {}, &report);
        EXPECT_TRUE(mesh.ok()) << (mesh.ok() ? "" : mesh.error().message);
        if (mesh.ok() && !report.face_lines.empty()) {
            EXPECT_EQ(report.face_lines.size(), mesh->face_count());
        }
        return report.face_lines;
    };
    // comments, blank lines, other statements and a continued face (it is numbered by its first line)
    const std::string obj =
        "# square\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\ng part\nf 1 2 3\n# next\nf 1 \\\n3 4\n"
        "s off\r\nf 2 3 4\r\n";
    EXPECT_EQ(lines_of(obj, MeshFormat::Obj), (std::vector<std::uint32_t>{8, 10, 13}));
    const std::string off = "OFF\n# c\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n\n3 0 2 3 255 0 0\n";
    EXPECT_EQ(lines_of(off, MeshFormat::Off), (std::vector<std::uint32_t>{8, 10}));
    PolygonMesh square;
    square.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    square.add_face({0, 1, 2});
    square.add_face({0, 2, 3});
    const std::string ascii = write_ply(square, PlyEncoding::Ascii);
    const auto header_lines = static_cast<std::uint32_t>(
        std::count(ascii.begin(), ascii.begin() + static_cast<std::ptrdiff_t>(ascii.find("end_header")), '\n') + 1);
    EXPECT_EQ(lines_of(ascii, MeshFormat::Ply),
              (std::vector<std::uint32_t>{header_lines + 5, header_lines + 6}));  // after the 4 vertex lines
    EXPECT_TRUE(lines_of(write_ply(square), MeshFormat::Ply).empty());            // binary: no lines
    // UTF-16 text keeps its line numbers
    std::string utf16 = "\xff\xfe";
    for (char c : off) {
        utf16 += c;
        utf16 += '\0';
    }
    EXPECT_EQ(lines_of(utf16, MeshFormat::Off), (std::vector<std::uint32_t>{8, 10}));
}

}  // namespace
}  // namespace surfaced
