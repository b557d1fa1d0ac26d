// The triangle-mesh field (geometry/implicit/triangle_mesh_field.h) against references in this file: the distance as
// the minimum over every triangle, the sign by the exact winding number (the sum of every triangle's solid angle), on
// closed meshes, a polygon mesh, a mesh with a hole and two overlapping shells; the cube mesh against the box
// primitive; the gradient against finite differences and the face normal on the surface; the factory's errors; the
// same values from two threads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <thread>
#include <vector>

#include "geometry/implicit/triangle_mesh_field.h"
#include "geometry/mesh/shapes.h"
#include "geometry/mesh/triangulate.h"
#include "geometry/spatial/closest_point.h"
#include "tests/support/simplify_meshes.h"

namespace surfaced::implicit {
namespace {

//! Brute force over the mesh's triangles (polygons split as the field splits them).
struct Reference {
    PolygonMesh triangles;
    explicit Reference(const PolygonMesh& mesh) : triangles(mesh.is_triangle_mesh() ? mesh : triangulate(mesh)) {}

    double distance(const Vec3& p) const {
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t f = 0; f < triangles.face_count(); ++f) {
            const auto t = triangles.face(f);
            const Vec3 c = triangle_closest_point(p, triangles.positions[t[0]], triangles.positions[t[1]],
                                                  triangles.positions[t[2]])
                               .point;
            best = std::min(best, norm(p - c));
        }
        return best;
    }
    double winding(const Vec3& p) const {
        double sum = 0;
        for (std::size_t f = 0; f < triangles.face_count(); ++f) {
            const auto t = triangles.face(f);
            sum += triangle_solid_angle(p, triangles.positions[t[0]], triangles.positions[t[1]],
                                        triangles.positions[t[2]]);
        }
        return sum / (4 * std::numbers::pi);
    }
};

FieldPtr field_of(const PolygonMesh& mesh, const TriangleMeshFieldOptions& options = {}) {
    auto field = triangle_mesh_field(mesh, options);
    EXPECT_TRUE(field.ok()) << (field.ok() ? "" : field.error().message);
    return field.ok() ? field.value() : nullptr;
}

Vec3 random_point(std::mt19937_64& rng, const Box3& box, double margin) {
    const double pad = margin * box.diagonal();
    std::uniform_real_distribution<double> u(0.0, 1.0);
    return {box.min.x - pad + u(rng) * (box.max.x - box.min.x + 2 * pad),
            box.min.y - pad + u(rng) * (box.max.y - box.min.y + 2 * pad),
            box.min.z - pad + u(rng) * (box.max.z - box.min.z + 2 * pad)};
}

//! Random points around `mesh`: the value's magnitude is the brute-force distance and its sign the exact winding
//! number's (points where that is within `ambiguous` of 1/2 are not judged: the hierarchy's error may tip them).
void expect_matches_reference(const PolygonMesh& mesh, int points, std::uint64_t seed, double ambiguous = 0.02) {
    const FieldPtr field = field_of(mesh);
    ASSERT_TRUE(field);
    const Reference reference(mesh);
    std::mt19937_64 rng(seed);
    const Box3 box = mesh.bounds();
    int judged = 0, inside = 0;
    for (int i = 0; i < points; ++i) {
        const Vec3 p = random_point(rng, box, 0.15);
        const double f = field->value(p);
        const double d = reference.distance(p);
        ASSERT_NEAR(std::fabs(f), d, 1e-12 * (1 + d)) << "point " << i;
        const double w = reference.winding(p);
        if (std::fabs(w - 0.5) < ambiguous) continue;
        ++judged;
        if (w >= 0.5) ++inside;
        EXPECT_EQ(f < 0, w >= 0.5) << "point " << i << " (" << p.x << ", " << p.y << ", " << p.z << "): winding number "
                                   << w << ", value " << f;
    }
    EXPECT_GT(judged, points * 9 / 10);
    EXPECT_GT(inside, points / 20);  // both signs are seen
    EXPECT_LT(inside, judged);
}

TEST(TriangleMeshField, KindAndLipschitz) {
    // closed: an exact distance
    const FieldPtr field = field_of(testing::triangle_cube());
    ASSERT_TRUE(field);
    EXPECT_EQ(field->kind(), FieldKind::ExactDistance);
    EXPECT_EQ(field->lipschitz(), 1.0);
    EXPECT_EQ(dynamic_cast<const TriangleMeshField&>(*field).triangle_count(), 12u);
    // closed as well: unwelded (every triangle its own corners, as STL stores them), quads, two overlapping shells,
    // inward-facing triangles
    PolygonMesh soup;
    const PolygonMesh cube = testing::triangle_cube();
    for (std::size_t f = 0; f < cube.face_count(); ++f) {
        const auto t = cube.face(f);
        const auto base = static_cast<Index>(soup.positions.size());
        for (Index v : t) soup.positions.push_back(cube.positions[v]);
        soup.add_face({base, base + 1, base + 2});
    }
    PolygonMesh two = testing::icosphere(1);
    const auto n = static_cast<Index>(two.positions.size());
    for (Index v = 0; v < n; ++v) two.positions.push_back(two.positions[v] + Vec3{0.5, 0, 0});
    for (std::size_t f = 0, count = two.face_count(); f < count; ++f) {
        const auto t = two.face(f);
        two.add_face({t[0] + n, t[1] + n, t[2] + n});
    }
    PolygonMesh inward = testing::triangle_cube();
    for (std::size_t f = 0; f < inward.face_count(); ++f)
        std::swap(inward.face_indices[inward.face_offsets[f] + 1], inward.face_indices[inward.face_offsets[f] + 2]);
    for (const PolygonMesh& closed : {soup, shapes::cube(), two, inward}) {
        const FieldPtr f = field_of(closed);
        ASSERT_TRUE(f);
        EXPECT_EQ(f->kind(), FieldKind::ExactDistance);
        EXPECT_TRUE(dynamic_cast<const TriangleMeshField&>(*f).closed());
    }
    EXPECT_GT(field_of(inward)->value({0, 0, 0}), 0);  // inward-facing: all outside
    // a hole (the top face removed) or a single triangle: the value jumps across the sheet that closes it
    PolygonMesh open;
    open.positions = cube.positions;
    for (std::size_t f = 0; f + 2 < cube.face_count(); ++f) open.add_face(cube.face(f));
    PolygonMesh triangle;
    triangle.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    triangle.add_face({0, 1, 2});
    for (const PolygonMesh& mesh : {open, triangle}) {
        const FieldPtr f = field_of(mesh);
        ASSERT_TRUE(f);
        EXPECT_EQ(f->kind(), FieldKind::General);
        EXPECT_EQ(f->lipschitz(), std::numeric_limits<double>::infinity());
        EXPECT_FALSE(dynamic_cast<const TriangleMeshField&>(*f).closed());
    }
}

TEST(TriangleMeshField, CubeMeshIsTheBoxPrimitive) {
    const FieldPtr mesh = field_of(testing::triangle_cube());
    const FieldPtr box = implicit::box({1, 1, 1});
    ASSERT_TRUE(mesh);
    std::mt19937_64 rng(5);
    const Box3 bounds{{-1, -1, -1}, {1, 1, 1}};
    for (int i = 0; i < 2000; ++i) {
        const Vec3 p = random_point(rng, bounds, 0.3);
        ASSERT_NEAR(mesh->value(p), box->value(p), 1e-12) << i;
    }
    // analytic values: centre, a face centre, an edge, outside a corner
    EXPECT_NEAR(mesh->value({0, 0, 0}), -1.0, 1e-15);
    EXPECT_NEAR(mesh->value({0.25, -0.5, 0.75}), -0.25, 1e-15);
    EXPECT_NEAR(mesh->value({0, 0, 3}), 2.0, 1e-15);
    EXPECT_NEAR(mesh->value({2, 2, 2}), std::sqrt(3.0), 1e-15);
    EXPECT_NEAR(mesh->value({1, 1, 0.3}), 0.0, 1e-15);
}

TEST(TriangleMeshField, MatchesBruteForceOnClosedMeshes) {
    expect_matches_reference(testing::icosphere(3), 400, 11);
    expect_matches_reference(testing::triangle_cube(), 400, 12);
}

TEST(TriangleMeshField, PolygonsAreTriangulated) {
    // quads, non-planar ones among them: the field splits them as triangulate() does
    const PolygonMesh torus = shapes::torus(24, 12);
    ASSERT_FALSE(torus.is_triangle_mesh());
    expect_matches_reference(torus, 400, 13);
}

TEST(TriangleMeshField, SignOnAMeshWithAHoleFollowsTheWindingNumber) {
    // the icosphere without its faces near the north pole: the winding number closes the hole
    const PolygonMesh sphere = testing::icosphere(3);
    PolygonMesh open;
    open.positions = sphere.positions;
    for (std::size_t f = 0; f < sphere.face_count(); ++f) {
        const auto t = sphere.face(f);
        const double z = (sphere.positions[t[0]].z + sphere.positions[t[1]].z + sphere.positions[t[2]].z) / 3;
        if (z < 0.8) open.add_face(t);
    }
    ASSERT_LT(open.face_count(), sphere.face_count());
    expect_matches_reference(open, 400, 14);
    // straight below the hole, inside; above it, outside; the value's magnitude stays the distance to the mesh
    const FieldPtr field = field_of(open);
    EXPECT_LT(field->value({0, 0, 0.5}), 0);
    EXPECT_GT(field->value({0, 0, 1.5}), 0);
}

TEST(TriangleMeshField, OverlappingShellsAreOneSolid) {
    // two spheres overlapping: winding number 2 in the lens, still inside
    const PolygonMesh a = testing::icosphere(2);
    PolygonMesh both = a;
    const auto base = static_cast<Index>(a.positions.size());
    for (const Vec3& p : a.positions) both.positions.push_back(p + Vec3{0.8, 0, 0});
    for (std::size_t f = 0; f < a.face_count(); ++f) {
        const auto t = a.face(f);
        both.add_face({t[0] + base, t[1] + base, t[2] + base});
    }
    expect_matches_reference(both, 400, 15);
    EXPECT_LT(field_of(both)->value({0.4, 0, 0}), -0.5);
}

TEST(TriangleMeshField, GradientMatchesFiniteDifferences) {
    for (const PolygonMesh& mesh : {testing::icosphere(3), testing::triangle_cube(), shapes::torus(24, 12)}) {
        const FieldPtr field = field_of(mesh);
        ASSERT_TRUE(field);
        std::mt19937_64 rng(21);
        const Box3 box = mesh.bounds();
        int compared = 0;
        const int points = 300;
        for (int i = 0; i < points; ++i) {
            const Vec3 p = random_point(rng, box, 0.15);
            const Vec3 g = field->gradient(p);
            ASSERT_NEAR(norm(g), 1.0, 1e-12);
            if (std::fabs(field->value(p)) < 1e-4) continue;
            const double h = 1e-6;
            const Vec3 fd = Vec3{field->value(p + Vec3{h, 0, 0}) - field->value(p - Vec3{h, 0, 0}),
                                 field->value(p + Vec3{0, h, 0}) - field->value(p - Vec3{0, h, 0}),
                                 field->value(p + Vec3{0, 0, h}) - field->value(p - Vec3{0, 0, h})} *
                            (0.5 / h);
            // a difference across the medial axis (where the closest point jumps) is no derivative: skip it
            if (std::fabs(norm(fd) - 1) > 1e-4) continue;
            ++compared;
            EXPECT_LT(norm(g - fd), 1e-5) << "point " << i << " (" << p.x << ", " << p.y << ", " << p.z << ")";
        }
        EXPECT_GT(compared, points * 9 / 10);
    }
}

TEST(TriangleMeshField, GradientOnTheSurfaceIsTheOutwardFaceNormal) {
    const FieldPtr field = field_of(testing::triangle_cube());
    ASSERT_TRUE(field);
    const auto expect_vec = [](const Vec3& a, const Vec3& b) {
        EXPECT_NEAR(a.x, b.x, 1e-12);
        EXPECT_NEAR(a.y, b.y, 1e-12);
        EXPECT_NEAR(a.z, b.z, 1e-12);
    };
    expect_vec(field->gradient({0.2, 0.1, 1}), {0, 0, 1});          // on the top face
    expect_vec(field->gradient({0.2, 0.1, 1 - 1e-12}), {0, 0, 1});  // just inside it
    expect_vec(field->gradient({0.2, 0.1, 1 + 1e-12}), {0, 0, 1});  // just outside it
    expect_vec(field->gradient({-1, 0.3, -0.4}), {-1, 0, 0});
    expect_vec(field->gradient({0.5, -1, 0.5}), {0, -1, 0});
    // inside and outside, away from the surface: towards the nearest face / away from the nearest point
    expect_vec(field->gradient({0, 0, 0.5}), {0, 0, 1});
    expect_vec(field->gradient({2, 2, 0}), Vec3{1, 1, 0} * (1 / std::sqrt(2.0)));
}

TEST(TriangleMeshField, FactoryErrors) {
    PolygonMesh empty;
    empty.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    auto none = triangle_mesh_field(empty);
    ASSERT_FALSE(none.ok());
    EXPECT_EQ(none.error().code, ErrorCode::InvalidArgument);

    PolygonMesh nan = testing::triangle_cube();
    nan.positions[5].y = std::numeric_limits<double>::quiet_NaN();
    auto non_finite = triangle_mesh_field(nan);
    ASSERT_FALSE(non_finite.ok());
    EXPECT_EQ(non_finite.error().code, ErrorCode::NonFinite);
    EXPECT_EQ(non_finite.error().element_kind, ElementKind::Vertex);
    EXPECT_EQ(non_finite.error().element, 5);

    PolygonMesh repeated = testing::triangle_cube();
    repeated.add_face({0, 1, 1});
    auto degenerate = triangle_mesh_field(repeated);
    ASSERT_FALSE(degenerate.ok());
    EXPECT_EQ(degenerate.error().code, ErrorCode::DegenerateFace);
    EXPECT_EQ(degenerate.error().element, 12);

    TriangleMeshFieldOptions options;
    for (double beta : {1.0, 0.5, std::numeric_limits<double>::infinity()}) {
        options.winding.accuracy = beta;
        auto bad = triangle_mesh_field(testing::triangle_cube(), options);
        ASSERT_FALSE(bad.ok()) << beta;
        EXPECT_EQ(bad.error().code, ErrorCode::InvalidArgument);
    }
    // the exact sum needs no accuracy
    options.winding.exact = true;
    EXPECT_TRUE(triangle_mesh_field(testing::triangle_cube(), options).ok());
}

TEST(TriangleMeshField, NonFiniteQueryIsNaN) {
    const FieldPtr field = field_of(testing::triangle_cube());
    ASSERT_TRUE(field);
    EXPECT_TRUE(std::isnan(field->value({std::numeric_limits<double>::quiet_NaN(), 0, 0})));
    EXPECT_TRUE(std::isnan(field->gradient({0, std::numeric_limits<double>::infinity(), 0}).x));
}

TEST(TriangleMeshField, TwoThreadsGiveTheSameValues) {
    const FieldPtr field = field_of(testing::icosphere(3));
    ASSERT_TRUE(field);
    std::mt19937_64 rng(31);
    std::vector<Vec3> points;
    for (int i = 0; i < 2000; ++i) points.push_back(random_point(rng, Box3{{-1, -1, -1}, {1, 1, 1}}, 0.2));
    std::vector<double> serial;
    for (const Vec3& p : points) serial.push_back(field->value(p));
    std::vector<double> a(points.size()), b(points.size());
    std::thread t1([&] {
        for (std::size_t i = 0; i < points.size(); ++i) a[i] = field->value(points[i]);
    });
    std::thread t2([&] {
        for (std::size_t i = points.size(); i-- > 0;) b[i] = field->value(points[i]);
    });
    t1.join();
    t2.join();
    EXPECT_EQ(a, serial);
    EXPECT_EQ(b, serial);
}

}  // namespace
}  // namespace surfaced::implicit
