// QEM simplification: counts reached, error measured by Hausdorff (not by the algorithm's own estimate), and the
// output invariants (no non-manifold, flipped, degenerate or duplicate faces) on closed, open, seamed, sliver and
// scanned meshes.
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>

#include "geometry/core/block_pool.h"
#include "geometry/io/mesh_io.h"
#include "geometry/mesh/shapes.h"
#include "geometry/mesh/triangulate.h"
#include "geometry/simplify/mesh_distance.h"
#include "geometry/simplify/qem.h"
#include "tests/support/mesh_asserts.h"
#include "tests/support/simplify_meshes.h"

namespace surfaced {
namespace {

using testing::boundary_loop_count;
using testing::edge_stats;

// The Stanford bunny (tests/data/bunny): 34835 vertices, 69666 triangles.
const std::string kBunnyPath = SURFACED_TEST_DATA_DIR "/bunny/bunny.obj";

//! The invariants every output must satisfy; `input` is the (triangulated) input for the flip check.
void expect_clean(const PolygonMesh& out, const PolygonMesh& input, const std::string& what) {
    SCOPED_TRACE(what);
    ASSERT_TRUE(validate(out).ok()) << validate(out).error().message;
    ASSERT_TRUE(out.is_triangle_mesh());
    const auto stats = edge_stats(out);
    EXPECT_EQ(stats.non_manifold_edges, 0u);
    EXPECT_EQ(stats.inconsistent_edges, 0u);
    EXPECT_EQ(testing::degenerate_faces(out), 0u);
    EXPECT_EQ(testing::duplicate_faces(out), 0u);
    EXPECT_EQ(testing::flipped_faces(out, input), 0u);
}

PolygonMesh bunny() {
    if (!std::filesystem::exists(kBunnyPath)) {
        ADD_FAILURE() << kBunnyPath << " is missing";
        return {};
    }
    auto mesh = read_obj(testing::read_file(kBunnyPath));
    EXPECT_TRUE(mesh.ok()) << (mesh.ok() ? "" : mesh.error().message);
    return mesh.ok() ? std::move(mesh.value()) : PolygonMesh{};
}

SimplifyOptions target(std::size_t faces) {
    SimplifyOptions options;
    options.target_faces = faces;
    return options;
}

TEST(Qem, SphereReachesTargetAndStaysClosed) {
    const PolygonMesh sphere = testing::icosphere(4);  // 5120 faces
    for (std::size_t faces : {2000u, 500u, 100u}) {
        auto out = simplify_qem(sphere, target(faces));
        ASSERT_TRUE(out.ok()) << out.error().message;
        EXPECT_LE(out->faces, faces);
        EXPECT_GE(out->faces, faces - 2);  // each collapse removes two faces of a closed mesh
        EXPECT_EQ(out->faces, out->mesh.face_count());
        EXPECT_FALSE(out->triangulated);
        EXPECT_TRUE(testing::is_watertight(out->mesh));
        EXPECT_EQ(testing::euler_characteristic(out->mesh), 2);
        expect_clean(out->mesh, sphere, "sphere to " + std::to_string(faces));
        // every face keeps facing outwards
        for (std::size_t f = 0; f < out->mesh.face_count(); ++f) {
            auto t = out->mesh.face(f);
            EXPECT_GT(dot(testing::face_normal(out->mesh, f), out->mesh.positions[t[0]]), 0) << "face " << f;
        }
        EXPECT_GT(out->achieved_error, 0);
        EXPECT_NEAR(out->relative_error, out->achieved_error / sphere.bounds().diagonal(), 1e-15);
    }
}

TEST(Qem, SphereKeepsVolumeWithinOnePercentAtTenPercentOfTheFaces) {
    const PolygonMesh sphere = testing::icosphere(5);  // 20480 faces
    const double before = testing::signed_volume(sphere);
    SimplifyOptions options;
    options.ratio = 0.1;
    auto out = simplify_qem(sphere, options);
    ASSERT_TRUE(out.ok());
    EXPECT_LE(out->faces, 2048u);
    const double after = testing::signed_volume(out->mesh);
    // Quadric placement puts vertices off the chords, so the volume barely changes (the icosphere itself is 0.2%
    // under the true sphere's 4/3 pi).
    EXPECT_NEAR(after / before, 1.0, 0.01) << before << " -> " << after;
    const MeshDistance d = mesh_distance(sphere, out->mesh);
    EXPECT_LT(d.hausdorff, 0.02);
    EXPECT_LT(d.rms, 0.005);
}

// Volume restoration (Lindstrom-Turk): with restore_volume 1 every collapse between interior vertices keeps the
// volume under its two fans, so a closed mesh keeps its volume; 0.5 lowers the RMS distance of plain quadrics, whose
// output lies inside a convex surface. The guarantees of every output hold either way.
TEST(Qem, RestoreVolumeKeepsTheVolumeAndLowersTheRmsError) {
    const PolygonMesh sphere = testing::icosphere(5);  // 20,480 faces
    const double before = testing::signed_volume(sphere);
    for (std::size_t faces : {2048u, 256u}) {
        SCOPED_TRACE(faces);
        std::array<double, 3> volume{}, rms{};
        const std::array<double, 3> restore{0.0, 0.5, 1.0};
        for (std::size_t i = 0; i < 3; ++i) {
            SimplifyOptions options = target(faces);
            options.restore_volume = restore[i];
            auto out = simplify_qem(sphere, options);
            ASSERT_TRUE(out.ok()) << out.error().message;
            EXPECT_EQ(out->faces, faces);
            expect_clean(out->mesh, sphere, "restore_volume " + std::to_string(restore[i]));
            volume[i] = testing::signed_volume(out->mesh);
            rms[i] = mesh_distance(sphere, out->mesh).rms;
        }
        EXPECT_LT(volume[0], before);  // inside
        // the volume change of each collapse is linear in the placement: restored exactly, up to rounding and the
        // collapses whose restored point the flip and reach checks refuse
        EXPECT_NEAR(volume[2] / before, 1.0, 1e-3) << before << " -> " << volume[2] << " (plain: " << volume[0] << ")";
        EXPECT_LT(std::fabs(volume[1] - before), 0.7 * std::fabs(volume[0] - before));
        EXPECT_LT(rms[1], 0.95 * rms[0]);
        EXPECT_LT(rms[2], 0.95 * rms[0]);
    }
}

TEST(Qem, RestoreVolumeLeavesBoundariesAndChecksItsRange) {
    // an open height field: boundary edges are not restored (their fans are not closed); the output stays clean
    PolygonMesh field = shapes::grid(24, 24, true);
    for (Vec3& p : field.positions) p.z = 0.2 * std::sin(3 * p.x) * std::cos(2 * p.y);
    SimplifyOptions options = target(200);
    options.restore_volume = 1.0;
    auto out = simplify_qem(field, options);
    ASSERT_TRUE(out.ok()) << out.error().message;
    expect_clean(out->mesh, field, "height field");
    EXPECT_EQ(boundary_loop_count(out->mesh), 1u);
    for (double bad : {-0.1, 1.5, std::numeric_limits<double>::quiet_NaN()}) {
        options.restore_volume = bad;
        auto refused = simplify_qem(field, options);
        ASSERT_FALSE(refused.ok());
        EXPECT_EQ(refused.error().code, ErrorCode::InvalidArgument);
    }
}

TEST(Qem, MaxErrorIsHonouredAsMeasuredByHausdorff) {
    const PolygonMesh sphere = testing::icosphere(5);
    for (double max_error : {0.002, 0.01, 0.05}) {
        SimplifyOptions options;
        options.max_error = max_error;
        auto out = simplify_qem(sphere, options);
        ASSERT_TRUE(out.ok());
        EXPECT_TRUE(out->error_measured);
        EXPECT_LE(out->achieved_error, max_error);
        EXPECT_LT(out->faces, sphere.face_count() / 2) << "max_error " << max_error << " should allow simplifying";
        // an independent, denser measurement (other seed, 4x the samples)
        MeshDistanceOptions dense;
        dense.samples = 400'000;
        dense.seed = 77;
        const MeshDistance d = mesh_distance(sphere, out->mesh, dense);
        EXPECT_LE(d.hausdorff, max_error * 1.05) << "max_error " << max_error;
        expect_clean(out->mesh, sphere, "max_error " + std::to_string(max_error));
    }
}

TEST(Qem, MaxErrorAndTargetStopAtWhicheverComesFirst) {
    const PolygonMesh sphere = testing::icosphere(4);
    SimplifyOptions options;
    options.max_error = 1e-9;  // nothing may move: no collapse
    options.target_faces = 100;
    auto tight = simplify_qem(sphere, options);
    ASSERT_TRUE(tight.ok());
    EXPECT_EQ(tight->faces, sphere.face_count());
    options.max_error = 1.0;  // the target comes first
    auto loose = simplify_qem(sphere, options);
    ASSERT_TRUE(loose.ok());
    EXPECT_LE(loose->faces, 100u);
    EXPECT_LE(loose->achieved_error, 1.0);
}

TEST(Qem, TorusFromQuadsIsTriangulatedFirstAndKeepsItsGenus) {
    const PolygonMesh torus = shapes::torus(48, 24);
    auto out = simplify_qem(torus, target(300));
    ASSERT_TRUE(out.ok()) << out.error().message;
    EXPECT_TRUE(out->triangulated);
    EXPECT_LE(out->faces, 300u);
    EXPECT_GE(out->faces, 290u);
    EXPECT_EQ(testing::euler_characteristic(out->mesh), 0);
    EXPECT_TRUE(testing::is_watertight(out->mesh));
    expect_clean(out->mesh, torus, "torus");
    EXPECT_LT(mesh_distance(torus, out->mesh).hausdorff, 0.05);
}

TEST(Qem, GridWithLockedBorderKeepsItsBoundaryExactly) {
    const PolygonMesh grid = shapes::grid(30, 30, true);  // 1800 faces, one boundary loop of 120 edges
    SimplifyOptions options;
    options.ratio = 0.1;
    options.lock_border = true;
    auto out = simplify_qem(grid, options);
    ASSERT_TRUE(out.ok());
    expect_clean(out->mesh, grid, "locked grid");
    EXPECT_EQ(boundary_loop_count(out->mesh), 1u);
    EXPECT_EQ(edge_stats(out->mesh).boundary_edges, 120u);
    EXPECT_EQ(testing::boundary_positions(out->mesh), testing::boundary_positions(grid));
    // flat, so every interior vertex can go: the target (10%) is reachable even with the 120 border vertices kept
    EXPECT_LE(out->faces, 180u);
    for (std::size_t f = 0; f < out->mesh.face_count(); ++f) EXPECT_GT(testing::face_normal(out->mesh, f).z, 0);
    EXPECT_LT(mesh_distance(grid, out->mesh).hausdorff, 1e-9);  // flat: no error at all
}

TEST(Qem, GridWithFreeBorderKeepsTheOutlineByConstraintPlanes) {
    const PolygonMesh grid = shapes::grid(30, 30, true);
    auto out = simplify_qem(grid, target(20));
    ASSERT_TRUE(out.ok());
    expect_clean(out->mesh, grid, "free grid");
    EXPECT_LE(out->faces, 20u);
    EXPECT_EQ(boundary_loop_count(out->mesh), 1u);
    // the square's outline stays the square: the corners survive and nothing moves off it
    EXPECT_LT(mesh_distance(grid, out->mesh).hausdorff, 1e-9);
}

TEST(Qem, LockedVerticesStayInPlace) {
    const PolygonMesh sphere = testing::icosphere(3);
    SimplifyOptions options;
    options.target_faces = 80;
    options.locked_vertices = {0, 5, 100, 300};
    auto out = simplify_qem(sphere, options);
    ASSERT_TRUE(out.ok());
    expect_clean(out->mesh, sphere, "locked vertices");
    for (Index v : options.locked_vertices) {
        bool found = false;
        for (const Vec3& p : out->mesh.positions) found = found || p == sphere.positions[v];
        EXPECT_TRUE(found) << "locked vertex " << v;
    }
}

//! A simplified uv_cylinder: every uv still describes its position, no face spans the seam, both sides survive.
void expect_cylinder_uvs(const PolygonMesh& m) {
    ASSERT_TRUE(m.has_uvs());
    ASSERT_EQ(m.uv_indices.size(), m.face_indices.size());
    for (std::size_t f = 0; f < m.face_count(); ++f) {
        double umin = 1, umax = 0;
        for (Index k = m.face_offsets[f]; k < m.face_offsets[f + 1]; ++k) {
            const Vec3& p = m.positions[m.face_indices[k]];
            const Vec2& uv = m.uvs[m.uv_indices[k]];
            umin = std::min(umin, uv.x);
            umax = std::max(umax, uv.x);
            // uv still describes the position: v = z/2 + 1/2, u = angle / 2 pi (0 or 1 on the seam)
            EXPECT_NEAR(uv.y, 0.5 * p.z + 0.5, 1e-6) << "face " << f;
            double angle = std::atan2(p.y, p.x) / (2 * std::numbers::pi);
            if (angle < 0) angle += 1;
            const double du =
                std::min({std::fabs(uv.x - angle), std::fabs(uv.x - angle - 1), std::fabs(uv.x - angle + 1)});
            EXPECT_LT(du, 0.02) << "face " << f;
        }
        EXPECT_LT(umax - umin, 0.5) << "face " << f << " spans the seam";
    }
    // both sides of the seam survive: corners with u == 0 and corners with u == 1
    bool zero = false, one = false;
    for (Index uv : m.uv_indices) {
        zero = zero || m.uvs[uv].x == 0.0;
        one = one || m.uvs[uv].x == 1.0;
    }
    EXPECT_TRUE(zero && one);
}

TEST(Qem, UvSeamsAreKeptAndUvsInterpolated) {
    const PolygonMesh cylinder = testing::uv_cylinder(64, 16);  // 2048 faces, seam at angle 0
    SimplifyOptions options;
    options.ratio = 0.25;
    auto out = simplify_qem(cylinder, options);
    ASSERT_TRUE(out.ok());
    EXPECT_LE(out->faces, 512u);
    expect_clean(out->mesh, cylinder, "uv cylinder");
    expect_cylinder_uvs(out->mesh);
}

// threads = 2 on a textured mesh: each half interpolates uvs into its own part of the uv list
TEST(Qem, TwoThreadsKeepUvSeamsAndInterpolateUvs) {
    const PolygonMesh cylinder = testing::uv_cylinder(256, 48);  // 24,576 faces
    SimplifyOptions options;
    options.ratio = 0.1;
    auto one = simplify_qem(cylinder, options);
    options.threads = 2;
    auto two = simplify_qem(cylinder, options), again = simplify_qem(cylinder, options);
    ASSERT_TRUE(one.ok() && two.ok() && again.ok());
    EXPECT_LE(two->faces, 2457u);
    EXPECT_GE(two->faces, 2455u);
    expect_clean(two->mesh, cylinder, "uv cylinder, 2 threads");
    expect_cylinder_uvs(two->mesh);
    EXPECT_NE(two->mesh.positions, one->mesh.positions);
    EXPECT_EQ(two->mesh.positions, again->mesh.positions);
    EXPECT_EQ(two->mesh.uv_indices, again->mesh.uv_indices);
    EXPECT_LT(mesh_distance(cylinder, two->mesh).rms, 1.05 * mesh_distance(cylinder, one->mesh).rms);
}

TEST(Qem, VertexNormalsAreInterpolated) {
    PolygonMesh sphere = testing::icosphere(3);
    sphere.normals = sphere.positions;  // unit sphere: the normal is the position
    auto out = simplify_qem(sphere, target(200));
    ASSERT_TRUE(out.ok());
    ASSERT_EQ(out->mesh.normals.size(), out->mesh.vertex_count());
    for (std::size_t v = 0; v < out->mesh.vertex_count(); ++v) {
        const Vec3& p = out->mesh.positions[v];
        EXPECT_NEAR(norm(out->mesh.normals[v]), 1.0, 1e-12);
        EXPECT_GT(dot(out->mesh.normals[v], p * (1.0 / norm(p))), 0.99) << "vertex " << v;
    }
}

TEST(Qem, SliversAndNearDegenerateTrianglesAreCleanedNotWorsened) {
    // A grid whose columns 10/11 and rows 5/6 are 1e-5 apart: long needle triangles (thinness ~1e-5), plus a
    // bump so that the surface is not flat.
    PolygonMesh mesh = shapes::grid(20, 20, true);
    for (Vec3& p : mesh.positions) {
        auto squeeze = [](double t) {
            const double col = std::round(t * 20);
            if (col == 11) return 10.0 / 20 + 1e-5;
            return t;
        };
        p.x = squeeze(p.x);
        p.y = squeeze(p.y);
        p.z = 0.2 * std::exp(-8 * ((p.x - 0.5) * (p.x - 0.5) + (p.y - 0.5) * (p.y - 0.5)));
    }
    std::size_t thin_before = 0;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        auto t = mesh.face(f);
        thin_before +=
            testing::triangle_thinness(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]) < 1e-3;
    }
    ASSERT_GT(thin_before, 40u);
    auto out = simplify_qem(mesh, target(200));
    ASSERT_TRUE(out.ok());
    expect_clean(out->mesh, mesh, "slivers");
    EXPECT_LE(out->faces, 200u);
    std::size_t thin_after = 0;
    for (std::size_t f = 0; f < out->mesh.face_count(); ++f) {
        auto t = out->mesh.face(f);
        thin_after += testing::triangle_thinness(out->mesh.positions[t[0]], out->mesh.positions[t[1]],
                                                 out->mesh.positions[t[2]]) < 1e-3;
    }
    EXPECT_LT(thin_after, thin_before / 4);
}

// Noise makes many collapses compete and many fail the checks: a stress test of the invariants at several targets.
TEST(Qem, NoisyMeshesStayCleanAtEveryTarget) {
    std::uint64_t state = 42;
    auto noise = [&] {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return static_cast<double>(state >> 11) * 0x1.0p-53 - 0.5;
    };
    PolygonMesh sphere = testing::icosphere(4);
    for (Vec3& p : sphere.positions) p *= 1.0 + 0.05 * noise();
    PolygonMesh terrain = shapes::grid(40, 40, true);
    // Noise of 20% of the grid spacing tilts input normals by up to ~20 degrees. (At noise comparable to the spacing,
    // the input's own normals point anywhere and "flipped relative to the surface" stops being well defined: the
    // checks are relative to the input's faces.)
    for (Vec3& p : terrain.positions) p.z = 0.005 * noise() + 0.1 * std::sin(6 * p.x) * std::cos(5 * p.y);
    for (const PolygonMesh* mesh : {&sphere, &terrain})
        for (double ratio : {0.5, 0.1, 0.02})
            for (bool lock : {false, true}) {
                SimplifyOptions options;
                options.ratio = ratio;
                options.lock_border = lock;
                auto out = simplify_qem(*mesh, options);
                ASSERT_TRUE(out.ok());
                const std::string what = std::string(mesh == &sphere ? "sphere" : "terrain") + " ratio " +
                                         std::to_string(ratio) + (lock ? " locked" : "");
                expect_clean(out->mesh, *mesh, what);
                EXPECT_EQ(boundary_loop_count(out->mesh), boundary_loop_count(*mesh)) << what;
                if (mesh == &sphere) {
                    EXPECT_TRUE(testing::is_watertight(out->mesh)) << what;
                }
                if (lock && mesh == &terrain) {
                    EXPECT_EQ(testing::boundary_positions(out->mesh), testing::boundary_positions(*mesh)) << what;
                }
            }
}

TEST(Qem, ZeroAreaInputTrianglesAreCollapsedAway) {
    // A bumpy grid where six triangles are made exactly degenerate (a corner moved onto the opposite edge): their
    // edges cost nothing, so they go first, and no collapse may create another one.
    PolygonMesh mesh = shapes::grid(12, 12, true);
    for (Vec3& p : mesh.positions) p.z = 0.2 * std::sin(3 * p.x) * std::cos(2 * p.y);
    for (std::size_t f = 0, made = 0; f < mesh.face_count() && made < 10; f += 23, ++made) {
        auto t = mesh.face(f);
        mesh.positions[t[0]] = (mesh.positions[t[1]] + mesh.positions[t[2]]) * 0.5;
    }
    ASSERT_GT(testing::degenerate_faces(mesh), 0u);
    for (double ratio : {0.9, 0.5, 0.1}) {
        SimplifyOptions options;
        options.ratio = ratio;
        auto out = simplify_qem(mesh, options);
        ASSERT_TRUE(out.ok());
        expect_clean(out->mesh, mesh, "zero-area input, ratio " + std::to_string(ratio));
    }
}

TEST(Qem, CadExportWithSliversAndZeroAreaCapsComesOutClean) {
    // CAD-style cylinders (needle fans, full-height strips, T-junctions closed by zero-area faces): every target
    // removes the zero-area faces and makes none
    for (const bool open : {false, true}) {
        const PolygonMesh mesh = testing::cad_cylinder(96, 40, open);
        ASSERT_GE(testing::degenerate_faces(mesh), 40u);
        for (double ratio : {0.9, 0.5, 0.2}) {
            SimplifyOptions options;
            options.ratio = ratio;
            auto out = simplify_qem(mesh, options);
            ASSERT_TRUE(out.ok()) << out.error().message;
            expect_clean(out->mesh, mesh,
                         std::string("cad cylinder") + (open ? " open" : "") + ", ratio " + std::to_string(ratio));
        }
    }
}

TEST(Qem, ScannedBunnyToFivePercent) {
    const PolygonMesh input = bunny();
    ASSERT_GT(input.face_count(), 60000u);
    const double diagonal = input.bounds().diagonal();
    SimplifyOptions options;
    options.ratio = 0.05;
    auto out = simplify_qem(input, options);
    ASSERT_TRUE(out.ok()) << out.error().message;
    EXPECT_LE(out->faces, input.face_count() / 20);
    EXPECT_GE(out->faces, input.face_count() / 20 - 20);
    expect_clean(out->mesh, input, "bunny 5%");
    EXPECT_EQ(boundary_loop_count(out->mesh), boundary_loop_count(input));
    const MeshDistance d = mesh_distance(input, out->mesh);
    EXPECT_LT(d.hausdorff / diagonal, 0.01);
    EXPECT_LT(d.rms / diagonal, 0.001);
    std::printf("bunny %zu -> %zu faces: Hausdorff %.3g (%.3g of diagonal), RMS %.3g, estimate %.3g\n",
                input.face_count(), out->faces, d.hausdorff, d.hausdorff / diagonal, d.rms, out->achieved_error);
}

TEST(Qem, ScannedBunnyWithMaxErrorAndLockedBorder) {
    const PolygonMesh input = bunny();
    ASSERT_GT(input.face_count(), 0u);
    const double max_error = 0.002 * input.bounds().diagonal();
    for (int threads : {1, 2}) {
        SimplifyOptions options;
        options.max_error = max_error;
        options.lock_border = true;
        options.threads = threads;
        auto out = simplify_qem(input, options);
        ASSERT_TRUE(out.ok());
        EXPECT_LE(out->achieved_error, max_error);
        EXPECT_LT(out->faces, input.face_count() / 3);
        expect_clean(out->mesh, input, "bunny max_error, threads " + std::to_string(threads));
        EXPECT_EQ(testing::boundary_positions(out->mesh), testing::boundary_positions(input));
        EXPECT_EQ(boundary_loop_count(out->mesh), boundary_loop_count(input));
    }
}

// A large closed mesh to 1%: counts and invariants at scale (speed is bench/simplify_bench.cpp's business).
TEST(Qem, LargeSphereToOnePercentStaysClean) {
    const PolygonMesh sphere = testing::icosphere(7);  // 327680 faces
    SimplifyOptions options;
    options.ratio = 0.01;
    auto out = simplify_qem(sphere, options);
    ASSERT_TRUE(out.ok());
    EXPECT_LE(out->faces, 3277u);
    EXPECT_GE(out->faces, 3270u);
    EXPECT_TRUE(testing::is_watertight(out->mesh));
    EXPECT_EQ(edge_stats(out->mesh).non_manifold_edges, 0u);
    EXPECT_EQ(testing::duplicate_faces(out->mesh), 0u);
}

// Quality floor on a 1%-of-the-faces run (Hausdorff 2.1e-3, RMS 7.5e-4 of the diagonal, with some margin): guards
// the simplifier's speed-oriented parts (polynomial fallback placement, heap, adjacency lists) against trading quality.
TEST(Qem, SphereQualityAtOnePercentStaysAtItsMeasuredLevel) {
    const PolygonMesh sphere = testing::icosphere(6);  // 81920 faces
    SimplifyOptions options;
    options.ratio = 0.01;
    auto out = simplify_qem(sphere, options);
    ASSERT_TRUE(out.ok());
    EXPECT_LE(out->faces, 819u);
    EXPECT_GE(out->faces, 817u);
    EXPECT_TRUE(testing::is_watertight(out->mesh));
    expect_clean(out->mesh, sphere, "icosphere 6 to 1%");
    const double diagonal = sphere.bounds().diagonal();
    const MeshDistance d = mesh_distance(sphere, out->mesh);
    EXPECT_LT(d.hausdorff / diagonal, 3.0e-3);
    EXPECT_LT(d.rms / diagonal, 8.0e-4);
}

// Two spheres sharing one vertex: the vertex has two closed fans (edge-manifold, not vertex-manifold). Its one-ring
// is the union of both fans; collapses next to it must still keep every edge manifold and both spheres closed.
TEST(Qem, VertexWithTwoClosedFansStaysClean) {
    const PolygonMesh a = testing::icosphere(2);  // 162 vertices, 320 faces
    const Index pinch = 0;
    PolygonMesh mesh = a;
    const Vec3 offset = a.positions[pinch] * 2.0;  // the second sphere touches the first at vertex 0, mirrored
    std::vector<Index> remap(a.vertex_count());
    for (std::size_t v = 0; v < a.vertex_count(); ++v) {
        if (v == pinch) {
            remap[v] = pinch;
            continue;
        }
        remap[v] = static_cast<Index>(mesh.positions.size());
        mesh.positions.push_back(offset - a.positions[v]);  // point reflection keeps it outside the first sphere
    }
    for (std::size_t f = 0; f < a.face_count(); ++f) {
        auto t = a.face(f);
        mesh.add_face({remap[t[0]], remap[t[2]], remap[t[1]]});  // reflection flips orientation: reverse it back
    }
    ASSERT_EQ(mesh.vertex_count(), 2 * a.vertex_count() - 1);
    ASSERT_EQ(edge_stats(mesh).non_manifold_edges, 0u);
    for (std::size_t faces : {400u, 100u, 20u}) {
        auto out = simplify_qem(mesh, target(faces));
        ASSERT_TRUE(out.ok()) << out.error().message;
        expect_clean(out->mesh, mesh, "two fans to " + std::to_string(faces));
        EXPECT_TRUE(testing::is_watertight(out->mesh)) << faces;
        EXPECT_LE(out->faces, std::max<std::size_t>(faces, 8));
    }
}

TEST(Qem, RefusesNonManifoldInputNamingTheEdge) {
    PolygonMesh fin;  // three triangles on edge (0, 1)
    fin.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
    fin.add_face({0, 1, 2});
    fin.add_face({1, 0, 3});
    fin.add_face({0, 1, 4});
    auto out = simplify_qem(fin, target(1));
    ASSERT_FALSE(out.ok());
    EXPECT_EQ(out.error().code, ErrorCode::NonManifold);
    EXPECT_NE(out.error().message.find("(0, 1)"), std::string::npos) << out.error().message;
    EXPECT_EQ(out.error().element_kind, ElementKind::Face);
}

TEST(Qem, RefusesInconsistentOrientation) {
    PolygonMesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
    mesh.add_face({0, 1, 2});
    mesh.add_face({1, 2, 3});  // traverses (1, 2) in the same direction as face 0
    auto out = simplify_qem(mesh, target(1));
    ASSERT_FALSE(out.ok());
    EXPECT_EQ(out.error().code, ErrorCode::NonManifold);
}

TEST(Qem, RejectsBadOptions) {
    const PolygonMesh sphere = testing::icosphere(1);
    EXPECT_EQ(simplify_qem(sphere, SimplifyOptions{}).error().code, ErrorCode::InvalidArgument);
    SimplifyOptions ratio;
    ratio.ratio = 1.5;
    EXPECT_EQ(simplify_qem(sphere, ratio).error().code, ErrorCode::InvalidArgument);
    SimplifyOptions error;
    error.max_error = -1;
    EXPECT_EQ(simplify_qem(sphere, error).error().code, ErrorCode::InvalidArgument);
    SimplifyOptions locked = target(10);
    locked.locked_vertices = {1000};
    EXPECT_EQ(simplify_qem(sphere, locked).error().code, ErrorCode::IndexOutOfRange);
    SimplifyOptions threads = target(10);
    threads.threads = 0;
    EXPECT_EQ(simplify_qem(sphere, threads).error().code, ErrorCode::InvalidArgument);
}

TEST(Qem, TetrahedronCannotCollapseFurther) {
    // every collapse of a tetrahedron would leave two faces back to back: the duplicate-face check stops it
    auto out = simplify_qem(shapes::tetrahedron(), target(0));
    ASSERT_TRUE(out.ok());
    EXPECT_EQ(out->faces, 4u);
    EXPECT_EQ(out->achieved_error, 0);
}

TEST(Qem, OctahedronStopsAtATetrahedronAtMost) {
    auto out = simplify_qem(shapes::octahedron(), target(0));
    ASSERT_TRUE(out.ok());
    EXPECT_GE(out->faces, 4u);
    expect_clean(out->mesh, shapes::octahedron(), "octahedron");
    EXPECT_TRUE(testing::is_watertight(out->mesh));
}

TEST(Qem, TriangleSoupHasNothingToCollapse) {
    // every collapse would leave a vertex without faces; the heap holds only current, invalid entries
    PolygonMesh soup;
    for (Index i = 0; i < 3000; ++i) {
        const double x = i % 100, y = i / 100;
        soup.positions.push_back({x, y, 0});
        soup.positions.push_back({x + 0.5, y, 0});
        soup.positions.push_back({x, y + 0.5, 0.25});
        soup.add_face({3 * i, 3 * i + 1, 3 * i + 2});
    }
    auto out = simplify_qem(soup, target(10));
    ASSERT_TRUE(out.ok()) << out.error().message;
    EXPECT_EQ(out->faces, soup.face_count());
    EXPECT_EQ(out->mesh.positions, soup.positions);
    EXPECT_EQ(out->mesh.face_indices, soup.face_indices);
}

TEST(Qem, IsDeterministic) {
    const PolygonMesh sphere = testing::icosphere(4);
    auto a = simplify_qem(sphere, target(300));
    auto b = simplify_qem(sphere, target(300));
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_EQ(a->mesh.face_indices, b->mesh.face_indices);
    ASSERT_EQ(a->mesh.positions.size(), b->mesh.positions.size());
    for (std::size_t i = 0; i < a->mesh.positions.size(); ++i) EXPECT_EQ(a->mesh.positions[i], b->mesh.positions[i]);
}

// With a BlockPool, arrays of 1 MiB and more are kept for the next simplification: a run on reused blocks, which still
// hold another mesh's data, gives the result of a run on fresh memory (the first run, without a pool).
TEST(Qem, IsDeterministicOnReusedMemory) {
    const PolygonMesh sphere = testing::icosphere(6);  // 81,920 triangles: several arrays of megabytes
    const PolygonMesh torus = triangulate(shapes::torus(256, 128));
    SimplifyOptions options;
    options.ratio = 0.02;
    const auto first = simplify_qem(sphere, options);
    ASSERT_TRUE(first.ok());
    BlockPool pool(std::size_t{64} << 20);
    options.block_pool = &pool;
    for (int round = 0; round < 2; ++round) {
        SCOPED_TRACE(round);
        ASSERT_TRUE(simplify_qem(torus, options).ok());  // the blocks now hold the torus's data
        const std::size_t reused = pool.reused_blocks();
        auto again = simplify_qem(sphere, options);
        ASSERT_TRUE(again.ok());
        if (pool.max_bytes() > 0) {  // (AddressSanitizer: the pool keeps nothing)
            EXPECT_GT(pool.reused_blocks(), reused);
        }
        EXPECT_EQ(again->mesh.face_indices, first->mesh.face_indices);
        EXPECT_EQ(again->mesh.positions, first->mesh.positions);
        EXPECT_EQ(again->achieved_error, first->achieved_error);
    }
}

// threads = 2: the two spatial halves collapse at once before the rest in global order. Same guarantees, errors
// within a few percent of one thread's, a result that depends on nothing but the input (run twice: the same), and
// not one thread's result (else the first phase did not run and the test would prove nothing).
TEST(Qem, TwoThreadsKeepTheGuaranteesAndTheQualityOfOne) {
    struct Case {
        std::string name;
        PolygonMesh mesh;
        double ratio;
    };
    std::vector<Case> cases;
    cases.push_back({"bunny 5%", bunny(), 0.05});
    cases.push_back({"icosphere 6 1%", testing::icosphere(6), 0.01});
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        ASSERT_GT(c.mesh.face_count(), 60000u);
        SimplifyOptions options;
        options.ratio = c.ratio;
        auto one = simplify_qem(c.mesh, options);
        options.threads = 2;
        auto two = simplify_qem(c.mesh, options);
        auto again = simplify_qem(c.mesh, options);
        ASSERT_TRUE(one.ok() && two.ok() && again.ok());
        const auto target = static_cast<std::size_t>(c.ratio * static_cast<double>(c.mesh.face_count()));
        EXPECT_LE(two->faces, target);
        EXPECT_GE(two->faces, target - 2);
        expect_clean(two->mesh, c.mesh, c.name + ", 2 threads");
        EXPECT_EQ(boundary_loop_count(two->mesh), boundary_loop_count(c.mesh));
        EXPECT_EQ(two->mesh.face_indices, again->mesh.face_indices);
        EXPECT_EQ(two->mesh.positions, again->mesh.positions);
        EXPECT_NE(two->mesh.positions, one->mesh.positions);
        const MeshDistance d1 = mesh_distance(c.mesh, one->mesh), d2 = mesh_distance(c.mesh, two->mesh);
        EXPECT_LT(d2.rms, 1.05 * d1.rms);
        EXPECT_LT(d2.hausdorff, 1.3 * d1.hausdorff);
        std::printf("%s: RMS %.3g (one thread %.3g), Hausdorff %.3g (%.3g)\n", c.name.c_str(), d2.rms, d1.rms,
                    d2.hausdorff, d1.hausdorff);
    }
}

// (max_error and lock_border with two threads: ScannedBunnyWithMaxErrorAndLockedBorder)
TEST(Qem, TwoThreadsWithVolumeRestoration) {
    const PolygonMesh sphere = testing::icosphere(6);
    SimplifyOptions plain = target(819);
    SimplifyOptions restoring = plain;
    restoring.restore_volume = 0.5;
    restoring.threads = 2;
    auto a = simplify_qem(sphere, plain), b = simplify_qem(sphere, restoring);
    ASSERT_TRUE(a.ok() && b.ok());
    expect_clean(b->mesh, sphere, "icosphere 6, restore_volume 0.5, 2 threads");
    EXPECT_LT(mesh_distance(sphere, b->mesh).rms, 0.9 * mesh_distance(sphere, a->mesh).rms);
}

// Below 20,000 triangles threads = 2 runs on one thread: the same result as threads = 1.
TEST(Qem, TwoThreadsOnSmallMeshesAreOneThread) {
    for (const PolygonMesh& mesh : {testing::icosphere(4), testing::uv_cylinder(96, 64)}) {
        SimplifyOptions options;
        options.ratio = 0.1;
        auto one = simplify_qem(mesh, options);
        options.threads = 2;
        auto two = simplify_qem(mesh, options);
        ASSERT_TRUE(one.ok() && two.ok());
        EXPECT_EQ(one->mesh.face_indices, two->mesh.face_indices);
        EXPECT_EQ(one->mesh.positions, two->mesh.positions);
        EXPECT_EQ(one->mesh.uv_indices, two->mesh.uv_indices);
        ASSERT_EQ(one->mesh.uvs.size(), two->mesh.uvs.size());
        for (std::size_t i = 0; i < one->mesh.uvs.size(); ++i) {
            EXPECT_EQ(one->mesh.uvs[i].x, two->mesh.uvs[i].x);
            EXPECT_EQ(one->mesh.uvs[i].y, two->mesh.uvs[i].y);
        }
    }
}

}  // namespace
}  // namespace surfaced
