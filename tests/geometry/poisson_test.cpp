// Screened Poisson reconstruction (geometry/reconstruct/poisson.h): clouds sampled from a sphere, a torus and a cube
// (with and without noise) reconstructed and compared with the true surface: Hausdorff and RMS distances (analytic
// for the sphere and torus, against the cube mesh otherwise), volume, watertight and manifold output oriented
// outwards, Euler characteristic; determinism; option errors; cancellation; the size estimate.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <functional>
#include <random>

#include "geometry/mesh/shapes.h"
#include "geometry/pointcloud/sampling.h"
#include "geometry/reconstruct/poisson.h"
#include "geometry/reconstruct/poisson_system.h"
#include "geometry/simplify/mesh_distance.h"
#include "tests/support/mesh_asserts.h"

namespace surfaced {
namespace {

constexpr double kPi = 3.14159265358979323846;

//! Area-uniform points on a sphere of radius r at the origin with exact normals; `noise`: Gaussian offsets of that
//! standard deviation along each coordinate.
PointCloud sphere_cloud(std::size_t n, double r, double noise, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> g;
    PointCloud cloud;
    while (cloud.size() < n) {
        const Vec3 d{g(rng), g(rng), g(rng)};
        const double len = norm(d);
        if (len < 1e-9) continue;
        const Vec3 normal = d * (1.0 / len);
        cloud.positions.push_back(normal * r + Vec3{g(rng), g(rng), g(rng)} * noise);
        cloud.normals.push_back(normal);
    }
    return cloud;
}

//! Area-uniform points on the torus with radii R, r around the z axis (rejection on the area element R + r cos v).
PointCloud torus_cloud(std::size_t n, double R, double r, double noise, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    std::normal_distribution<double> g;
    PointCloud cloud;
    while (cloud.size() < n) {
        const double u = 2 * kPi * u01(rng), v = 2 * kPi * u01(rng);
        if (u01(rng) * (R + r) > R + r * std::cos(v)) continue;
        const Vec3 normal{std::cos(v) * std::cos(u), std::cos(v) * std::sin(u), std::sin(v)};
        const Vec3 p{(R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u), r * std::sin(v)};
        cloud.positions.push_back(p + Vec3{g(rng), g(rng), g(rng)} * noise);
        cloud.normals.push_back(normal);
    }
    return cloud;
}

struct SurfaceError {
    double hausdorff = 0, rms = 0;
};

//! Two-sided distance between the mesh and an analytic surface: the distance function at the mesh's vertices and
//! area samples, and the distance from exact surface samples (`truth`) to the mesh.
SurfaceError analytic_error(const PolygonMesh& mesh, const std::function<double(const Vec3&)>& distance,
                            const PointCloud& truth) {
    SurfaceError e;
    double sum = 0;
    std::size_t count = 0;
    auto add = [&](double d) {
        e.hausdorff = std::max(e.hausdorff, d);
        sum += d * d;
        ++count;
    };
    for (const Vec3& p : mesh.positions) add(std::abs(distance(p)));
    MeshSamplingOptions so;
    so.count = 20'000;
    const Result<PointCloud> on_mesh = sample_mesh(mesh, so);
    EXPECT_TRUE(on_mesh.ok());
    if (on_mesh)
        for (const Vec3& p : on_mesh->positions) add(std::abs(distance(p)));
    const SurfaceDistance to_mesh(mesh);
    for (const Vec3& p : truth.positions) add(to_mesh.distance(p));
    e.rms = std::sqrt(sum / static_cast<double>(count));
    return e;
}

double sphere_distance(const Vec3& p) { return norm(p) - 1.0; }
double torus_distance(const Vec3& p) {
    const double q = std::hypot(p.x, p.y) - 1.0;
    return std::hypot(q, p.z) - 0.4;
}

void expect_closed_outward(const PolygonMesh& mesh, std::int64_t euler) {
    ASSERT_GT(mesh.face_count(), 0u);
    EXPECT_TRUE(mesh.is_triangle_mesh());
    EXPECT_TRUE(testing::is_watertight(mesh));
    EXPECT_EQ(testing::non_manifold_vertices(mesh), 0u);
    EXPECT_EQ(testing::euler_characteristic(mesh), euler);
}

//! The solve and the meshing alone: the iso-surface as meshed, without the fit of its vertices to the samples (whose
//! effect reconstruct_quality_test.cpp measures), so that the distances below are the indicator function's.
PoissonOptions options_at(int depth) {
    PoissonOptions o;
    o.depth = depth;
    o.fit_to_samples = false;
    return o;
}

//! The cell size of the finest level for a cloud whose bounding box's largest side is `extent`.
double cell_size(double extent, int depth) { return extent * PoissonOptions{}.scale / std::ldexp(1.0, depth); }

void expect_sphere(const PointCloud& cloud, const PoissonOptions& options, double hausdorff, double rms) {
    const Result<PoissonResult> r = reconstruct_poisson(cloud, options);
    ASSERT_TRUE(r.ok()) << r.error().message;
    expect_closed_outward(r->mesh, 2);
    const SurfaceError e = analytic_error(r->mesh, sphere_distance, sphere_cloud(5000, 1.0, 0, 99));
    EXPECT_LE(e.hausdorff, hausdorff);
    EXPECT_LE(e.rms, rms);
    EXPECT_NEAR(testing::signed_volume(r->mesh), 4.0 / 3.0 * kPi, 0.005 * 4.0 / 3.0 * kPi);
}

// Measured (depth 5 / 6): Hausdorff 0.13 / 0.16 cells, RMS 0.031 / 0.021 cells, volume 0.11% / 0.01% under.
TEST(Poisson, SphereWithinAQuarterCell) {
    for (int depth : {5, 6}) {
        SCOPED_TRACE(depth);
        const double h = cell_size(2.0, depth);
        expect_sphere(sphere_cloud(40'000, 1.0, 0.0, 3), options_at(depth), 0.2 * h, 0.035 * h);
    }
}

// Gaussian noise of 1% of the radius per coordinate: the surface stays within 2 sigma (measured Hausdorff 0.0098,
// RMS 0.0022 at depth 6).
TEST(Poisson, NoisySphereWithinTwoSigma) {
    expect_sphere(sphere_cloud(40'000, 1.0, 0.01, 3), options_at(6), 0.02, 0.004);
}

// Dirichlet conditions (chi = 0 on the cube, 0.1 from the sphere) pull the surface a little towards the faces:
// measured at depth 5 Hausdorff 0.24 cells, RMS 0.052 cells.
TEST(Poisson, SphereWithDirichletBoundary) {
    PoissonOptions o = options_at(6);
    o.boundary = PoissonBoundary::Dirichlet;
    o.depth = 5;
    const double h = cell_size(2.0, 5);
    expect_sphere(sphere_cloud(40'000, 1.0, 0.0, 3), o, 0.3 * h, 0.06 * h);
}

// Genus 1: Euler characteristic 0. Measured at depth 6: Hausdorff 0.16 cells, RMS 0.023 cells, volume 0.06% under.
TEST(Poisson, TorusHasGenusOne) {
    const int depth = 6;
    const Result<PoissonResult> r = reconstruct_poisson(torus_cloud(30'000, 1.0, 0.4, 0.0, 5), options_at(depth));
    ASSERT_TRUE(r.ok()) << r.error().message;
    expect_closed_outward(r->mesh, 0);
    const SurfaceError e = analytic_error(r->mesh, torus_distance, torus_cloud(5000, 1.0, 0.4, 0, 99));
    const double h = cell_size(2.8, depth);
    EXPECT_LE(e.hausdorff, 0.2 * h);
    EXPECT_LE(e.rms, 0.035 * h);
    const double volume = 2 * kPi * kPi * 1.0 * 0.4 * 0.4;
    EXPECT_NEAR(testing::signed_volume(r->mesh), volume, 0.005 * volume);
}

// Sharp edges and corners are rounded over about a cell (the basis is smooth at that scale): measured Hausdorff
// 0.99 cells (at the corners), RMS 0.079 cells, volume 0.24% over.
TEST(Poisson, CubeCornersWithinACell) {
    const int depth = 6;
    MeshSamplingOptions so;
    so.count = 40'000;
    const Result<PointCloud> cloud = sample_mesh(shapes::cube(), so);
    ASSERT_TRUE(cloud.ok());
    const Result<PoissonResult> r = reconstruct_poisson(*cloud, options_at(depth));
    ASSERT_TRUE(r.ok()) << r.error().message;
    expect_closed_outward(r->mesh, 2);
    MeshDistanceOptions mo;
    mo.samples = 20'000;
    const MeshDistance d = mesh_distance(r->mesh, shapes::cube(), mo);
    const double h = cell_size(1.0, depth);
    EXPECT_LE(d.hausdorff, 1.2 * h);
    EXPECT_LE(d.rms, 0.1 * h);
    EXPECT_NEAR(testing::signed_volume(r->mesh), 1.0, 0.01);
}

// 250 points for depth 5 (about 0.06 per finest cell): splatting each sample at the depth where its cells hold
// samples_per_node samples keeps the surface within a cell, where splatting all on the finest level
// (samples_per_node far below the density) raises a bump at every sample. Measured Hausdorff 0.028 against 0.12.
TEST(Poisson, SparseSamplesSplatOnCoarserLevels) {
    const PointCloud cloud = sphere_cloud(250, 1.0, 0.0, 6);
    const PointCloud truth = sphere_cloud(2000, 1.0, 0, 99);
    PoissonOptions o = options_at(5);
    const Result<PoissonResult> adapted = reconstruct_poisson(cloud, o);
    o.samples_per_node = 0.01;  // far below the density anywhere: every sample on the finest level
    const Result<PoissonResult> finest = reconstruct_poisson(cloud, o);
    ASSERT_TRUE(adapted.ok() && finest.ok());
    expect_closed_outward(adapted->mesh, 2);
    const SurfaceError a = analytic_error(adapted->mesh, sphere_distance, truth);
    const SurfaceError f = analytic_error(finest->mesh, sphere_distance, truth);
    EXPECT_LT(a.hausdorff, 0.5 * f.hausdorff);
    EXPECT_LT(a.hausdorff, cell_size(2.0, 5));
}

// Depth 9 on two small spheres 20 radii apart (400 points each): a dense grid over the cube would take 513^3 nodes
// (540 MB at 4 bytes each) for ~2 x 10^4 surface cells. The sparse extraction's tables stay near the surface, the
// output is two closed, manifold, outward spheres, and where the finest level does not reach (samples about 2 cells
// apart on average, splatted coarser) the surface is extracted inside coarser leaves on the finest grid all the same.
TEST(Poisson, SparseExtractionAtDepthNine) {
    const int depth = 9;
    PointCloud cloud = sphere_cloud(400, 1.0, 0.0, 11);
    const PointCloud other = sphere_cloud(400, 1.0, 0.0, 12);
    for (Vec3& p : cloud.positions) p.x -= 10;
    for (std::size_t i = 0; i < other.size(); ++i) {
        cloud.positions.push_back(other.positions[i] + Vec3{10, 0, 0});
        cloud.normals.push_back(other.normals[i]);
    }
    const Result<PoissonResult> r = reconstruct_poisson(cloud, options_at(depth));
    ASSERT_TRUE(r.ok()) << r.error().message;
    expect_closed_outward(r->mesh, 4);
    const double dense_grid_bytes = 4 * std::pow(std::ldexp(1.0, depth) + 1, 3);
    EXPECT_LT(static_cast<double>(r->stats.extraction_bytes), dense_grid_bytes / 64);
    // coarse leaves were meshed: node values interpolated there
    EXPECT_GT(r->stats.field_evaluations, 0u);
    EXPECT_NEAR(testing::signed_volume(r->mesh), 2 * 4.0 / 3.0 * kPi, 0.03 * 2 * 4.0 / 3.0 * kPi);
}

// A second thread for the assembly passes, the splats (even and odd levels), the interpolation between levels (rows
// by parity), the conjugate gradients and the marching cubes (two halves of the cells) changes nothing: every row
// is summed alone and in the same order, sums are taken over fixed chunks, and the meshing's cut depends on the
// cells alone; the fit to the samples moves each vertex by its own position alone. 70,000 samples: above the size at
// which the per-sample passes take a second thread.
TEST(Poisson, BitIdenticalWithTwoThreads) {
    const PointCloud cloud = sphere_cloud(70'000, 1.0, 0.0, 12);
    PoissonOptions o = options_at(8);
    o.fit_to_samples = true;  // and the fit's two halves of the vertices
    const Result<PoissonResult> one = reconstruct_poisson(cloud, o);
    o.threads = 2;
    const Result<PoissonResult> two = reconstruct_poisson(cloud, o);
    ASSERT_TRUE(one.ok() && two.ok());
    ASSERT_GE(one->stats.dofs.back(), 65'536u);  // large enough for the second thread
    EXPECT_EQ(one->iso_value, two->iso_value);
    ASSERT_EQ(one->mesh.positions.size(), two->mesh.positions.size());
    for (std::size_t i = 0; i < one->mesh.positions.size(); ++i)
        ASSERT_EQ(one->mesh.positions[i], two->mesh.positions[i]);
    EXPECT_EQ(one->mesh.face_indices, two->mesh.face_indices);
}

TEST(Poisson, DeterministicAcrossRuns) {
    const PointCloud cloud = torus_cloud(4000, 1.0, 0.4, 0.02, 8);
    const Result<PoissonResult> a = reconstruct_poisson(cloud, options_at(5));
    const Result<PoissonResult> b = reconstruct_poisson(cloud, options_at(5));
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_EQ(a->iso_value, b->iso_value);
    ASSERT_EQ(a->mesh.positions.size(), b->mesh.positions.size());
    for (std::size_t i = 0; i < a->mesh.positions.size(); ++i) ASSERT_EQ(a->mesh.positions[i], b->mesh.positions[i]);
    EXPECT_EQ(a->mesh.face_indices, b->mesh.face_indices);
}

// Confidence = normal length: scaling every normal alike changes nothing, and zero-length normals drop the point.
TEST(Poisson, ConfidenceWeights) {
    const PointCloud clean = sphere_cloud(4000, 1.0, 0.0, 4);
    PointCloud weighted = clean;
    for (Vec3& n : weighted.normals) n *= 3.0;
    for (int i = 0; i < 200; ++i) {  // inside the bounding box, pointing inwards, without weight
        weighted.positions.push_back(Vec3{0.3, -0.2, 0.1} * (i / 200.0));
        weighted.normals.push_back({0, 0, 0});
    }
    PoissonOptions o = options_at(5);
    const Result<PoissonResult> plain = reconstruct_poisson(clean, o);
    o.use_confidence = true;
    const Result<PoissonResult> conf = reconstruct_poisson(weighted, o);
    ASSERT_TRUE(plain.ok() && conf.ok());
    // the same system up to rounding (chi agrees to ~1e-12; the mesher's vertex placement may amplify that a little)
    EXPECT_NEAR(plain->iso_value, conf->iso_value, 1e-9);
    MeshDistanceOptions mo;
    mo.samples = 5000;
    EXPECT_LT(mesh_distance(plain->mesh, conf->mesh, mo).hausdorff, 0.02 * cell_size(2.0, 5));
}

TEST(Poisson, RejectsBadInput) {
    PointCloud cloud = sphere_cloud(100, 1.0, 0.0, 1);
    PointCloud no_normals = cloud;
    no_normals.normals.clear();
    EXPECT_EQ(reconstruct_poisson(no_normals, {}).error().code, ErrorCode::InvalidArgument);
    PointCloud zero = cloud;
    zero.normals[7] = {0, 0, 0};
    const Result<PoissonResult> z = reconstruct_poisson(zero, {});
    ASSERT_FALSE(z.ok());
    EXPECT_EQ(z.error().element, 7);
    PointCloud same(cloud);
    for (Vec3& p : same.positions) p = {1, 2, 3};
    EXPECT_EQ(reconstruct_poisson(same, {}).error().code, ErrorCode::InvalidArgument);
    PointCloud nan = cloud;
    nan.positions[3].x = std::nan("");
    EXPECT_FALSE(reconstruct_poisson(nan, {}).ok());
    for (int depth : {1, 11})
        EXPECT_EQ(reconstruct_poisson(cloud, options_at(depth)).error().code, ErrorCode::InvalidArgument);
    PoissonOptions o;
    o.point_weight = -1;
    EXPECT_EQ(reconstruct_poisson(cloud, o).error().code, ErrorCode::InvalidArgument);
    o = {};
    o.scale = 0.5;
    EXPECT_EQ(reconstruct_poisson(cloud, o).error().code, ErrorCode::InvalidArgument);
    o = {};
    o.samples_per_node = 0;
    EXPECT_EQ(reconstruct_poisson(cloud, o).error().code, ErrorCode::InvalidArgument);
}

TEST(Poisson, Cancelled) {
    std::atomic<bool> stop{true};
    Cancel cancel;
    cancel.flag = &stop;
    const Result<PoissonResult> r = reconstruct_poisson(sphere_cloud(1000, 1.0, 0.0, 2), options_at(5), cancel);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, ErrorCode::Cancelled);
}

// The prediction for a sphere filling the cube is within a factor 2 of the octree actually built and of the cells
// the surface crosses.
TEST(Poisson, SizeEstimate) {
    const PointCloud cloud = sphere_cloud(15'000, 1.0, 0.0, 3);
    for (int depth : {5, 6}) {
        const Result<PoissonResult> r = reconstruct_poisson(cloud, options_at(depth));
        ASSERT_TRUE(r.ok());
        std::size_t cells = 0;
        for (std::size_t c : r->stats.cells) cells += c;
        const PoissonEstimate e = estimate_poisson(cloud.size(), options_at(depth));
        EXPECT_GT(static_cast<double>(e.octree_cells), 0.5 * static_cast<double>(cells)) << depth;
        EXPECT_LT(static_cast<double>(e.octree_cells), 2.0 * static_cast<double>(cells)) << depth;
        // the surface cells the extraction meshes (no dense grid): for this sphere, 0.83 of the assumed area
        EXPECT_GT(static_cast<double>(e.grid_cells), 0.5 * static_cast<double>(r->stats.surface_cells)) << depth;
        EXPECT_LT(static_cast<double>(e.grid_cells), 2.0 * static_cast<double>(r->stats.surface_cells)) << depth;
    }
    EXPECT_GT(estimate_poisson(1'000'000, options_at(9)).bytes, estimate_poisson(1'000'000, options_at(8)).bytes);
    // no dense grid: a small cloud at depth 10 is predicted well below the 4 bytes per node (4.3 GB) it alone took
    EXPECT_LT(static_cast<double>(estimate_poisson(3000, options_at(10)).bytes), 0.25 * 4 * std::pow(1025.0, 3));
}

// A plane sampled four times as densely on one half as on the other: away from the seam and the plane's edges (more
// than the density kernel's two cells), each dense sample stands for a quarter of a sparse one's area, and the
// shares sum to the area.
TEST(Poisson, AreaSharesFollowInverseDensity) {
    reconstruct::OrientedSamples samples;
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int i = 0; i < 50'000; ++i) {
        const double x = i < 40'000 ? 0.5 * u(rng) : 0.5 + 0.5 * u(rng);
        samples.positions.push_back({x, u(rng), 0.5});
        samples.normals.push_back({0, 0, 1});
        samples.weights.push_back(1.0);
        samples.weight_sum += 1.0;
    }
    samples.area = 1.0;
    reconstruct::assign_area_shares(samples, 4);
    ASSERT_EQ(samples.area_shares.size(), samples.positions.size());
    double sum = 0, dense = 0, sparse = 0;
    int dense_count = 0, sparse_count = 0;
    for (std::size_t i = 0; i < samples.positions.size(); ++i) {
        sum += samples.area_shares[i];
        const Vec3& p = samples.positions[i];
        if (p.y < 0.125 || p.y > 0.875) continue;
        if (p.x > 0.125 && p.x < 0.375) {
            dense += samples.area_shares[i];
            ++dense_count;
        } else if (p.x > 0.625 && p.x < 0.875) {
            sparse += samples.area_shares[i];
            ++sparse_count;
        }
    }
    EXPECT_NEAR(sum, 1.0, 1e-9);
    ASSERT_GT(dense_count, 0);
    ASSERT_GT(sparse_count, 0);
    EXPECT_NEAR((sparse / sparse_count) / (dense / dense_count), 4.0, 0.2);
}

}  // namespace
}  // namespace surfaced
