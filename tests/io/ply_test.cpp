// PLY reader/writer: ascii and both binary byte orders, extra properties and elements of every type, round trips.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "geometry/io/mesh_io.h"
#include "geometry/io/pointcloud_io.h"
#include "tests/io/format_test_helpers.h"

namespace surfaced {
namespace {

using format_test::expect_same_mesh;
using format_test::fails_with;

//! Appends binary values in a chosen byte order (so big-endian files can be made on any host).
struct Writer {
    bool big_endian = false;
    std::string bytes;

    template <class T>
    Writer& put(T value) {
        static_assert(std::is_arithmetic_v<T>);
        unsigned char raw[sizeof(T)];
        std::memcpy(raw, &value, sizeof(T));
        const bool swap = (std::endian::native == std::endian::big) != big_endian;
        for (std::size_t i = 0; i < sizeof(T); ++i) bytes += static_cast<char>(raw[swap ? sizeof(T) - 1 - i : i]);
        return *this;
    }
};

// Vertex colours beside the mesh: uchar red green blue (alpha on request) after the coordinates, in both encodings;
// the mesh reader still reads the mesh, the point reader the colours (rounded to the nearest of 255 levels).
TEST(PlyWrite, VertexColorsAsUcharChannels) {
    PolygonMesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    mesh.face_offsets = {0, 3};
    mesh.face_indices = {0, 1, 2};
    const std::vector<Color> colors = {{1, 0, 0, 1}, {0.5f, 0.25f, 0, 0.5f}, {0, 0, 1, 0}};
    for (PlyEncoding encoding : {PlyEncoding::Ascii, PlyEncoding::BinaryLittleEndian})
        for (bool alpha : {false, true}) {
            const std::string bytes = write_ply(mesh, encoding, colors, alpha);
            auto back = read_ply(bytes);
            ASSERT_TRUE(back.ok()) << back.error().message;
            expect_same_mesh(back.value(), mesh);
            auto points = read_ply_points(bytes);
            ASSERT_TRUE(points.ok()) << points.error().message;
            ASSERT_EQ(points->colors.size(), 3u);
            EXPECT_EQ(points->has_alpha, alpha);
            const double half_level = 0.5 / 255 + 1e-6;  // 0.5 is 127.5 levels: rounded to 128
            for (std::size_t v = 0; v < 3; ++v) {
                EXPECT_NEAR(points->colors[v].r, colors[v].r, half_level);
                EXPECT_NEAR(points->colors[v].g, colors[v].g, half_level);
                EXPECT_NEAR(points->colors[v].b, colors[v].b, half_level);
                EXPECT_NEAR(points->colors[v].a, alpha ? colors[v].a : 1.0f, half_level);
            }
        }
    // no colours, or not one per vertex: none written
    EXPECT_EQ(write_ply(mesh, PlyEncoding::Ascii, {}), write_ply(mesh, PlyEncoding::Ascii));
    EXPECT_EQ(write_ply(mesh, PlyEncoding::Ascii, std::span(colors).first(2)), write_ply(mesh, PlyEncoding::Ascii));
}

TEST(PlyRead, AsciiWithExtraPropertiesElementsAndComments) {
    const std::string text =
        "ply\n"
        "format ascii 1.0\n"
        "comment made by hand\n"
        "obj_info nothing\n"
        "element vertex 4\n"
        "property float x\n"
        "property uchar red\n"
        "property float y\n"
        "property list uchar float weights\n"
        "property double z\n"
        "element face 2\n"
        "property uchar flags\n"
        "property list int int vertex_index\n"
        "property list uchar float texcoord\n"
        "element edge 1\n"
        "property int vertex1\n"
        "property int vertex2\n"
        "end_header\n"
        "0 255 0 2 0.5 0.5 0\n"
        "1 0 0 0 0\n"
        "1 7 1 1 9 0.25\n"
        "0 1 1 3 1 2 3 -7.5\n"
        "1 3 0 1 2 6 0 0 1 0 1 1\n"
        "0 3 0 2 3 0\n"
        "0 1\n";
    auto mesh = read_ply(text);
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    ASSERT_EQ(mesh->vertex_count(), 4u);
    EXPECT_EQ(mesh->positions[2], (Vec3{1, 1, 0.25}));
    EXPECT_EQ(mesh->positions[3], (Vec3{0, 1, -7.5}));
    EXPECT_EQ(mesh->face_indices, (std::vector<Index>{0, 1, 2, 0, 2, 3}));
    EXPECT_FALSE(mesh->has_normals());
    EXPECT_TRUE(validate(*mesh).ok());
}

//! The same 4-vertex, 2-face mesh with unusual types, in either binary byte order.
std::string binary_quad(bool big_endian) {
    std::string header = std::string("ply\nformat ") + (big_endian ? "binary_big_endian" : "binary_little_endian") +
                         " 1.0\n"
                         "comment extra properties of every kind\n"
                         "element vertex 4\n"
                         "property double x\n"
                         "property short tag\n"
                         "property double y\n"
                         "property list ushort int extra\n"
                         "property double z\n"
                         "property uchar alpha\n"
                         "element material 1\n"
                         "property float shininess\n"
                         "property list uint char name\n"
                         "element face 2\n"
                         "property list int ushort vertex_indices\n"
                         "property list uchar double uv\n"
                         "end_header\n";
    Writer w{big_endian, header};
    const double xyz[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0.1}, {0, 1, -1e-300}};
    for (int v = 0; v < 4; ++v) {
        w.put(xyz[v][0]).put(std::int16_t{-3}).put(xyz[v][1]);
        w.put(std::uint16_t(v));  // list of v ints
        for (int k = 0; k < v; ++k) w.put(std::int32_t{k * 1000});
        w.put(xyz[v][2]).put(std::uint8_t{200});
    }
    w.put(0.5f).put(std::uint32_t{3}).put(std::int8_t{'a'}).put(std::int8_t{'b'}).put(std::int8_t{'c'});
    w.put(std::int32_t{3}).put(std::uint16_t{0}).put(std::uint16_t{1}).put(std::uint16_t{2});
    w.put(std::uint8_t{2}).put(0.25).put(0.75);
    w.put(std::int32_t{3}).put(std::uint16_t{0}).put(std::uint16_t{2}).put(std::uint16_t{3});
    w.put(std::uint8_t{0});
    return w.bytes;
}

TEST(PlyRead, BinaryBothByteOrders) {
    for (bool big : {false, true}) {
        SCOPED_TRACE(big ? "big endian" : "little endian");
        auto mesh = read_ply(binary_quad(big));
        ASSERT_TRUE(mesh.ok()) << mesh.error().message;
        ASSERT_EQ(mesh->vertex_count(), 4u);
        EXPECT_EQ(mesh->positions[2], (Vec3{1, 1, 0.1}));
        EXPECT_EQ(mesh->positions[3].z, -1e-300);
        EXPECT_EQ(mesh->face_indices, (std::vector<Index>{0, 1, 2, 0, 2, 3}));
    }
}

TEST(PlyRead, FloatAndIntegerCoordinatesUcharCountsUintIndices) {
    Writer w{false,
             "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty int y\n"
             "property uchar z\nproperty float nx\nproperty float ny\nproperty float nz\n"
             "element face 1\nproperty list uchar uint vertex_indices\nend_header\n"};
    w.put(1.5f).put(std::int32_t{-2}).put(std::uint8_t{250}).put(0.f).put(0.f).put(1.f);
    w.put(0.f).put(std::int32_t{0}).put(std::uint8_t{0}).put(0.f).put(0.f).put(1.f);
    w.put(2.f).put(std::int32_t{7}).put(std::uint8_t{1}).put(0.f).put(1.f).put(0.f);
    w.put(std::uint8_t{3}).put(std::uint32_t{2}).put(std::uint32_t{1}).put(std::uint32_t{0});
    auto mesh = read_ply(w.bytes);
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    EXPECT_EQ(mesh->positions[0], (Vec3{1.5, -2, 250}));
    EXPECT_EQ(mesh->positions[2], (Vec3{2, 7, 1}));
    ASSERT_TRUE(mesh->has_normals());  // nx/ny/nz are read when all three are there
    EXPECT_EQ(mesh->normals[2], (Vec3{0, 1, 0}));
    EXPECT_EQ(mesh->face_indices, (std::vector<Index>{2, 1, 0}));
}

TEST(PlyRead, CrlfHeaderAndUtf8Bom) {
    auto mesh = read_ply(
        "\xef\xbb\xbfply\r\nformat ascii 1.0\r\nelement vertex 3\r\nproperty float x\r\nproperty float y\r\n"
        "property float z\r\nelement face 1\r\nproperty list uchar int vertex_indices\r\nend_header\r\n"
        "0 0 0\r\n1 0 0\r\n0 1 0\r\n3 0 1 2\r\n");
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    EXPECT_EQ(mesh->face_count(), 1u);
}

TEST(PlyRead, StrayHeaderLinesAreIgnored) {
    // Blender 2.4x writes a "Created by" line into the header; other unknown first words are skipped the same way.
    const std::string body =
        "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    auto plain = read_ply("ply\nformat ascii 1.0\n" + body);
    auto blender = read_ply(
        "ply\nformat ascii 1.0\nCreated by Blender 2.49 - www.blender.org, source file: ''\n"
        "x_made_up_keyword 1 2 3\n" +
        body);
    ASSERT_TRUE(plain.ok()) << plain.error().message;
    ASSERT_TRUE(blender.ok()) << blender.error().message;
    expect_same_mesh(*plain, *blender);

    // Known keywords keep their checks, and lines after a stray one keep their numbers.
    EXPECT_TRUE(fails_with(read_ply("ply\nformat ascii 1.0\nCreated by Blender 2.49\nelement vertex\n" + body),
                           ErrorCode::ParseError, "line 4: element line needs a name and a count"));
    EXPECT_TRUE(fails_with(read_ply("ply\nformat ascii 1.0\nCreated by Blender\nelement vertex -3\n" + body),
                           ErrorCode::ParseError, "line 4: element count '-3' is not a non-negative integer"));
    EXPECT_TRUE(fails_with(read_ply("ply\nCreated by Blender\nformat ascii 2.0\n" + body), ErrorCode::Unsupported,
                           "line 3: PLY version '2.0'"));
    auto bad_body =
        read_ply("ply\nformat ascii 1.0\nCreated by Blender\n" + body.substr(0, body.size() - 8) + "3 0 1 9\n");
    EXPECT_TRUE(fails_with(bad_body, ErrorCode::IndexOutOfRange, "line 14: face index 9 out of range"));
    if (!bad_body.ok()) {
        EXPECT_EQ(bad_body.error().line, 14);
    }
}

TEST(PlyRead, LimitsAndRepeatedVertices) {
    const std::string text =
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n4 0 2 3 3\n";
    EXPECT_TRUE(fails_with(read_ply(text), ErrorCode::DegenerateFace, "line 15: face 1 uses vertex 3 more than once"));
    ReadOptions options;
    options.allow_repeated_vertices = true;
    EXPECT_TRUE(read_ply(text, options).ok());
    options = {};
    options.max_vertices = 3;
    EXPECT_TRUE(fails_with(read_ply(text, options), ErrorCode::BudgetExceeded, "line 3: header declares 4 vertices"));
    options = {};
    options.max_faces = 1;
    EXPECT_TRUE(fails_with(read_ply(text, options), ErrorCode::BudgetExceeded, "line 7: header declares 2 faces"));
    options = {};
    options.max_face_size = 3;
    EXPECT_TRUE(fails_with(read_ply(text, options), ErrorCode::BudgetExceeded, "line 14: face 0 has 4 vertices"));
}

PolygonMesh mesh_for_round_trip(bool with_normals, bool big_face) {
    PolygonMesh m = format_test::cube();
    m.positions[0] = {0.1, 1.0 / 3.0, -2.0 / 7.0};
    m.positions[5] = {1e-300, 1.7976931348623157e308, 4.9e-324};
    if (with_normals)
        for (std::size_t i = 0; i < m.positions.size(); ++i) m.normals.push_back({0.5, -1.0 / 3.0, double(i)});
    if (big_face) {
        // a 300-gon forces `list uint uint`
        std::vector<Index> ring;
        for (int i = 0; i < 300; ++i) {
            ring.push_back(static_cast<Index>(m.positions.size()));
            m.positions.push_back({std::cos(i * 0.021), std::sin(i * 0.021), 2});
            if (with_normals) m.normals.push_back({0, 0, 1});
        }
        m.add_face(ring);
    }
    return m;
}

TEST(PlyWrite, RoundTripIsExact) {
    for (PlyEncoding encoding : {PlyEncoding::Ascii, PlyEncoding::BinaryLittleEndian})
        for (bool normals : {false, true})
            for (bool big_face : {false, true}) {
                SCOPED_TRACE(::testing::Message() << "binary=" << (encoding == PlyEncoding::BinaryLittleEndian)
                                                  << " normals=" << normals << " big_face=" << big_face);
                const PolygonMesh original = mesh_for_round_trip(normals, big_face);
                const std::string bytes = write_ply(original, encoding);
                EXPECT_EQ(bytes.find(big_face ? "property list uint uint vertex_indices"
                                              : "property list uchar uint vertex_indices"),
                          bytes.find("property list"));
                auto back = read_ply(bytes);
                ASSERT_TRUE(back.ok()) << back.error().message;
                expect_same_mesh(original, *back);
            }
}

TEST(PlyLarge, QuarterMillionFacesRoundTrip) {
    const PolygonMesh grid = format_test::big_grid(500);
    for (PlyEncoding encoding : {PlyEncoding::Ascii, PlyEncoding::BinaryLittleEndian}) {
        auto back = read_ply(write_ply(grid, encoding));
        ASSERT_TRUE(back.ok()) << back.error().message;
        expect_same_mesh(grid, *back);
    }
}

TEST(PlyWrite, BinaryLayoutIsExact) {
    PolygonMesh m;
    m.positions = {{1, 2, 3}, {4, 5, 6}, {7, 8, 9}};
    m.add_face({0, 1, 2});
    const std::string bytes = write_ply(m, PlyEncoding::BinaryLittleEndian);
    const std::size_t body = bytes.find("end_header\n") + 11;
    EXPECT_EQ(bytes.size() - body, 3 * 24 + 1 + 3 * 4);
    double first = 0;
    std::memcpy(&first, bytes.data() + body, 8);
    if constexpr (std::endian::native == std::endian::little) {
        EXPECT_EQ(first, 1.0);
    }
    EXPECT_EQ(static_cast<unsigned char>(bytes[body + 72]), 3u);
}

TEST(PlyWrite, AsciiNumbersAreShortestWithoutNegativeZero) {
    PolygonMesh mesh;
    mesh.positions = {{-0.0, 0.1, 1}, {1, 2.5, -0.0}, {0, 1, 1e-300}};
    mesh.add_face({0, 1, 2});
    const std::string text = write_ply(mesh, PlyEncoding::Ascii);
    EXPECT_NE(text.find("end_header\n0 0.1 1\n1 2.5 0\n0 1 1e-300\n3 0 1 2\n"), std::string::npos) << text;
}

}  // namespace
}  // namespace surfaced
