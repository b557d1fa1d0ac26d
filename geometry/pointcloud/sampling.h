// Point samples of a surface, for tests and demos: area-uniform samples of a polygon mesh, and samples of the zero
// set of an implicit field.
#pragma once

#include <cstddef>
#include <cstdint>

#include "geometry/core/cancel.h"
#include "geometry/core/result.h"
#include "geometry/implicit/field.h"
#include "geometry/mesh/polygon_mesh.h"
#include "geometry/pointcloud/point_cloud.h"

namespace surfaced {

struct MeshSamplingOptions {
    std::size_t count = 10'000;
    std::uint64_t seed = 1;  //!< same seed, same mesh, same count: the same points on every platform
    Cancel cancel;
};

//! `count` points distributed uniformly by area over the mesh's faces (polygons fan-triangulated; a face is chosen
//! with probability proportional to its area, then a uniform point in it), each with the unit normal of the
//! triangle it lies in. Errors: whatever validate(mesh) reports, InvalidArgument (zero total area), Cancelled.
//! Cost: O(faces + count log faces).
Result<PointCloud> sample_mesh(const PolygonMesh& mesh, const MeshSamplingOptions& options = {});

struct FieldSamplingOptions {
    std::size_t count = 10'000;
    std::uint64_t seed = 1;
    //! Accept a projected point when |f| <= tolerance; 0 means 1e-6 of the bounds' diagonal.
    double tolerance = 0;
    int newton_steps = 16;  //!< projection steps per candidate, 1..100
    //! Candidates tried before giving up: count * max_attempts_per_point (a field with little surface inside the
    //! bounds yields fewer points, never an endless loop). Each candidate costs up to 4 * (newton_steps + 1) field
    //! evaluations (value and a central-difference gradient).
    std::size_t max_attempts_per_point = 20;
    Cancel cancel;
};

//! Points on the zero set f = 0 inside `bounds`: uniform random points in the box, each moved by Newton steps
//! along the gradient (p <- p - f(p) grad f / |grad f|^2) and kept when |f| <= tolerance and it is still inside
//! the box. Normals are the normalised gradient (outward, as f < 0 inside). The density follows the projection,
//! so it is not exactly area-uniform. May return fewer than `count` points (see max_attempts_per_point).
//! Errors: InvalidArgument (empty or non-finite bounds, options out of range, no point found at all), Cancelled.
Result<PointCloud> sample_field(const implicit::Field& field, const Box3& bounds,
                                const FieldSamplingOptions& options = {});

}  // namespace surfaced
