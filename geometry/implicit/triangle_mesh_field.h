// A triangle mesh as an implicit field: the signed distance to the mesh (geometry/spatial/signed_distance.h), so that
// a mesh can take part in CSG, smooth blends, offsets and shells with the analytic primitives.
//
// Value: the Euclidean distance to the closest surface point, negative where the generalized winding number is
// >= 1/2. FieldKind::ExactDistance, Lipschitz 1, on a closed mesh (every edge shared by two faces traversing it in
// opposite directions, outward-oriented): there |f| is the distance to the surface f = 0, the mesh itself.
//
// Meshes with holes (or open sheets): the sign follows the winding number, which is smooth away from the mesh and
// crosses 1/2 on a surface that spans each hole (for a small hole, close to the minimal surface through its rim). So
// the zero set f = 0 is the mesh plus that closing sheet, and the solid is closed. But |f| is still the distance to
// the mesh alone: across the closing sheet, away from the mesh, f jumps from +d to -d. There f is neither a distance
// nor Lipschitz, sphere tracing may step through the sheet, and meshing finds the sheet only as a sign change between
// grid nodes (its vertices are placed on the jump, with gradients that are not the sheet's normal). Orientation:
// a closed mesh with inward-facing triangles has winding number -1 inside, so everything is "outside" (f >= 0).
//
// Gradient: s (p - c) / |p - c|, with c the closest surface point and s the sign, which is the exact gradient of the
// signed distance wherever it is differentiable; on the surface (|p - c| below 1e-9 of the mesh's bounding-box
// diagonal), the closest triangle's unit normal, turned to point where f grows.
//
// Cost per evaluation (value or gradient): one closest-point descent and one hierarchical winding number over the
// same BVH, each about O(log F) node visits for a query away from the surface (more near it, where leaves are summed
// exactly). Built once by the factory: O(F log F) time, O(F) memory; evaluation is const and thread-safe.
#pragma once

#include <cstddef>
#include <vector>

#include "geometry/core/result.h"
#include "geometry/implicit/primitives.h"
#include "geometry/mesh/polygon_mesh.h"
#include "geometry/spatial/bvh.h"
#include "geometry/spatial/closest_point.h"
#include "geometry/spatial/winding_number.h"

namespace surfaced::implicit {

struct TriangleMeshFieldOptions {
    //! How the sign's winding number is computed: the hierarchy with accuracy (beta) > 1 (default 2), or the exact
    //! sum over every triangle (O(F) per evaluation: small meshes only).
    WindingNumberOptions winding;
    //! The BVH build (leaf size, bins, cancellation). Polygons are always triangulated.
    BvhOptions bvh;
};

class TriangleMeshField final : public Field {
public:
    //! Use triangle_mesh_field(), which checks the mesh and options.
    TriangleMeshField(TriangleBvh bvh, WindingTree tree, std::vector<Vec3> positions,
                      const WindingNumberOptions& winding);

    double value(const Vec3& p) const override;
    Vec3 gradient(const Vec3& p) const override;
    FieldKind kind() const override { return FieldKind::ExactDistance; }
    double lipschitz() const override { return 1.0; }

    const TriangleBvh& bvh() const { return bvh_; }
    std::size_t triangle_count() const { return bvh_.triangles.size(); }

private:
    //! The closest surface point and the sign (+1 outside, -1 inside); false for a non-finite query.
    bool evaluate(const Vec3& p, SurfacePoint& closest, double& sign) const;

    TriangleBvh bvh_;
    WindingTree tree_;
    std::vector<Vec3> positions_;
    WindingNumberOptions winding_;
    double surface_epsilon_ = 0;
};

//! The signed-distance field of `mesh` (polygons are triangulated). InvalidArgument for a mesh without faces or
//! winding options out of range (accuracy <= 1 or not finite); the errors of validate() (NonFinite for a non-finite
//! coordinate, IndexOutOfRange, DegenerateFace, naming the vertex or face) and of build_bvh (Cancelled).
Result<FieldPtr> triangle_mesh_field(const PolygonMesh& mesh, const TriangleMeshFieldOptions& options = {});

}  // namespace surfaced::implicit
