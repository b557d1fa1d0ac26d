// Trimming by sampling density: per-vertex density values from the kd-tree, a cut along their level set (each
// triangle clipped against the linear interpolation of its vertices' values, as marching triangles does), then
// removal of small edge-connected pieces.
#include "geometry/reconstruct/trim.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <numeric>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>

#include "geometry/pointcloud/kd_tree.h"

namespace surfaced {
namespace {

constexpr std::size_t kCancelStride = 4096;

GeoError cancelled() { return make_error(ErrorCode::Cancelled, "trim: cancelled"); }

Status check_options(const PointCloud& cloud, double cube_size, const TrimOptions& options) {
    if (cloud.empty()) return make_error(ErrorCode::InvalidArgument, "trim: the point cloud is empty");
    if (!(std::isfinite(cube_size) && cube_size > 0))
        return make_error(ErrorCode::InvalidArgument, "trim: the reconstruction's cube size must be positive");
    if (!(std::isfinite(options.trim) && options.trim >= 0))
        return make_error(ErrorCode::InvalidArgument, "trim: trim must be finite and >= 0");
    if (!(options.island_area >= 0 && options.island_area <= 1))
        return make_error(ErrorCode::InvalidArgument, "trim: island_area must be in [0, 1]");
    if (!(std::isfinite(options.samples_per_node) && options.samples_per_node > 0))
        return make_error(ErrorCode::InvalidArgument, "trim: samples_per_node must be finite and > 0");
    if (options.neighbors < 1 || options.neighbors > 64)
        return make_error(ErrorCode::InvalidArgument, "trim: neighbors must be in 1..64");
    for (const Vec3& p : cloud.positions)
        if (!is_finite(p)) return make_error(ErrorCode::NonFinite, "trim: the point cloud has a non-finite point");
    return Ok{};
}

double triangle_area(const Vec3& a, const Vec3& b, const Vec3& c) { return 0.5 * norm(cross(b - a, c - a)); }

//! Union-find over faces, path halving.
Index find_root(std::vector<Index>& parent, Index i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
}

//! The density value at each of `points` (see trim.h), or nullopt when cancelled.
std::optional<std::vector<double>> density_at(const KdTree& tree, std::span<const Vec3> points, double cube_size,
                                              const TrimOptions& options, const Cancel& cancel) {
    const std::size_t k = std::min(options.neighbors, tree.size());
    // h = sqrt(samples_per_node * pi r^2 / k) is the side of a square holding samples_per_node samples at the
    // density k / (pi r^2); the value is log2(cube_size / h). r is bounded below so that a point on k coincident
    // samples gets a large finite value rather than infinity.
    const double factor = std::sqrt(options.samples_per_node * std::numbers::pi / static_cast<double>(k));
    const double min_r = cube_size * 0x1p-40;
    std::vector<double> density(points.size());
    std::vector<Neighbor> near;
    for (std::size_t v = 0; v < points.size(); ++v) {
        if (v % kCancelStride == 0 && cancel.requested()) return std::nullopt;
        tree.knn(points[v], k, near);
        const double r = std::max(std::sqrt(near.back().distance2), min_r);
        density[v] = std::log2(cube_size / (factor * r));
    }
    return density;
}

//! The median density value at up to 4096 evenly spaced samples, or nullopt when cancelled.
std::optional<double> median_at_samples(const KdTree& tree, const PointCloud& cloud, double cube_size,
                                        const TrimOptions& options, const Cancel& cancel) {
    std::vector<Vec3> probes;
    const std::size_t stride = std::max<std::size_t>(1, cloud.size() / 4096);
    for (std::size_t i = 0; i < cloud.size(); i += stride) probes.push_back(cloud.positions[i]);
    auto values = density_at(tree, probes, cube_size, options, cancel);
    if (!values) return std::nullopt;
    auto middle = values->begin() + static_cast<std::ptrdiff_t>(values->size() / 2);
    std::nth_element(values->begin(), middle, values->end());
    return *middle;
}

}  // namespace

Result<double> typical_sample_density(const PointCloud& cloud, double cube_size, const TrimOptions& options,
                                      const Cancel& cancel) {
    if (auto ok = check_options(cloud, cube_size, options); !ok) return ok.error();
    const KdTree tree(cloud.positions);
    const std::optional<double> typical = median_at_samples(tree, cloud, cube_size, options, cancel);
    if (!typical) return cancelled();
    return *typical;
}

Result<std::vector<double>> vertex_density(const PolygonMesh& mesh, const PointCloud& cloud, double cube_size,
                                           const TrimOptions& options, const Cancel& cancel) {
    if (auto ok = check_options(cloud, cube_size, options); !ok) return ok.error();
    const KdTree tree(cloud.positions);
    auto density = density_at(tree, mesh.positions, cube_size, options, cancel);
    if (!density) return cancelled();
    return std::move(*density);
}

Result<TrimReport> trim_reconstruction(PolygonMesh& mesh, const PointCloud& cloud, const PoissonResult& result,
                                       const TrimOptions& options, const Cancel& cancel) {
    if (!mesh.is_triangle_mesh())
        return make_error(ErrorCode::NotTriangleMesh, "trim: the mesh must consist of triangles");
    if (auto ok = check_options(cloud, result.cube_size, options); !ok) return ok.error();
    const KdTree tree(cloud.positions);
    auto density = density_at(tree, mesh.positions, result.cube_size, options, cancel);
    if (!density) return cancelled();
    const std::vector<double>& value = *density;

    const std::size_t face_count = mesh.face_count();
    TrimReport report;
    if (!value.empty()) {
        const auto [lo, hi] = std::minmax_element(value.begin(), value.end());
        report.min_density = *lo;
        report.max_density = *hi;
    }
    const std::optional<double> typical = median_at_samples(tree, cloud, result.cube_size, options, cancel);
    if (!typical) return cancelled();
    report.sample_density = *typical;

    // small holes: a connected region of vertices below the level whose faces' share of the area is below
    // island_area of the total is kept (PoissonRecon's --aRatio does the same), so that a gap between samples
    // does not punch a hole; the level is lowered below those vertices' values.
    std::vector<double> level(value);  // the values the cut uses
    if (options.trim > 0 && options.island_area > 0) {
        const std::size_t n = mesh.vertex_count();
        std::vector<Index> parent(n);
        std::iota(parent.begin(), parent.end(), Index{0});
        for (std::size_t f = 0; f < face_count; ++f) {
            const auto t = mesh.face(f);
            for (int i = 0; i < 3; ++i) {
                const Index a = t[static_cast<std::size_t>(i)], b = t[static_cast<std::size_t>((i + 1) % 3)];
                if (value[a] > options.trim || value[b] > options.trim) continue;
                const Index ra = find_root(parent, a), rb = find_root(parent, b);
                if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
            }
        }
        std::vector<double> below_area(n, 0.0);
        double total = 0;
        for (std::size_t f = 0; f < face_count; ++f) {
            const auto t = mesh.face(f);
            const double a = triangle_area(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]);
            total += a;
            for (Index v : t)
                if (value[v] <= options.trim) below_area[find_root(parent, v)] += a / 3;
        }
        for (std::size_t v = 0; v < n; ++v)
            if (value[v] <= options.trim &&
                below_area[find_root(parent, static_cast<Index>(v))] < options.island_area * total)
                level[v] = std::numeric_limits<double>::infinity();
    }

    // cut along the level: a vertex is kept when its value exceeds trim (strictly, so that the cut points lie
    // inside edges and a kept vertex keeps its whole star: no pinched vertices); a triangle with kept and removed
    // vertices keeps the part on the kept side, a triangle or a quad (split along its shorter diagonal).
    std::vector<Vec3> positions = mesh.positions;
    std::vector<Index> triangles;
    triangles.reserve(mesh.face_indices.size());
    if (options.trim > 0) {
        std::unordered_map<std::uint64_t, Index> cuts;  // undirected edge (min, max) -> new vertex
        auto cut = [&](Index p, Index q) {
            if (p > q) std::swap(p, q);
            const std::uint64_t key = (std::uint64_t{p} << 32) | q;
            const auto [it, inserted] = cuts.try_emplace(key, static_cast<Index>(positions.size()));
            if (inserted) {
                const double t = (options.trim - level[p]) / (level[q] - level[p]);
                positions.push_back(mesh.positions[p] + (mesh.positions[q] - mesh.positions[p]) * t);
            }
            return it->second;
        };
        for (std::size_t f = 0; f < face_count; ++f) {
            if (f % kCancelStride == 0 && cancel.requested()) return cancelled();
            const auto face = mesh.face(f);
            int kept = 0;
            for (Index v : face) kept += level[v] > options.trim ? 1 : 0;
            if (kept == 3) {
                triangles.insert(triangles.end(), face.begin(), face.end());
                continue;
            }
            ++report.faces_removed;
            if (kept == 0) continue;
            Index polygon[4];
            int n = 0;
            for (int i = 0; i < 3; ++i) {
                const Index p = face[static_cast<std::size_t>(i)], q = face[static_cast<std::size_t>((i + 1) % 3)];
                const bool in_p = level[p] > options.trim, in_q = level[q] > options.trim;
                if (in_p) polygon[n++] = p;
                if (in_p != in_q) polygon[n++] = cut(p, q);
            }
            if (n == 3) {
                triangles.insert(triangles.end(), polygon, polygon + 3);
            } else {
                const bool diagonal02 = norm(positions[polygon[2]] - positions[polygon[0]]) <=
                                        norm(positions[polygon[3]] - positions[polygon[1]]);
                const Index* q = polygon;
                if (diagonal02)
                    triangles.insert(triangles.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
                else
                    triangles.insert(triangles.end(), {q[1], q[2], q[3], q[1], q[3], q[0]});
            }
        }
    } else {
        triangles = mesh.face_indices;
    }

    // islands: edge-connected pieces by union-find over the triangles sharing an edge
    const std::size_t tri_count = triangles.size() / 3;
    std::vector<bool> keep_triangle(tri_count, true);
    if (options.island_area > 0 && tri_count > 0) {
        if (cancel.requested()) return cancelled();
        std::vector<Index> parent(tri_count);
        std::iota(parent.begin(), parent.end(), Index{0});
        std::unordered_map<std::uint64_t, Index> edge_face;
        edge_face.reserve(tri_count * 2);
        for (std::size_t t = 0; t < tri_count; ++t)
            for (int i = 0; i < 3; ++i) {
                Index a = triangles[3 * t + static_cast<std::size_t>(i)];
                Index b = triangles[3 * t + static_cast<std::size_t>((i + 1) % 3)];
                if (a > b) std::swap(a, b);
                const auto [it, inserted] = edge_face.try_emplace((std::uint64_t{a} << 32) | b, static_cast<Index>(t));
                if (!inserted) {
                    const Index ra = find_root(parent, it->second), rb = find_root(parent, static_cast<Index>(t));
                    if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
                }
            }
        std::vector<double> area(tri_count, 0.0);
        double total = 0;
        for (std::size_t t = 0; t < tri_count; ++t) {
            const double a = triangle_area(positions[triangles[3 * t]], positions[triangles[3 * t + 1]],
                                           positions[triangles[3 * t + 2]]);
            area[find_root(parent, static_cast<Index>(t))] += a;
            total += a;
        }
        for (std::size_t t = 0; t < tri_count; ++t) {
            const Index root = find_root(parent, static_cast<Index>(t));
            keep_triangle[t] = area[root] >= options.island_area * total;
            if (root == t && !keep_triangle[t]) ++report.islands_removed;
        }
    }

    // compact: surviving vertices in index order (the original ones, then the cut points)
    std::vector<Index> remap(positions.size(), kInvalidIndex);
    for (std::size_t t = 0; t < tri_count; ++t)
        if (keep_triangle[t])
            for (int i = 0; i < 3; ++i) remap[triangles[3 * t + static_cast<std::size_t>(i)]] = 0;
    PolygonMesh out;
    for (std::size_t v = 0; v < positions.size(); ++v)
        if (remap[v] == 0) {
            remap[v] = static_cast<Index>(out.positions.size());
            out.positions.push_back(positions[v]);
        }
    out.face_indices.reserve(triangles.size());
    out.face_offsets.reserve(tri_count + 1);
    for (std::size_t t = 0; t < tri_count; ++t) {
        if (!keep_triangle[t]) continue;
        for (int i = 0; i < 3; ++i) out.face_indices.push_back(remap[triangles[3 * t + static_cast<std::size_t>(i)]]);
        out.face_offsets.push_back(static_cast<Index>(out.face_indices.size()));
    }
    mesh = std::move(out);
    return report;
}

}  // namespace surfaced
