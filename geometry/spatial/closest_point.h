// Closest point on a triangle mesh: the nearest surface point to a query, with the face it lies on, its barycentric
// coordinates in that face's triangle and the distance.
//
// Reference: C. Ericson, "Real-Time Collision Detection", 2005, sec. 5.1.5 (Voronoi regions of a triangle).
#pragma once

#include <array>
#include <limits>
#include <optional>

#include "geometry/spatial/bvh.h"

namespace surfaced {

//! A point on the surface: `point` = sum of barycentric[k] * position of vertices[k] (the corners of the triangle it
//! lies on; for a polygon, one triangle of its triangulation), on mesh face `face`.
struct SurfacePoint {
    Vec3 point;
    double distance = 0;  //!< from the query
    Index face = kInvalidIndex;
    std::array<Index, 3> vertices{kInvalidIndex, kInvalidIndex, kInvalidIndex};
    std::array<double, 3> barycentric{0, 0, 0};
};

struct ClosestPointOptions {
    //! Only surface points at most this far from the query count; farther means no answer (and a faster query).
    double max_distance = std::numeric_limits<double>::infinity();
};

//! The closest point of triangle (a, b, c) to p and its barycentric coordinates (for a, b, c). Exact regions for
//! degenerate triangles too (a segment or a point): the answer is then on the nearest of the three edges.
struct TrianglePoint {
    Vec3 point;
    std::array<double, 3> barycentric{1, 0, 0};
};
TrianglePoint triangle_closest_point(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

//! The nearest point of the surface to `query`, by a depth-first descent that visits the nearer child first and skips
//! boxes farther than the best point so far. Ties (several points at one distance) go to one of them. Nothing for an
//! empty hierarchy, a non-finite query or when the surface is farther than options.max_distance.
std::optional<SurfacePoint> closest_point(const TriangleBvh& bvh, const Vec3& query,
                                          const ClosestPointOptions& options = {});

}  // namespace surfaced
