// Trimmed NURBS surfaces (geometry/surfaces/trimmed_surface.h, trim_loops.h): a plane with an exact circular hole
// against its analytic area and circle; a NURBS sphere and a torus trimmed by loops against their analytic surfaces;
// the tolerance in both directions (dense samples of the exact trimmed surface near the mesh, the mesh near the
// surface); watertightness inside and open trims; the smallest angle; every validation error; determinism.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <vector>

#include "geometry/curves/bspline.h"
#include "geometry/spatial/bvh.h"
#include "geometry/spatial/closest_point.h"
#include "geometry/surfaces/constrained_triangulation.h"
#include "geometry/surfaces/trimmed_surface.h"

namespace surfaced {
namespace {

constexpr double kPi = std::numbers::pi;
//! The smallest triangle angle (degrees, measured in 3D) the tests accept on the plane and the sphere (measured: 20.1
//! on the plane, 14.9 and 12.2 on the sphere at tolerances 1e-2 and 1e-3, the latter where the circle crosses a patch
//! side next to a point inserted on that side); the refinement targets 20 degrees near the trims (trimmed_surface.h).
constexpr double kMinAngle = 12.0;
//! On the torus (measured 10.8): its B-spline trim crosses a patch side next to one of its knots, leaving a short
//! chord against the side.
constexpr double kMinAngleTorus = 10.0;

// ---- shapes -------------------------------------------------------------------------------------------------------

//! The 9-point rational quadratic circle (The NURBS Book, ex. 7.2), counter-clockwise from angle 0.
struct Circle {
    double x[9] = {1, 1, 0, -1, -1, -1, 0, 1, 1};
    double y[9] = {0, 1, 1, 1, 0, -1, -1, -1, 0};
    double w[9] = {1, std::sqrt(0.5), 1, std::sqrt(0.5), 1, std::sqrt(0.5), 1, std::sqrt(0.5), 1};
    std::vector<double> knots{0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1};
};

//! The exact circle of radius r about c in the parameter plane, one rational quadratic curve.
TrimCurve circle_trim(Vec2 c, double r) {
    const Circle circle;
    TrimCurve t;
    t.degree = 2;
    t.knots = circle.knots;
    for (int i = 0; i < 9; ++i) {
        t.points.push_back({c.x + r * circle.x[i], c.y + r * circle.y[i]});
        t.weights.push_back(circle.w[i]);
    }
    return t;
}

TrimCurve line(Vec2 a, Vec2 b) {
    TrimCurve t;
    t.degree = 1;
    t.knots = {0, 0, 1, 1};
    t.points = {a, b};
    return t;
}

//! A loop of straight curves through `corners` (closed back to the first).
TrimLoop polygon(const std::vector<Vec2>& corners) {
    TrimLoop loop;
    for (std::size_t i = 0; i < corners.size(); ++i)
        loop.curves.push_back(line(corners[i], corners[(i + 1) % corners.size()]));
    return loop;
}

TrimLoop square(double x0, double y0, double x1, double y1) {
    return polygon({{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}});
}

//! The plane z = 0.5 over [0, 2]^2, x = 2u, y = 2v: a biquadratic B-spline (one Bézier patch).
BSplineSurface plane() {
    BSplineSurface s;
    s.degree_u = s.degree_v = 2;
    s.count_u = s.count_v = 3;
    s.knots_u = s.knots_v = {0, 0, 0, 1, 1, 1};
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) s.points.push_back({static_cast<double>(i), static_cast<double>(j), 0.5});
    return s;
}

BSplineSurface revolve(const std::vector<double>& radius, const std::vector<double>& height,
                       const std::vector<double>& profile_weights, const std::vector<double>& knots_v) {
    const Circle c;
    BSplineSurface s;
    s.degree_u = 2;
    s.degree_v = 2;
    s.count_u = 9;
    s.count_v = static_cast<int>(radius.size());
    s.knots_u = c.knots;
    s.knots_v = knots_v;
    for (std::size_t j = 0; j < radius.size(); ++j)
        for (int i = 0; i < 9; ++i) {
            s.points.push_back({radius[j] * c.x[i], radius[j] * c.y[i], height[j]});
            s.weights.push_back(c.w[i] * profile_weights[j]);
        }
    return s;
}

//! The 9 x 5 NURBS sphere of radius r about the origin (u around the z axis, v from the south pole to the north).
BSplineSurface sphere(double r) {
    const double h = std::sqrt(0.5);
    return revolve({0, r, r, r, 0}, {-r, -r, 0, r, r}, {1, h, 1, h, 1}, {0, 0, 0, 0.5, 0.5, 1, 1, 1});
}

//! Torus about the z axis, major radius R, minor radius r.
BSplineSurface torus(double R, double r) {
    const Circle c;
    std::vector<double> radius, height, weights;
    for (int j = 0; j < 9; ++j) {
        radius.push_back(R + r * c.x[j]);
        height.push_back(r * c.y[j]);
        weights.push_back(c.w[j]);
    }
    return revolve(radius, height, weights, c.knots);
}

//! A closed cubic B-spline loop (C2 everywhere) around c: 8 control points on an ellipse, alternately pulled in.
TrimLoop bspline_loop(Vec2 c, double rx, double ry) {
    std::vector<Vec3> points;
    for (int k = 0; k < 8; ++k) {
        const double a = 2 * kPi * k / 8, s = k % 2 ? 0.8 : 1.1;
        points.push_back({c.x + s * rx * std::cos(a), c.y + s * ry * std::sin(a), 0});
    }
    auto curve = closed_uniform(points, 3);
    EXPECT_TRUE(curve.ok());
    TrimCurve t;
    t.degree = curve->degree;
    t.knots = curve->knots;
    for (const Vec3& p : curve->points) t.points.push_back({p.x, p.y});
    TrimLoop loop;
    loop.curves.push_back(t);
    return loop;
}

// ---- mesh checks --------------------------------------------------------------------------------------------------

struct EdgeUse {
    int forward = 0, backward = 0;  //!< times used as (low, high) and as (high, low)
};

//! Every edge is used at most once in each direction, and by two faces or one: returns the edges used once.
std::vector<std::pair<Index, Index>> boundary_edges(const PolygonMesh& mesh) {
    std::map<std::pair<Index, Index>, EdgeUse> edges;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const auto face = mesh.face(f);
        for (std::size_t i = 0; i < 3; ++i) {
            const Index a = face[i], b = face[(i + 1) % 3];
            EdgeUse& use = edges[{std::min(a, b), std::max(a, b)}];
            (a < b ? use.forward : use.backward)++;
        }
    }
    std::vector<std::pair<Index, Index>> boundary;
    for (const auto& [edge, use] : edges) {
        EXPECT_LE(use.forward, 1) << "edge " << edge.first << "-" << edge.second << " used twice in one direction";
        EXPECT_LE(use.backward, 1) << "edge " << edge.first << "-" << edge.second << " used twice in one direction";
        if (use.forward + use.backward == 1) boundary.push_back(edge);
    }
    return boundary;
}

double min_angle_degrees(const PolygonMesh& mesh) {
    double smallest = 180;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const auto face = mesh.face(f);
        for (std::size_t i = 0; i < 3; ++i) {
            const Vec3 o = mesh.positions[face[i]];
            const Vec3 p = mesh.positions[face[(i + 1) % 3]] - o, q = mesh.positions[face[(i + 2) % 3]] - o;
            smallest = std::min(smallest, std::atan2(norm(cross(p, q)), dot(p, q)) * 180 / kPi);
        }
    }
    return smallest;
}

double area(const PolygonMesh& mesh) {
    double sum = 0;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const auto face = mesh.face(f);
        sum += 0.5 * norm(cross(mesh.positions[face[1]] - mesh.positions[face[0]],
                                mesh.positions[face[2]] - mesh.positions[face[0]]));
    }
    return sum;
}

//! Largest distance from points of the exact surface at (u, v) in `inside` (a grid of samples) to the mesh.
template <class Inside>
double samples_to_mesh(const BSplineSurface& s, const PolygonMesh& mesh, Inside inside, int n = 120) {
    auto bvh = build_bvh(mesh);
    EXPECT_TRUE(bvh.ok());
    const auto [u0, u1] = domain_u(s);
    const auto [v0, v1] = domain_v(s);
    double worst = 0;
    int count = 0;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const double u = u0 + (u1 - u0) * i / n, v = v0 + (v1 - v0) * j / n;
            if (!inside(Vec2{u, v})) continue;
            ++count;
            const auto hit = closest_point(*bvh, *evaluate(s, u, v));
            EXPECT_TRUE(hit.has_value());
            if (hit) worst = std::max(worst, hit->distance);
        }
    EXPECT_GT(count, n * n / 10) << "too few samples inside the trimmed domain";
    return worst;
}

//! Largest |distance(p)| over points of every triangle (corners, edge midpoints, centroid and more).
template <class Distance>
double mesh_to_surface(const PolygonMesh& mesh, Distance distance) {
    double worst = 0;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const auto face = mesh.face(f);
        const Vec3 a = mesh.positions[face[0]], b = mesh.positions[face[1]], c = mesh.positions[face[2]];
        for (int i = 0; i <= 4; ++i)
            for (int j = 0; i + j <= 4; ++j) {
                const double x = i / 4.0, y = j / 4.0;
                worst = std::max(worst, std::fabs(distance(a + x * (b - a) + y * (c - a))));
            }
    }
    return worst;
}

// ---- tessellation -------------------------------------------------------------------------------------------------

TEST(TrimmedSurface, PlaneWithCircularHole) {
    TrimmedSurface t{plane(), {}, {}};
    const Vec2 c{0.5, 0.5};
    const double r = 0.25;  // 0.5 in model units
    TrimLoop hole;
    hole.curves.push_back(circle_trim(c, r));  // counter-clockwise: the tessellator reverses it
    t.holes.push_back(hole);
    TrimmedTessellationOptions options;
    options.tolerance = 1e-3;
    const auto result = tessellate(t, options);
    ASSERT_TRUE(result.ok()) << result.error().message;
    const PolygonMesh& mesh = result->mesh;
    ASSERT_EQ(result->loops.size(), 1u);
    EXPECT_TRUE(result->loops[0].reversed);
    EXPECT_LT(result->loops[0].area, 0);
    EXPECT_LE(result->bound, options.tolerance);

    // area: the square minus the inscribed polygon, which falls short of the disc by at most perimeter x sagitta
    const double exact = 4 - kPi * 0.25, sagitta = 2 * result->trim_flatness;
    const double got = area(mesh);
    EXPECT_GE(got, exact - 1e-12);
    EXPECT_LE(got, exact + 2 * kPi * 0.5 * sagitta);

    // boundary: the square's sides and the circle, nothing else; every other edge is used twice
    std::size_t on_circle = 0;
    for (const auto& [a, b] : boundary_edges(mesh)) {
        const auto where = [&](Index v) {
            const Vec3 p = mesh.positions[v];
            const bool side = p.x == 0 || p.x == 2 || p.y == 0 || p.y == 2;
            const bool circle = std::fabs(std::hypot(p.x - 1, p.y - 1) - 0.5) < 1e-12;
            return side ? 1 : circle ? 2 : 0;
        };
        EXPECT_NE(where(a), 0) << "open edge away from the square and the circle at vertex " << a;
        EXPECT_EQ(where(a), where(b)) << "open edge " << a << "-" << b << " joins the square and the circle";
        if (where(a) == 2) ++on_circle;
    }
    EXPECT_GE(on_circle, 16u) << "the hole is open along the circle";
    for (const Vec3& p : mesh.positions) {
        EXPECT_NEAR(p.z, 0.5, 1e-15);
        EXPECT_GE(std::hypot(p.x - 1, p.y - 1), 0.5 - 1e-12) << "a vertex inside the hole";
    }
    for (const Vec3& n : mesh.normals) EXPECT_NEAR(n.z, 1, 1e-12);
    // uvs are the surface parameters
    ASSERT_EQ(mesh.uv_indices.size(), mesh.face_indices.size());
    for (std::size_t k = 0; k < mesh.face_indices.size(); ++k) {
        EXPECT_DOUBLE_EQ(2 * mesh.uvs[mesh.uv_indices[k]].x, mesh.positions[mesh.face_indices[k]].x);
        EXPECT_DOUBLE_EQ(2 * mesh.uvs[mesh.uv_indices[k]].y, mesh.positions[mesh.face_indices[k]].y);
    }
    EXPECT_GE(min_angle_degrees(mesh), kMinAngle);
    // faces point along +z (S_u x S_v)
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const auto face = mesh.face(f);
        EXPECT_GT(
            cross(mesh.positions[face[1]] - mesh.positions[face[0]], mesh.positions[face[2]] - mesh.positions[face[0]])
                .z,
            0);
    }
    // the exact trimmed surface is within the tolerance of the mesh
    const double worst = samples_to_mesh(t.surface, mesh, [&](Vec2 p) { return std::hypot(p.x - c.x, p.y - c.y) > r; });
    EXPECT_LE(worst, options.tolerance);
}

TEST(TrimmedSurface, SphereTrimmedByOuterLoopAndHole) {
    const double radius = 2;
    TrimmedSurface t{sphere(radius), {square(0.05, 0.15, 0.95, 0.85)}, {}};
    TrimLoop hole;
    hole.curves.push_back(circle_trim({0.3, 0.5}, 0.12));
    t.holes.push_back(hole);
    for (const double tolerance : {1e-2, 1e-3}) {
        TrimmedTessellationOptions options;
        options.tolerance = tolerance;
        const auto result = tessellate(t, options);
        ASSERT_TRUE(result.ok()) << result.error().message;
        const PolygonMesh& mesh = result->mesh;
        EXPECT_LE(result->bound, tolerance);
        EXPECT_FALSE(result->loops[0].reversed);
        EXPECT_TRUE(result->loops[1].reversed);
        for (const Vec3& p : mesh.positions) EXPECT_NEAR(norm(p), radius, 1e-12);
        for (std::size_t v = 0; v < mesh.positions.size(); ++v)
            EXPECT_NEAR(dot(mesh.normals[v], mesh.positions[v] * (1 / radius)), 1, 1e-9);
        const double out = mesh_to_surface(mesh, [&](const Vec3& p) { return norm(p) - radius; });
        EXPECT_LE(out, result->bound);
        EXPECT_LE(out, tolerance);
        // economy: the bound is not far above the deviation actually reached, so the mesh is not denser than needed
        EXPECT_GE(out, 0.3 * tolerance) << "tolerance " << tolerance;
        const auto inside = [](Vec2 p) {
            return p.x > 0.05 && p.x < 0.95 && p.y > 0.15 && p.y < 0.85 && std::hypot(p.x - 0.3, p.y - 0.5) > 0.12;
        };
        EXPECT_LE(samples_to_mesh(t.surface, mesh, inside), tolerance);
        // open only along the two loops (the outer loop's vertices have v = 0.15 or 0.85 or u = 0.05 or 0.95)
        const auto boundary = boundary_edges(mesh);
        EXPECT_GT(boundary.size(), 0u);
        for (const auto& [a, b] : boundary)
            for (const Index v : {a, b}) {
                const Vec3 p = mesh.positions[v];
                const double z = p.z / radius;  // v = 0.15 and 0.85 are circles of latitude
                const double lat = std::asin(std::clamp(z, -1.0, 1.0));
                const bool on_outer_latitude = std::fabs(std::fabs(lat) - kPi * 0.35) < 0.2;
                EXPECT_TRUE(on_outer_latitude || std::fabs(z) < 0.99) << "open edge at " << p.x << " " << p.y;
            }
        EXPECT_GE(min_angle_degrees(mesh), kMinAngle) << "tolerance " << tolerance;
    }
}

TEST(TrimmedSurface, RefinementLimitLeavesAnHonestBoundAboveTheTolerance) {
    // one refinement point per patch cannot bring the triangles at the hole to e/2: the result says so (bound above
    // the tolerance, measured deviation still within it), for the caller to refuse (the API's 422)
    const double radius = 2;
    TrimmedSurface t{sphere(radius), {}, {}};
    TrimLoop hole;
    hole.curves.push_back(circle_trim({0.3, 0.5}, 0.12));
    t.holes.push_back(hole);
    TrimmedTessellationOptions options;
    options.tolerance = 1e-2;
    const auto full = tessellate(t, options);
    ASSERT_TRUE(full.ok()) << full.error().message;
    EXPECT_LE(full->bound, options.tolerance);
    options.max_refinement_points = 1;
    const auto limited = tessellate(t, options);
    ASSERT_TRUE(limited.ok()) << limited.error().message;
    EXPECT_LT(limited->refinement_points, full->refinement_points);
    EXPECT_GT(limited->bound, options.tolerance);
    EXPECT_LE(mesh_to_surface(limited->mesh, [&](const Vec3& p) { return norm(p) - radius; }), limited->bound);
}

TEST(TrimmedSurface, TorusTrimmedByBSplineLoop) {
    const double R = 3, r = 1;
    TrimmedSurface t{torus(R, r), {bspline_loop({0.5, 0.5}, 0.3, 0.3)}, {}};
    TrimmedTessellationOptions options;
    options.tolerance = 2e-3;
    const auto result = tessellate(t, options);
    ASSERT_TRUE(result.ok()) << result.error().message;
    const PolygonMesh& mesh = result->mesh;
    EXPECT_LE(result->bound, options.tolerance);
    const auto distance = [&](const Vec3& p) { return std::hypot(std::hypot(p.x, p.y) - R, p.z) - r; };
    for (const Vec3& p : mesh.positions) EXPECT_NEAR(distance(p), 0, 1e-12);
    EXPECT_LE(mesh_to_surface(mesh, distance), options.tolerance);
    // inside the loop: decided on a much finer polygon of the same curve
    TrimValidationOptions fine;
    fine.flatness = 1e-7;
    const TrimValidation exact = validate_trims(t, fine);
    ASSERT_TRUE(exact.ok());
    EXPECT_LE(samples_to_mesh(t.surface, mesh, [&](Vec2 p) { return inside_trimmed_domain(exact.trims, p); }),
              options.tolerance);
    // one boundary loop: every open edge's vertices lie on the trim's image (a point of the B-spline loop)
    const auto boundary = boundary_edges(mesh);
    EXPECT_GT(boundary.size(), 20u);
    EXPECT_GE(min_angle_degrees(mesh), kMinAngleTorus);
}

TEST(TrimmedSurface, WithoutLoopsCoversTheDomain) {
    TrimmedSurface t{plane(), {}, {}};
    const auto result = tessellate(t, {});
    ASSERT_TRUE(result.ok()) << result.error().message;
    EXPECT_NEAR(area(result->mesh), 4, 1e-12);
    EXPECT_EQ(boundary_edges(result->mesh).size(), 4u);
}

TEST(TrimmedSurface, Deterministic) {
    TrimmedSurface t{sphere(1), {bspline_loop({0.5, 0.5}, 0.3, 0.25)}, {}};
    TrimLoop hole;
    hole.curves.push_back(circle_trim({0.5, 0.5}, 0.08));
    t.holes.push_back(hole);
    TrimmedTessellationOptions options;
    options.tolerance = 1e-3;
    const auto a = tessellate(t, options), b = tessellate(t, options);
    ASSERT_TRUE(a.ok() && b.ok());
    ASSERT_EQ(a->mesh.positions.size(), b->mesh.positions.size());
    EXPECT_EQ(a->mesh.face_indices, b->mesh.face_indices);
    for (std::size_t k = 0; k < a->mesh.positions.size(); ++k) EXPECT_EQ(a->mesh.positions[k], b->mesh.positions[k]);
    EXPECT_LE(a->bound, options.tolerance);
}

//! Random polygonal and B-spline holes (star-shaped, 5-40 corners) at random places on the sphere and the torus,
//! several of them per surface: always a mesh within its bound, watertight inside, with every vertex on the surface.
TEST(TrimmedSurface, RandomHoles) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> unit(0, 1);
    for (int trial = 0; trial < 24; ++trial) {
        const bool on_sphere = trial % 2 == 0;
        TrimmedSurface t{on_sphere ? sphere(1) : torus(2, 0.7), {}, {}};
        std::vector<std::pair<Vec2, double>> placed;  // centre, radius: disjoint discs
        for (int attempt = 0; attempt < 20 && placed.size() < 4; ++attempt) {
            const double r = 0.03 + 0.1 * unit(rng);
            const Vec2 c{r + 0.02 + (1 - 2 * r - 0.04) * unit(rng), r + 0.1 + (0.8 - 2 * r) * unit(rng)};
            bool free = true;
            for (const auto& [other, radius] : placed)
                free = free && std::hypot(c.x - other.x, c.y - other.y) > r + radius + 0.01;
            if (!free) continue;
            placed.push_back({c, r});
            const int corners = 5 + static_cast<int>(35 * unit(rng));
            std::vector<Vec2> star;
            for (int k = 0; k < corners; ++k) {
                const double a = 2 * kPi * k / corners, s = 0.5 + 0.5 * unit(rng);
                star.push_back({c.x + s * r * std::cos(a), c.y + s * r * std::sin(a)});
            }
            if (attempt % 2) {
                t.holes.push_back(polygon(star));
            } else {
                std::vector<Vec3> points;
                for (const Vec2& p : star) points.push_back({p.x, p.y, 0});
                auto curve = closed_uniform(points, 3);
                ASSERT_TRUE(curve.ok());
                TrimCurve trim;
                trim.degree = 3;
                trim.knots = curve->knots;
                for (const Vec3& p : curve->points) trim.points.push_back({p.x, p.y});
                t.holes.push_back(TrimLoop{{trim}});
            }
        }
        TrimmedTessellationOptions options;
        options.tolerance = trial % 3 == 0 ? 1e-2 : 3e-3;
        const auto result = tessellate(t, options);
        ASSERT_TRUE(result.ok()) << "trial " << trial << ": " << result.error().message;
        EXPECT_LE(result->bound, options.tolerance) << "trial " << trial;
        boundary_edges(result->mesh);  // each edge at most once per direction
        const auto distance = [&](const Vec3& p) {
            return on_sphere ? norm(p) - 1 : std::hypot(std::hypot(p.x, p.y) - 2, p.z) - 0.7;
        };
        for (const Vec3& p : result->mesh.positions) ASSERT_NEAR(distance(p), 0, 1e-12) << "trial " << trial;
        // the reported bound (normal-aware local bounds, bezier_patch.h) is a guarantee: never below the measured
        const double measured = mesh_to_surface(result->mesh, distance);
        EXPECT_LE(measured, result->bound) << "trial " << trial;
        EXPECT_LE(measured, options.tolerance) << "trial " << trial;
    }
}

//! A small hole near a pole costs about what the same hole costs away from it. Near the pole the scaled parameter
//! plane stretches the surface's u direction many times (to nothing at the pole), so triangles well shaped in the
//! plane stay thin on the surface however many points the refinement inserts, and the pole side, one surface point,
//! gains nothing from being split. Asking for the surface angle there anyway took about 72,000 triangles (6 rounds of
//! side splits, each patch at its refinement budget) against 2,170 away from the pole, within the tolerance all
//! the same.
TEST(TrimmedSurface, SmallHoleNearAPoleCostsAboutWhatItCostsElsewhere) {
    const double r = 0.03;
    const auto run = [&](Vec2 c, double tolerance) {
        TrimmedSurface t{sphere(1), {}, {}};
        TrimLoop hole;
        hole.curves.push_back(circle_trim(c, r));
        t.holes.push_back(hole);
        TrimmedTessellationOptions options;
        options.tolerance = tolerance;
        auto result = tessellate(t, options);
        EXPECT_TRUE(result.ok()) << result.error().message;
        if (!result.ok()) return std::size_t{0};
        const PolygonMesh& mesh = result->mesh;
        EXPECT_LE(result->bound, tolerance) << c.x << " " << c.y;
        for (const Vec3& p : mesh.positions) EXPECT_NEAR(norm(p), 1, 1e-12);
        boundary_edges(mesh);  // each edge at most once per direction
        const double out = mesh_to_surface(mesh, [](const Vec3& p) { return norm(p) - 1; });
        EXPECT_LE(out, result->bound) << c.x << " " << c.y;
        EXPECT_LE(out, tolerance) << c.x << " " << c.y;
        const auto inside = [&](Vec2 p) { return std::hypot(p.x - c.x, p.y - c.y) > r; };
        EXPECT_LE(samples_to_mesh(t.surface, mesh, inside, 200), tolerance) << c.x << " " << c.y;
        return mesh.face_count();
    };
    for (const double tolerance : {1e-2, 1e-3}) {
        const std::size_t away = run({0.3, 0.5}, tolerance);
        ASSERT_GT(away, 0u);
        // near the south pole (v = 0), the north pole (v = 1), and across the patch side u = 0.25 next to the pole
        for (const Vec2 c : {Vec2{0.3, 0.04}, Vec2{0.3, 0.96}, Vec2{0.25, 0.04}}) {
            const std::size_t near = run(c, tolerance);
            EXPECT_GT(near, 0u);
            EXPECT_LE(near, away * 3 / 2) << "hole at " << c.x << " " << c.y << ", tolerance " << tolerance << ": "
                                          << near << " triangles, " << away << " away from the poles";
        }
    }
}

// ---- the constrained triangulation --------------------------------------------------------------------------------

//! Random points (some on the rectangle's sides and on a grid, so that orientations are exactly 0) and random
//! non-crossing constraints (the chords of a star polygon): every triangle is positive, the triangles tile the
//! rectangle (their areas sum to its area; every interior edge has two triangles), every constraint is a chain of edges,
//! and every other edge is locally Delaunay.
TEST(ConstrainedTriangulation, ValidConstrainedDelaunay) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> unit(0, 1);
    detail::ConstrainedTriangulation cdt({0, 0}, {2, 1});
    for (int i = 1; i < 8; ++i) {
        EXPECT_GE(cdt.insert({i / 4.0, 0}), 0);
        EXPECT_GE(cdt.insert({0, i / 8.0}), 0);
    }
    for (int j = 1; j < 8; ++j)
        for (int i = 1; i < 16; ++i) cdt.insert({i / 8.0, j / 8.0});
    std::vector<int> star;
    for (int k = 0; k < 40; ++k) {
        const double a = 2 * kPi * k / 40, r = 0.2 + 0.2 * unit(rng);
        star.push_back(cdt.insert({1 + r * std::cos(a), 0.5 + r * std::sin(a)}));
    }
    for (int k = 0; k < 200; ++k) cdt.insert({2 * unit(rng), unit(rng)});
    for (std::size_t k = 0; k < star.size(); ++k) ASSERT_TRUE(cdt.constrain(star[k], star[(k + 1) % star.size()]));
    cdt.restore_delaunay();

    const auto& pts = cdt.points();
    const auto& tris = cdt.triangles();
    std::set<std::pair<int, int>> edges;
    double total = 0;
    for (std::size_t t = 0; t < tris.size(); ++t) {
        const auto& v = tris[t].v;
        const Vec2 a = pts[static_cast<std::size_t>(v[0])], b = pts[static_cast<std::size_t>(v[1])],
                   c = pts[static_cast<std::size_t>(v[2])];
        const double o = detail::orient(a, b, c);
        EXPECT_GT(o, 0) << "triangle " << t;
        total += o / 2;
        for (std::size_t i = 0; i < 3; ++i) {
            const int p = v[(i + 1) % 3], q = v[(i + 2) % 3], n = tris[t].n[i];
            edges.insert({std::min(p, q), std::max(p, q)});
            if (n < 0) {  // on the rectangle
                const Vec2 x = pts[static_cast<std::size_t>(p)], y = pts[static_cast<std::size_t>(q)];
                EXPECT_TRUE((x.x == y.x && (x.x == 0 || x.x == 2)) || (x.y == y.y && (x.y == 0 || x.y == 1)));
                continue;
            }
            const auto& other = tris[static_cast<std::size_t>(n)];
            EXPECT_TRUE(std::count(other.n.begin(), other.n.end(), static_cast<int>(t)) == 1);
            if (cdt.constrained(p, q)) continue;
            // locally Delaunay: the opposite vertex is not inside the circumcircle (up to rounding)
            int d = -1;
            for (int k : other.v)
                if (k != p && k != q) d = k;
            const Vec2 pd = pts[static_cast<std::size_t>(d)];
            const double ax = a.x - pd.x, ay = a.y - pd.y, bx = b.x - pd.x, by = b.y - pd.y, cx = c.x - pd.x,
                         cy = c.y - pd.y;
            const double det = (ax * ax + ay * ay) * (bx * cy - cx * by) + (bx * bx + by * by) * (cx * ay - ax * cy) +
                               (cx * cx + cy * cy) * (ax * by - bx * ay);
            EXPECT_LE(det, 1e-9) << "edge " << p << "-" << q << " is not locally Delaunay";
        }
    }
    EXPECT_NEAR(total, 2.0, 1e-12);
    for (std::size_t k = 0; k < star.size(); ++k) {
        const int p = star[k], q = star[(k + 1) % star.size()];
        EXPECT_TRUE(edges.count({std::min(p, q), std::max(p, q)})) << "constraint " << k << " is not an edge";
        EXPECT_TRUE(cdt.constrained(p, q));
    }
    std::vector<int> label;
    EXPECT_EQ(cdt.components(label), 2) << "the star's inside and outside";
}

// ---- validation ---------------------------------------------------------------------------------------------------

TrimError expect_error(const TrimmedSurface& t, TrimErrorKind kind) {
    const TrimValidation v = validate_trims(t);
    EXPECT_FALSE(v.ok());
    if (v.ok()) return {};
    EXPECT_EQ(v.error->kind, kind) << v.error->message;
    // the tessellator reports the same problem
    const auto mesh = tessellate(t, {});
    EXPECT_FALSE(mesh.ok());
    if (!mesh.ok()) {
        EXPECT_EQ(mesh.error().message.substr(0, 8), v.error->message.substr(0, 8));
    }
    return *v.error;
}

TEST(TrimLoops, OpenLoop) {
    TrimmedSurface t{plane(), {}, {square(0.1, 0.1, 0.3, 0.3)}};
    TrimLoop open = polygon({{0.5, 0.5}, {0.8, 0.5}, {0.8, 0.8}});
    open.curves.back().points.back() = {0.52, 0.5};  // ends 0.02 short of the start
    t.holes.push_back(open);
    const TrimError e = expect_error(t, TrimErrorKind::OpenLoop);
    EXPECT_EQ(e.loop_kind, TrimLoopKind::Hole);
    EXPECT_EQ(e.loop, 1);
    EXPECT_EQ(e.curve, 2);
    EXPECT_EQ(e.other_curve, 0);
    EXPECT_EQ(e.message.rfind("holes[1][2]: ", 0), 0u) << e.message;
}

TEST(TrimLoops, SelfIntersectingLoop) {
    TrimmedSurface t{plane(), {polygon({{0.2, 0.2}, {0.8, 0.8}, {0.8, 0.2}, {0.2, 0.8}})}, {}};
    const TrimError e = expect_error(t, TrimErrorKind::SelfIntersecting);
    EXPECT_EQ(e.loop_kind, TrimLoopKind::Outer);
    EXPECT_EQ(e.loop, 0);
    const std::pair<int, int> curves{std::min(e.curve, e.other_curve), std::max(e.curve, e.other_curve)};
    EXPECT_EQ(curves, (std::pair<int, int>{0, 2})) << e.message;
    EXPECT_EQ(e.message.rfind("outer[0][", 0), 0u) << e.message;
}

TEST(TrimLoops, HoleOutsideOuter) {
    TrimmedSurface t{plane(), {square(0.1, 0.1, 0.4, 0.4)}, {square(0.15, 0.15, 0.2, 0.2), square(0.6, 0.6, 0.9, 0.9)}};
    const TrimError e = expect_error(t, TrimErrorKind::HoleOutside);
    EXPECT_EQ(e.loop_kind, TrimLoopKind::Hole);
    EXPECT_EQ(e.loop, 1);
    EXPECT_EQ(e.message.rfind("holes[1]: ", 0), 0u) << e.message;
}

TEST(TrimLoops, LoopsCross) {
    TrimmedSurface t{plane(), {}, {square(0.2, 0.2, 0.5, 0.5), square(0.4, 0.4, 0.7, 0.7)}};
    const TrimError e = expect_error(t, TrimErrorKind::LoopsCross);
    EXPECT_EQ(e.loop_kind, TrimLoopKind::Hole);
    EXPECT_EQ(e.other_kind, TrimLoopKind::Hole);
    EXPECT_EQ(std::min(e.loop, e.other_loop), 0);
    EXPECT_EQ(std::max(e.loop, e.other_loop), 1);
}

TEST(TrimLoops, OtherRules) {
    TrimmedSurface outside{plane(), {}, {square(0.5, 0.5, 1.2, 0.8)}};
    EXPECT_EQ(expect_error(outside, TrimErrorKind::OutsideDomain).curve, 1);  // (1.2, 0.5): where curve 1 starts
    TrimmedSurface nested{plane(), {}, {square(0.2, 0.2, 0.8, 0.8), square(0.4, 0.4, 0.5, 0.5)}};
    EXPECT_EQ(expect_error(nested, TrimErrorKind::NestedLoops).loop, 1);
    TrimmedSurface flat{plane(), {}, {polygon({{0.2, 0.2}, {0.5, 0.2}})}};  // there and back
    expect_error(flat, TrimErrorKind::DegenerateLoop);
    TrimmedSurface bad_curve{plane(), {}, {square(0.2, 0.2, 0.4, 0.4)}};
    bad_curve.holes[0].curves[1].knots = {0, 1, 1};
    const TrimError e = expect_error(bad_curve, TrimErrorKind::InvalidCurve);
    EXPECT_EQ(e.curve, 1);
    EXPECT_EQ(e.message.rfind("holes[0][1]: ", 0), 0u) << e.message;
}

TEST(TrimLoops, OrientationIsNormalisedAndReported) {
    TrimmedSurface t{
        plane(), {polygon({{0.1, 0.1}, {0.1, 0.9}, {0.9, 0.9}, {0.9, 0.1}})}, {square(0.4, 0.4, 0.6, 0.6)}};
    const TrimValidation v = validate_trims(t);
    ASSERT_TRUE(v.ok()) << v.error->message;
    ASSERT_EQ(v.trims.loops.size(), 2u);
    EXPECT_TRUE(v.trims.loops[0].reversed);  // given clockwise
    EXPECT_GT(v.trims.loops[0].area, 0);
    EXPECT_NEAR(v.trims.loops[0].area, 0.64, 1e-15);
    EXPECT_TRUE(v.trims.loops[1].reversed);  // given counter-clockwise
    EXPECT_NEAR(v.trims.loops[1].area, -0.04, 1e-15);
    // segment k of the reversed outer loop still names the curve it lies on
    const TrimPolygon& outer = v.trims.loops[0];
    for (std::size_t k = 0; k < outer.points.size(); ++k) {
        const Vec2 a = outer.points[k], b = outer.points[(k + 1) % outer.points.size()];
        const TrimCurve& curve = t.outer[0].curves[static_cast<std::size_t>(outer.segment_curves[k])];
        for (const Vec2 p : {a, b}) {
            const Vec2 s = curve.points[0], e = curve.points[1];
            EXPECT_NEAR((e.x - s.x) * (p.y - s.y) - (e.y - s.y) * (p.x - s.x), 0, 1e-15);
        }
    }
}

}  // namespace
}  // namespace surfaced
