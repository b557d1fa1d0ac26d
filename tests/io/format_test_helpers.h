// Helpers shared by the OBJ/OFF/PLY/STL tests (header-only so that the test list in CMake stays as it is).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>
#include <string>
#include <utility>

#include "geometry/core/result.h"
#include "geometry/mesh/polygon_mesh.h"

namespace surfaced::format_test {

inline std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    EXPECT_TRUE(in.good()) << "cannot open " << path;
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

inline std::string malformed_dir() { return std::string(SURFACED_SOURCE_DIR) + "/tests/data/malformed"; }
inline std::string shapes_dir() { return std::string(SURFACED_TEST_DATA_DIR) + "/opensubdiv-shapes"; }

//! V - E + F, edges counted as unordered vertex pairs.
inline std::int64_t euler(const PolygonMesh& mesh) {
    std::set<std::pair<Index, Index>> edges;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        auto face = mesh.face(f);
        for (std::size_t i = 0; i < face.size(); ++i) {
            Index a = face[i], b = face[(i + 1) % face.size()];
            edges.insert({std::min(a, b), std::max(a, b)});
        }
    }
    return static_cast<std::int64_t>(mesh.vertex_count()) - static_cast<std::int64_t>(edges.size()) +
           static_cast<std::int64_t>(mesh.face_count());
}

//! Unit cube, 8 vertices and 6 outward quads.
inline PolygonMesh cube() {
    PolygonMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    m.add_face({0, 3, 2, 1});
    m.add_face({4, 5, 6, 7});
    m.add_face({0, 1, 5, 4});
    m.add_face({1, 2, 6, 5});
    m.add_face({2, 3, 7, 6});
    m.add_face({3, 0, 4, 7});
    return m;
}

//! An n x n grid of quads with irregular coordinates (for large-file tests).
inline PolygonMesh big_grid(int n) {
    PolygonMesh m;
    m.positions.reserve(std::size_t(n + 1) * (n + 1));
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) m.positions.push_back({i / 7.0, j / 3.0, (i * 31 + j * 17) % 101 * 1e-3 + 0.1});
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const auto v = static_cast<Index>(j * (n + 1) + i);
            m.add_face({v, v + 1, static_cast<Index>(v + n + 2), static_cast<Index>(v + n + 1)});
        }
    return m;
}

//! Bit-exact comparison of everything a PolygonMesh holds.
inline void expect_same_mesh(const PolygonMesh& a, const PolygonMesh& b) {
    ASSERT_EQ(a.positions.size(), b.positions.size());
    for (std::size_t i = 0; i < a.positions.size(); ++i) {
        EXPECT_EQ(a.positions[i].x, b.positions[i].x) << "vertex " << i;
        EXPECT_EQ(a.positions[i].y, b.positions[i].y) << "vertex " << i;
        EXPECT_EQ(a.positions[i].z, b.positions[i].z) << "vertex " << i;
    }
    EXPECT_EQ(a.face_offsets, b.face_offsets);
    EXPECT_EQ(a.face_indices, b.face_indices);
    ASSERT_EQ(a.uvs.size(), b.uvs.size());
    for (std::size_t i = 0; i < a.uvs.size(); ++i) {
        EXPECT_EQ(a.uvs[i].x, b.uvs[i].x);
        EXPECT_EQ(a.uvs[i].y, b.uvs[i].y);
    }
    EXPECT_EQ(a.uv_indices, b.uv_indices);
    ASSERT_EQ(a.normals.size(), b.normals.size());
    for (std::size_t i = 0; i < a.normals.size(); ++i) EXPECT_TRUE(a.normals[i] == b.normals[i]) << "normal " << i;
    ASSERT_EQ(a.tags.creases.size(), b.tags.creases.size());
    for (std::size_t i = 0; i < a.tags.creases.size(); ++i) {
        EXPECT_EQ(a.tags.creases[i].v0, b.tags.creases[i].v0);
        EXPECT_EQ(a.tags.creases[i].v1, b.tags.creases[i].v1);
        EXPECT_EQ(a.tags.creases[i].sharpness, b.tags.creases[i].sharpness);
    }
    ASSERT_EQ(a.tags.corners.size(), b.tags.corners.size());
    for (std::size_t i = 0; i < a.tags.corners.size(); ++i) {
        EXPECT_EQ(a.tags.corners[i].vertex, b.tags.corners[i].vertex);
        EXPECT_EQ(a.tags.corners[i].sharpness, b.tags.corners[i].sharpness);
    }
    EXPECT_EQ(a.tags.holes, b.tags.holes);
    EXPECT_EQ(a.tags.boundary, b.tags.boundary);
}

//! The error's code, and that its message contains `needle` (e.g. "line 12:").
template <class T>
::testing::AssertionResult fails_with(const Result<T>& result, ErrorCode code, const std::string& needle) {
    if (result.ok()) return ::testing::AssertionFailure() << "expected " << to_string(code) << ", but it succeeded";
    const GeoError& e = result.error();
    if (e.code != code)
        return ::testing::AssertionFailure()
               << "expected " << to_string(code) << ", got " << to_string(e.code) << ": " << e.message;
    if (e.message.find(needle) == std::string::npos)
        return ::testing::AssertionFailure() << "message '" << e.message << "' does not contain '" << needle << "'";
    return ::testing::AssertionSuccess() << e.message;
}

}  // namespace surfaced::format_test
