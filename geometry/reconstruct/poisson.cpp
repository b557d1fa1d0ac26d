#include "geometry/reconstruct/poisson.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <type_traits>
#include <utility>

#include "geometry/reconstruct/extract_surface.h"
#include "geometry/reconstruct/fit_to_samples.h"
#include "geometry/reconstruct/octree.h"
#include "geometry/reconstruct/poisson_system.h"
#include "geometry/reconstruct/solver.h"

namespace surfaced {
namespace {

using reconstruct::OrientedSamples;

// The coarsest octree level (4 cells per side), complete over the cube.
constexpr int kMinDepth = 2;
// The sampling density that weights the samples' normals and sets their splatting depths is measured this many levels
// above the finest.
constexpr int kDensityLevels = 1;
// Cells a plane crosses per unit area in a grid of unit cells, averaged over orientations: E|nx|+|ny|+|nz| = 1.5.
constexpr double kCellsPerArea = 1.5;

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

Status check_options(const PoissonOptions& o) {
    if (o.depth < 2 || o.depth > 10) return make_error(ErrorCode::InvalidArgument, "poisson: depth must be in 2..10");
    if (!std::isfinite(o.point_weight) || o.point_weight < 0)
        return make_error(ErrorCode::InvalidArgument, "poisson: point_weight must be finite and >= 0");
    if (!std::isfinite(o.samples_per_node) || o.samples_per_node <= 0)
        return make_error(ErrorCode::InvalidArgument, "poisson: samples_per_node must be finite and > 0");
    if (!std::isfinite(o.scale) || o.scale < 1 || o.scale > 100)
        return make_error(ErrorCode::InvalidArgument, "poisson: scale must be in [1, 100]");
    if (o.max_iterations < 1 || o.max_iterations > 100000)
        return make_error(ErrorCode::InvalidArgument, "poisson: max_iterations must be in 1..100000");
    if (!std::isfinite(o.tolerance) || o.tolerance < 0 || o.tolerance >= 1)
        return make_error(ErrorCode::InvalidArgument, "poisson: tolerance must be in [0, 1)");
    if (o.threads < 0) return make_error(ErrorCode::InvalidArgument, "poisson: threads must be >= 0");
    return Ok{};
}

//! Area of the sampled surface in unit-cube units, from the cells holding samples on the deepest level where they
//! hold samples_per_node samples each on average. Samples fall into the surface's M cells about like a Poisson
//! process: with lambda = N / M per cell, M (1 - e^-lambda) cells are occupied, which is solved for M.
//! \pre the samples are in Morton order (sort_spatially), so that each cell's samples are consecutive on every level.
double estimate_area(const OrientedSamples& samples, int max_depth, double samples_per_node) {
    const auto n = static_cast<double>(samples.positions.size());
    double area = 0;
    for (int depth = kMinDepth; depth <= max_depth; ++depth) {
        std::size_t runs = 0;  // = occupied cells
        std::uint64_t previous = 0;
        for (std::size_t i = 0; i < samples.positions.size(); ++i) {
            const std::uint64_t cell = reconstruct::cell_key(samples.positions[i], depth);
            runs += i == 0 || cell != previous ? 1 : 0;
            previous = cell;
        }
        const auto occupied = static_cast<double>(runs);
        const double mean = n / occupied;  // = lambda / (1 - e^-lambda), increasing in lambda
        if (depth > kMinDepth && mean < samples_per_node) break;
        double lo = 0, hi = mean;
        for (int it = 0; it < 60; ++it) {
            const double mid = 0.5 * (lo + hi);
            (mid / -std::expm1(-mid) < mean ? lo : hi) = mid;
        }
        // nearly every sample alone in its cell says little about the empty cells: no correction then
        const double cells = mean < 1.05 ? occupied : n / hi;
        area = cells * std::ldexp(1.0, -2 * depth) / kCellsPerArea;
    }
    return area;
}

//! Interleaves the bits of a cell's coordinates (Morton order): cells close in space are close in this order on
//! every level, since a coarser cell's code is the finer one's shifted.
std::uint64_t morton_code(std::uint64_t key) {
    auto spread = [](std::uint64_t x) {
        x &= 0x1fffff;
        x = (x | x << 32) & 0x1f00000000ffffull;
        x = (x | x << 16) & 0x1f0000ff0000ffull;
        x = (x | x << 8) & 0x100f00f00f00f00full;
        x = (x | x << 4) & 0x10c30c30c30c30c3ull;
        x = (x | x << 2) & 0x1249249249249249ull;
        return x;
    };
    return spread(reconstruct::key_i(key)) | spread(reconstruct::key_j(key)) << 1 |
           spread(reconstruct::key_k(key)) << 2;
}

//! Puts the samples in Morton order of their finest cells, so that every per-sample pass of every level (splats,
//! screening, lookups of the samples' cells) walks the level's arrays nearly in order instead of at random. Ties
//! keep the input order, so the result depends on the cloud only.
void sort_spatially(OrientedSamples& samples, int depth) {
    const std::size_t n = samples.positions.size();
    std::vector<std::pair<std::uint64_t, std::uint32_t>> order(n);
    for (std::size_t i = 0; i < n; ++i)
        order[i] = {morton_code(reconstruct::cell_key(samples.positions[i], depth)), static_cast<std::uint32_t>(i)};
    std::sort(order.begin(), order.end());
    auto permute = [&](auto& values) {
        std::remove_reference_t<decltype(values)> sorted(n);
        for (std::size_t i = 0; i < n; ++i) sorted[i] = values[order[i].second];
        values = std::move(sorted);
    };
    permute(samples.positions);
    permute(samples.normals);
    permute(samples.weights);
}

}  // namespace

Result<PoissonResult> reconstruct_poisson(const PointCloud& cloud, const PoissonOptions& options,
                                          const Cancel& cancel) {
    if (Status s = check_options(options); !s) return s.error();
    if (Status s = validate(cloud); !s) return s.error();
    if (!cloud.has_normals())
        return make_error(ErrorCode::InvalidArgument,
                          "poisson: the point cloud has no normals (estimate and orient them first)");

    const auto start = std::chrono::steady_clock::now();
    // samples: weights, unit normals, the bounding cube
    OrientedSamples samples;
    std::vector<Vec3> positions;
    Box3 box;
    for (std::size_t i = 0; i < cloud.size(); ++i) {
        const double length = norm(cloud.normals[i]);
        if (length == 0) {
            if (options.use_confidence) continue;
            return element_error(ErrorCode::InvalidArgument,
                                 "poisson: point " + std::to_string(i) + " has a zero normal", ElementKind::Vertex,
                                 static_cast<std::int64_t>(i));
        }
        positions.push_back(cloud.positions[i]);
        samples.normals.push_back(cloud.normals[i] * (1.0 / length));
        samples.weights.push_back(options.use_confidence ? length : 1.0);
        samples.weight_sum += samples.weights.back();
        box.add(cloud.positions[i]);
    }
    if (positions.size() < 4)
        return make_error(ErrorCode::InvalidArgument, "poisson: fewer than 4 points with a non-zero normal");
    const Vec3 extent = box.max - box.min;
    const double side = std::max({extent.x, extent.y, extent.z}) * options.scale;
    if (!(side > 0) || !std::isfinite(side))
        return make_error(ErrorCode::InvalidArgument, "poisson: the points do not span a volume (all equal)");
    const Vec3 center = (box.min + box.max) * 0.5;
    const Vec3 origin = center - Vec3{side, side, side} * 0.5;
    samples.positions.reserve(positions.size());
    for (const Vec3& p : positions) samples.positions.push_back((p - origin) * (1.0 / side));
    sort_spatially(samples, options.depth);
    samples.area = estimate_area(samples, options.depth, options.samples_per_node);
    const int density_depth = std::max(kMinDepth, options.depth - kDensityLevels);
    const std::vector<double> density = reconstruct::sample_density(samples, density_depth);
    reconstruct::assign_splat_depths(samples, density, density_depth, kMinDepth, options.depth,
                                     options.samples_per_node);
    reconstruct::assign_area_shares(samples, density);

    Result<reconstruct::PoissonOctree> tree =
        reconstruct::build_octree(samples.positions, kMinDepth, options.depth, cancel, options.threads != 1);
    if (!tree) return tree.error();
    const double seconds_octree = seconds_since(start);

    reconstruct::SolverOptions solver;
    solver.alpha = options.point_weight;
    solver.dirichlet = options.boundary == PoissonBoundary::Dirichlet;
    solver.max_iterations = options.max_iterations;
    solver.tolerance = options.tolerance;
    solver.threads = options.threads;
    solver.cancel = cancel;
    std::vector<reconstruct::LevelSolveStats> level_stats;
    Result<reconstruct::IndicatorValues> chi = reconstruct::solve_cascadic(*tree, samples, solver, &level_stats);
    if (!chi) return chi.error();

    PoissonResult result;
    double iso = 0;
    for (std::size_t i = 0; i < samples.positions.size(); ++i) iso += samples.area_shares[i] * chi->at_samples[i];
    iso /= samples.area;
    result.iso_value = iso;
    result.cube_origin = origin;
    result.cube_size = side;

    for (std::size_t l = 0; l < tree->levels.size(); ++l) {
        result.stats.cells.push_back(tree->levels[l].cells.size());
        result.stats.dofs.push_back(level_stats[l].dofs);
        result.stats.iterations.push_back(level_stats[l].iterations);
        result.stats.residuals.push_back(level_stats[l].relative_residual);
    }
    result.stats.octree_bytes = tree->memory_bytes();
    for (const std::vector<double>& v : chi->values) result.stats.octree_bytes += v.capacity() * sizeof(double);
    result.stats.area_estimate = samples.area * side * side;

    result.stats.seconds_octree = seconds_octree;
    for (const reconstruct::LevelSolveStats& l : level_stats) {
        result.stats.seconds_system += l.assembly_seconds;
        result.stats.seconds_solve += l.solve_seconds;
    }
    const auto extract_start = std::chrono::steady_clock::now();
    reconstruct::ExtractionStats extraction;
    Result<PolygonMesh> mesh =
        reconstruct::extract_surface(*tree, *chi, iso, cancel, &extraction, options.threads != 1);
    if (!mesh) return mesh.error();
    result.mesh = std::move(*mesh);
    result.stats.seconds_extract = seconds_since(extract_start);
    if (options.fit_to_samples) {
        const auto fit_start = std::chrono::steady_clock::now();
        const double cell = std::ldexp(1.0, -options.depth);
        if (Status s = reconstruct::fit_to_samples(result.mesh, samples, cell, cancel, options.threads != 1); !s)
            return s.error();
        result.stats.seconds_fit = seconds_since(fit_start);
    }
    for (Vec3& p : result.mesh.positions) p = origin + p * side;
    result.stats.field_evaluations = extraction.interpolated_nodes;
    result.stats.surface_cells = extraction.surface_cells;
    result.stats.extraction_bytes = extraction.bytes;
    return result;
}

PoissonEstimate estimate_poisson(std::size_t points, const PoissonOptions& options) {
    PoissonEstimate e;
    const int depth = std::clamp(options.depth, kMinDepth, 10);
    // a sphere filling the cube: area pi in unit-cube units; the band of active cells is about 4 cells thick
    const double area = 3.14159265358979;
    double active_total = 0;
    for (int d = kMinDepth; d <= depth; ++d) {
        const double all = std::ldexp(1.0, 3 * d);
        const double surface = kCellsPerArea * area * std::ldexp(1.0, 2 * d);
        const double occupied = std::min(static_cast<double>(points), surface);
        active_total += d == kMinDepth ? all : std::min({all, 27 * occupied, 4 * surface});
    }
    e.octree_cells = static_cast<std::uint64_t>(active_total);
    // the extraction visits the finest cells the surface crosses (and a few neighbours), not the whole grid
    const double surface_cells = kCellsPerArea * area * std::ldexp(1.0, 2 * depth);
    e.grid_cells = static_cast<std::uint64_t>(surface_cells);
    // per active cell: its key sets and their row tables, the values, right-hand sides and solver vectors, the finest
    // level's stencil rows (about 120 bytes: 1M points at depths 9 and 10 measured 16-32% and 25-42% below the
    // prediction); per point: the samples, their splat levels and per-level
    // corner indices and weights; per surface cell: the extraction's tables and the output mesh (about 2 triangles)
    e.bytes = static_cast<std::uint64_t>(120 * active_total + 120 * static_cast<double>(points) + 100 * surface_cells);
    return e;
}

}  // namespace surfaced
