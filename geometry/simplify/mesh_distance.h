// Distances between triangle meshes: Metro-style sampling of each surface and exact point-to-surface queries through
// an AABB tree.
//
// References: P. Cignoni, C. Rocchini, R. Scopigno, "Metro: Measuring Error on Simplified Surfaces", 1998.
//             C. Ericson, "Real-Time Collision Detection", 2005, sec. 5.1.5 (closest point on a triangle).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>

#include "geometry/core/types.h"
#include "geometry/mesh/polygon_mesh.h"

namespace surfaced {

//! Closest point to `p` on the triangle (a, b, c); works for degenerate triangles too.
Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);
//! Euclidean distance from `p` to the triangle (a, b, c).
double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

//! Nearest-point queries against the surface of a mesh (polygons fan-triangulated), through a bounding volume
//! hierarchy of its triangles (median splits, <= 4 triangles per leaf). Immutable after construction, so queries may
//! run concurrently. Build O(F log F), query O(log F) typical.
class SurfaceDistance {
public:
    explicit SurfaceDistance(const PolygonMesh& mesh);
    ~SurfaceDistance();
    SurfaceDistance(SurfaceDistance&&) noexcept;
    SurfaceDistance& operator=(SurfaceDistance&&) noexcept;

    //! Distance from p to the nearest point of the surface; +infinity for a mesh without faces.
    double distance(const Vec3& p) const;
    //! Nearest point of the surface and the triangle it lies on (index into the fan triangulation: face order).
    Vec3 closest_point(const Vec3& p, std::size_t* triangle = nullptr) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

struct MeshDistanceOptions {
    //! Area-weighted random samples per surface, in addition to every vertex. 0 = vertices only.
    std::size_t samples = 100'000;
    std::uint64_t seed = 1;  //!< the sampling is deterministic for a seed (own generator, same on every platform)
};

struct MeshDistance {
    double hausdorff = 0;                       //!< max(forward_max, backward_max)
    double rms = 0;                             //!< sqrt of the mean squared distance over both sample sets together
    double forward_max = 0, forward_rms = 0;    //!< samples of `a` to the surface of `b`
    double backward_max = 0, backward_rms = 0;  //!< samples of `b` to the surface of `a`
    std::size_t forward_samples = 0, backward_samples = 0;
};

//! Symmetric Hausdorff and two-sided RMS distance between the surfaces of `a` and `b`, sampled at every vertex plus
//! `options.samples` area-weighted points per surface. A sampled Hausdorff distance is a lower bound of the true one,
//! converging as samples grow. Both meshes need faces (a mesh without faces is at infinite distance).
MeshDistance mesh_distance(const PolygonMesh& a, const PolygonMesh& b, const MeshDistanceOptions& options = {});

}  // namespace surfaced
