// mesh_field (dual marching cubes + QEF): volumes and areas against analytic values, sharp cube edges and corners,
// and the mesh invariants (closed, manifold edges and vertices, consistent outward orientation, no zero-area
// triangles, inside the bounds) on every output, including surfaces cut by the bounds, two sheets in one cell,
// ambiguous configurations and the adaptive mode. The fields are defined here so that these tests do not depend on
// the scene code.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <atomic>
#include <cmath>
#include <map>
#include <numbers>
#include <set>
#include <vector>

#include "geometry/implicit/mesh_field.h"
#include "geometry/implicit/operators.h"
#include "geometry/implicit/qef.h"
#include "tests/support/mesh_asserts.h"

namespace surfaced::implicit {
namespace {

constexpr double kPi = std::numbers::pi;

class Sphere : public Field {
public:
    explicit Sphere(double r, Vec3 c = {}) : r_(r), c_(c) {}
    double value(const Vec3& p) const override { return norm(p - c_) - r_; }
    Vec3 gradient(const Vec3& p) const override {
        const Vec3 d = p - c_;
        const double l = norm(d);
        return l > 0 ? d * (1 / l) : Vec3{0, 0, 1};
    }
    FieldKind kind() const override { return FieldKind::ExactDistance; }

private:
    double r_;
    Vec3 c_;
};

class BoxField : public Field {
public:
    explicit BoxField(Vec3 half) : half_(half) {}
    double value(const Vec3& p) const override {
        const Vec3 q{std::fabs(p.x) - half_.x, std::fabs(p.y) - half_.y, std::fabs(p.z) - half_.z};
        const Vec3 o{std::max(q.x, 0.0), std::max(q.y, 0.0), std::max(q.z, 0.0)};
        return norm(o) + std::min(std::max({q.x, q.y, q.z}), 0.0);
    }
    Vec3 gradient(const Vec3& p) const override {
        const Vec3 q{std::fabs(p.x) - half_.x, std::fabs(p.y) - half_.y, std::fabs(p.z) - half_.z};
        const Vec3 s{p.x >= 0 ? 1.0 : -1.0, p.y >= 0 ? 1.0 : -1.0, p.z >= 0 ? 1.0 : -1.0};
        const Vec3 o{std::max(q.x, 0.0), std::max(q.y, 0.0), std::max(q.z, 0.0)};
        const double l = norm(o);
        if (l > 0) return Vec3{o.x * s.x, o.y * s.y, o.z * s.z} * (1 / l);
        int a = 0;
        if (q.y > q[a]) a = 1;
        if (q.z > q[a]) a = 2;
        Vec3 g;
        g[a] = s[a];
        return g;
    }
    FieldKind kind() const override { return FieldKind::ExactDistance; }

private:
    Vec3 half_;
};

class Torus : public Field {
public:
    Torus(double major, double minor) : R_(major), r_(minor) {}
    double value(const Vec3& p) const override {
        const double q = std::hypot(p.x, p.y) - R_;
        return std::hypot(q, p.z) - r_;
    }
    FieldKind kind() const override { return FieldKind::ExactDistance; }

private:
    double R_, r_;
};

// max(a, -b): a bound, Lipschitz 1.
class Difference : public Field {
public:
    Difference(const Field& a, const Field& b) : a_(a), b_(b) {}
    double value(const Vec3& p) const override { return std::max(a_.value(p), -b_.value(p)); }
    Vec3 gradient(const Vec3& p) const override {
        return a_.value(p) >= -b_.value(p) ? a_.gradient(p) : b_.gradient(p) * -1.0;
    }
    FieldKind kind() const override { return FieldKind::DistanceBound; }

private:
    const Field &a_, &b_;
};

// Polynomial smooth minimum with radius k.
class SmoothUnion : public Field {
public:
    SmoothUnion(const Field& a, const Field& b, double k) : a_(a), b_(b), k_(k) {}
    double value(const Vec3& p) const override {
        const double a = a_.value(p), b = b_.value(p);
        const double h = std::clamp(0.5 + 0.5 * (b - a) / k_, 0.0, 1.0);
        return b * (1 - h) + a * h - k_ * h * (1 - h);
    }
    FieldKind kind() const override { return FieldKind::DistanceBound; }

private:
    const Field &a_, &b_;
    double k_;
};

// |f| - t: a thin shell, two sheets.
class Shell : public Field {
public:
    Shell(const Field& f, double t) : f_(f), t_(t) {}
    double value(const Vec3& p) const override { return std::fabs(f_.value(p)) - t_; }
    FieldKind kind() const override { return FieldKind::DistanceBound; }

private:
    const Field& f_;
    double t_;
};

class Gyroid : public Field {
public:
    explicit Gyroid(double scale) : s_(scale) {}
    double value(const Vec3& p) const override {
        const Vec3 q = p * s_;
        return std::sin(q.x) * std::cos(q.y) + std::sin(q.y) * std::cos(q.z) + std::sin(q.z) * std::cos(q.x);
    }
    FieldKind kind() const override { return FieldKind::General; }
    double lipschitz() const override { return std::numeric_limits<double>::infinity(); }

private:
    double s_;
};

// Pseudo-random values on a lattice, trilinearly interpolated: every marching-cubes case, ambiguous faces included.
class Noise : public Field {
public:
    Noise(double spacing, unsigned seed) : h_(spacing), seed_(seed) {}
    double value(const Vec3& p) const override {
        const double fx = std::floor(p.x / h_), fy = std::floor(p.y / h_), fz = std::floor(p.z / h_);
        const double tx = p.x / h_ - fx, ty = p.y / h_ - fy, tz = p.z / h_ - fz;
        double v = 0;
        for (int c = 0; c < 8; ++c) {
            const int dx = c & 1, dy = (c >> 1) & 1, dz = (c >> 2) & 1;
            const double w = (dx ? tx : 1 - tx) * (dy ? ty : 1 - ty) * (dz ? tz : 1 - tz);
            v += w * lattice(static_cast<long>(fx) + dx, static_cast<long>(fy) + dy, static_cast<long>(fz) + dz);
        }
        return v;
    }
    FieldKind kind() const override { return FieldKind::General; }
    double lipschitz() const override { return std::numeric_limits<double>::infinity(); }

private:
    double lattice(long x, long y, long z) const {
        std::uint64_t h = seed_ * 0x9E3779B97F4A7C15ull;
        for (long v : {x, y, z}) {
            h ^= static_cast<std::uint64_t>(v) + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
            h *= 0xBF58476D1CE4E5B9ull;
            h ^= h >> 31;
        }
        return static_cast<double>(h >> 11) / static_cast<double>(1ull << 53) - 0.5;
    }
    double h_;
    unsigned seed_;
};

double surface_area(const PolygonMesh& mesh) {
    double area = 0;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const auto t = mesh.face(f);
        area +=
            0.5 * norm(cross(mesh.positions[t[1]] - mesh.positions[t[0]], mesh.positions[t[2]] - mesh.positions[t[0]]));
    }
    return area;
}

struct Invariants {
    std::size_t boundary_edges = 0, non_manifold_edges = 0, inconsistent_edges = 0, non_manifold_vertices = 0;
    std::size_t zero_area = 0, outside_bounds = 0;
    double min_quality = 1;
};

Invariants check(const PolygonMesh& mesh, const Box3& bounds) {
    Invariants r;
    const auto e = testing::edge_stats(mesh);
    r.boundary_edges = e.boundary_edges;
    r.non_manifold_edges = e.non_manifold_edges;
    r.inconsistent_edges = e.inconsistent_edges;
    r.non_manifold_vertices = testing::non_manifold_vertices(mesh);  // one fan per vertex
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const auto t = mesh.face(f);
        const Vec3 &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
        const double area2 = norm(cross(b - a, c - a));
        const double l = std::max({dot(b - a, b - a), dot(c - b, c - b), dot(a - c, a - c)});
        if (!(area2 > 0)) ++r.zero_area;
        r.min_quality = std::min(r.min_quality, l > 0 ? area2 / l : 0.0);
    }
    for (const Vec3& p : mesh.positions)
        for (int a = 0; a < 3; ++a)
            if (p[a] < bounds.min[a] || p[a] > bounds.max[a]) ++r.outside_bounds;
    return r;
}

#define EXPECT_VALID_MESH(mesh, bounds)                  \
    do {                                                 \
        ASSERT_TRUE((mesh).is_triangle_mesh());          \
        ASSERT_TRUE(validate(mesh).ok());                \
        const Invariants inv_ = check((mesh), (bounds)); \
        EXPECT_EQ(inv_.boundary_edges, 0u);              \
        EXPECT_EQ(inv_.non_manifold_edges, 0u);          \
        EXPECT_EQ(inv_.inconsistent_edges, 0u);          \
        EXPECT_EQ(inv_.non_manifold_vertices, 0u);       \
        EXPECT_EQ(inv_.zero_area, 0u);                   \
        EXPECT_EQ(inv_.outside_bounds, 0u);              \
    } while (0)

Box3 cube_bounds(double h) { return Box3{{-h, -h, -h}, {h, h, h}}; }

PolygonMesh mesh_ok(const Field& field, const Box3& bounds, const MeshFieldOptions& options,
                    MeshFieldStats* stats = nullptr) {
    auto result = mesh_field(field, bounds, options, stats);
    EXPECT_TRUE(result.ok()) << (result.ok() ? "" : result.error().message);
    return result.ok() ? std::move(result).value() : PolygonMesh{};
}

MeshFieldOptions at(int resolution, MeshFieldMode mode = MeshFieldMode::Uniform) {
    MeshFieldOptions o;
    o.resolution = resolution;
    o.mode = mode;
    return o;
}

// ---- QEF ------------------------------------------------------------------------------------------------------------

TEST(Qef, RecoversCornerAndEdgeAndPlane) {
    // three orthogonal planes through (0.3, 0.2, 0.1): rank 3, the corner exactly
    Qef corner;
    corner.add({0.3, 0.9, 0.5}, {1, 0, 0});
    corner.add({0.0, 0.2, 0.7}, {0, 1, 0});
    corner.add({0.6, 0.4, 0.1}, {0, 0, 1});
    int rank = 0;
    Vec3 x = corner.solve(0.05, &rank);
    EXPECT_EQ(rank, 3);
    EXPECT_NEAR(x.x, 0.3, 1e-12);
    EXPECT_NEAR(x.y, 0.2, 1e-12);
    EXPECT_NEAR(x.z, 0.1, 1e-12);
    // two planes: the point on their line closest to the mass point
    Qef edge;
    edge.add({0.5, 0.0, 0.2}, {1, 0, 0});
    edge.add({0.0, 0.5, 0.6}, {0, 1, 0});
    x = edge.solve(0.05, &rank);
    EXPECT_EQ(rank, 2);
    EXPECT_NEAR(x.x, 0.5, 1e-12);
    EXPECT_NEAR(x.y, 0.5, 1e-12);
    EXPECT_NEAR(x.z, 0.4, 1e-12);
    // nearly parallel planes are truncated to one: stays near the mass point instead of shooting away
    Qef flat;
    flat.add({0, 0, 0}, {0, 0, 1});
    flat.add({1, 0, 0.001}, {0.001, 0, 1});
    x = flat.solve(0.05, &rank);
    EXPECT_EQ(rank, 1);
    EXPECT_LT(std::fabs(x.x - 0.5), 0.01);
    EXPECT_LT(flat.error(x), 1e-5);
}

TEST(Qef, JacobiEigenDecomposition) {
    const double m[3][3] = {{4, 1, 2}, {1, 3, 0.5}, {2, 0.5, 5}};
    double values[3], vectors[3][3];
    symmetric_eigen3(m, values, vectors);
    for (int k = 0; k < 3; ++k)
        for (int i = 0; i < 3; ++i) {
            double mv = 0;
            for (int j = 0; j < 3; ++j) mv += m[i][j] * vectors[j][k];
            EXPECT_NEAR(mv, values[k] * vectors[i][k], 1e-12);
        }
    EXPECT_NEAR(values[0] + values[1] + values[2], 12.0, 1e-12);
}

// ---- accuracy against analytic values -----------------------------------------------------------------------------

TEST(MeshField, SphereVolumeAndAreaAt64) {
    const Sphere sphere(1.0);
    const Box3 bounds = cube_bounds(1.25);
    const PolygonMesh mesh = mesh_ok(sphere, bounds, at(64));
    EXPECT_VALID_MESH(mesh, bounds);
    const double volume = 4.0 / 3.0 * kPi, area = 4 * kPi;
    EXPECT_NEAR(testing::signed_volume(mesh) / volume, 1.0, 0.005);
    EXPECT_NEAR(surface_area(mesh) / area, 1.0, 0.005);
    EXPECT_EQ(testing::euler_characteristic(mesh), 2);
}

TEST(MeshField, TorusVolumeAndAreaAt64) {
    const Torus torus(1.0, 0.35);
    const Box3 bounds{{-1.5, -1.5, -0.5}, {1.5, 1.5, 0.5}};
    const PolygonMesh mesh = mesh_ok(torus, bounds, at(64));
    EXPECT_VALID_MESH(mesh, bounds);
    const double volume = 2 * kPi * kPi * 1.0 * 0.35 * 0.35, area = 4 * kPi * kPi * 1.0 * 0.35;
    EXPECT_NEAR(testing::signed_volume(mesh) / volume, 1.0, 0.005);
    EXPECT_NEAR(surface_area(mesh) / area, 1.0, 0.005);
    EXPECT_EQ(testing::euler_characteristic(mesh), 0);
}

TEST(MeshField, BoxVolumeAndAreaAt32) {
    const BoxField box({1.0, 0.7, 0.5});
    const Box3 bounds = cube_bounds(1.3);
    const PolygonMesh mesh = mesh_ok(box, bounds, at(32));
    EXPECT_VALID_MESH(mesh, bounds);
    const double volume = 8 * 1.0 * 0.7 * 0.5, area = 8 * (1.0 * 0.7 + 0.7 * 0.5 + 1.0 * 0.5);
    EXPECT_NEAR(testing::signed_volume(mesh) / volume, 1.0, 0.005);
    EXPECT_NEAR(surface_area(mesh) / area, 1.0, 0.005);
    EXPECT_EQ(testing::euler_characteristic(mesh), 2);
}

TEST(MeshField, BoxMinusSphereVolumeAt64) {
    // the example: a unit box minus a ball of radius 0.5 centred on its top face (removes half a ball)
    const BoxField box({1, 1, 1});
    const Sphere ball(0.5, {0, 0, 1});
    const Difference shape(box, ball);
    const Box3 bounds = cube_bounds(1.25);
    const PolygonMesh mesh = mesh_ok(shape, bounds, at(64));
    EXPECT_VALID_MESH(mesh, bounds);
    const double volume = 8.0 - 2.0 / 3.0 * kPi * 0.125;
    EXPECT_NEAR(testing::signed_volume(mesh) / volume, 1.0, 0.005);
    const double area = 24.0 - kPi * 0.25 + 2 * kPi * 0.25;  // faces - disc + hemisphere
    EXPECT_NEAR(surface_area(mesh) / area, 1.0, 0.005);
}

TEST(MeshField, SmoothUnionConvergesAndIsBetweenUnionAndHull) {
    const Sphere a(0.6, {-0.45, 0, 0}), b(0.6, {0.45, 0, 0});
    const SmoothUnion blend(a, b, 0.3);
    const Box3 bounds{{-1.3, -0.9, -0.9}, {1.3, 0.9, 0.9}};
    const double v48 = testing::signed_volume(mesh_ok(blend, bounds, at(48)));
    const PolygonMesh fine = mesh_ok(blend, bounds, at(160));
    EXPECT_VALID_MESH(fine, bounds);
    const double v160 = testing::signed_volume(fine);
    EXPECT_NEAR(v48 / v160, 1.0, 0.005);
    // the blend adds material to the plain union: union volume = two balls - the lens
    const double r = 0.6, d = 0.9;
    const double lens = kPi * (4 * r + d) * (2 * r - d) * (2 * r - d) / 12;
    const double union_volume = 2 * 4.0 / 3.0 * kPi * r * r * r - lens;
    EXPECT_GT(v160, union_volume * 1.01);
    EXPECT_LT(v160, union_volume * 1.2);
}

// ---- sharp features -----------------------------------------------------------------------------------------------

TEST(MeshField, CubeEdgesAndCornersStaySharp) {
    const double size = 2.0;  // side length
    const BoxField cube({1, 1, 1});
    const Box3 bounds = cube_bounds(1.37);  // grid planes do not line up with the faces
    const MeshFieldOptions options = at(40);
    const PolygonMesh mesh = mesh_ok(cube, bounds, options);
    EXPECT_VALID_MESH(mesh, bounds);
    // every vertex on the cube's surface
    double worst_surface = 0;
    for (const Vec3& p : mesh.positions) worst_surface = std::max(worst_surface, std::fabs(cube.value(p)));
    EXPECT_LT(worst_surface, 1e-3 * size);
    // vertices within a cell of an edge lie on that edge (the edge is not rounded off)
    const double h = 2 * 1.37 / 40;
    double worst_edge = 0;
    std::size_t near_edge = 0;
    for (const Vec3& p : mesh.positions) {
        const Vec3 q{std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)};
        for (int a = 0; a < 3; ++a) {  // the 4 edges parallel to axis a are at |other coordinates| = 1
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            const double distance = std::hypot(q[b] - 1, q[c] - 1);
            if (distance < 0.5 * h) {
                ++near_edge;
                worst_edge = std::max(worst_edge, distance);
            }
        }
    }
    EXPECT_GT(near_edge, 12u * 25);  // about 2 / h = 29 cells along each of the 12 edges
    EXPECT_LT(worst_edge, 1e-3 * size);
    // each corner has a vertex on it
    for (int corner = 0; corner < 8; ++corner) {
        const Vec3 c{corner & 1 ? 1.0 : -1.0, corner & 2 ? 1.0 : -1.0, corner & 4 ? 1.0 : -1.0};
        double best = 1e9;
        for (const Vec3& p : mesh.positions) best = std::min(best, norm(p - c));
        EXPECT_LT(best, 1e-3 * size) << "corner " << corner;
    }
    EXPECT_NEAR(testing::signed_volume(mesh), 8.0, 8.0 * 1e-3);
}

TEST(MeshField, RotatedBoxEdgesStaySharp) {
    // the same cube rotated 30 degrees about z: edges no longer along grid lines
    class Rotated : public Field {
    public:
        explicit Rotated(const Field& f) : f_(f) {}
        double value(const Vec3& p) const override { return f_.value(rotate(p)); }
        FieldKind kind() const override { return FieldKind::ExactDistance; }
        static Vec3 rotate(const Vec3& p) {
            const double c = std::cos(kPi / 6), s = std::sin(kPi / 6);
            return {c * p.x + s * p.y, -s * p.x + c * p.y, p.z};
        }

    private:
        const Field& f_;
    };
    const BoxField cube({0.8, 0.8, 0.8});
    const Rotated rotated(cube);
    const Box3 bounds = cube_bounds(1.3);
    const PolygonMesh mesh = mesh_ok(rotated, bounds, at(48));
    EXPECT_VALID_MESH(mesh, bounds);
    // Off the grid axes a cell next to an edge can see both faces while the edge itself runs through the
    // neighbouring cell: its vertex (the box-constrained QEF minimiser) then sits a little inside the edge. Measured
    // here: 0.0048 (0.3% of the side, 9% of a cell) for 112 of 6272 vertices; every other vertex within 1e-3. The
    // curved-crease re-sampling does not change this (the planes are exact here; the edge is outside the cell), nor
    // does the final projection (moving onto the nearer face would leave the cell).
    const double h = 2.6 / 48;
    double worst = 0;
    std::size_t off = 0;
    for (const Vec3& p : mesh.positions) {
        worst = std::max(worst, std::fabs(rotated.value(p)));
        if (std::fabs(rotated.value(p)) > 1e-3 * 1.6) ++off;
    }
    std::printf("rotated cube: worst vertex %.2e (%.3f%% of the side), %zu of %zu beyond 1e-3 of the side\n", worst,
                100 * worst / 1.6, off, mesh.vertex_count());
    EXPECT_LT(worst, 0.1 * h);
    EXPECT_LT(off * 20, mesh.vertex_count());
    EXPECT_NEAR(testing::signed_volume(mesh) / (1.6 * 1.6 * 1.6), 1.0, 0.005);
}

// The web client's example: a unit box minus a ball of radius 0.5 centred on its top face, at resolution 32 in
// [-1.5, 1.5]^3, built from the scene operators (analytic gradients). The hole's rim is a curved sharp crease: the
// circle z = 1, x^2 + y^2 = 0.25. Vertices near it must lie on the surface and, in cells the circle runs through, on
// the circle (a jagged rim is vertices pulled off it by tangent planes of the sphere that meet away from it).
struct CreaseMeasure {
    double worst_surface = 0;  // largest distance to the surface of a vertex within one cell of the circle
    double worst_crease = 0;   // largest distance to the circle of a vertex in a cell the circle crosses
    double worst_on_both = 0;  // largest distance to the circle of a vertex on both surfaces (within 0.02 h)
    std::size_t near = 0, crease = 0, on_both = 0;
};

CreaseMeasure measure_rim(const PolygonMesh& mesh, const Box3& bounds, double h) {
    const Vec3 centre{0, 0, 1};
    auto to_circle = [&](const Vec3& p) { return std::hypot(std::hypot(p.x, p.y) - 0.5, p.z - 1); };
    // exact distance to the surface near the rim: the top face outside the disc, the spherical cap inside the box
    auto to_surface = [&](const Vec3& p) {
        const double rho = std::hypot(p.x, p.y);
        const double top = rho >= 0.5 ? std::fabs(p.z - 1) : to_circle(p);
        const double cap = p.z <= 1 ? std::fabs(norm(p - centre) - 0.5) : to_circle(p);
        return std::min(top, cap);
    };
    // cells crossed by the circle
    std::set<std::array<long, 3>> crossed;
    auto cell_of = [&](const Vec3& p) {
        return std::array<long, 3>{static_cast<long>(std::floor((p.x - bounds.min.x) / h)),
                                   static_cast<long>(std::floor((p.y - bounds.min.y) / h)),
                                   static_cast<long>(std::floor((p.z - bounds.min.z) / h))};
    };
    for (int s = 0; s < 20000; ++s) {
        const double t = 2 * kPi * s / 20000;
        for (double dz : {-1e-9, 1e-9})  // z = 1 may be a grid plane: the cells on both sides
            crossed.insert(cell_of({0.5 * std::cos(t), 0.5 * std::sin(t), 1.0 + dz}));
    }
    CreaseMeasure m;
    for (const Vec3& p : mesh.positions) {
        const double dc = to_circle(p);
        if (dc > h) continue;
        ++m.near;
        m.worst_surface = std::max(m.worst_surface, to_surface(p));
        if (crossed.count(cell_of(p))) {
            ++m.crease;
            m.worst_crease = std::max(m.worst_crease, dc);
        }
        if (std::fabs(p.z - 1) < 0.02 * h && std::fabs(norm(p - centre) - 0.5) < 0.02 * h) {
            ++m.on_both;
            m.worst_on_both = std::max(m.worst_on_both, dc);
        }
    }
    return m;
}

TEST(MeshField, CurvedCreaseOfBoxMinusBallIsSharp) {
    const FieldPtr shape = csg_difference({box({1, 1, 1}), translate(sphere(0.5), {0, 0, 1})});
    const Box3 bounds = cube_bounds(1.5);
    for (int resolution : {32, 48}) {
        const double h = 3.0 / resolution;
        MeshFieldStats stats;
        const PolygonMesh mesh = mesh_ok(*shape, bounds, at(resolution), &stats);
        EXPECT_VALID_MESH(mesh, bounds);
        std::printf("resolution %d: %llu field evaluations, %zu vertices\n", resolution,
                    static_cast<unsigned long long>(stats.field_evaluations), mesh.vertex_count());
        const CreaseMeasure m = measure_rim(mesh, bounds, h);
        std::printf(
            "resolution %d (h %.4f): %zu vertices within a cell of the rim, worst %.2e (%.3f h) off the "
            "surface; %zu in crossed cells, worst %.2e (%.3f h) off the circle; %zu on both surfaces, worst "
            "%.2e off the circle\n",
            resolution, h, m.near, m.worst_surface, m.worst_surface / h, m.crease, m.worst_crease, m.worst_crease / h,
            m.on_both, m.worst_on_both);
        ASSERT_GT(m.crease, static_cast<std::size_t>(2 * kPi * 0.5 / h));  // the rim has vertices all round
        EXPECT_LT(m.worst_surface, 0.02 * h);
        EXPECT_LT(m.worst_crease, 0.03 * h);
        EXPECT_LT(m.worst_on_both, 0.03 * h);
        EXPECT_GE(2 * m.on_both, m.crease);  // most vertices of crossed cells are on both sheets
    }
}

// Normals for renderers: split along the cube's edges (90 degrees > 40), smooth over the ball, same positions.
TEST(MeshField, SplitNormalsAtCreasesKeepsPositionsAndWeldsBack) {
    const FieldPtr shape = csg_difference({box({1, 1, 1}), translate(sphere(0.5), {0, 0, 1})});
    const Box3 bounds = cube_bounds(1.5);
    const PolygonMesh mesh = mesh_ok(*shape, bounds, at(32));
    EXPECT_VALID_MESH(mesh, bounds);
    const PolygonMesh split = split_normals_at_creases(mesh, 40);
    ASSERT_EQ(split.face_count(), mesh.face_count());
    ASSERT_EQ(split.normals.size(), split.positions.size());
    EXPECT_GT(split.vertex_count(), mesh.vertex_count());
    // welding by exact position gives the original faces back: closed and manifold as before
    std::map<std::array<double, 3>, Index> original;
    for (Index v = 0; v < mesh.vertex_count(); ++v)
        original[{mesh.positions[v].x, mesh.positions[v].y, mesh.positions[v].z}] = v;
    ASSERT_EQ(original.size(), mesh.vertex_count());
    for (std::size_t f = 0; f < mesh.face_count(); ++f)
        for (int k = 0; k < 3; ++k) {
            const Vec3& p = split.positions[split.face(f)[k]];
            const auto it = original.find({p.x, p.y, p.z});
            ASSERT_NE(it, original.end());
            EXPECT_EQ(it->second, mesh.face(f)[k]);
        }
    // every corner's normal is within 40 degrees of its face's normal (across a cube edge the average would be 45
    // degrees off at best); on the flat faces away from edges, the face's axis exactly
    std::size_t sharp_corners = 0;
    for (std::size_t f = 0; f < split.face_count(); ++f) {
        const auto t = split.face(f);
        Vec3 n = cross(split.positions[t[1]] - split.positions[t[0]], split.positions[t[2]] - split.positions[t[0]]);
        n = n * (1.0 / norm(n));
        for (Index v : t) {
            EXPECT_NEAR(norm(split.normals[v]), 1.0, 1e-12);
            EXPECT_GT(dot(split.normals[v], n), std::cos(40 * kPi / 180) - 1e-9);
            const Vec3& p = split.positions[v];
            // on the cube's edges along y and z at x = +-1
            const bool on_cube_edge = std::fabs(std::fabs(p.x) - 1) < 1e-9 &&
                                      (std::fabs(std::fabs(p.y) - 1) < 1e-9 || std::fabs(std::fabs(p.z) - 1) < 1e-9);
            if (on_cube_edge) {
                ++sharp_corners;
                EXPECT_NEAR(std::fabs(dot(split.normals[v], n)), 1.0, 1e-9);  // the face's own axis
            }
        }
    }
    EXPECT_GT(sharp_corners, 100u);
    // no split at 180 degrees: as many vertices as the input, smooth normals
    EXPECT_EQ(split_normals_at_creases(mesh, 180).vertex_count(), mesh.vertex_count());
}

// ---- invariants on hard inputs ------------------------------------------------------------------------------------

TEST(MeshField, SurfaceCutByTheBoundsIsClosedWithFlatCaps) {
    const Sphere sphere(1.0);
    const Box3 bounds{{-0.6, -1.2, -1.2}, {0.7, 1.2, 1.2}};  // cuts off two caps
    const PolygonMesh mesh = mesh_ok(sphere, bounds, at(64));
    EXPECT_VALID_MESH(mesh, bounds);
    // analytic: the ball between two planes x = -0.6 and x = 0.7
    auto cap = [](double h) { return kPi * h * h * (3 - h) / 3; };  // cap of height h of the unit ball
    const double volume = 4.0 / 3.0 * kPi - cap(0.4) - cap(0.3);
    EXPECT_NEAR(testing::signed_volume(mesh) / volume, 1.0, 0.005);
    // the caps are flat: their vertices lie on the cut planes
    std::size_t on_caps = 0;
    for (const Vec3& p : mesh.positions)
        if (std::fabs(p.x + 0.6) < 1e-6 || std::fabs(p.x - 0.7) < 1e-6) ++on_caps;
    EXPECT_GT(on_caps, 100u);
}

TEST(MeshField, FieldNegativeEverywhereGivesTheBoundsBox) {
    class Inside : public Field {
    public:
        double value(const Vec3&) const override { return -1; }
        FieldKind kind() const override { return FieldKind::DistanceBound; }
    };
    const Box3 bounds{{0, 0, 0}, {2, 1, 1}};
    const PolygonMesh mesh = mesh_ok(Inside{}, bounds, at(8));
    EXPECT_VALID_MESH(mesh, bounds);
    EXPECT_NEAR(testing::signed_volume(mesh), 2.0, 2.0 * 1e-3);
}

TEST(MeshField, TwoSheetsInOneCellStaySeparate) {
    // a spherical shell thinner than a cell: both sheets cross the same cells
    const Sphere sphere(0.8);
    const Shell shell(sphere, 0.01);
    const Box3 bounds = cube_bounds(1.0);
    MeshFieldStats stats;
    const PolygonMesh mesh = mesh_ok(shell, bounds, at(24), &stats);  // cell 0.083 >> thickness 0.02
    EXPECT_VALID_MESH(mesh, bounds);
    EXPECT_GT(mesh.face_count(), 1000u);
    // a thin plate crossing cells diagonally
    class Plate : public Field {
    public:
        double value(const Vec3& p) const override { return std::fabs(p.x + 0.3 * p.y + 0.2 * p.z - 0.01) - 0.004; }
        FieldKind kind() const override { return FieldKind::DistanceBound; }
        double lipschitz() const override { return 1.1; }
    };
    const PolygonMesh plate = mesh_ok(Plate{}, bounds, at(16));
    EXPECT_VALID_MESH(plate, bounds);
}

TEST(MeshField, AmbiguousConfigurationsStayManifold) {
    // random trilinear noise at about the grid spacing: every marching-cubes case, many ambiguous faces, including
    // the ones where both cells keep both segments of a face in one patch (non-manifold in plain dual MC)
    std::uint64_t fixes = 0;
    for (unsigned seed = 1; seed <= 6; ++seed) {
        const Noise noise(0.13 + 0.01 * seed, seed);
        const Box3 bounds = cube_bounds(1.0);
        MeshFieldStats stats;
        const PolygonMesh mesh = mesh_ok(noise, bounds, at(20 + 3 * static_cast<int>(seed)), &stats);
        SCOPED_TRACE(seed);
        EXPECT_VALID_MESH(mesh, bounds);
        EXPECT_GT(mesh.face_count(), 100u);
        fixes += stats.non_manifold_fixes;
    }
    EXPECT_GT(fixes, 0u);  // the inserted-vertex case was exercised
}

TEST(MeshField, GyroidAtCoarseResolution) {
    const Gyroid gyroid(6.0);
    const Box3 bounds = cube_bounds(1.0);
    for (int resolution : {8, 13, 32}) {
        SCOPED_TRACE(resolution);
        const PolygonMesh mesh = mesh_ok(gyroid, bounds, at(resolution));
        EXPECT_VALID_MESH(mesh, bounds);
    }
}

// ---- adaptive mode ------------------------------------------------------------------------------------------------

TEST(MeshField, AdaptiveEvaluatesLessForTheSameMesh) {
    const BoxField box({1, 1, 1});
    const Sphere ball(0.5, {0, 0, 1});
    const Difference shape(box, ball);
    const Box3 bounds = cube_bounds(1.25);
    MeshFieldStats uniform_stats, adaptive_stats;
    const PolygonMesh uniform = mesh_ok(shape, bounds, at(96), &uniform_stats);
    const PolygonMesh adaptive = mesh_ok(shape, bounds, at(96, MeshFieldMode::Adaptive), &adaptive_stats);
    EXPECT_VALID_MESH(adaptive, bounds);
    // the same surface (same cells, same triangles, same volume), for far fewer evaluations
    EXPECT_EQ(adaptive.face_count(), uniform.face_count());
    EXPECT_EQ(adaptive_stats.surface_cells, uniform_stats.surface_cells);
    EXPECT_NEAR(testing::signed_volume(adaptive), testing::signed_volume(uniform), 1e-9);
    EXPECT_LT(adaptive_stats.field_evaluations * 2, uniform_stats.field_evaluations);
}

TEST(MeshField, AdaptiveSimplificationKeepsInvariantsVolumeAndTolerance) {
    const BoxField box({1, 1, 1});
    const Sphere ball(0.5, {0, 0, 1});
    const Difference shape(box, ball);
    const Box3 bounds = cube_bounds(1.25);
    const double h = 2.5 / 40;
    MeshFieldOptions options = at(40, MeshFieldMode::Adaptive);
    options.simplify_tolerance = 0.1 * h;
    MeshFieldStats stats;
    const PolygonMesh adaptive = mesh_ok(shape, bounds, options, &stats);
    EXPECT_VALID_MESH(adaptive, bounds);
    EXPECT_LT(adaptive.face_count() * 3, stats.triangles_before_simplify);  // flat faces coarsened
    const double volume = 8.0 - 2.0 / 3.0 * kPi * 0.125;
    EXPECT_NEAR(testing::signed_volume(adaptive) / volume, 1.0, 0.005);
    double worst = 0;
    for (const Vec3& p : adaptive.positions) worst = std::max(worst, std::fabs(shape.value(p)));
    EXPECT_LT(worst, 0.1 * h + 2e-3);
}

TEST(MeshField, AdaptiveSphereAndGeneralFieldFallback) {
    const Sphere sphere(1.0);
    const Box3 bounds = cube_bounds(1.25);
    const PolygonMesh mesh = mesh_ok(sphere, bounds, at(64, MeshFieldMode::Adaptive));
    EXPECT_VALID_MESH(mesh, bounds);
    EXPECT_NEAR(testing::signed_volume(mesh) / (4.0 / 3.0 * kPi), 1.0, 0.005);
    // a General field cannot be culled: evaluated like uniform, still valid
    const Gyroid gyroid(6.0);
    MeshFieldStats stats;
    const PolygonMesh g = mesh_ok(gyroid, cube_bounds(1.0), at(16, MeshFieldMode::Adaptive), &stats);
    EXPECT_VALID_MESH(g, cube_bounds(1.0));
    EXPECT_GE(stats.field_evaluations, 17u * 17 * 17);
}

// ---- budget, cancel, bad options ----------------------------------------------------------------------------------

class CountingField : public Field {
public:
    double value(const Vec3& p) const override {
        ++calls;
        return norm(p) - 0.5;
    }
    FieldKind kind() const override { return FieldKind::ExactDistance; }
    mutable std::atomic<std::uint64_t> calls{0};
};

TEST(MeshField, BudgetCheckedBeforeAnyEvaluation) {
    CountingField field;
    MeshFieldOptions options = at(200);
    options.max_cells = 100 * 100 * 100;
    auto result = mesh_field(field, cube_bounds(1), options);
    ASSERT_FALSE(result.ok());
    EXPECT_EQ(result.error().code, ErrorCode::BudgetExceeded);
    EXPECT_EQ(field.calls.load(), 0u);
    // the grid follows the bounds' aspect: 200 x 100 x 50 cells
    options.max_cells = std::uint64_t{1} << 40;
    auto grid = mesh_field_grid(Box3{{0, 0, 0}, {4, 2, 1}}, options);
    ASSERT_TRUE(grid.ok());
    EXPECT_EQ(grid->nx, 200);
    EXPECT_EQ(grid->ny, 100);
    EXPECT_EQ(grid->nz, 50);
    EXPECT_EQ(grid->cells, 200u * 100 * 50);
    // a huge resolution never overflows into a small number
    options.resolution = 65536;
    options.max_cells = 256 * 256 * 256;
    EXPECT_EQ(mesh_field_grid(cube_bounds(1), options).error().code, ErrorCode::BudgetExceeded);
}

TEST(MeshField, BadOptionsAreInvalidArgument) {
    const Sphere sphere(1);
    EXPECT_EQ(mesh_field(sphere, cube_bounds(1), at(1)).error().code, ErrorCode::InvalidArgument);
    EXPECT_EQ(mesh_field(sphere, Box3{{0, 0, 0}, {1, 0, 1}}, at(8)).error().code, ErrorCode::InvalidArgument);
    EXPECT_EQ(mesh_field(sphere, Box3{}, at(8)).error().code, ErrorCode::InvalidArgument);
    MeshFieldOptions options;
    options.cell_size = -1;
    EXPECT_EQ(mesh_field(sphere, cube_bounds(1), options).error().code, ErrorCode::InvalidArgument);
    options.cell_size = std::nan("");
    EXPECT_EQ(mesh_field(sphere, cube_bounds(1), options).error().code, ErrorCode::InvalidArgument);
    options.cell_size = 0.25;  // 8 cells
    auto grid = mesh_field_grid(cube_bounds(1), options);
    ASSERT_TRUE(grid.ok());
    EXPECT_EQ(grid->nx, 8);
}

TEST(MeshField, CancelIsHonoured) {
    const Sphere sphere(1);
    std::atomic<bool> abort{true};
    for (MeshFieldMode mode : {MeshFieldMode::Uniform, MeshFieldMode::Adaptive}) {
        MeshFieldOptions options = at(64, mode);
        options.cancel.flag = &abort;
        auto result = mesh_field(sphere, cube_bounds(1.25), options);
        ASSERT_FALSE(result.ok());
        EXPECT_EQ(result.error().code, ErrorCode::Cancelled);
    }
    MeshFieldOptions options = at(64);
    options.cancel.deadline = Cancel::Clock::now() - std::chrono::seconds(1);
    EXPECT_EQ(mesh_field(sphere, cube_bounds(1.25), options).error().code, ErrorCode::Cancelled);
}

TEST(MeshField, NoSignChangeGivesAnEmptyMesh) {
    const Sphere far(0.1, {5, 5, 5});
    const PolygonMesh mesh = mesh_ok(far, cube_bounds(1), at(16));
    EXPECT_EQ(mesh.face_count(), 0u);
    EXPECT_EQ(mesh.vertex_count(), 0u);
}

TEST(MeshField, NanFieldValuesCountAsOutside) {
    class HalfNan : public Field {
    public:
        double value(const Vec3& p) const override { return p.x > 0.3 ? std::nan("") : norm(p) - 0.6; }
        FieldKind kind() const override { return FieldKind::General; }
    };
    const Box3 bounds = cube_bounds(1);
    const PolygonMesh mesh = mesh_ok(HalfNan{}, bounds, at(20));
    EXPECT_VALID_MESH(mesh, bounds);
    EXPECT_GT(mesh.face_count(), 100u);
}

}  // namespace
}  // namespace surfaced::implicit
