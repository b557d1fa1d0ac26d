// Signed distance to a triangle mesh as an implicit field (see triangle_mesh_field.h).
#include "geometry/implicit/triangle_mesh_field.h"

#include <cmath>
#include <limits>
#include <memory>
#include <utility>

namespace surfaced::implicit {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

//! Below this fraction of the bounding-box diagonal a query counts as on the surface for the gradient: p - c is then
//! too short for its direction to be trusted, and the closest triangle's normal is used instead.
constexpr double kSurfaceEpsilon = 1e-9;

}  // namespace

TriangleMeshField::TriangleMeshField(TriangleBvh bvh, WindingTree tree, std::vector<Vec3> positions,
                                     const WindingNumberOptions& winding)
    : bvh_(std::move(bvh)), tree_(std::move(tree)), positions_(std::move(positions)), winding_(winding) {
    surface_epsilon_ = kSurfaceEpsilon * bvh_.bounds().diagonal();
}

bool TriangleMeshField::evaluate(const Vec3& p, SurfacePoint& closest, double& sign) const {
    auto near = closest_point(bvh_, p);
    if (!near) return false;  // only for a non-finite query: the hierarchy is not empty
    auto w = winding_number(bvh_, tree_, p, winding_);
    if (!w) return false;
    closest = *near;
    sign = w->value >= 0.5 ? -1.0 : 1.0;
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
