// Binned SAH construction (Wald 2007): at each node the triangle centroids are dropped into `bins` equal slabs per
// axis, and the split between two slabs with the lowest surface area cost A_L N_L + A_R N_R is compared with the cost
// of a leaf. The nodes are written depth-first into one array, so a left child needs no index.
#include "geometry/spatial/bvh.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "geometry/mesh/triangulate.h"

namespace surfaced {

namespace {

double half_area(const Box3& b) {
    if (b.empty()) return 0.0;
    const double dx = b.max.x - b.min.x, dy = b.max.y - b.min.y, dz = b.max.z - b.min.z;
    return dx * dy + dy * dz + dz * dx;
}

//! Inlined: the binning calls it once per triangle per axis.
[[gnu::always_inline]] inline void grow(Box3& b, const Box3& o) {
    b.min.x = std::min(b.min.x, o.min.x);
    b.min.y = std::min(b.min.y, o.min.y);
    b.min.z = std::min(b.min.z, o.min.z);
    b.max.x = std::max(b.max.x, o.max.x);
    b.max.y = std::max(b.max.y, o.max.y);
    b.max.z = std::max(b.max.z, o.max.z);
}

//! A node still to be built: the range of `order` it covers, its parent when it is a right child, and its depth.
struct Task {
    std::size_t begin = 0, end = 0;
    std::size_t right_of = SIZE_MAX;  //!< parent whose right child this is, or SIZE_MAX
    std::size_t depth = 1;
};

struct Bin {
    Box3 bounds;
    std::size_t count = 0;
};

//! The slab a centroid coordinate falls in; clamped before the conversion so it is always in [0, bins).
int bin_of(double c, double lo, double scale, int bins) {
    const double t = (c - lo) * scale;
    if (!(t > 0)) return 0;
    if (t >= bins - 1) return bins - 1;
    return static_cast<int>(t);
}

//! Subtrees with at most this many triangles become one leaf of the ray layout. Sixteen rather than eight: the
//! filter runs through a larger leaf's consecutive blocks faster than a ray takes the extra level of nodes that
//! smaller leaves need (docs/benchmarks.md).
constexpr Index kRayLeafTriangles = 16;
//! A ray leaf with more triangles than this is split when its node has a free slot.
constexpr Index kRayLeafSplit = 4;

//! The float at or below x (at or above for round_up): boxes rounded outward still contain what they held.
float round_down(double x) {
    float f = static_cast<float>(x);
    if (static_cast<double>(f) > x) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
    return f;
}
float round_up(double x) {
    float f = static_cast<float>(x);
    if (static_cast<double>(f) < x) f = std::nextafter(f, std::numeric_limits<float>::infinity());
    return f;
}

//! Collapses the binary hierarchy into 8-wide ray nodes: each ray node takes a binary node's two children and keeps
//! opening the largest (by surface area) of its children that is not a ray leaf until it has eight. A binary subtree
//! of at most kRayLeafTriangles triangles is a ray leaf (its triangles are contiguous, the tree being depth-first).
void build_ray_nodes(TriangleBvh& bvh) {
    const std::size_t n = bvh.nodes.size();
    // each binary node's triangle range, children after their parent in the array
    std::vector<Index> first(n), count(n);
    for (std::size_t i = n; i-- > 0;) {
        const BvhNode& node = bvh.nodes[i];
        if (node.is_leaf()) {
            first[i] = node.index;
            count[i] = node.count;
        } else {
            first[i] = first[i + 1];
            count[i] = count[i + 1] + count[node.index];
        }
    }
    auto ray_leaf = [&](Index b) { return bvh.nodes[b].is_leaf() || count[b] <= kRayLeafTriangles; };

    bvh.ray_nodes.clear();
    bvh.ray_nodes.reserve(n / 4 + 1);
    const Box3& root = bvh.nodes[0].bounds;
    bvh.ray_centre = (root.min + root.max) * 0.5;
    bvh.ray_extent = 0;
    for (int a = 0; a < 3; ++a)
        bvh.ray_extent = std::max({bvh.ray_extent, root.max[a] - bvh.ray_centre[a], bvh.ray_centre[a] - root.min[a]});
    // every triangle in float and copied, four a block in the order of `triangles` (the last block's unused lanes
    // zero)
    bvh.ray_triangles.resize((bvh.triangles.size() + 3) / 4);
    for (std::size_t t = 0; t < bvh.triangles.size(); ++t) {
        RayTriangles& block = bvh.ray_triangles[t / 4];
        block.triangle[t % 4] = bvh.triangles[t];
        for (std::size_t c = 0; c < 3; ++c)
            for (int a = 0; a < 3; ++a)
                block.p[3 * c + static_cast<std::size_t>(a)][t % 4] =
                    static_cast<float>(bvh.triangles[t].p[c][a] - bvh.ray_centre[a]);
    }
    struct Pending {
        Index binary, ray;
    };
    std::vector<Pending> stack;
    bvh.ray_nodes.emplace_back();
    stack.push_back({0, 0});
    while (!stack.empty()) {
        const Pending p = stack.back();
        stack.pop_back();
        Index children[kRayNodeWidth];
        int size = 0;
        if (ray_leaf(p.binary)) {
            children[size++] = p.binary;  // the root alone
        } else {
            children[size++] = p.binary + 1;
            children[size++] = bvh.nodes[p.binary].index;
            while (size < kRayNodeWidth) {
                // the largest inner child; when there is none, the largest leaf that fills more than one block of
                // four (its halves take no more blocks, and the node's free slots test their boxes at no extra cost)
                int open = -1;
                double open_area = -1;
                for (int pass = 0; pass < 2 && open < 0; ++pass)
                    for (int k = 0; k < size; ++k) {
                        const Index c = children[k];
                        const bool candidate =
                            pass == 0 ? !ray_leaf(c) : !bvh.nodes[c].is_leaf() && count[c] > kRayLeafSplit;
                        if (!candidate) continue;
                        const double area = half_area(bvh.nodes[c].bounds);
                        if (area > open_area) {
                            open_area = area;
                            open = k;
                        }
                    }
                if (open < 0) break;
                const Index b = children[open];
                children[open] = b + 1;
                children[size++] = bvh.nodes[b].index;
            }
        }
        for (int k = 0; k < kRayNodeWidth; ++k) {
            Index child = 0, leaf_count = 0;
            Box3 box;  // empty: +inf min, -inf max
            if (k < size) {
                const Index b = children[k];
                box = bvh.nodes[b].bounds;
                if (ray_leaf(b)) {
                    child = first[b];
                    leaf_count = count[b];
                } else {
                    child = static_cast<Index>(bvh.ray_nodes.size());
                    bvh.ray_nodes.emplace_back();
                    stack.push_back({b, child});
                }
            }
            RayNode& node = bvh.ray_nodes[p.ray];
            const double lo[3] = {box.min.x, box.min.y, box.min.z}, hi[3] = {box.max.x, box.max.y, box.max.z};
            for (int a = 0; a < 3; ++a) {
                node.box[a][k] = k < size ? round_down(lo[a]) : std::numeric_limits<float>::infinity();
                node.box[3 + a][k] = k < size ? round_up(hi[a]) : -std::numeric_limits<float>::infinity();
            }
            node.child[k] = child;
            node.count[k] = static_cast<std::uint8_t>(leaf_count);
        }
    }
    bvh.ray_nodes.shrink_to_fit();
}

}  // namespace

Result<TriangleBvh> build_bvh(const PolygonMesh& input, const BvhOptions& options) {
    if (options.max_leaf_size < 1 || options.max_leaf_size > 64)
        return make_error(ErrorCode::InvalidArgument, "max_leaf_size must be in 1..64");
    if (options.bins < 2 || options.bins > 256) return make_error(ErrorCode::InvalidArgument, "bins must be in 2..256");
    if (auto status = validate(input); !status) return status.error();

    TriangleBvh bvh;
    bvh.face_count = input.face_count();

    // triangles in face order, each with the face it came from
    PolygonMesh split;
    const PolygonMesh* mesh = &input;
    if (!input.is_triangle_mesh()) {
        if (!options.triangulate) {
            for (std::size_t f = 0; f < input.face_count(); ++f)
                if (input.face_size(f) != 3)
                    return element_error(ErrorCode::NotTriangleMesh,
                                         "face " + std::to_string(f) + " has " + std::to_string(input.face_size(f)) +
                                             " vertices; the hierarchy takes triangles only",
                                         ElementKind::Face, static_cast<std::int64_t>(f));
        }
        split = triangulate(input);
        mesh = &split;
        bvh.triangulated = true;
    }
    const std::size_t n = mesh->face_count();
    if (n == 0) return bvh;
    if (n >= std::size_t{kInvalidIndex} / 2)
        return make_error(ErrorCode::BudgetExceeded, "too many triangles for 32-bit node indices");

    std::vector<Index> source_face(n);
    {
        std::size_t t = 0;
        for (std::size_t f = 0; f < input.face_count(); ++f)
            for (std::size_t k = 2; k < input.face_size(f); ++k) source_face[t++] = static_cast<Index>(f);
    }

    std::vector<Box3> boxes(n);
    std::vector<Vec3> centroids(n);
    std::vector<Index> order(n);
    for (std::size_t t = 0; t < n; ++t) {
        const auto face = mesh->face(t);
        for (Index v : face) boxes[t].add(mesh->positions[v]);
        centroids[t] = (boxes[t].min + boxes[t].max) * 0.5;
        order[t] = static_cast<Index>(t);
    }

    const int bins = options.bins;
    const auto max_leaf = static_cast<std::size_t>(options.max_leaf_size);
    std::vector<Bin> bin(static_cast<std::size_t>(bins));
    std::vector<double> right_area(static_cast<std::size_t>(bins));
    std::vector<std::size_t> right_count(static_cast<std::size_t>(bins));

    bvh.nodes.reserve(2 * n / std::max<std::size_t>(1, max_leaf / 2) + 1);
    std::vector<Task> stack{{0, n, SIZE_MAX, 1}};
    std::size_t built = 0;
    while (!stack.empty()) {
        const Task task = stack.back();
        stack.pop_back();
        if (++built % 4096 == 0 && options.cancel.requested())
            return make_error(ErrorCode::Cancelled, "building the triangle hierarchy was cancelled");

        const std::size_t self = bvh.nodes.size();
        if (task.right_of != SIZE_MAX) bvh.nodes[task.right_of].index = static_cast<Index>(self);
        bvh.nodes.emplace_back();
        bvh.depth = std::max(bvh.depth, task.depth);

        Box3 bounds, centre_bounds;
        for (std::size_t i = task.begin; i < task.end; ++i) {
            grow(bounds, boxes[order[i]]);
            centre_bounds.add(centroids[order[i]]);
        }
        bvh.nodes[self].bounds = bounds;
        const std::size_t count = task.end - task.begin;

        // best binned split over the three axes
        const double leaf_cost = static_cast<double>(count);
        const double inv_area = half_area(bounds) > 0 ? 1.0 / half_area(bounds) : 0.0;
        double best_cost = std::numeric_limits<double>::infinity();
        int best_axis = -1, best_bin = 0;
        for (int axis = 0; axis < 3 && count > 1; ++axis) {
            const double lo = centre_bounds.min[axis], extent = centre_bounds.max[axis] - lo;
            if (!(extent > 0)) continue;
            const double scale = bins / extent;
            std::fill(bin.begin(), bin.end(), Bin{});
            for (std::size_t i = task.begin; i < task.end; ++i) {
                Bin& b = bin[static_cast<std::size_t>(bin_of(centroids[order[i]][axis], lo, scale, bins))];
                ++b.count;
                grow(b.bounds, boxes[order[i]]);
            }
            // Only the non-empty bins matter: the splits between two consecutive non-empty bins a < b (after bin
            // a, ..., after bin b - 1) all part the triangles alike, and the first of them, after a, is the one
            // the sweep keeps. right_area and right_count are indexed by the non-empty bin that starts the right side.
            int used[256];
            int used_count = 0;
            for (int k = 0; k < bins; ++k)
                if (bin[static_cast<std::size_t>(k)].count != 0) used[used_count++] = k;
            Box3 acc;
            std::size_t acc_count = 0;
            for (int u = used_count - 1; u > 0; --u) {
                const Bin& b = bin[static_cast<std::size_t>(used[u])];
                grow(acc, b.bounds);
                acc_count += b.count;
                right_area[static_cast<std::size_t>(u)] = half_area(acc);
                right_count[static_cast<std::size_t>(u)] = acc_count;
            }
            acc = Box3{};
            acc_count = 0;
            for (int u = 0; u + 1 < used_count; ++u) {  // split after bin used[u]
                const Bin& b = bin[static_cast<std::size_t>(used[u])];
                grow(acc, b.bounds);
                acc_count += b.count;
                const std::size_t rc = right_count[static_cast<std::size_t>(u + 1)];
                const int k = used[u];
                // traversal step costs about one triangle test
                const double cost = 1.0 + (half_area(acc) * static_cast<double>(acc_count) +
                                           right_area[static_cast<std::size_t>(u + 1)] * static_cast<double>(rc)) *
                                              inv_area;
                if (cost < best_cost) {
                    best_cost = cost;
                    best_axis = axis;
                    best_bin = k;
                }
            }
        }

        const bool leaf = count == 1 || (count <= max_leaf && (best_axis < 0 || leaf_cost <= best_cost));
        if (leaf) {
            bvh.nodes[self].index = static_cast<Index>(task.begin);
            bvh.nodes[self].count = static_cast<Index>(count);
            continue;
        }

        std::size_t mid;
        if (best_axis >= 0) {
            const double lo = centre_bounds.min[best_axis];
            const double scale = bins / (centre_bounds.max[best_axis] - lo);
            const auto first = order.begin() + static_cast<std::ptrdiff_t>(task.begin);
            const auto last = order.begin() + static_cast<std::ptrdiff_t>(task.end);
            mid = static_cast<std::size_t>(
                std::partition(first, last,
                               [&](Index t) { return bin_of(centroids[t][best_axis], lo, scale, bins) <= best_bin; }) -
                order.begin());
        } else {
            // every centroid in one point (or no useful split) but too many for a leaf: halve the range
            mid = task.begin + count / 2;
        }
        stack.push_back({mid, task.end, self, task.depth + 1});
        stack.push_back({task.begin, mid, SIZE_MAX, task.depth + 1});
    }

    bvh.triangles.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const Index t = order[i];
        const auto face = mesh->face(t);
        BvhTriangle& out = bvh.triangles[i];
        for (int k = 0; k < 3; ++k) {
            out.vertices[static_cast<std::size_t>(k)] = face[static_cast<std::size_t>(k)];
            out.p[static_cast<std::size_t>(k)] = mesh->positions[face[static_cast<std::size_t>(k)]];
        }
        out.face = source_face[t];
    }
    bvh.nodes.shrink_to_fit();
    // leaf sizes fit the ray nodes' 8-bit counts (max_leaf_size <= 64)
    if (options.ray_nodes) build_ray_nodes(bvh);
    return bvh;
}

}  // namespace surfaced
