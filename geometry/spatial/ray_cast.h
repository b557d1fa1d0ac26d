// Ray casting against a triangle mesh: the first hit (distance, face, barycentric coordinates, normal) or every hit.
// The ray-triangle test is watertight: a ray through an edge or a vertex shared by several triangles hits at least
// one of them, never slips between. Rays walk the hierarchy's 8-wide float ray layout when it was built
// (BvhOptions::ray_nodes, the default), with rounding margins that never lose a hit, and every hit is decided by the
// same double-precision test, so the answers do not depend on the layout.
//
// Reference: S. Woop, C. Benthin, I. Wald, "Watertight Ray/Triangle Intersection", JCGT 2(1), 2013.
#pragma once

#include <array>
#include <limits>
#include <optional>
#include <vector>

#include "geometry/spatial/bvh.h"

namespace surfaced {

//! The points origin + t * direction for t_min <= t <= t_max. The direction need not be unit length (t is then in
//! units of its length) but must not be zero.
struct Ray {
    Ray() = default;
    Ray(const Vec3& o, const Vec3& d, double t0 = 0, double t1 = std::numeric_limits<double>::infinity())
        : origin(o), direction(d), t_min(t0), t_max(t1) {}

    Vec3 origin;
    Vec3 direction;
    double t_min = 0;
    double t_max = std::numeric_limits<double>::infinity();
};

struct RayHit {
    double t = 0;
    Vec3 point;   //!< origin + t * direction
    Vec3 normal;  //!< unit normal of the triangle hit, by its vertex order (counter-clockwise seen from the front)
    Index face = kInvalidIndex;
    std::array<Index, 3> vertices{kInvalidIndex, kInvalidIndex, kInvalidIndex};  //!< corners of the triangle hit
    std::array<double, 3> barycentric{0, 0, 0};                                  //!< weights of those corners
};

//! The nearest hit with t in [t_min, t_max]; nothing for an empty hierarchy, a zero or non-finite direction, a
//! non-finite origin, or when the ray misses. Both sides of a triangle are hit (RayHit::normal tells which).
std::optional<RayHit> ray_first_hit(const TriangleBvh& bvh, const Ray& ray);

//! Every triangle the ray hits with t in [t_min, t_max], by increasing t. A ray through an edge or vertex shared by
//! several triangles hits each of those it touches (a hit per triangle, possibly at one t).
std::vector<RayHit> ray_all_hits(const TriangleBvh& bvh, const Ray& ray);

//! The watertight test of one triangle alone: t and the barycentric coordinates of a, b, c, or nothing. Use the
//! hierarchy for more than one triangle; this is the test it runs at each leaf.
struct RayTriangleHit {
    double t = 0;
    std::array<double, 3> barycentric{0, 0, 0};
};
std::optional<RayTriangleHit> ray_triangle(const Ray& ray, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace surfaced
