// Point queries and ray casting (see query.h).
#include "geometry/implicit/query.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace surfaced::implicit {
namespace {

constexpr int kMaxBisections = 64;
constexpr int kCancelPollSteps = 256;

Vec3 unit_or_zero(const Vec3& v) {
    const double n = norm(v);
    return (n > 0 && std::isfinite(n)) ? v * (1.0 / n) : Vec3{};
}

RayHit make_hit(const Field& field, const Vec3& o, const Vec3& d, double t, int steps) {
    RayHit hit;
    hit.hit = true;
    hit.t = t;
    hit.point = o + d * t;
    hit.normal = unit_or_zero(field.gradient(hit.point));
    hit.steps = steps;
    return hit;
}

bool uses_sphere_tracing(const Field& field) {
    return field.kind() != FieldKind::General && std::isfinite(field.lipschitz()) && field.lipschitz() > 0;
}

//! Casts one ray (direction already unit). Returns false if the cancel fired.
bool trace(const Field& field, const Vec3& o, const Vec3& d, const RayOptions& options, RayHit& out) {
    out = RayHit{};
    int steps = 0;
    auto cancelled = [&] { return steps % kCancelPollSteps == 0 && options.cancel.requested(); };
    if (uses_sphere_tracing(field)) {
        const double lipschitz = std::max(field.lipschitz(), 1e-12);
        double t = 0;
        while (steps < options.max_steps) {
            const double v = field.value(o + d * t);
            ++steps;
            if (cancelled()) return false;
            if (!std::isfinite(v)) break;
            const double step = std::abs(v) / lipschitz;
            if (step <= options.hit_tolerance) {
                out = make_hit(field, o, d, t, steps);
                return true;
            }
            t += step;
            if (t > options.max_distance) break;
        }
        out.steps = steps;
        return true;
    }

    // General field: fixed steps, sign change, bisection.
    const double h =
        options.general_step > 0 ? options.general_step : options.max_distance / static_cast<double>(options.max_steps);
    double t0 = 0, v0 = field.value(o);
    ++steps;
    if (std::isfinite(v0) && std::abs(v0) <= options.hit_tolerance) {
        out = make_hit(field, o, d, 0, steps);
        return true;
    }
    while (steps < options.max_steps && t0 < options.max_distance) {
        const double t1 = std::min(t0 + h, options.max_distance);
        const double v1 = field.value(o + d * t1);
        ++steps;
        if (cancelled()) return false;
        if (std::isfinite(v1) && std::abs(v1) <= options.hit_tolerance) {
            out = make_hit(field, o, d, t1, steps);
            return true;
        }
        if (std::isfinite(v0) && std::isfinite(v1) && ((v0 < 0) != (v1 < 0))) {
            double lo = t0, hi = t1, vlo = v0;
            for (int i = 0; i < kMaxBisections && hi - lo > options.hit_tolerance; ++i) {
                const double mid = 0.5 * (lo + hi);
                const double vm = field.value(o + d * mid);
                ++steps;
                if (!std::isfinite(vm)) break;
                if ((vm < 0) == (vlo < 0)) {
                    lo = mid;
                    vlo = vm;
                } else {
                    hi = mid;
                }
            }
            out = make_hit(field, o, d, 0.5 * (lo + hi), steps);
            return true;
        }
        t0 = t1;
        v0 = v1;
    }
    out.steps = steps;
    return true;
}

GeoError cancelled_error() { return make_error(ErrorCode::Cancelled, "the query was cancelled (deadline passed)"); }

}  // namespace

const char* to_string(PointClass c) {
    switch (c) {
        case PointClass::Inside: return "inside";
        case PointClass::On: return "on";
        case PointClass::Outside: return "outside";
        case PointClass::Undefined: return "undefined";
    }
    return "undefined";
}

PointClass classify(double value, double tolerance) {
    if (std::isnan(value)) return PointClass::Undefined;
    if (value < -tolerance) return PointClass::Inside;
    if (value > tolerance) return PointClass::Outside;
    return PointClass::On;
}

Result<std::vector<PointSample>> query_points(const Field& field, std::span<const Vec3> points,
                                              const PointQueryOptions& options) {
    if (!(options.tolerance >= 0) || !std::isfinite(options.tolerance))
        return make_error(ErrorCode::InvalidArgument, "tolerance must be finite and >= 0");
    std::vector<PointSample> out;
    out.reserve(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (i % 1024 == 0 && options.cancel.requested()) return cancelled_error();
        PointSample s;
        s.value = field.value(points[i]);
        s.gradient = field.gradient(points[i]);
        s.cls = classify(s.value, options.tolerance);
        out.push_back(s);
    }
    return out;
}

RayHit cast_ray(const Field& field, const Ray& ray, const RayOptions& options) {
    RayOptions uncancelled = options;
    uncancelled.cancel = Cancel{};
    RayHit hit;
    trace(field, ray.origin, unit_or_zero(ray.direction), uncancelled, hit);
    return hit;
}

Result<std::vector<RayHit>> cast_rays(const Field& field, std::span<const Ray> rays, const RayOptions& options) {
    if (!(options.max_distance > 0) || !std::isfinite(options.max_distance))
        return make_error(ErrorCode::InvalidArgument, "max_distance must be finite and > 0");
    if (options.max_steps < 1) return make_error(ErrorCode::InvalidArgument, "max_steps must be >= 1");
    if (!(options.hit_tolerance > 0) || !std::isfinite(options.hit_tolerance))
        return make_error(ErrorCode::InvalidArgument, "hit_tolerance must be finite and > 0");
    if (!(options.general_step >= 0) || !std::isfinite(options.general_step))
        return make_error(ErrorCode::InvalidArgument, "general_step must be finite and >= 0");
    std::vector<RayHit> out(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const Ray& ray = rays[i];
        const double n = norm(ray.direction);
        if (!is_finite(ray.origin) || !std::isfinite(n) || n == 0)
            return element_error(ErrorCode::InvalidArgument,
                                 "ray " + std::to_string(i) + " needs a finite origin and a non-zero direction",
                                 ElementKind::None, static_cast<std::int64_t>(i));
        if (options.cancel.requested()) return cancelled_error();
        if (!trace(field, ray.origin, ray.direction * (1.0 / n), options, out[i])) return cancelled_error();
    }
    return out;
}

}  // namespace surfaced::implicit
