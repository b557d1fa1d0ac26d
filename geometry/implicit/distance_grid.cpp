// Grid layout and field sampling for narrow-band distance grids (see distance_grid.h); the mesh conversion is in
// mesh_distance_grid.cpp.
#include "geometry/implicit/distance_grid.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace surfaced::implicit {

Box3 default_distance_grid_bounds(const Box3& mesh_box, double voxel_size, int band) {
    const double grow = (band + 1) * voxel_size;
    Box3 out = mesh_box;
    out.min -= Vec3{grow, grow, grow};
    out.max += Vec3{grow, grow, grow};
    return out;
}

Result<DistanceGridLayout> distance_grid_layout(const Box3& bounds, double voxel_size, std::uint64_t max_nodes) {
    if (!(voxel_size > 0) || !std::isfinite(voxel_size))
        return GeoError{ErrorCode::InvalidArgument, "voxel_size must be a positive finite number"};
    if (bounds.empty() || !is_finite(bounds.min) || !is_finite(bounds.max))
        return GeoError{ErrorCode::InvalidArgument, "the grid's bounds must be a finite, non-empty box"};
    DistanceGridLayout out;
    out.origin = bounds.min;
    out.spacing = voxel_size;
    double count = 1;
    for (int a = 0; a < 3; ++a) {
        const double extent = bounds.max[a] - bounds.min[a];
        // ceil with a little slack, so that bounds an exact multiple of h away do not get an extra node by rounding
        const double cells = std::max(1.0, std::ceil(extent / voxel_size - 1e-9));
        const double n = cells + 1;
        count *= n;
        if (!std::isfinite(n) || n > static_cast<double>(max_nodes) || count > static_cast<double>(max_nodes))
            return GeoError{ErrorCode::BudgetExceeded, "a grid of voxel size " + std::to_string(voxel_size) +
                                                           " over these bounds has more than " +
                                                           std::to_string(max_nodes) + " nodes"};
        out.dims[static_cast<std::size_t>(a)] = static_cast<std::size_t>(n);
    }
    out.nodes = static_cast<std::uint64_t>(out.dims[0]) * out.dims[1] * out.dims[2];
    if (out.nodes > max_nodes)
        return GeoError{ErrorCode::BudgetExceeded, "the grid has " + std::to_string(out.nodes) +
                                                       " nodes; the limit is " + std::to_string(max_nodes)};
    return out;
}

Result<LevelSetGrid> field_distance_grid(const Field& field, const DistanceGridOptions& options,
                                         DistanceGridStats* stats) {
    if (options.band < 1 || options.band > kMaxDistanceBand)
        return GeoError{ErrorCode::InvalidArgument,
                        "band must be in 1.." + std::to_string(kMaxDistanceBand) + " voxels"};
    if (!options.bounds) return GeoError{ErrorCode::InvalidArgument, "a field's grid needs bounds"};
    auto layout = distance_grid_layout(*options.bounds, options.voxel_size, options.max_nodes);
    if (!layout) return layout.error();
    const DistanceGridLayout& g = layout.value();
    const double h = g.spacing, limit = options.band * h;
    // How many nodes along x a sample clamps for sure: |f| - L * distance stays above the band.
    const double lipschitz = field.lipschitz();
    const bool bounded = field.kind() != FieldKind::General && std::isfinite(lipschitz) && lipschitz > 0;

    LevelSetGrid out;
    out.dims = g.dims;
    out.origin = g.origin;
    out.spacing = {h, h, h};
    out.values.resize(g.nodes);
    std::uint64_t evaluations = 0, band_nodes = 0;
    const std::size_t nx = g.dims[0], ny = g.dims[1], nz = g.dims[2];
    for (std::size_t k = 0; k < nz; ++k) {
        if (options.cancel.requested()) return GeoError{ErrorCode::Cancelled, "cancelled while sampling the field"};
        for (std::size_t j = 0; j < ny; ++j) {
            double* row = out.values.data() + nx * (j + ny * k);
            const double y = g.origin.y + static_cast<double>(j) * h, z = g.origin.z + static_cast<double>(k) * h;
            for (std::size_t i = 0; i < nx;) {
                const double f = field.value({g.origin.x + static_cast<double>(i) * h, y, z});
                ++evaluations;
                if (std::isnan(f))
                    return GeoError{ErrorCode::NonFinite, "the field is NaN at grid node (" + std::to_string(i) + ", " +
                                                              std::to_string(j) + ", " + std::to_string(k) + ")"};
                if (std::abs(f) < limit) {
                    row[i++] = f;
                    ++band_nodes;
                    continue;
                }
                const double clamped = f < 0 ? -limit : limit;
                row[i++] = clamped;
                if (!bounded) continue;
                // a relative margin, so that the rounding of the samples skipped cannot put them back in the band
                const double skip = std::floor((std::abs(f) - limit * (1 + 1e-9)) / (lipschitz * h * (1 + 1e-9)));
                const std::size_t end =
                    skip >= static_cast<double>(nx - i) ? nx : i + static_cast<std::size_t>(std::max(0.0, skip));
                for (; i < end; ++i) row[i] = clamped;
            }
        }
    }
    if (stats) {
        *stats = DistanceGridStats{};
        stats->layout = g;
        stats->band_nodes = band_nodes;
        stats->field_evaluations = evaluations;
    }
    return out;
}

}  // namespace surfaced::implicit
