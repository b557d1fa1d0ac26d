// triangulate: n - 2 triangles per polygon, orientation kept, concave polygons without flipped or overlapping
// triangles, uv indices carried per corner.
#include "geometry/mesh/triangulate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <random>

namespace surfaced {
namespace {

Vec3 polygon_vector_area(const std::vector<Vec3>& p) {
    Vec3 s;
    for (std::size_t i = 0; i < p.size(); ++i) s += cross(p[i] - p[0], p[(i + 1) % p.size()] - p[0]);
    return s * 0.5;
}

PolygonMesh single_polygon(const std::vector<Vec3>& points) {
    PolygonMesh m;
    m.positions = points;
    std::vector<Index> face(points.size());
    for (std::size_t i = 0; i < face.size(); ++i) face[i] = static_cast<Index>(i);
    m.add_face(face);
    return m;
}

//! Every triangle must face the polygon's way (no flips) and the areas must add up to the polygon's (no overlaps:
//! with all triangles positively oriented, any overlap or spill outside would make the sum differ).
void expect_valid_triangulation(const PolygonMesh& polygon, const PolygonMesh& tris, double tolerance = 1e-9) {
    ASSERT_EQ(polygon.face_count(), 1u);
    const std::size_t n = polygon.face_size(0);
    ASSERT_EQ(tris.face_count(), n - 2);
    ASSERT_TRUE(tris.is_triangle_mesh());
    std::vector<Vec3> pts;
    for (Index v : polygon.face(0)) pts.push_back(polygon.positions[v]);
    const Vec3 area = polygon_vector_area(pts);
    const double total = norm(area);
    const Vec3 normal = area * (1.0 / total);
    double sum = 0;
    for (std::size_t f = 0; f < tris.face_count(); ++f) {
        auto t = tris.face(f);
        const Vec3 a =
            cross(tris.positions[t[1]] - tris.positions[t[0]], tris.positions[t[2]] - tris.positions[t[0]]) * 0.5;
        const double signed_area = dot(a, normal);
        EXPECT_GT(signed_area, -tolerance * total) << "triangle " << f << " is flipped";
        sum += signed_area;
    }
    EXPECT_NEAR(sum, total, tolerance * total);
}

TEST(Triangulate, CountsAreSumOfNMinusTwo) {
    PolygonMesh m;
    for (int i = 0; i < 12; ++i) m.positions.push_back({std::cos(i * 0.5), std::sin(i * 0.5), 0});
    m.add_face({0, 1, 2});
    m.add_face({0, 2, 3, 4});
    m.add_face({4, 5, 6, 7, 8});
    m.add_face({0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11});
    const PolygonMesh t = triangulate(m);
    EXPECT_EQ(t.face_count(), 1u + 2u + 3u + 10u);
    EXPECT_TRUE(t.is_triangle_mesh());
    EXPECT_EQ(t.positions.size(), m.positions.size());
    EXPECT_TRUE(validate(t).ok());
}

TEST(Triangulate, TrianglesAreUntouchedAndTagsDropped) {
    PolygonMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
    m.add_face({0, 1, 2});
    m.add_face({1, 3, 2});
    m.tags.creases.push_back({0, 1, 2.0});
    const PolygonMesh t = triangulate(m);
    EXPECT_EQ(t.face_indices, m.face_indices);
    EXPECT_EQ(t.face_offsets, m.face_offsets);
    EXPECT_TRUE(t.tags.empty());
}

TEST(Triangulate, ConvexPolygonIsFannedFromFirstCorner) {
    PolygonMesh m = single_polygon({{0, 0, 0}, {1, 0, 0}, {1.5, 1, 0}, {0.5, 1.5, 0}, {-0.5, 1, 0}});
    const PolygonMesh t = triangulate(m);
    ASSERT_EQ(t.face_count(), 3u);
    for (std::size_t f = 0; f < 3; ++f) EXPECT_EQ(t.face(f)[0], 0u);
    expect_valid_triangulation(m, t);
}

TEST(Triangulate, OrientationPreservedOnAClosedCube) {
    PolygonMesh cube;
    for (int i = 0; i < 8; ++i) cube.positions.push_back({double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)});
    cube.add_face({0, 2, 3, 1});
    cube.add_face({4, 5, 7, 6});
    cube.add_face({0, 1, 5, 4});
    cube.add_face({2, 6, 7, 3});
    cube.add_face({0, 4, 6, 2});
    cube.add_face({1, 3, 7, 5});
    const PolygonMesh t = triangulate(cube);
    ASSERT_EQ(t.face_count(), 12u);
    // Every directed edge of the input survives in the same direction (consistent orientation), and every new
    // diagonal appears once in each direction.
    std::map<std::pair<Index, Index>, int> directed;
    for (std::size_t f = 0; f < t.face_count(); ++f) {
        auto tri = t.face(f);
        for (int k = 0; k < 3; ++k) ++directed[{tri[k], tri[(k + 1) % 3]}];
    }
    for (const auto& [edge, count] : directed) {
        EXPECT_EQ(count, 1);
        EXPECT_EQ(directed.count({edge.second, edge.first}), 1u) << edge.first << "->" << edge.second;
    }
}

TEST(Triangulate, ConcaveLShape) {
    // Corner 0 is reflex: a fan from it would put a triangle outside the polygon.
    const PolygonMesh m = single_polygon({{1, 1, 0}, {1, 2, 0}, {0, 2, 0}, {0, 0, 0}, {2, 0, 0}, {2, 1, 0}});
    expect_valid_triangulation(m, triangulate(m));
}

TEST(Triangulate, ConcaveArrowInATiltedPlane) {
    // An arrow head (two reflex corners), rotated out of the xy plane and moved far from the origin.
    const std::vector<Vec3> flat = {{0, 0, 0}, {4, 0, 0}, {4, -1, 0}, {6, 1, 0},
                                    {4, 3, 0}, {4, 2, 0}, {0, 2, 0},  {1, 1, 0}};
    std::vector<Vec3> tilted;
    const double a = 0.7, b = -1.1;
    for (const Vec3& p : flat) {
        const Vec3 r1{p.x, p.y * std::cos(a) - p.z * std::sin(a), p.y * std::sin(a) + p.z * std::cos(a)};
        const Vec3 r2{r1.x * std::cos(b) + r1.z * std::sin(b), r1.y, -r1.x * std::sin(b) + r1.z * std::cos(b)};
        tilted.push_back(r2 + Vec3{100, -50, 20});
    }
    const PolygonMesh m = single_polygon(tilted);
    expect_valid_triangulation(m, triangulate(m));
}

TEST(Triangulate, ClockwiseConcavePolygonKeepsItsOrientation) {
    // The same L wound the other way: triangles must face -z like the polygon does.
    std::vector<Vec3> pts = {{1, 1, 0}, {1, 2, 0}, {0, 2, 0}, {0, 0, 0}, {2, 0, 0}, {2, 1, 0}};
    std::reverse(pts.begin(), pts.end());
    const PolygonMesh m = single_polygon(pts);
    const PolygonMesh t = triangulate(m);
    expect_valid_triangulation(m, t);
    for (std::size_t f = 0; f < t.face_count(); ++f) {
        auto tri = t.face(f);
        EXPECT_LT(cross(t.positions[tri[1]] - t.positions[tri[0]], t.positions[tri[2]] - t.positions[tri[0]]).z, 0);
    }
}

TEST(Triangulate, RandomStarShapedPolygons) {
    // Star-shaped around the origin with random radii: simple, usually very concave.
    std::mt19937 rng(1234);
    std::uniform_real_distribution<double> radius(0.2, 1.0);
    for (int trial = 0; trial < 200; ++trial) {
        const int n = 4 + trial % 40;
        std::vector<Vec3> pts;
        for (int i = 0; i < n; ++i) {
            const double angle = 2 * std::numbers::pi * i / n;
            const double r = radius(rng);
            pts.push_back({r * std::cos(angle), r * std::sin(angle), 0});
        }
        const PolygonMesh m = single_polygon(pts);
        SCOPED_TRACE("trial " + std::to_string(trial) + ", n = " + std::to_string(n));
        expect_valid_triangulation(m, triangulate(m));
    }
}

TEST(Triangulate, CarriesUvIndicesPerCorner) {
    // A concave polygon with its own uv per corner: each output corner must keep the (vertex, uv) pairing.
    PolygonMesh m = single_polygon({{1, 1, 0}, {1, 2, 0}, {0, 2, 0}, {0, 0, 0}, {2, 0, 0}, {2, 1, 0}});
    for (int i = 0; i < 6; ++i) m.uvs.push_back({0.1 * i, 1 - 0.1 * i});
    m.uv_indices = {5, 4, 3, 2, 1, 0};
    std::map<Index, Index> uv_of;
    for (std::size_t c = 0; c < m.face_indices.size(); ++c) uv_of[m.face_indices[c]] = m.uv_indices[c];
    const PolygonMesh t = triangulate(m);
    ASSERT_EQ(t.uv_indices.size(), t.face_indices.size());
    EXPECT_EQ(t.uvs.size(), m.uvs.size());
    for (std::size_t c = 0; c < t.face_indices.size(); ++c) EXPECT_EQ(t.uv_indices[c], uv_of[t.face_indices[c]]);
    EXPECT_TRUE(validate(t).ok());
}

TEST(Triangulate, DegeneratePolygonsStillGiveNMinusTwo) {
    // Collinear (no plane) and self-intersecting (bow tie) polygons: garbage in, but the contract on counts holds.
    const PolygonMesh line = single_polygon({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {4, 0, 0}});
    EXPECT_EQ(triangulate(line).face_count(), 3u);
    const PolygonMesh bow = single_polygon({{0, 0, 0}, {2, 2, 0}, {2, 0, 0}, {0, 2, 0}, {-1, 1, 0}, {-1, 0.5, 0}});
    const PolygonMesh t = triangulate(bow);
    EXPECT_EQ(t.face_count(), 4u);
    EXPECT_TRUE(validate(t).ok());
}

TEST(Triangulate, LargeConcavePolygon) {
    // A comb with 2000 teeth (10002 corners): exercises the reflex-list bookkeeping at a size where a naive ear test
    // over all corners would be slow.
    const int teeth = 2000;
    // Outline: the spine's bottom edge left to right, then the teeth from right to left.
    std::vector<Vec3> outline;
    outline.push_back({0, -1, 0});
    outline.push_back({double(teeth), -1, 0});
    for (int i = teeth - 1; i >= 0; --i) {
        outline.push_back({i + 1.0, 0, 0});
        outline.push_back({i + 0.75, 0, 0});
        outline.push_back({i + 0.75, 1, 0});
        outline.push_back({i + 0.25, 1, 0});
        outline.push_back({i + 0.25, 0, 0});
    }
    outline.push_back({0, 0, 0});
    const PolygonMesh m = single_polygon(outline);
    expect_valid_triangulation(m, triangulate(m), 1e-9);
}

}  // namespace
}  // namespace surfaced
