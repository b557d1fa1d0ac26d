// STL reader: ascii and binary (detected by size, not by "solid"), exact welding, degenerate triangles dropped.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "geometry/io/mesh_io.h"
#include "tests/io/format_test_helpers.h"

namespace surfaced {
namespace {

using format_test::fails_with;
using Triangle = std::array<Vec3, 3>;

//! The unit cube as 12 outward triangles, 36 corners (each vertex repeated), the way STL stores it.
std::vector<Triangle> cube_triangles() {
    const PolygonMesh cube = format_test::cube();
    std::vector<Triangle> out;
    for (std::size_t f = 0; f < cube.face_count(); ++f) {
        auto q = cube.face(f);
        out.push_back({cube.positions[q[0]], cube.positions[q[1]], cube.positions[q[2]]});
        out.push_back({cube.positions[q[0]], cube.positions[q[2]], cube.positions[q[3]]});
    }
    return out;
}

std::string ascii_stl(const std::vector<Triangle>& triangles, const std::string& name = "cube") {
    std::string s = "solid " + name + "\n";
    for (const auto& t : triangles) {
        s += "  facet normal 0 0 0\n    outer loop\n";
        for (const Vec3& p : t)
            s += "      vertex " + std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + "\n";
        s += "    endloop\n  endfacet\n";
    }
    return s + "endsolid " + name + "\n";
}

void put_u32(std::string& s, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) s += static_cast<char>((v >> (8 * i)) & 0xff);
}
void put_f32(std::string& s, float f) {
    std::uint32_t bits = 0;
    std::memcpy(&bits, &f, 4);
    put_u32(s, bits);
}

std::string binary_stl(const std::vector<Triangle>& triangles, const std::string& header_text) {
    std::string s = header_text;
    s.resize(80, ' ');
    put_u32(s, static_cast<std::uint32_t>(triangles.size()));
    for (const auto& t : triangles) {
        for (int k = 0; k < 3; ++k) put_f32(s, 0.f);
        for (const Vec3& p : t) {
            put_f32(s, static_cast<float>(p.x));
            put_f32(s, static_cast<float>(p.y));
            put_f32(s, static_cast<float>(p.z));
        }
        s += '\0';
        s += '\0';
    }
    return s;
}

void expect_welded_cube(const Result<PolygonMesh>& mesh) {
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    EXPECT_EQ(mesh->vertex_count(), 8u);
    EXPECT_EQ(mesh->face_count(), 12u);
    EXPECT_TRUE(mesh->is_triangle_mesh());
    EXPECT_EQ(format_test::euler(*mesh), 2);
    EXPECT_TRUE(validate(*mesh).ok());
}

TEST(StlRead, AsciiCubeIsWelded) {
    auto mesh = read_stl(ascii_stl(cube_triangles()));
    expect_welded_cube(mesh);
    // first triangle keeps its corner order
    EXPECT_EQ(mesh->positions[mesh->face_indices[1]], (Vec3{0, 1, 0}));
}

TEST(StlRead, BinaryCubeStartingWithSolid) {
    const std::string bytes = binary_stl(cube_triangles(), "solid cube exported by a tool that lies");
    ASSERT_EQ(bytes.substr(0, 5), "solid");
    expect_welded_cube(read_stl(bytes));
    EXPECT_EQ(sniff_format(bytes), MeshFormat::Stl);
}

TEST(StlRead, BinaryAndAsciiAgree) {
    auto a = read_stl(ascii_stl(cube_triangles()));
    auto b = read_stl(binary_stl(cube_triangles(), "binary"));
    ASSERT_TRUE(a.ok() && b.ok());
    format_test::expect_same_mesh(*a, *b);
}

TEST(StlRead, UppercaseKeywordsCrlfAndSeveralSolids) {
    auto tris = cube_triangles();
    std::vector<Triangle> first(tris.begin(), tris.begin() + 6), second(tris.begin() + 6, tris.end());
    std::string text = ascii_stl(first, "a") + ascii_stl(second, "b");
    for (const char* kw : {"facet", "outer", "loop", "vertex", "endloop", "endfacet"}) {
        std::string upper(kw);
        for (char& c : upper) c = static_cast<char>(c - 'a' + 'A');
        for (std::size_t pos = 0; (pos = text.find(std::string(" ") + kw + " ", pos)) != std::string::npos;)
            text.replace(pos + 1, upper.size(), upper);
    }
    std::string crlf;
    for (char c : text) {
        if (c == '\n') crlf += '\r';
        crlf += c;
    }
    expect_welded_cube(read_stl(crlf));
}

TEST(StlRead, NegativeZeroWeldsWithZero) {
    std::vector<Triangle> t = {{Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 1, 0}},
                               {Vec3{-0.0, 0, -0.0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}}};
    auto mesh = read_stl(binary_stl(t, "zeros"));
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    EXPECT_EQ(mesh->vertex_count(), 4u);
}

TEST(StlRead, DegenerateTrianglesAreDropped) {
    auto tris = cube_triangles();
    tris.insert(tris.begin() + 3, Triangle{Vec3{0, 0, 0}, Vec3{0, 0, 0}, Vec3{1, 1, 1}});  // two equal corners
    tris.push_back(Triangle{Vec3{5, 5, 5}, Vec3{5, 5, 5}, Vec3{5, 5, 5}});                 // a point
    expect_welded_cube(read_stl(binary_stl(tris, "")));  // and no stray vertex at (5,5,5)
    expect_welded_cube(read_stl(ascii_stl(tris)));
}

TEST(StlRead, PaddedBinaryIsRead) {
    // Not "solid", size bigger than 84 + 50n: binary with trailing bytes, which are ignored.
    std::string bytes = binary_stl(cube_triangles(), "padded") + std::string(17, '\0');
    expect_welded_cube(read_stl(bytes));
}

TEST(StlRead, Limits) {
    ReadOptions options;
    options.max_faces = 11;
    EXPECT_TRUE(
        fails_with(read_stl(binary_stl(cube_triangles(), "x"), options), ErrorCode::BudgetExceeded, "offset 80: "));
    EXPECT_TRUE(fails_with(read_stl(ascii_stl(cube_triangles()), options), ErrorCode::BudgetExceeded,
                           "line 79: more than max_faces (11) triangles"));
    options = {};
    options.max_vertices = 7;
    EXPECT_TRUE(fails_with(read_stl(binary_stl(cube_triangles(), "x"), options), ErrorCode::BudgetExceeded,
                           "max_vertices (7)"));
}

TEST(StlRead, LargeGridWeldsExactly) {
    // 200 x 200 quads: 80,000 triangles welded into 201 x 201 vertices.
    std::vector<Triangle> tris;
    const int n = 200;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            Vec3 a{double(i), double(j), 0}, b{double(i + 1), double(j), 0}, c{double(i + 1), double(j + 1), 0},
                d{double(i), double(j + 1), 0};
            tris.push_back({a, b, c});
            tris.push_back({a, c, d});
        }
    auto mesh = read_stl(binary_stl(tris, "grid"));
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    EXPECT_EQ(mesh->vertex_count(), std::size_t(n + 1) * (n + 1));
    EXPECT_EQ(mesh->face_count(), std::size_t(2 * n * n));
    EXPECT_EQ(format_test::euler(*mesh), 1);
}

// ---- write_stl --------------------------------------------------------------------------------------------------

float stored_float(const std::string& bytes, std::size_t offset) {
    std::uint32_t bits = 0;
    for (int i = 3; i >= 0; --i) bits = (bits << 8) | static_cast<unsigned char>(bytes[offset + i]);
    float f;
    std::memcpy(&f, &bits, 4);
    return f;
}

TEST(StlWrite, BinaryLayoutFanTrianglesAndUnitFacetNormals) {
    const PolygonMesh cube = format_test::cube();  // 6 quads -> 12 triangles
    const std::string bytes = write_stl(cube);
    ASSERT_EQ(bytes.size(), 84u + 12u * 50u);
    EXPECT_NE(bytes.substr(0, 5), "solid");  // a binary header must not look like ascii STL
    EXPECT_EQ(static_cast<unsigned char>(bytes[80]), 12u);
    EXPECT_EQ(bytes[81] | bytes[82] | bytes[83], 0);
    std::size_t t = 0;
    for (std::size_t f = 0; f < cube.face_count(); ++f) {
        const auto face = cube.face(f);
        for (std::size_t k = 1; k + 1 < face.size(); ++k, ++t) {
            const std::size_t at = 84 + t * 50;
            const Vec3 corners[3] = {cube.positions[face[0]], cube.positions[face[k]], cube.positions[face[k + 1]]};
            // the facet normal: the unit normal of the fan triangle, outward for the outward cube
            const Vec3 n{stored_float(bytes, at), stored_float(bytes, at + 4), stored_float(bytes, at + 8)};
            EXPECT_NEAR(norm(n), 1.0, 1e-6) << "triangle " << t;
            const Vec3 expected = cross(corners[1] - corners[0], corners[2] - corners[0]);
            EXPECT_NEAR(dot(n, expected * (1.0 / norm(expected))), 1.0, 1e-6) << "triangle " << t;
            for (int c = 0; c < 3; ++c)
                for (int axis = 0; axis < 3; ++axis)
                    EXPECT_EQ(stored_float(bytes, at + 12 + 12 * c + 4 * axis), static_cast<float>(corners[c][axis]));
            EXPECT_EQ(bytes[at + 48] | bytes[at + 49], 0);  // attribute byte count
        }
    }
}

TEST(StlWrite, ReadsBackToTheSameTrianglesAndConnectivity) {
    // float-representable coordinates: STL stores float32, so these come back bit for bit
    PolygonMesh grid = format_test::big_grid(6);
    for (Vec3& p : grid.positions)
        for (int axis = 0; axis < 3; ++axis) p[axis] = static_cast<float>(p[axis]);
    auto read = read_stl(write_stl(grid));
    ASSERT_TRUE(read.ok()) << read.error().message;
    ASSERT_EQ(read->face_count(), 2 * grid.face_count());
    EXPECT_EQ(read->vertex_count(), grid.vertex_count());  // corners weld back into the grid's vertices
    EXPECT_EQ(format_test::euler(*read), format_test::euler(grid));
    std::size_t t = 0;
    for (std::size_t f = 0; f < grid.face_count(); ++f) {
        const auto face = grid.face(f);
        for (std::size_t k = 1; k + 1 < face.size(); ++k, ++t) {
            const auto got = read->face(t);
            ASSERT_EQ(got.size(), 3u);
            EXPECT_TRUE(read->positions[got[0]] == grid.positions[face[0]]) << "triangle " << t;
            EXPECT_TRUE(read->positions[got[1]] == grid.positions[face[k]]) << "triangle " << t;
            EXPECT_TRUE(read->positions[got[2]] == grid.positions[face[k + 1]]) << "triangle " << t;
        }
    }
}

TEST(StlWrite, NonConvexPolygonIsTriangulatedInsideItsOutline) {
    // an L-shaped hexagon whose fan from corner 0 would cover area outside it: every written triangle must face +z
    // and the areas must add up to the polygon's (3)
    PolygonMesh mesh;
    mesh.positions = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}};
    mesh.add_face({2, 3, 4, 5, 0, 1});  // starting at a corner next to the reflex one
    const std::string bytes = write_stl(mesh);
    ASSERT_EQ(bytes.size(), 84u + 4u * 50u);
    double area = 0;
    for (std::size_t t = 0; t < 4; ++t) {
        const std::size_t at = 84 + t * 50;
        Vec3 c[3];
        for (int k = 0; k < 3; ++k)
            c[k] = {stored_float(bytes, at + 12 + 12 * k), stored_float(bytes, at + 16 + 12 * k),
                    stored_float(bytes, at + 20 + 12 * k)};
        const Vec3 n = cross(c[1] - c[0], c[2] - c[0]);
        EXPECT_GT(n.z, 0) << "triangle " << t;
        area += 0.5 * norm(n);
    }
    EXPECT_DOUBLE_EQ(area, 3.0);
}

TEST(StlWrite, DegenerateTriangleGetsAZeroNormal) {
    PolygonMesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
    mesh.add_face({0, 1, 2});
    const std::string bytes = write_stl(mesh);
    ASSERT_EQ(bytes.size(), 84u + 50u);
    for (int axis = 0; axis < 3; ++axis) EXPECT_EQ(stored_float(bytes, 84 + 4 * axis), 0.0f);
}

}  // namespace
}  // namespace surfaced
