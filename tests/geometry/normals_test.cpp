// compute_vertex_normals: unit length, outward on closed convex shapes, area weighting, degenerate fallbacks.
#include "geometry/mesh/normals.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace surfaced {
namespace {

// Unit cube centred at the origin, quads wound counter-clockwise seen from outside.
PolygonMesh make_cube() {
    PolygonMesh m;
    for (int i = 0; i < 8; ++i)
        m.positions.push_back({(i & 1) ? 0.5 : -0.5, (i & 2) ? 0.5 : -0.5, (i & 4) ? 0.5 : -0.5});
    m.add_face({0, 2, 3, 1});  // -z
    m.add_face({4, 5, 7, 6});  // +z
    m.add_face({0, 1, 5, 4});  // -y
    m.add_face({2, 6, 7, 3});  // +y
    m.add_face({0, 4, 6, 2});  // -x
    m.add_face({1, 3, 7, 5});  // +x
    return m;
}

// Latitude/longitude sphere: quads between rings, triangle fans at the poles; outward orientation.
PolygonMesh make_uv_sphere(int rings, int segments, double radius = 1.0, Vec3 centre = {}) {
    PolygonMesh m;
    m.positions.push_back(centre + Vec3{0, 0, radius});
    for (int r = 1; r < rings; ++r) {
        const double theta = std::numbers::pi * r / rings;
        for (int s = 0; s < segments; ++s) {
            const double phi = 2 * std::numbers::pi * s / segments;
            m.positions.push_back(centre + radius * Vec3{std::sin(theta) * std::cos(phi),
                                                         std::sin(theta) * std::sin(phi), std::cos(theta)});
        }
    }
    m.positions.push_back(centre + Vec3{0, 0, -radius});
    auto ring = [&](int r, int s) { return static_cast<Index>(1 + (r - 1) * segments + (s % segments)); };
    const auto south = static_cast<Index>(m.positions.size() - 1);
    for (int s = 0; s < segments; ++s) m.add_face({0, ring(1, s), ring(1, s + 1)});
    for (int r = 1; r + 1 < rings; ++r)
        for (int s = 0; s < segments; ++s) m.add_face({ring(r, s), ring(r + 1, s), ring(r + 1, s + 1), ring(r, s + 1)});
    for (int s = 0; s < segments; ++s) m.add_face({ring(rings - 1, s), south, ring(rings - 1, s + 1)});
    return m;
}

TEST(Normals, CubeCornersPointAlongTheDiagonal) {
    const PolygonMesh cube = make_cube();
    const auto normals = compute_vertex_normals(cube);
    ASSERT_EQ(normals.size(), cube.vertex_count());
    for (std::size_t v = 0; v < normals.size(); ++v) {
        EXPECT_NEAR(norm(normals[v]), 1.0, 1e-12);
        // Three incident faces of equal area: the normal is the corner direction itself.
        const Vec3 expected = cube.positions[v] * (1.0 / norm(cube.positions[v]));
        EXPECT_NEAR(dot(normals[v], expected), 1.0, 1e-12) << "vertex " << v;
    }
}

TEST(Normals, SphereNormalsAreUnitAndOutward) {
    const Vec3 centre{3, -2, 5};  // off the origin: the result must not depend on where the mesh sits
    const PolygonMesh sphere = make_uv_sphere(12, 24, 2.0, centre);
    const auto normals = compute_vertex_normals(sphere);
    for (std::size_t v = 0; v < normals.size(); ++v) {
        EXPECT_NEAR(norm(normals[v]), 1.0, 1e-12);
        Vec3 radial = sphere.positions[v] - centre;
        radial *= 1.0 / norm(radial);
        // Close to the radial direction (the tessellation makes it approximate, but never inward).
        EXPECT_GT(dot(normals[v], radial), 0.99) << "vertex " << v;
    }
}

TEST(Normals, ReversedOrientationFlipsNormals) {
    PolygonMesh cube = make_cube();
    for (std::size_t f = 0; f < cube.face_count(); ++f)
        std::reverse(cube.face_indices.begin() + cube.face_offsets[f],
                     cube.face_indices.begin() + cube.face_offsets[f + 1]);
    const auto normals = compute_vertex_normals(cube);
    for (std::size_t v = 0; v < normals.size(); ++v) EXPECT_LT(dot(normals[v], cube.positions[v]), 0) << "vertex " << v;
}

TEST(Normals, WeightedByFaceArea) {
    // Two triangles sharing edge (0,1): a big one in the z = 0 plane and a small one tilted up. The shared vertices'
    // normal is the normalised sum of the two vector areas, so it leans towards the big face's +z.
    PolygonMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0.5, 4, 0}, {0.5, -0.1, 0.1}};
    m.add_face({0, 1, 2});  // area 2, normal +z
    m.add_face({1, 0, 3});  // small
    const auto normals = compute_vertex_normals(m);
    const Vec3 big{0, 0, 2};
    const Vec3 small = cross(m.positions[0] - m.positions[1], m.positions[3] - m.positions[1]) * 0.5;
    Vec3 expected = big + small;
    expected *= 1.0 / norm(expected);
    EXPECT_NEAR(dot(normals[0], expected), 1.0, 1e-12);
    EXPECT_NEAR(dot(normals[1], expected), 1.0, 1e-12);
    EXPECT_NEAR(dot(normals[2], Vec3{0, 0, 1}), 1.0, 1e-12);
}

TEST(Normals, ConcavePolygonUsesNewellNormal) {
    // An L-shaped hexagon, counter-clockwise in the xy plane: its first three corners happen to turn clockwise, so a
    // normal from one corner's cross product would point down; Newell's sum does not.
    PolygonMesh m;
    m.positions = {{1, 1, 0}, {1, 2, 0}, {0, 2, 0}, {0, 0, 0}, {2, 0, 0}, {2, 1, 0}};
    m.add_face({0, 1, 2, 3, 4, 5});
    for (const Vec3& n : compute_vertex_normals(m)) EXPECT_NEAR(n.z, 1.0, 1e-12);
}

TEST(Normals, IsolatedAndDegenerateVerticesGetUp) {
    PolygonMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {5, 5, 5}};
    m.add_face({0, 1, 2});  // collinear: zero area
    const auto normals = compute_vertex_normals(m);
    ASSERT_EQ(normals.size(), 4u);
    for (const Vec3& n : normals) EXPECT_EQ(n, (Vec3{0, 0, 1}));
}

TEST(Normals, EmptyMesh) { EXPECT_TRUE(compute_vertex_normals(PolygonMesh{}).empty()); }

}  // namespace
}  // namespace surfaced
