// Binned SAH construction (Wald 2007): at each node the triangle centroids are dropped into `bins` equal slabs per
// axis, and the split between two slabs with the lowest surface area cost A_L N_L + A_R N_R is compared with the cost
// of a leaf. The nodes are written depth-first into one array, so a left child needs no index.
#include "geometry/spatial/bvh.h"

#include <algorithm>
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

void grow(Box3& b, const Box3& o) {
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
            Box3 acc;
            std::size_t acc_count = 0;
            for (int k = bins - 1; k > 0; --k) {
                grow(acc, bin[static_cast<std::size_t>(k)].bounds);
                acc_count += bin[static_cast<std::size_t>(k)].count;
                right_area[static_cast<std::size_t>(k)] = half_area(acc);
                right_count[static_cast<std::size_t>(k)] = acc_count;
            }
            acc = Box3{};
            acc_count = 0;
            for (int k = 0; k < bins - 1; ++k) {  // split between bin k and k + 1
                grow(acc, bin[static_cast<std::size_t>(k)].bounds);
                acc_count += bin[static_cast<std::size_t>(k)].count;
                const std::size_t rc = right_count[static_cast<std::size_t>(k + 1)];
                if (acc_count == 0 || rc == 0) continue;
                // traversal step costs about one triangle test
                const double cost = 1.0 + (half_area(acc) * static_cast<double>(acc_count) +
                                           right_area[static_cast<std::size_t>(k + 1)] * static_cast<double>(rc)) *
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
    return bvh;
}

}  // namespace surfaced
