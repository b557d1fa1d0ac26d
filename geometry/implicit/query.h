// Questions asked of an implicit field: which side of the surface points are on, the value and gradient there,
// and where rays first meet the surface.
//
// Ray casting. Fields with a Lipschitz bound (ExactDistance, DistanceBound) are sphere traced (Hart 1996): from t,
// step |f(p)| / L, which cannot jump over the surface; a hit is |f| / L <= hit_tolerance. General fields (algebraic
// expressions: their Lipschitz constant is only an estimate) are marched with fixed steps of `general_step` along
// the ray, looking for a sign change (or |f| <= hit_tolerance), which is then refined by bisection to
// hit_tolerance in t. The fallback finds every crossing where the field changes sign over an interval longer than
// general_step; thinner features (shorter than one step along the ray) can be missed. Each field evaluation counts
// as one step; max_steps bounds the marching (a ray that runs out is a miss with steps = max_steps); the
// bisection after a sign change adds at most 64 more.
//
// Rays start at t = 0 (a ray starting inside the solid reports where it leaves it). Directions are normalised, so t
// is a distance. Undefined values (NaN from an expression) classify as Undefined and are skipped while marching.
// Every function polls options.cancel between points / rays (and every 256 steps of one ray) and returns
// ErrorCode::Cancelled when it fires.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "geometry/core/cancel.h"
#include "geometry/core/result.h"
#include "geometry/implicit/field.h"

namespace surfaced::implicit {

enum class PointClass { Inside, On, Outside, Undefined };

//! Short stable name: "inside", "on", "outside", "undefined".
const char* to_string(PointClass c);

//! Inside when value < -tolerance, on when |value| <= tolerance, outside when value > tolerance (tolerance in the
//! field's value units: a distance for ExactDistance fields).
PointClass classify(double value, double tolerance);

struct PointQueryOptions {
    double tolerance = 1e-6;  //!< >= 0
    Cancel cancel;
};

struct PointSample {
    double value = 0;
    Vec3 gradient;
    PointClass cls = PointClass::Outside;
};

//! Value, gradient and class at each point.
Result<std::vector<PointSample>> query_points(const Field& field, std::span<const Vec3> points,
                                              const PointQueryOptions& options = {});

struct Ray {
    Vec3 origin;
    Vec3 direction;  //!< non-zero; normalised by the caster
};

struct RayOptions {
    double max_distance = 100;    //!< > 0: farthest t searched
    int max_steps = 1000;         //!< >= 1: field evaluations per ray
    double hit_tolerance = 1e-7;  //!< > 0
    double general_step = 0;      //!< step for General fields; 0 = max_distance / max_steps
    Cancel cancel;
};

struct RayHit {
    bool hit = false;
    double t = 0;  //!< along the normalised direction
    Vec3 point;
    Vec3 normal;    //!< unit gradient at the hit (outward); zero if the gradient vanishes there
    int steps = 0;  //!< field evaluations used
};

//! One ray. Precondition: |direction| > 0 and the options are in range (cast_rays checks both).
RayHit cast_ray(const Field& field, const Ray& ray, const RayOptions& options);

//! Many rays; InvalidArgument (element = ray index) for a zero or non-finite direction or out-of-range options.
Result<std::vector<RayHit>> cast_rays(const Field& field, std::span<const Ray> rays, const RayOptions& options = {});

}  // namespace surfaced::implicit
