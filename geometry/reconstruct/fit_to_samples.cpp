#include "geometry/reconstruct/fit_to_samples.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "geometry/core/two_parts.h"
#include "geometry/reconstruct/key_map.h"

namespace surfaced::reconstruct {

namespace {

constexpr int kSteps = 2;
//! h^2 = kBandwidthFactor g^2 / count: `count` samples on about 1.3 (3g)^2 of surface (a plane through the 3 x 3 x 3
//! grid cells of width g) put 6 within pi h^2
constexpr double kBandwidthFactor = 6 * 1.3 * 9 / 3.14159265358979;
constexpr double kCutoff2 = 4.0;  //!< the kernel (1 - d^2 / (2h)^2)^3 ends at 2h
//! The curvature term's share: 1 for a sample normal within 20 degrees of the mean normal, 0 beyond 30
constexpr float kSmoothCosine = 0.9397f;
constexpr float kSharpCosine = 0.8660f;
constexpr float kBendRamp = 1.0f / (kSmoothCosine - kSharpCosine);
constexpr double kFadeStart = 3, kFadeEnd = 5;  //!< h in finest cells: the full fit below, none above
constexpr double kNoiseFactor = 4.0;            //!< (two standard errors)^2
constexpr double kSpacingsPerCell = 2.5;        //!< the neighbour grid's cell, in typical sample spacings
constexpr std::size_t kPollEvery = 4096;
constexpr std::size_t kThreadedVertices = 32768;

struct GridSample {
    Vec3 position;
    Vec3 normal;
    double weight = 0;
};

//! The samples sorted by grid cell, and each occupied cell's key with where its samples start.
struct SampleGrid {
    double cell = 0;
    std::uint32_t cells_per_side = 0;
    std::vector<GridSample> samples;
    std::vector<std::uint64_t> keys;    //!< sorted, distinct
    std::vector<std::uint32_t> starts;  //!< keys.size() + 1 entries

    std::uint32_t coordinate(double x) const {
        const double c = std::floor(x / cell);
        if (!(c > 0)) return 0;
        return static_cast<std::uint32_t>(std::min(c, static_cast<double>(cells_per_side - 1)));
    }
    std::uint64_t key(const Vec3& p) const { return pack_key(coordinate(p.x), coordinate(p.y), coordinate(p.z)); }
};

SampleGrid build_grid(const OrientedSamples& samples, double cell) {
    SampleGrid grid;
    grid.cell = cell;
    grid.cells_per_side = static_cast<std::uint32_t>(std::ceil(1.0 / cell)) + 1;
    std::vector<std::pair<std::uint64_t, std::uint32_t>> order(samples.positions.size());
    for (std::size_t i = 0; i < order.size(); ++i)
        order[i] = {grid.key(samples.positions[i]), static_cast<std::uint32_t>(i)};
    std::sort(order.begin(), order.end());
    grid.samples.reserve(order.size());
    for (std::size_t i = 0; i < order.size(); ++i) {
        const std::uint32_t s = order[i].second;
        grid.samples.push_back({samples.positions[s], samples.normals[s], samples.weights[s]});
        if (i == 0 || order[i].first != order[i - 1].first) {
            grid.keys.push_back(order[i].first);
            grid.starts.push_back(static_cast<std::uint32_t>(i));
        }
    }
    grid.starts.push_back(static_cast<std::uint32_t>(order.size()));
    return grid;
}

//! Ranges of grid.samples in the 3 x 3 x 3 cells around `key`: one range per row (j, k), cells i - 1 .. i + 1.
void gather(const SampleGrid& grid, std::uint64_t key, std::vector<std::pair<std::uint32_t, std::uint32_t>>& ranges) {
    ranges.clear();
    const std::uint32_t i = key_i(key), j = key_j(key), k = key_k(key);
    const std::uint32_t i0 = i > 0 ? i - 1 : 0, i1 = i + 1;
    for (std::uint32_t kk = k > 0 ? k - 1 : 0; kk <= k + 1; ++kk)
        for (std::uint32_t jj = j > 0 ? j - 1 : 0; jj <= j + 1; ++jj) {
            const std::uint64_t lo = pack_key(i0, jj, kk), hi = pack_key(i1, jj, kk);
            auto first = std::lower_bound(grid.keys.begin(), grid.keys.end(), lo);
            auto last = first;
            while (last != grid.keys.end() && *last <= hi) ++last;
            if (first == last) continue;
            ranges.emplace_back(grid.starts[static_cast<std::size_t>(first - grid.keys.begin())],
                                grid.starts[static_cast<std::size_t>(last - grid.keys.begin())]);
        }
}

//! Four floats side by side (GCC and Clang vector extensions: SSE on x86-64, NEON on ARM).
typedef float Float4 __attribute__((vector_size(16)));

//! The candidate samples of one group of vertices, four to a block (structure of arrays), positions relative to
//! `origin` (a corner of the group's cell, so that floats keep about 1e-7 of the cell); the last block is padded with
//! samples of weight 0.
struct Candidates {
    struct Block {
        Float4 x, y, z, nx, ny, nz, w;
    };
    Vec3 origin;
    std::vector<Block> blocks;
    std::size_t count = 0;

    void clear(const Vec3& corner) {
        origin = corner;
        blocks.clear();
        count = 0;
    }
    void add(const GridSample& s) {
        const std::size_t lane = count % 4;
        if (lane == 0) blocks.push_back(Block{});
        Block& b = blocks.back();
        const Vec3 p = s.position - origin;
        b.x[lane] = static_cast<float>(p.x);
        b.y[lane] = static_cast<float>(p.y);
        b.z[lane] = static_cast<float>(p.z);
        b.nx[lane] = static_cast<float>(s.normal.x);
        b.ny[lane] = static_cast<float>(s.normal.y);
        b.nz[lane] = static_cast<float>(s.normal.z);
        b.w[lane] = static_cast<float>(s.weight);
        ++count;
    }
};

//! Scratch of one vertex, per candidate: its weight if it faces the vertex (else 0), its curvature term's factor.
struct VertexScratch {
    std::vector<Float4> weight, bend;
};

double sum_lanes(const Float4& v) {
    return (static_cast<double>(v[0]) + static_cast<double>(v[1])) +
           (static_cast<double>(v[2]) + static_cast<double>(v[3]));
}

//! Two steps for one vertex over the candidates (see the top of fit_to_samples.h). Branch-free loops over all the
//! candidates, four at a time: a sample facing away has weight 0, one beyond the cutoff a kernel value of 0. The
//! same operations in the same order for a vertex wherever it is processed, so the result is too.
Vec3 fit_vertex(const Vec3& position, const Vec3& normal, const Candidates& c, double bandwidth2, double finest_cell,
                VertexScratch& scratch) {
    const std::size_t n = c.blocks.size();
    const Float4 zero = {0, 0, 0, 0};
    // samples sparser than the grid: their planes reach farther than chi's cells do, and the fit fades out
    const double cells = std::sqrt(bandwidth2) / finest_cell;
    const double fade = std::clamp((kFadeEnd - cells) / (kFadeEnd - kFadeStart), 0.0, 1.0);
    if (fade == 0) return position;
    const Float4 inverse_cutoff = zero + static_cast<float>(1.0 / (kCutoff2 * bandwidth2));
    const Float4 nx0 = zero + static_cast<float>(normal.x), ny0 = zero + static_cast<float>(normal.y),
                 nz0 = zero + static_cast<float>(normal.z);
    Vec3 x = position - c.origin;
    // each sample's weight if it faces the vertex (one facing away belongs to another sheet, the far side of a thin
    // part), the samples' mean normal m around the vertex, and per sample how much of the curvature term to use
    scratch.weight.resize(n);
    Float4 bent_x = zero, bent_y = zero, bent_z = zero;
    {
        const Float4 px = zero + static_cast<float>(x.x), py = zero + static_cast<float>(x.y),
                     pz = zero + static_cast<float>(x.z);
        Float4 sx = zero, sy = zero, sz = zero;
        for (std::size_t i = 0; i < n; ++i) {
            const Candidates::Block& b = c.blocks[i];
            scratch.weight[i] = b.nx * nx0 + b.ny * ny0 + b.nz * nz0 > zero ? b.w : zero;
            const Float4 dx = px - b.x, dy = py - b.y, dz = pz - b.z;
            Float4 t = 1.0f - (dx * dx + dy * dy + dz * dz) * inverse_cutoff;
            t = t > zero ? t : zero;
            const Float4 w = scratch.weight[i] * t * t * t;
            sx += w * b.nx;
            sy += w * b.ny;
            sz += w * b.nz;
        }
        Vec3 mean_normal{sum_lanes(sx), sum_lanes(sy), sum_lanes(sz)};
        const double length = norm(mean_normal);
        if (!(length > 0)) return position;
        mean_normal = mean_normal * (1.0 / length);
        bent_x = zero + static_cast<float>(mean_normal.x);
        bent_y = zero + static_cast<float>(mean_normal.y);
        bent_z = zero + static_cast<float>(mean_normal.z);
        scratch.bend.resize(n);
        for (std::size_t i = 0; i < n; ++i) {
            const Candidates::Block& b = c.blocks[i];
            // from the cosine between the sample's normal and m: 1/2 within 20 degrees, 0 beyond 30
            Float4 g = (b.nx * bent_x + b.ny * bent_y + b.nz * bent_z - kSharpCosine) * kBendRamp;
            g = g > zero ? g : zero;
            g = g < 1.0f ? g : zero + 1.0f;
            scratch.bend[i] = g * 0.5f;
        }
    }
    for (int step = 0; step < kSteps; ++step) {
        const Float4 px = zero + static_cast<float>(x.x), py = zero + static_cast<float>(x.y),
                     pz = zero + static_cast<float>(x.z);
        // sum w, sum w^2, sum w s, sum w s^2 and sum w s n (s: the offset from the sample's plane)
        Float4 w_sum = zero, w2_sum = zero, s_sum = zero, s2_sum = zero, mx = zero, my = zero, mz = zero;
        for (std::size_t i = 0; i < n; ++i) {
            const Candidates::Block& b = c.blocks[i];
            const Float4 dx = px - b.x, dy = py - b.y, dz = pz - b.z;
            Float4 t = 1.0f - (dx * dx + dy * dy + dz * dz) * inverse_cutoff;
            t = t > zero ? t : zero;
            const Float4 w = scratch.weight[i] * t * t * t;
            const Float4 offset =
                b.nx * dx + b.ny * dy + b.nz * dz +
                scratch.bend[i] * ((bent_x - b.nx) * dx + (bent_y - b.ny) * dy + (bent_z - b.nz) * dz);
            const Float4 ws = w * offset;
            w_sum += w;
            w2_sum += w * w;
            s_sum += ws;
            s2_sum += ws * offset;
            mx += ws * b.nx;
            my += ws * b.ny;
            mz += ws * b.nz;
        }
        const double w_total = sum_lanes(w_sum);
        if (!(w_total > 0)) break;
        const double mean = sum_lanes(s_sum) / w_total;
        const double variance = std::max(0.0, sum_lanes(s2_sum) / w_total - mean * mean);
        const double effective = w_total * w_total / sum_lanes(w2_sum);
        const double signal = mean * mean;
        if (!(signal > 0)) break;
        const double shrink = fade * signal / (signal + kNoiseFactor * variance / effective);
        Vec3 delta = Vec3{sum_lanes(mx), sum_lanes(my), sum_lanes(mz)} * (shrink / w_total);
        const double length = norm(delta);
        if (length > finest_cell) delta = delta * (finest_cell / length);
        x -= delta;
    }
    return c.origin + x;
}

}  // namespace

Status fit_to_samples(PolygonMesh& mesh, const OrientedSamples& samples, double cell, const Cancel& cancel,
                      bool threaded) {
    const std::size_t n = mesh.positions.size();
    if (n == 0 || samples.positions.empty()) return Ok{};
    const double spacing = std::sqrt(samples.area / static_cast<double>(samples.positions.size()));
    const SampleGrid grid = build_grid(samples, std::max({2 * cell, kSpacingsPerCell * spacing, 1e-6}));
    // the mesh's normal at each vertex, for the facing test only (so neither normalised nor weighted beyond the
    // triangles' areas): the sum of its triangles' cross products, each half of the vertices on its own thread
    // reading all the triangles
    std::vector<Vec3> normals(n, Vec3{0, 0, 0});
    const std::size_t middle = n / 2;
    run_two_parts(threaded && n >= kThreadedVertices, [&](int part) {
        const std::size_t begin = part == 0 ? 0 : middle, end = part == 0 ? middle : n;
        const std::vector<Index>& corners = mesh.face_indices;
        for (std::size_t f = 0; f + 1 < mesh.face_offsets.size(); ++f) {
            const std::size_t first = mesh.face_offsets[f], count = mesh.face_offsets[f + 1] - first;
            for (std::size_t c = 0; c < count; ++c) {
                const Index v = corners[first + c];
                if (v < begin || v >= end) continue;
                const Vec3& p = mesh.positions[v];
                const Vec3& next = mesh.positions[corners[first + (c + 1) % count]];
                const Vec3& previous = mesh.positions[corners[first + (c + count - 1) % count]];
                normals[v] += cross(next - p, previous - p);
            }
        }
    });

    std::atomic<bool> cancelled{false};
    run_two_parts(threaded && n >= kThreadedVertices, [&](int part) {
        const std::size_t begin = part == 0 ? 0 : middle, end = part == 0 ? middle : n;
        std::vector<std::pair<std::uint64_t, std::uint32_t>> order;
        order.reserve(end - begin);
        for (std::size_t v = begin; v < end; ++v)
            order.emplace_back(grid.key(mesh.positions[v]), static_cast<std::uint32_t>(v));
        std::sort(order.begin(), order.end());
        std::vector<std::pair<std::uint32_t, std::uint32_t>> ranges;
        Candidates candidates_of_group;
        VertexScratch scratch;
        for (std::size_t g = 0; g < order.size();) {
            const std::uint64_t key = order[g].first;
            gather(grid, key, ranges);
            candidates_of_group.clear(Vec3{key_i(key) * grid.cell, key_j(key) * grid.cell, key_k(key) * grid.cell});
            for (const auto& [b, e] : ranges)
                for (std::uint32_t s = b; s < e; ++s) candidates_of_group.add(grid.samples[s]);
            const std::size_t count = candidates_of_group.count;
            // h^2: about the squared distance to the 6th nearest sample, at least a finest cell squared
            const double bandwidth2 =
                count == 0
                    ? 0
                    : std::max(cell * cell, kBandwidthFactor * grid.cell * grid.cell / static_cast<double>(count));
            std::size_t next = g;
            for (; next < order.size() && order[next].first == key; ++next) {
                if (next % kPollEvery == 0 && (cancelled.load(std::memory_order_relaxed) || cancel.requested())) {
                    cancelled = true;
                    return;
                }
                if (count == 0) continue;
                const std::uint32_t v = order[next].second;
                mesh.positions[v] =
                    fit_vertex(mesh.positions[v], normals[v], candidates_of_group, bandwidth2, cell, scratch);
            }
            g = next;
        }
    });
    if (cancelled) return make_error(ErrorCode::Cancelled, "poisson: cancelled while fitting the mesh to the samples");
    return Ok{};
}

}  // namespace surfaced::reconstruct
