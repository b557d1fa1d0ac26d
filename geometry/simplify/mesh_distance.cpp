#include "geometry/simplify/mesh_distance.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

namespace surfaced {

Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    // Ericson 5.1.5: find the Voronoi region of the triangle that contains p, without normalising anything, so
    // degenerate triangles fall into an edge or vertex region instead of dividing by zero.
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return a;
    const Vec3 bp = p - b;
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return b;
    const double vc = d1 * d4 - d3 * d2;
    // (an edge region only when the edge has a length: with a == b, d1 - d3 = |ab|^2 = 0 and the point belongs to
    // edge ac or bc, found below)
    if (vc <= 0 && d1 >= 0 && d3 <= 0 && d1 - d3 > 0) return a + ab * (d1 / (d1 - d3));
    const Vec3 cp = p - c;
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return c;
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0 && d2 - d6 > 0) return a + ac * (d2 / (d2 - d6));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0 && (d4 - d3) + (d5 - d6) > 0)
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    const double sum = va + vb + vc;
    if (!(sum > 0)) {
        // Collinear corners that the region tests did not catch (rounding): nearest of the three edges.
        Vec3 best = a;
        double best_d = std::numeric_limits<double>::infinity();
        const Vec3 ends[3][2] = {{a, b}, {b, c}, {c, a}};
        for (const auto& e : ends) {
            const Vec3 d = e[1] - e[0];
            const double len2 = dot(d, d);
            const double t = len2 > 0 ? std::clamp(dot(p - e[0], d) / len2, 0.0, 1.0) : 0.0;
            const Vec3 q = e[0] + d * t;
            const double dist = dot(p - q, p - q);
            if (dist < best_d) {
                best_d = dist;
                best = q;
            }
        }
        return best;
    }
    const double denom = 1.0 / sum;
    return a + ab * (vb * denom) + ac * (vc * denom);
}

double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    return norm(p - closest_point_on_triangle(p, a, b, c));
}

namespace {

struct Node {
    Box3 box;
    std::uint32_t first = 0;  //!< leaf: first triangle in order_; inner: index of the left child (right = left + 1)
    std::uint32_t count = 0;  //!< triangles in a leaf; 0 for an inner node
};

inline void grow(Box3& box, const Vec3& p) {
    box.min = {std::min(box.min.x, p.x), std::min(box.min.y, p.y), std::min(box.min.z, p.z)};
    box.max = {std::max(box.max.x, p.x), std::max(box.max.y, p.y), std::max(box.max.z, p.z)};
}

double box_distance2(const Box3& box, const Vec3& p) {
    double d2 = 0;
    for (int i = 0; i < 3; ++i) {
        const double v = p[i] < box.min[i] ? box.min[i] - p[i] : (p[i] > box.max[i] ? p[i] - box.max[i] : 0.0);
        d2 += v * v;
    }
    return d2;
}

//! SplitMix64: small, fast and the same on every platform (std distributions are not).
struct Random {
    std::uint64_t state;
    std::uint64_t next() {
        std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }  // [0, 1)
};

std::vector<std::array<Index, 3>> fan_triangles(const PolygonMesh& mesh) {
    std::vector<std::array<Index, 3>> tris;
    tris.reserve(mesh.face_indices.size());
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        auto face = mesh.face(f);
        for (std::size_t j = 1; j + 1 < face.size(); ++j) tris.push_back({face[0], face[j], face[j + 1]});
    }
    return tris;
}

}  // namespace

struct SurfaceDistance::Impl {
    std::vector<Vec3> positions;
    std::vector<std::array<Index, 3>> tris;
    std::vector<std::uint32_t> order;
    std::vector<Node> nodes;

    void build() {
        order.resize(tris.size());
        std::iota(order.begin(), order.end(), 0u);
        if (tris.empty()) return;
        std::vector<Vec3> centroids(tris.size());
        for (std::size_t t = 0; t < tris.size(); ++t)
            centroids[t] = (positions[tris[t][0]] + positions[tris[t][1]] + positions[tris[t][2]]) * (1.0 / 3.0);
        nodes.reserve(2 * tris.size() / 4 + 2);
        nodes.push_back({});
        // Iterative build (a stack of ranges) so that deep trees cannot overflow the call stack.
        struct Task {
            std::uint32_t node, begin, end;
        };
        std::vector<Task> stack{{0, 0, static_cast<std::uint32_t>(tris.size())}};
        while (!stack.empty()) {
            const Task task = stack.back();
            stack.pop_back();
            Box3 box, cbox;
            // std::min/max rather than Box3::add: fmin/fmax are library calls and this loop is the build's cost
            for (std::uint32_t i = task.begin; i < task.end; ++i) {
                for (Index v : tris[order[i]]) grow(box, positions[v]);
                grow(cbox, centroids[order[i]]);
            }
            nodes[task.node].box = box;
            const std::uint32_t count = task.end - task.begin;
            if (count <= 4) {
                nodes[task.node].first = task.begin;
                nodes[task.node].count = count;
                continue;
            }
            int axis = 0;
            const Vec3 extent = cbox.max - cbox.min;
            if (extent.y > extent[axis]) axis = 1;
            if (extent.z > extent[axis]) axis = 2;
            const std::uint32_t mid = task.begin + count / 2;
            std::nth_element(order.begin() + task.begin, order.begin() + mid, order.begin() + task.end,
                             [&](std::uint32_t l, std::uint32_t r) { return centroids[l][axis] < centroids[r][axis]; });
            const auto left = static_cast<std::uint32_t>(nodes.size());
            nodes.push_back({});
            nodes.push_back({});
            nodes[task.node].first = left;
            nodes[task.node].count = 0;
            stack.push_back({left, task.begin, mid});
            stack.push_back({left + 1, mid, task.end});
        }
    }

    Vec3 closest(const Vec3& p, std::size_t* triangle, double& best_d2) const {
        best_d2 = std::numeric_limits<double>::infinity();
        Vec3 best;
        std::size_t best_t = 0;
        if (nodes.empty()) return p;
        std::uint32_t stack[128];
        int top = 0;
        stack[top++] = 0;
        while (top > 0) {
            const Node& node = nodes[stack[--top]];
            if (box_distance2(node.box, p) >= best_d2) continue;
            if (node.count > 0) {
                for (std::uint32_t i = node.first; i < node.first + node.count; ++i) {
                    const auto& t = tris[order[i]];
                    const Vec3 q = closest_point_on_triangle(p, positions[t[0]], positions[t[1]], positions[t[2]]);
                    const double d2 = dot(p - q, p - q);
                    if (d2 < best_d2) {
                        best_d2 = d2;
                        best = q;
                        best_t = order[i];
                    }
                }
                continue;
            }
            // Visit the nearer child first so that the farther one is usually pruned.
            const std::uint32_t l = node.first, r = node.first + 1;
            const double dl = box_distance2(nodes[l].box, p), dr = box_distance2(nodes[r].box, p);
            if (top + 2 > 128) continue;  // unreachable: median splits keep the depth near log2(F / 4)
            if (dl < dr) {
                stack[top++] = r;
                stack[top++] = l;
            } else {
                stack[top++] = l;
                stack[top++] = r;
            }
        }
        if (triangle) *triangle = best_t;
        return best;
    }
};

SurfaceDistance::SurfaceDistance(const PolygonMesh& mesh) : impl_(std::make_unique<Impl>()) {
    impl_->positions = mesh.positions;
    impl_->tris = fan_triangles(mesh);
    impl_->build();
}
SurfaceDistance::~SurfaceDistance() = default;
SurfaceDistance::SurfaceDistance(SurfaceDistance&&) noexcept = default;
SurfaceDistance& SurfaceDistance::operator=(SurfaceDistance&&) noexcept = default;

double SurfaceDistance::distance(const Vec3& p) const {
    double d2 = 0;
    impl_->closest(p, nullptr, d2);
    return std::sqrt(d2);
}

Vec3 SurfaceDistance::closest_point(const Vec3& p, std::size_t* triangle) const {
    double d2 = 0;
    return impl_->closest(p, triangle, d2);
}

namespace {

struct OneSided {
    double max = 0, sum2 = 0;
    std::size_t count = 0;
};

//! Distances from every vertex of `from` and `samples` area-weighted points on its surface to `to`.
OneSided sample_to(const PolygonMesh& from, const SurfaceDistance& to, const MeshDistanceOptions& options) {
    OneSided out;
    auto add = [&](const Vec3& p) {
        const double d = to.distance(p);
        out.max = std::max(out.max, d);
        out.sum2 += d * d;
        ++out.count;
    };
    for (const Vec3& p : from.positions) add(p);
    if (options.samples == 0) return out;
    const auto tris = fan_triangles(from);
    std::vector<double> cumulative(tris.size());
    double total = 0;
    for (std::size_t t = 0; t < tris.size(); ++t) {
        const Vec3& a = from.positions[tris[t][0]];
        total += 0.5 * norm(cross(from.positions[tris[t][1]] - a, from.positions[tris[t][2]] - a));
        cumulative[t] = total;
    }
    if (!(total > 0)) return out;
    // The same stream for both directions, so that a mesh gets the same samples whichever side it is on and
    // mesh_distance(a, b) mirrors mesh_distance(b, a) exactly.
    Random random{options.seed * 0x2545F4914F6CDD1Dull};
    for (std::size_t s = 0; s < options.samples; ++s) {
        const double pick = random.uniform() * total;
        auto it = std::upper_bound(cumulative.begin(), cumulative.end(), pick);
        const std::size_t t = std::min<std::size_t>(static_cast<std::size_t>(it - cumulative.begin()), tris.size() - 1);
        // Uniform point in a triangle: (1 - sqrt(r1), sqrt(r1) (1 - r2), sqrt(r1) r2) (Osada et al. 2002).
        const double r1 = std::sqrt(random.uniform()), r2 = random.uniform();
        const Vec3& a = from.positions[tris[t][0]];
        const Vec3& b = from.positions[tris[t][1]];
        const Vec3& c = from.positions[tris[t][2]];
        add(a * (1 - r1) + b * (r1 * (1 - r2)) + c * (r1 * r2));
    }
    return out;
}

}  // namespace

MeshDistance mesh_distance(const PolygonMesh& a, const PolygonMesh& b, const MeshDistanceOptions& options) {
    const SurfaceDistance to_a(a), to_b(b);
    const OneSided forward = sample_to(a, to_b, options);
    const OneSided backward = sample_to(b, to_a, options);
    MeshDistance out;
    out.forward_max = forward.max;
    out.backward_max = backward.max;
    out.forward_samples = forward.count;
    out.backward_samples = backward.count;
    out.forward_rms = forward.count ? std::sqrt(forward.sum2 / static_cast<double>(forward.count)) : 0;
    out.backward_rms = backward.count ? std::sqrt(backward.sum2 / static_cast<double>(backward.count)) : 0;
    out.hausdorff = std::max(forward.max, backward.max);
    const std::size_t n = forward.count + backward.count;
    out.rms = n ? std::sqrt((forward.sum2 + backward.sum2) / static_cast<double>(n)) : 0;
    return out;
}

}  // namespace surfaced
