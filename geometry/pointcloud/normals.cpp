#include "geometry/pointcloud/normals.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "geometry/pointcloud/kd_tree.h"
#include "geometry/pointcloud/symmetric_eigen.h"

namespace surfaced {
namespace {

constexpr std::size_t kMaxK = 256;
constexpr std::size_t kPollEvery = 2048;

Status orient_over_graph(PointCloud& cloud, const std::vector<Index>& lists, std::size_t stride, const Cancel& cancel);

GeoError cancelled(const char* what) { return make_error(ErrorCode::Cancelled, std::string(what) + " was cancelled"); }

//! Smallest-eigenvalue eigenvector of the neighbourhood covariance, or a zero vector when the neighbourhood spans
//! no plane (all points equal, or collinear: then every direction orthogonal to the line is equally good).
Vec3 pca_normal(const std::vector<Vec3>& points, const std::vector<Neighbor>& neighbors) {
    Vec3 centroid;
    for (const Neighbor& n : neighbors) centroid += points[n.index];
    centroid *= 1.0 / static_cast<double>(neighbors.size());
    std::array<std::array<double, 3>, 3> c{};
    for (const Neighbor& n : neighbors) {
        const Vec3 d = points[n.index] - centroid;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) c[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] += d[i] * d[j];
    }
    const SymmetricEigen3 e = symmetric_eigen3(c);
    // the neighbourhood must extend in two directions for a plane to be defined
    if (!(e.values[1] > 1e-12 * e.values[2]) || !(e.values[2] > 0)) return {};
    return e.vectors[0];
}

}  // namespace

Status estimate_normals(PointCloud& cloud, const NormalEstimationOptions& options) {
    if (options.k < 3 || options.k > kMaxK)
        return make_error(ErrorCode::InvalidArgument,
                          "k = " + std::to_string(options.k) + " is out of range 3.." + std::to_string(kMaxK));
    if (cloud.size() < 3)
        return make_error(ErrorCode::InvalidArgument,
                          "normal estimation needs at least 3 points, the cloud has " + std::to_string(cloud.size()));
    if (Status s = validate(cloud); !s) return s;

    const KdTree tree(cloud.positions);
    const std::size_t n = cloud.size();
    std::vector<Vec3> normals(n);
    std::vector<char> defined(n, 0);
    std::vector<Neighbor> neighbors;
    // the neighbours (the point itself excluded) are kept for the orientation graph
    const std::size_t stride = std::min(options.k, n) - 1;
    std::vector<Index> lists;
    if (options.orient) lists.assign(n * stride, kInvalidIndex);
    for (std::size_t i = 0; i < n; ++i) {
        if (i % kPollEvery == 0 && options.cancel.requested()) return cancelled("normal estimation");
        tree.knn(cloud.positions[i], options.k, neighbors);
        if (options.orient) {
            std::size_t slot = 0;
            for (const Neighbor& nb : neighbors)
                if (nb.index != i && slot < stride) lists[i * stride + slot++] = nb.index;
        }
        const Vec3 normal = pca_normal(cloud.positions, neighbors);
        const double len = norm(normal);
        if (len > 0) {
            normals[i] = normal * (1.0 / len);
            defined[i] = 1;
        }
    }
    // degenerate neighbourhoods borrow the nearest defined normal (searching wider), else +z
    for (std::size_t i = 0; i < n; ++i) {
        if (defined[i]) continue;
        if (i % kPollEvery == 0 && options.cancel.requested()) return cancelled("normal estimation");
        normals[i] = {0, 0, 1};
        for (std::size_t k = options.k * 4;; k *= 4) {
            tree.knn(cloud.positions[i], std::min(k, n), neighbors);
            auto found = std::find_if(neighbors.begin(), neighbors.end(),
                                      [&](const Neighbor& nb) { return defined[nb.index] != 0; });
            if (found != neighbors.end()) {
                normals[i] = normals[found->index];
                break;
            }
            if (k >= n || k >= kMaxK * 64) break;
        }
    }
    cloud.normals = std::move(normals);
    if (!options.orient) return Ok{};
    return orient_over_graph(cloud, lists, stride, options.cancel);
}

Status orient_normals(PointCloud& cloud, const OrientationOptions& options) {
    if (options.k < 2 || options.k > kMaxK)
        return make_error(ErrorCode::InvalidArgument,
                          "k = " + std::to_string(options.k) + " is out of range 2.." + std::to_string(kMaxK));
    if (!cloud.has_normals()) return make_error(ErrorCode::InvalidArgument, "the point cloud has no normals to orient");
    if (Status s = validate(cloud); !s) return s;
    const std::size_t n = cloud.size();
    if (n == 0) return Ok{};

    // kNN lists (the point itself excluded), then the orientation over that graph
    const KdTree tree(cloud.positions);
    const std::size_t k = std::min(options.k + 1, n);  // +1: the point itself comes first
    std::vector<Index> lists(n * (k - 1), kInvalidIndex);
    std::vector<Neighbor> neighbors;
    for (std::size_t i = 0; i < n; ++i) {
        if (i % kPollEvery == 0 && options.cancel.requested()) return cancelled("normal orientation");
        tree.knn(cloud.positions[i], k, neighbors);
        std::size_t slot = 0;
        for (const Neighbor& nb : neighbors)
            if (nb.index != i && slot < k - 1) lists[i * (k - 1) + slot++] = nb.index;
    }
    return orient_over_graph(cloud, lists, k - 1, options.cancel);
}

namespace {

Status orient_over_graph(PointCloud& cloud, const std::vector<Index>& lists, std::size_t stride, const Cancel& cancel) {
    const std::size_t n = cloud.size();
    // kNN graph edges with their cost 1 - |n_i . n_j| (each undirected edge may appear twice: harmless below)
    const std::vector<Vec3>& normals_in = cloud.normals;
    struct Edge {
        float cost;
        Index a, b;
    };
    std::vector<Edge> edges;
    edges.reserve(lists.size());
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t slot = 0; slot < stride; ++slot) {
            const Index j = lists[i * stride + slot];
            if (j == kInvalidIndex) continue;
            const auto cost = static_cast<float>(1.0 - std::fabs(dot(normals_in[i], normals_in[j])));
            edges.push_back({cost, static_cast<Index>(i), j});
        }
    }
    if (cancel.requested()) return cancelled("normal orientation");

    // minimum spanning forest (Kruskal): the cheapest edges, those between nearly parallel normals, come first
    std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) {
        if (x.cost != y.cost) return x.cost < y.cost;
        if (x.a != y.a) return x.a < y.a;
        return x.b < y.b;
    });
    std::vector<Index> parent(n);
    for (std::size_t i = 0; i < n; ++i) parent[i] = static_cast<Index>(i);
    auto find = [&](Index v) {
        while (parent[v] != v) {
            parent[v] = parent[parent[v]];  // path halving
            v = parent[v];
        }
        return v;
    };
    std::vector<Index> tree_offsets(n + 1, 0), tree_edges;
    std::vector<std::pair<Index, Index>> accepted;
    accepted.reserve(n);
    for (const Edge& e : edges) {
        const Index ra = find(e.a), rb = find(e.b);
        if (ra == rb) continue;
        parent[ra] = rb;
        accepted.push_back({e.a, e.b});
        if (accepted.size() + 1 == n) break;  // one tree spans everything
    }
    edges = {};
    for (const auto& [a, b] : accepted) {
        ++tree_offsets[a + 1];
        ++tree_offsets[b + 1];
    }
    for (std::size_t i = 0; i < n; ++i) tree_offsets[i + 1] += tree_offsets[i];
    tree_edges.resize(tree_offsets[n]);
    {
        std::vector<Index> fill(tree_offsets.begin(), tree_offsets.end() - 1);
        for (const auto& [a, b] : accepted) {
            tree_edges[fill[a]++] = b;
            tree_edges[fill[b]++] = a;
        }
    }

    // each tree's seed: its point of largest z (ties: largest x, then y), made to face +z
    auto higher = [&](Index a, Index b) {
        const Vec3 &p = cloud.positions[a], &q = cloud.positions[b];
        if (p.z != q.z) return p.z > q.z;
        if (p.x != q.x) return p.x > q.x;
        return p.y > q.y;
    };
    std::vector<Index> seed_of_root(n, kInvalidIndex);
    for (std::size_t i = 0; i < n; ++i) {
        const Index r = find(static_cast<Index>(i));
        if (seed_of_root[r] == kInvalidIndex || higher(static_cast<Index>(i), seed_of_root[r]))
            seed_of_root[r] = static_cast<Index>(i);
    }

    // propagate from each seed along its tree: a point takes the side of its tree parent
    std::vector<Vec3>& normals = cloud.normals;
    std::vector<char> done(n, 0);
    std::vector<Index> stack;
    std::size_t reached = 0;
    for (std::size_t r = 0; r < n; ++r) {
        const Index seed = seed_of_root[r];
        if (seed == kInvalidIndex) continue;
        if (normals[seed].z < 0) normals[seed] *= -1.0;
        done[seed] = 1;
        stack.push_back(seed);
        while (!stack.empty()) {
            const Index v = stack.back();
            stack.pop_back();
            if (++reached % kPollEvery == 0 && cancel.requested()) return cancelled("normal orientation");
            for (Index t = tree_offsets[v]; t < tree_offsets[v + 1]; ++t) {
                const Index w = tree_edges[t];
                if (done[w]) continue;
                if (dot(normals[v], normals[w]) < 0) normals[w] *= -1.0;
                done[w] = 1;
                stack.push_back(w);
            }
        }
    }
    return Ok{};
}

}  // namespace
}  // namespace surfaced
