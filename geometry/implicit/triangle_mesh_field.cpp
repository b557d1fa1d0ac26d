// Signed distance to a triangle mesh as an implicit field (see triangle_mesh_field.h).
#include "geometry/implicit/triangle_mesh_field.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <utility>

namespace surfaced::implicit {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

//! Below this fraction of the bounding-box diagonal a query counts as on the surface for the gradient: p - c is then
//! too short for its direction to be trusted, and the closest triangle's normal is used instead.
constexpr double kSurfaceEpsilon = 1e-9;

//! Whether every edge is traversed as often in one direction as in the other (a closed surface, as a chain: the
//! winding number is then an integer everywhere off the mesh, and the sign changes only across the mesh). Vertices
//! at the same position count as one, so an unwelded closed mesh (STL-like) is closed too.
bool balanced_edges(const TriangleBvh& bvh, const std::vector<Vec3>& positions) {
    std::vector<Index> order(positions.size());
    for (std::size_t v = 0; v < order.size(); ++v) order[v] = static_cast<Index>(v);
    const auto less = [&](Index a, Index b) {
        const Vec3 &p = positions[a], &q = positions[b];
        if (p.x != q.x) return p.x < q.x;
        if (p.y != q.y) return p.y < q.y;
        if (p.z != q.z) return p.z < q.z;
        return a < b;
    };
    std::sort(order.begin(), order.end(), less);
    std::vector<Index> canonical(positions.size());
    for (std::size_t i = 0; i < order.size(); ++i)
        canonical[order[i]] =
            i > 0 && positions[order[i]] == positions[order[i - 1]] ? canonical[order[i - 1]] : order[i];
    // each directed edge as (min, max, +1 for min -> max / -1 for max -> min); sorted, the sums per edge must vanish
    struct Directed {
        Index lo, hi;
        int direction;
    };
    std::vector<Directed> edges;
    edges.reserve(bvh.triangles.size() * 3);
    for (const BvhTriangle& t : bvh.triangles)
        for (int k = 0; k < 3; ++k) {
            const Index a = canonical[t.vertices[static_cast<std::size_t>(k)]],
                        b = canonical[t.vertices[static_cast<std::size_t>((k + 1) % 3)]];
            if (a != b) edges.push_back(a < b ? Directed{a, b, 1} : Directed{b, a, -1});  // no zero-length edges
        }
    std::sort(edges.begin(), edges.end(),
              [](const Directed& x, const Directed& y) { return x.lo != y.lo ? x.lo < y.lo : x.hi < y.hi; });
    for (std::size_t i = 0; i < edges.size();) {
        std::int64_t sum = 0;
        std::size_t j = i;
        for (; j < edges.size() && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi; ++j)
            sum += edges[j].direction;
        if (sum != 0) return false;
        i = j;
    }
    return true;
}

}  // namespace

TriangleMeshField::TriangleMeshField(TriangleBvh bvh, WindingTree tree, std::vector<Vec3> positions,
                                     const WindingNumberOptions& winding)
    : bvh_(std::move(bvh)), tree_(std::move(tree)), positions_(std::move(positions)), winding_(winding) {
    surface_epsilon_ = kSurfaceEpsilon * bvh_.bounds().diagonal();
    closed_ = balanced_edges(bvh_, positions_);
}

FieldKind TriangleMeshField::kind() const { return closed_ ? FieldKind::ExactDistance : FieldKind::General; }

double TriangleMeshField::lipschitz() const { return closed_ ? 1.0 : std::numeric_limits<double>::infinity(); }

bool TriangleMeshField::evaluate(const Vec3& p, SurfacePoint& closest, double& sign) const {
    auto near = closest_point(bvh_, p);
    if (!near) return false;  // only for a non-finite query: the hierarchy is not empty
    auto w = winding_number_value(bvh_, tree_, p, winding_);
    if (!w) return false;
    closest = *near;
    sign = *w >= 0.5 ? -1.0 : 1.0;
    return true;
}

double TriangleMeshField::value(const Vec3& p) const {
    SurfacePoint closest;
    double sign = 1;
    if (!evaluate(p, closest, sign)) return kNaN;
    return sign * closest.distance;
}

Vec3 TriangleMeshField::gradient(const Vec3& p) const {
    SurfacePoint closest;
    double sign = 1;
    if (!evaluate(p, closest, sign)) return {kNaN, kNaN, kNaN};
    const Vec3 away = p - closest.point;
    if (closest.distance > surface_epsilon_) return away * (sign / closest.distance);
    const Vec3& a = positions_[closest.vertices[0]];
    const Vec3& b = positions_[closest.vertices[1]];
    const Vec3& c = positions_[closest.vertices[2]];
    Vec3 n = cross(b - a, c - a);
    const double length = norm(n);
    if (!(length > 0)) {
        // a degenerate (zero-area) closest triangle has no normal: the direction away from it, or any unit vector
        if (closest.distance > 0) return away * (sign / closest.distance);
        return {0, 0, 1};
    }
    n *= 1.0 / length;
    // f grows along the gradient: outside (sign +1) that is away from the surface, inside towards it
    if (sign * dot(away, n) < 0) n *= -1.0;
    return n;
}

Result<FieldPtr> triangle_mesh_field(const PolygonMesh& mesh, const TriangleMeshFieldOptions& options) {
    if (mesh.face_count() == 0)
        return make_error(ErrorCode::InvalidArgument, "a mesh field needs at least one face (the mesh has none)");
    if (!options.winding.exact && !(options.winding.accuracy > 1 && std::isfinite(options.winding.accuracy)))
        return make_error(ErrorCode::InvalidArgument, "winding accuracy must be finite and > 1");
    BvhOptions bvh_options = options.bvh;
    bvh_options.triangulate = true;
    auto bvh = build_bvh(mesh, bvh_options);  // validates the mesh first (finite coordinates, indices, faces)
    if (!bvh) return bvh.error();
    if (bvh->empty())
        return make_error(ErrorCode::InvalidArgument, "a mesh field needs at least one triangle (the mesh has none)");
    WindingTree tree = build_winding_tree(bvh.value());
    return FieldPtr(std::make_shared<const TriangleMeshField>(std::move(bvh.value()), std::move(tree), mesh.positions,
                                                              options.winding));
}

}  // namespace surfaced::implicit
