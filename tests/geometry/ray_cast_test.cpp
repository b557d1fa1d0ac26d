// Ray casting: first and all hits through the hierarchy against brute force over every triangle; the triangle test
// against plane intersection; and watertightness: rays aimed exactly at vertices and at points of shared edges (of a
// grid, a sphere and the bunny) never slip through.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <limits>
#include <random>
#include <string>
#include <tuple>

#include "geometry/mesh/shapes.h"
#include "geometry/mesh/triangulate.h"
#include "geometry/spatial/ray_cast.h"
#include "geometry/spatial/ray_dispatch.h"
#include "tests/support/spatial_meshes.h"

namespace surfaced {
namespace {

//! Brute force with the same triangle test: the smallest t over every triangle, or +infinity.
double brute_force_first(const PolygonMesh& mesh, const Ray& ray, std::size_t* hits = nullptr) {
    double best = std::numeric_limits<double>::infinity();
    std::size_t count = 0;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const auto t = mesh.face(f);
        const auto hit = ray_triangle(ray, mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]);
        if (!hit) continue;
        ++count;
        best = std::min(best, hit->t);
    }
    if (hits) *hits = count;
    return best;
}

Ray ray_towards(const Vec3& from, const Vec3& to) { return {from, to - from}; }

void expect_hierarchy_matches_brute_force(const PolygonMesh& mesh, int rays, std::uint64_t seed) {
    auto bvh = build_bvh(mesh);
    ASSERT_TRUE(bvh.ok());
    std::mt19937_64 rng(seed);
    const Box3 box = mesh.bounds();
    int hit_count = 0;
    for (int i = 0; i < rays; ++i) {
        // from around the mesh towards a point inside its box: most rays hit, some miss
        const Ray ray = ray_towards(testing::random_point(rng, box, 0.5), testing::random_point(rng, box, 0.0));
        std::size_t expected_all = 0;
        const double expected = brute_force_first(mesh, ray, &expected_all);
        const auto hit = ray_first_hit(*bvh, ray);
        const auto all = ray_all_hits(*bvh, ray);
        EXPECT_EQ(all.size(), expected_all) << "ray " << i;
        if (expected == std::numeric_limits<double>::infinity()) {
            EXPECT_FALSE(hit.has_value()) << "ray " << i;
            continue;
        }
        ++hit_count;
        ASSERT_TRUE(hit.has_value()) << "ray " << i;
        EXPECT_EQ(hit->t, expected) << "ray " << i;
        ASSERT_FALSE(all.empty());
        EXPECT_EQ(all.front().t, expected);
        for (std::size_t k = 1; k < all.size(); ++k) EXPECT_LE(all[k - 1].t, all[k].t);
        // the hit's description is consistent: point on the ray, barycentrics rebuild it, unit normal across the
        // triangle
        const Vec3 on_ray = ray.origin + ray.direction * hit->t;
        EXPECT_LT(norm(on_ray - hit->point), 1e-12 * box.diagonal());
        const auto tri = mesh.face(hit->face);
        const Vec3 p0 = mesh.positions[tri[0]], p1 = mesh.positions[tri[1]], p2 = mesh.positions[tri[2]];
        const Vec3 rebuilt = p0 * hit->barycentric[0] + p1 * hit->barycentric[1] + p2 * hit->barycentric[2];
        EXPECT_LT(norm(rebuilt - hit->point), 1e-9 * box.diagonal());
        EXPECT_NEAR(norm(hit->normal), 1.0, 1e-12);
        EXPECT_NEAR(dot(hit->normal, p1 - p0), 0.0, 1e-9 * box.diagonal());
    }
    EXPECT_GT(hit_count, rays / 4);
}

TEST(RayCast, TriangleTestMatchesPlaneIntersection) {
    std::mt19937_64 rng(11);
    const Box3 unit{{0, 0, 0}, {1, 1, 1}};
    int hits = 0;
    for (int i = 0; i < 20000; ++i) {
        const Vec3 a = testing::random_point(rng, unit, 0), b = testing::random_point(rng, unit, 0),
                   c = testing::random_point(rng, unit, 0);
        const Ray ray = ray_towards(testing::random_point(rng, unit, 1.0), testing::random_point(rng, unit, 0));
        const Vec3 n = cross(b - a, c - a);
        const double denom = dot(n, ray.direction);
        if (std::fabs(denom) < 1e-6 * norm(n) * norm(ray.direction)) continue;  // grazing: no clean reference
        const double t = dot(n, a - ray.origin) / denom;
        const Vec3 p = ray.origin + ray.direction * t;
        // barycentrics of p by sub-triangle areas along n
        const double area = dot(n, n);
        const double wa = dot(cross(b - p, c - p), n) / area, wb = dot(cross(c - p, a - p), n) / area;
        const double wc = 1 - wa - wb;
        const double margin = std::min({wa, wb, wc});
        const auto hit = ray_triangle(ray, a, b, c);
        if (std::fabs(margin) < 1e-9 || (t < 1e-9 && t > -1e-9)) continue;  // on an edge or at the origin
        const bool expected = margin > 0 && t >= 0;
        ASSERT_EQ(hit.has_value(), expected) << "triangle " << i;
        if (!expected) continue;
        ++hits;
        EXPECT_NEAR(hit->t, t, 1e-9 * std::max(1.0, t));
        EXPECT_NEAR(hit->barycentric[0], wa, 1e-9);
        EXPECT_NEAR(hit->barycentric[1], wb, 1e-9);
        EXPECT_NEAR(hit->barycentric[2], wc, 1e-9);
    }
    EXPECT_GT(hits, 1000);
}

TEST(RayCast, MatchesBruteForceOnSphere) { expect_hierarchy_matches_brute_force(testing::icosphere(3), 1000, 1); }

TEST(RayCast, MatchesBruteForceOnBunny) {
    const PolygonMesh& bunny = testing::spatial_bunny();
    ASSERT_GT(bunny.face_count(), 0u);
    expect_hierarchy_matches_brute_force(bunny, 60, 2);
}

TEST(RayCast, NoMissesThroughGridVerticesAndEdges) {
    // 10 x 10 quads in [0,1]^2 split in two: rays straight down at every vertex, the midpoint of every axis edge and
    // of every diagonal (on the boundary too: the ray is exactly on its line), and obliquely at the interior ones
    // from two origins (the oblique ray passes within rounding of the target, so only shared edges are sure hits)
    const PolygonMesh grid = shapes::grid(10, 10, true);
    auto bvh = build_bvh(grid);
    ASSERT_TRUE(bvh.ok());
    int misses = 0, rays = 0;
    for (int i = 0; i <= 20; ++i)
        for (int j = 0; j <= 20; ++j) {
            const Vec3 target{i / 20.0, j / 20.0, 0.0};
            const bool interior = i > 0 && i < 20 && j > 0 && j < 20;
            for (const Vec3& origin : {target + Vec3{0, 0, 1}, Vec3{0.37, -0.21, 2.0}, Vec3{1.3, 1.7, -0.9}}) {
                if (!interior && origin.z != 1.0) continue;
                ++rays;
                const auto hit = ray_first_hit(*bvh, ray_towards(origin, target));
                if (!hit) {
                    ++misses;
                    ADD_FAILURE() << "missed (" << target.x << ", " << target.y << ") from (" << origin.x << ", "
                                  << origin.y << ", " << origin.z << ")";
                    continue;
                }
                EXPECT_NEAR(hit->t, 1.0, 1e-12);
            }
        }
    EXPECT_EQ(misses, 0);
    EXPECT_EQ(rays, 21 * 21 + 19 * 19 * 2);
}

TEST(RayCast, NoMissesThroughSharedEdgesAndVerticesOfClosedMeshes) {
    // Rays aimed at a vertex or a point of an edge, where every face around that vertex or edge faces the same way
    // as seen along the ray: the ray crosses the surface there, so it must hit at or before the target however
    // the rounding of the target falls. (Where the faces around face both ways the target is on the silhouette, and
    // rounding may legitimately put the ray just outside; those targets, and edges of holes, are skipped.)
    std::mt19937_64 rng(5);
    for (const PolygonMesh& mesh : {testing::icosphere(3), testing::spatial_bunny()}) {
        ASSERT_GT(mesh.face_count(), 0u);
        auto bvh = build_bvh(mesh);
        ASSERT_TRUE(bvh.ok());
        std::map<std::pair<Index, Index>, std::vector<std::size_t>> edge_faces;
        std::vector<std::vector<std::size_t>> vertex_faces(mesh.vertex_count());
        for (std::size_t f = 0; f < mesh.face_count(); ++f) {
            const auto t = mesh.face(f);
            for (int k = 0; k < 3; ++k) {
                edge_faces[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}].push_back(f);
                vertex_faces[t[k]].push_back(f);
            }
        }
        auto normal = [&](std::size_t f) {
            const auto t = mesh.face(f);
            return cross(mesh.positions[t[1]] - mesh.positions[t[0]], mesh.positions[t[2]] - mesh.positions[t[0]]);
        };
        auto crossing = [&](const std::vector<std::size_t>& faces, const Vec3& d) {
            int front = 0, back = 0;
            for (std::size_t f : faces) (dot(normal(f), d) < 0 ? front : back)++;
            return faces.size() >= 2 && (front == 0 || back == 0);
        };
        const Box3 box = mesh.bounds();
        std::uniform_real_distribution<double> lambda(0.0, 1.0);
        std::uniform_int_distribution<std::size_t> pick(0, mesh.face_count() - 1);
        int misses = 0, aimed = 0;
        for (int i = 0; i < 4000; ++i) {
            const auto face = mesh.face(pick(rng));
            const Index va = face[i % 3], vb = face[(i + 1) % 3];
            const Vec3 a = mesh.positions[va], b = mesh.positions[vb];
            // a vertex every fourth ray, otherwise a point of an edge
            const bool at_vertex = i % 4 == 0;
            const Vec3 target = at_vertex ? a : a + (b - a) * lambda(rng);
            const Ray ray = ray_towards(testing::random_point(rng, box, 0.5), target);
            const auto& around = at_vertex ? vertex_faces[va] : edge_faces[{std::min(va, vb), std::max(va, vb)}];
            if (!crossing(around, ray.direction)) continue;
            ++aimed;
            const auto hit = ray_first_hit(*bvh, ray);
            if (!hit || hit->t > 1.0 + 1e-9) {
                ++misses;
                ADD_FAILURE() << "ray " << i << (hit ? " hit late" : " missed");
            }
        }
        EXPECT_EQ(misses, 0);
        EXPECT_GT(aimed, 3000);
    }
}

TEST(RayCast, ParityOnClosedSphereAndRayLimits) {
    const PolygonMesh sphere = testing::icosphere(3);
    auto bvh = build_bvh(sphere);
    ASSERT_TRUE(bvh.ok());
    std::mt19937_64 rng(9);
    for (int i = 0; i < 200; ++i) {
        const Vec3 d = testing::random_unit(rng);
        // from the centre: exactly one crossing; from outside, through the centre: two
        EXPECT_EQ(ray_all_hits(*bvh, {{0, 0, 0}, d}).size(), 1u);
        const auto through = ray_all_hits(*bvh, {d * 3.0, d * -1.0});
        ASSERT_EQ(through.size(), 2u);
        EXPECT_NEAR(through[0].t, 2.0, 0.02);
        EXPECT_NEAR(through[1].t, 4.0, 0.02);
        EXPECT_LT(dot(through[0].normal, d * -1.0), 0);  // entering through the front
        EXPECT_GT(dot(through[1].normal, d * -1.0), 0);  // leaving through the back
        // t limits
        Ray limited{d * 3.0, d * -1.0, 2.5, 10.0};
        const auto second = ray_first_hit(*bvh, limited);
        ASSERT_TRUE(second.has_value());
        EXPECT_EQ(second->t, through[1].t);
        limited.t_max = 3.9;
        EXPECT_FALSE(ray_first_hit(*bvh, limited).has_value());
    }
    EXPECT_FALSE(ray_first_hit(*bvh, {{0, 0, 0}, {0, 0, 0}}).has_value());
    const double inf = std::numeric_limits<double>::infinity();
    EXPECT_FALSE(ray_first_hit(*bvh, {{0, 0, 0}, {inf, 0, 0}}).has_value());
}

TEST(RayCast, RaysWithoutAMeaningHitNothingAndUnboundedOnesHitBothWays) {
    // refused by both layouts: NaN or infinite coordinates, NaN or reversed t limits
    const PolygonMesh sphere = testing::icosphere(2);
    auto bvh = build_bvh(sphere);
    ASSERT_TRUE(bvh.ok());
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    const Vec3 o{0.1, -0.2, 3}, d{0, 0.1, -1};
    for (const Ray& ray : {Ray{{nan, 0, 3}, d}, Ray{{0, 0, -inf}, d}, Ray{o, {0, nan, -1}}, Ray{o, d, nan, inf},
                           Ray{o, d, 0, nan}, Ray{o, d, 3, 2}}) {
        EXPECT_FALSE(ray_first_hit(*bvh, ray).has_value());
        EXPECT_TRUE(ray_all_hits(*bvh, ray).empty());
    }
    // from the centre with t unbounded below: the crossing behind (t < 0) comes first, the same in both layouts
    BvhOptions binary_only;
    binary_only.ray_nodes = false;
    auto binary = build_bvh(sphere, binary_only);
    ASSERT_TRUE(binary.ok());
    const Ray both_ways{{0, 0, 0}, {0.2113, 0.3719, -0.9041}, -inf, inf};  // through no edge or vertex
    const auto hits = ray_all_hits(*bvh, both_ways);
    ASSERT_EQ(hits.size(), 2u);
    EXPECT_LT(hits[0].t, 0);
    EXPECT_GT(hits[1].t, 0);
    const auto first = ray_first_hit(*bvh, both_ways), first_binary = ray_first_hit(*binary, both_ways);
    ASSERT_TRUE(first.has_value() && first_binary.has_value());
    EXPECT_EQ(first->t, hits[0].t);
    EXPECT_EQ(first->t, first_binary->t);
    EXPECT_EQ(first->face, first_binary->face);
}

// ---- the float ray layout (TriangleBvh::ray_nodes) against the binary double path and brute force --------------

//! Every hit by brute force with the same triangle test, as (t, face, corners) by increasing t then face.
std::vector<std::tuple<double, Index, std::array<Index, 3>>> brute_force_all(const PolygonMesh& mesh, const Ray& ray) {
    std::vector<std::tuple<double, Index, std::array<Index, 3>>> out;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const auto t = mesh.face(f);
        if (const auto hit = ray_triangle(ray, mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]))
            out.emplace_back(hit->t, static_cast<Index>(f), std::array<Index, 3>{t[0], t[1], t[2]});
    }
    std::sort(out.begin(), out.end());
    return out;
}

//! ray_all_hits equals brute force hit for hit (t exactly, face and corners), and ray_first_hit is its first.
void expect_all_hits_equal_brute_force(const TriangleBvh& bvh, const PolygonMesh& mesh, const Ray& ray,
                                       const std::string& what) {
    const auto expected = brute_force_all(mesh, ray);
    auto all = ray_all_hits(bvh, ray);
    std::sort(all.begin(), all.end(), [](const RayHit& a, const RayHit& b) {
        return std::tie(a.t, a.face, a.vertices) < std::tie(b.t, b.face, b.vertices);
    });
    ASSERT_EQ(all.size(), expected.size()) << what;
    for (std::size_t k = 0; k < all.size(); ++k) {
        EXPECT_EQ(all[k].t, std::get<0>(expected[k])) << what;
        EXPECT_EQ(all[k].face, std::get<1>(expected[k])) << what;
        EXPECT_EQ(all[k].vertices, std::get<2>(expected[k])) << what;
    }
    const auto first = ray_first_hit(bvh, ray);
    ASSERT_EQ(first.has_value(), !expected.empty()) << what;
    if (first) {
        EXPECT_EQ(first->t, std::get<0>(expected.front())) << what;
    }
}

TEST(RayCast, EveryHitOnGridVerticesAndEdgesEqualsBruteForce) {
    // rays through the vertices and edges of a grid split into triangles, at random heights and angles, straight
    // down (two direction components exactly 0), lying in the grid's plane along its lines (edge on), and with
    // t_min beyond the grid: hit for hit what every triangle says alone
    const PolygonMesh grid = shapes::grid(10, 10, true);
    auto bvh = build_bvh(grid);
    ASSERT_TRUE(bvh.ok());
    ASSERT_FALSE(bvh->ray_nodes.empty());
    std::mt19937_64 rng(21);
    std::uniform_int_distribution<int> cell(0, 20);
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    int rays = 0;
    for (int i = 0; i < 3000; ++i) {
        // a vertex (even, even), an axis edge's midpoint or a diagonal's midpoint
        const Vec3 target{cell(rng) / 20.0, cell(rng) / 20.0, 0.0};
        Ray ray;
        switch (i % 5) {
            case 0: ray = ray_towards({u(rng), u(rng), 1.5}, target); break;
            case 1: ray = ray_towards({u(rng), u(rng), -1.5}, target); break;
            case 2: ray = {target + Vec3{0, 0, 1}, {0, 0, -1}}; break;
            case 3: ray = {target + Vec3{-1, 0, 0}, {1, 0, 0}}; break;             // in the plane, along a grid line
            default: ray = {target + Vec3{0, 0, 1}, {0, 0, -1}, 1.0, 3.0}; break;  // t_min exactly at the plane
        }
        ++rays;
        expect_all_hits_equal_brute_force(*bvh, grid, ray, "ray " + std::to_string(i));
    }
    EXPECT_EQ(rays, 3000);
}

TEST(RayCast, FloatLayoutGivesTheDoublePathsAnswers) {
    // the same rays through the float layout and through the binary double nodes alone (ray_nodes = false): the
    // same first face, t, barycentrics and point, and the same every-hit list
    BvhOptions binary_only;
    binary_only.ray_nodes = false;
    std::mt19937_64 rng(23);
    int compared = 0, hits = 0;
    for (const PolygonMesh& mesh : {testing::icosphere(3), testing::spatial_bunny(), shapes::torus(60, 40),
                                    testing::translated(shapes::torus(60, 40), {1e5, 2e5, -3e5})}) {
        ASSERT_GT(mesh.face_count(), 0u);
        const PolygonMesh triangles = mesh.is_triangle_mesh() ? mesh : triangulate(mesh);
        auto wide = build_bvh(triangles);
        auto binary = build_bvh(triangles, binary_only);
        ASSERT_TRUE(wide.ok() && binary.ok());
        ASSERT_FALSE(wide->ray_nodes.empty());
        ASSERT_TRUE(binary->ray_nodes.empty());
        const Box3 box = triangles.bounds();
        for (int i = 0; i < 1000; ++i) {
            const Ray ray = ray_towards(testing::random_point(rng, box, 0.5), testing::random_point(rng, box, 0.0));
            const auto a = ray_first_hit(*wide, ray), b = ray_first_hit(*binary, ray);
            ++compared;
            ASSERT_EQ(a.has_value(), b.has_value()) << "ray " << i;
            if (a) {
                ++hits;
                EXPECT_EQ(a->face, b->face) << "ray " << i;
                EXPECT_EQ(a->t, b->t) << "ray " << i;
                EXPECT_EQ(a->barycentric, b->barycentric) << "ray " << i;
                EXPECT_EQ(a->point, b->point) << "ray " << i;
                EXPECT_EQ(a->normal, b->normal) << "ray " << i;
            }
            if (i % 10 == 0) {
                const auto all_a = ray_all_hits(*wide, ray), all_b = ray_all_hits(*binary, ray);
                ASSERT_EQ(all_a.size(), all_b.size()) << "ray " << i;
                for (std::size_t k = 0; k < all_a.size(); ++k) {
                    EXPECT_EQ(all_a[k].t, all_b[k].t);
                    EXPECT_EQ(all_a[k].face, all_b[k].face);
                }
            }
        }
    }
    EXPECT_EQ(compared, 4000);
    EXPECT_GT(hits, 1500);
}

TEST(RayCast, FloatLayoutAtTheEdgesOfTheFloatRange) {
    // meshes far from the origin, tiny (products in float's subnormal range), huge (corners beyond float), and rays
    // the float layout hands to the double path (origin beyond 2^100, a direction of 1e-200): hit for hit brute force
    std::mt19937_64 rng(29);
    const PolygonMesh sphere = testing::icosphere(2);
    auto scaled = [](PolygonMesh m, double s, const Vec3& offset) {
        for (Vec3& p : m.positions) p = p * s + offset;
        return m;
    };
    for (const PolygonMesh& mesh :
         {scaled(sphere, 1.0, {3e7, -1e7, 5e6}), scaled(sphere, 1e-25, {0, 0, 0}), scaled(sphere, 1e-25, {1e-20, 0, 0}),
          scaled(sphere, 1e200, {0, 0, 0}), scaled(sphere, 1e35, {2e35, 0, 0})}) {
        auto bvh = build_bvh(mesh);
        ASSERT_TRUE(bvh.ok());
        const Box3 box = mesh.bounds();
        std::uniform_int_distribution<std::size_t> pick(0, mesh.positions.size() - 1);
        for (int i = 0; i < 300; ++i) {
            Ray ray;
            if (i % 3 == 0) {
                ray = ray_towards(testing::random_point(rng, box, 0.5), testing::random_point(rng, box, 0.0));
            } else {
                // at a vertex, or at the midpoint of two (often an edge)
                const Vec3 a = mesh.positions[pick(rng)], b = mesh.positions[pick(rng)];
                ray = ray_towards(testing::random_point(rng, box, 0.5), i % 3 == 1 ? a : (a + b) * 0.5);
            }
            expect_all_hits_equal_brute_force(*bvh, mesh, ray, "ray " + std::to_string(i));
        }
    }
    // rays the float layout does not take
    const PolygonMesh unit = testing::icosphere(2);
    auto bvh = build_bvh(unit);
    ASSERT_TRUE(bvh.ok());
    for (int i = 0; i < 100; ++i) {
        const Vec3 d = testing::random_unit(rng);
        expect_all_hits_equal_brute_force(*bvh, unit, {d * -0x1p101, d}, "far origin");
        expect_all_hits_equal_brute_force(*bvh, unit, {d * -3.0, d * 1e-200}, "tiny direction");
        expect_all_hits_equal_brute_force(*bvh, unit, {d * -3.0, d * 1e200}, "huge direction");
    }
}

TEST(RayCast, LargeLeavesUseSeveralFloatBlocks) {
    // leaves of up to 64 triangles (several blocks of four per leaf)
    BvhOptions options;
    options.max_leaf_size = 64;
    const PolygonMesh sphere = testing::icosphere(3);
    auto bvh = build_bvh(sphere, options);
    ASSERT_TRUE(bvh.ok());
    std::mt19937_64 rng(31);
    const Box3 box = sphere.bounds();
    for (int i = 0; i < 300; ++i)
        expect_all_hits_equal_brute_force(
            *bvh, sphere, ray_towards(testing::random_point(rng, box, 0.5), testing::random_point(rng, box, 0.0)),
            "ray " + std::to_string(i));
}

TEST(RayCast, SsePathGivesTheSameAnswers) {
    // the tests above run the AVX box test where the processor has it; these run the SSE one
    spatial_detail::ray_avx_disabled = true;
    const PolygonMesh grid = shapes::grid(10, 10, true);
    auto bvh = build_bvh(grid);
    ASSERT_TRUE(bvh.ok());
    std::mt19937_64 rng(37);
    std::uniform_int_distribution<int> cell(0, 20);
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    for (int i = 0; i < 1000; ++i) {
        const Vec3 target{cell(rng) / 20.0, cell(rng) / 20.0, 0.0};
        const Ray ray =
            i % 2 == 0 ? ray_towards({u(rng), u(rng), 1.5}, target) : Ray{target + Vec3{0, 0, 1}, {0, 0, -1}};
        expect_all_hits_equal_brute_force(*bvh, grid, ray, "ray " + std::to_string(i));
    }
    const PolygonMesh far = testing::translated(testing::icosphere(3), {3e7, -1e7, 5e6});
    auto far_bvh = build_bvh(far);
    ASSERT_TRUE(far_bvh.ok());
    const Box3 box = far.bounds();
    std::uniform_int_distribution<std::size_t> pick(0, far.positions.size() - 1);
    for (int i = 0; i < 500; ++i)
        expect_all_hits_equal_brute_force(*far_bvh, far,
                                          ray_towards(testing::random_point(rng, box, 0.5), far.positions[pick(rng)]),
                                          "ray " + std::to_string(i));
    spatial_detail::ray_avx_disabled = false;
}

}  // namespace
}  // namespace surfaced
