// Implicit-surface meshing (geometry/implicit/mesh_field.h): time, field evaluations and triangle count against
// resolution, uniform vs adaptive, for a smooth field (sphere), a CSG field with sharp edges (box minus ball) and a
// detailed one (a gyroid sheet clipped by a ball). Best of several runs, single thread. Then the scene's mesh node
// (geometry/implicit/triangle_mesh_field.h): the cost of one evaluation, and a triangle mesh minus a ball meshed at
// resolution 64 against the same shape built from primitives.
//
//   build/bench/bench_implicit [--quick | --mesh-node]     (--quick: resolutions 32..128 only; --mesh-node: only
//                                                          the mesh-node table)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "bench/support/bench_data.h"
#include "geometry/implicit/mesh_field.h"
#include "geometry/implicit/operators.h"
#include "geometry/implicit/triangle_mesh_field.h"
#include "geometry/mesh/shapes.h"
#include "geometry/subdivision/subdivide.h"

namespace {

using namespace surfaced;
using bench::icosphere;
using namespace surfaced::implicit;

class Sphere : public Field {
public:
    Sphere(double r, Vec3 c = {}) : r_(r), c_(c) {}
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

class BoxMinusBall : public Field {
public:
    double value(const Vec3& p) const override {
        const Vec3 q{std::fabs(p.x) - 1, std::fabs(p.y) - 1, std::fabs(p.z) - 1};
        const Vec3 o{std::max(q.x, 0.0), std::max(q.y, 0.0), std::max(q.z, 0.0)};
        const double box = norm(o) + std::min(std::max({q.x, q.y, q.z}), 0.0);
        return std::max(box, -ball_.value(p));
    }
    FieldKind kind() const override { return FieldKind::DistanceBound; }

private:
    Sphere ball_{0.5, {0, 0, 1}};
};

// A gyroid sheet of half-thickness t (scaled to a 1-Lipschitz bound: |grad g| <= 2 sqrt(3) s), inside a ball.
class GyroidBall : public Field {
public:
    double value(const Vec3& p) const override {
        const Vec3 q = p * s_;
        const double g = std::sin(q.x) * std::cos(q.y) + std::sin(q.y) * std::cos(q.z) + std::sin(q.z) * std::cos(q.x);
        return std::max(std::fabs(g) / (2 * std::sqrt(3.0) * s_) - 0.03, norm(p) - 1.0);
    }
    FieldKind kind() const override { return FieldKind::DistanceBound; }

private:
    double s_ = 8.0;
};

struct Run {
    double ms = 0;
    MeshFieldStats stats;
    std::size_t triangles = 0;
};

Run measure(const Field& field, const Box3& bounds, int resolution, MeshFieldMode mode, double tolerance, int repeats) {
    Run best;
    best.ms = 1e300;
    for (int r = 0; r < repeats; ++r) {
        MeshFieldOptions options;
        options.resolution = resolution;
        options.mode = mode;
        options.simplify_tolerance = tolerance;
        MeshFieldStats stats;
        const auto t0 = std::chrono::steady_clock::now();
        auto mesh = mesh_field(field, bounds, options, &stats);
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        if (!mesh) {
            std::fprintf(stderr, "meshing failed: %s\n", mesh.error().message.c_str());
            std::exit(1);
        }
        if (ms < best.ms) best = Run{ms, stats, mesh->face_count()};
    }
    return best;
}

//! The cube [-1, 1]^3 as 12 outward triangles.
PolygonMesh cube_mesh() {
    PolygonMesh mesh;
    for (int i = 0; i < 8; ++i) mesh.positions.push_back({i & 1 ? 1.0 : -1.0, i & 2 ? 1.0 : -1.0, i & 4 ? 1.0 : -1.0});
    const Index quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) {
        mesh.add_face({q[0], q[1], q[2]});
        mesh.add_face({q[0], q[2], q[3]});
    }
    return mesh;
}

//! Nanoseconds per value() at random points of `bounds`, best of three passes over the same points.
double ns_per_value(const Field& field, const Box3& bounds) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<Vec3> points(100'000);
    for (Vec3& p : points)
        p = {bounds.min.x + u(rng) * (bounds.max.x - bounds.min.x),
             bounds.min.y + u(rng) * (bounds.max.y - bounds.min.y),
             bounds.min.z + u(rng) * (bounds.max.z - bounds.min.z)};
    double best = 1e300, sink = 0;
    for (int r = 0; r < 3; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        for (const Vec3& p : points) sink += field.value(p);
        best = std::min(best, std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count());
    }
    if (sink == 12345.678) std::printf(" ");  // keeps the loop
    return best / static_cast<double>(points.size());
}

//! A triangle mesh minus a ball of radius 0.5 centred at (0, 0, 1), meshed at resolution 64, uniform and adaptive;
//! the first row builds the same solid from the box primitive.
void mesh_node_table() {
    const Box3 cube{{-1.25, -1.25, -1.25}, {1.25, 1.25, 1.25}};
    const FieldPtr ball = translate(implicit::sphere(0.5), {0, 0, 1});
    struct Case {
        std::string name;
        FieldPtr solid;
        std::size_t triangles;
    };
    std::vector<Case> cases;
    cases.push_back({"box primitive", implicit::box({1, 1, 1}), 0});
    cases.push_back({"cube mesh", triangle_mesh_field(cube_mesh()).value(), 12});
    for (int levels : {3, 5}) {
        const PolygonMesh sphere = icosphere(levels);
        cases.push_back(
            {"icosphere " + std::to_string(levels), triangle_mesh_field(sphere).value(), sphere.face_count()});
    }
    std::printf(
        "\n| solid minus ball, resolution 64 | triangles | ns per value (solid alone) | uniform ms | "
        "uniform evaluations | adaptive ms | adaptive evaluations | output triangles |\n");
    std::printf("|---|---:|---:|---:|---:|---:|---:|---:|\n");
    for (const Case& c : cases) {
        const FieldPtr scene = csg_difference({c.solid, ball});
        const Run uniform = measure(*scene, cube, 64, MeshFieldMode::Uniform, 0, 3);
        const Run adaptive = measure(*scene, cube, 64, MeshFieldMode::Adaptive, 0, 3);
        std::printf("| %s | %zu | %.0f | %.1f | %llu | %.1f | %llu | %zu |\n", c.name.c_str(), c.triangles,
                    ns_per_value(*c.solid, cube), uniform.ms,
                    static_cast<unsigned long long>(uniform.stats.field_evaluations), adaptive.ms,
                    static_cast<unsigned long long>(adaptive.stats.field_evaluations), uniform.triangles);
        std::fflush(stdout);
    }
}

}  // namespace

int main(int argc, char** argv) {
    const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
    if (argc > 1 && std::strcmp(argv[1], "--mesh-node") == 0) {
        mesh_node_table();
        return 0;
    }
    const Sphere sphere(1.0);
    const BoxMinusBall box_minus_ball;
    const GyroidBall gyroid;
    struct Case {
        const char* name;
        const Field* field;
        Box3 bounds;
    };
    const Box3 cube{{-1.25, -1.25, -1.25}, {1.25, 1.25, 1.25}};
    const Case cases[] = {
        {"sphere", &sphere, cube}, {"box minus ball", &box_minus_ball, cube}, {"gyroid in ball", &gyroid, cube}};
    std::vector<int> resolutions = {32, 64, 128};
    if (!quick) resolutions.push_back(256);

    std::printf(
        "| field | resolution | grid cells | surface cells | uniform ms | uniform evaluations | adaptive ms | "
        "adaptive evaluations | evaluations ratio | triangles | adaptive + QEM (0.1 cell) triangles | QEM ms |\n");
    std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (const Case& c : cases)
        for (int resolution : resolutions) {
            const int repeats = resolution >= 256 ? 1 : 3;
            const Run uniform = measure(*c.field, c.bounds, resolution, MeshFieldMode::Uniform, 0, repeats);
            const Run adaptive = measure(*c.field, c.bounds, resolution, MeshFieldMode::Adaptive, 0, repeats);
            std::string simplified = "-", simplify_ms = "-";
            if (resolution <= 64) {  // QEM to a measured Hausdorff distance costs seconds beyond this
                const double h = 2.5 / resolution;
                const Run s = measure(*c.field, c.bounds, resolution, MeshFieldMode::Adaptive, 0.1 * h, 1);
                simplified = std::to_string(s.triangles);
                char buf[32];
                std::snprintf(buf, sizeof buf, "%.0f", s.ms - adaptive.ms);
                simplify_ms = buf;
            }
            std::printf("| %s | %d | %llu | %llu | %.1f | %llu | %.1f | %llu | %.3f | %zu | %s | %s |\n", c.name,
                        resolution, static_cast<unsigned long long>(uniform.stats.grid.cells),
                        static_cast<unsigned long long>(uniform.stats.surface_cells), uniform.ms,
                        static_cast<unsigned long long>(uniform.stats.field_evaluations), adaptive.ms,
                        static_cast<unsigned long long>(adaptive.stats.field_evaluations),
                        static_cast<double>(adaptive.stats.field_evaluations) /
                            static_cast<double>(uniform.stats.field_evaluations),
                        uniform.triangles, simplified.c_str(), simplify_ms.c_str());
            std::fflush(stdout);
        }
    mesh_node_table();
    return 0;
}
