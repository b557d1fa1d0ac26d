#include "geometry/pointcloud/sampling.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

namespace surfaced {
namespace {

constexpr std::size_t kPollEvery = 1024;

//! Uniform double in [0, 1) from the top 53 bits of a 64-bit Mersenne twister: mt19937_64's output sequence is
//! fixed by the standard, std::uniform_real_distribution's mapping is not, so this keeps seeds portable.
class Random {
public:
    explicit Random(std::uint64_t seed) : engine_(seed) {}
    double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }

private:
    std::mt19937_64 engine_;
};

}  // namespace

Result<PointCloud> sample_mesh(const PolygonMesh& mesh, const MeshSamplingOptions& options) {
    if (Status s = validate(mesh); !s) return s.error();
    if (mesh.face_count() == 0) return make_error(ErrorCode::InvalidArgument, "the mesh has no faces to sample");

    // fan triangles with their cumulative areas
    struct Triangle {
        Index a, b, c;
    };
    std::vector<Triangle> triangles;
    std::vector<double> cumulative;
    triangles.reserve(mesh.face_indices.size() - 2 * mesh.face_count());
    cumulative.reserve(triangles.capacity());
    double total = 0;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const auto face = mesh.face(f);
        for (std::size_t i = 1; i + 1 < face.size(); ++i) {
            const Vec3& p0 = mesh.positions[face[0]];
            const double area = 0.5 * norm(cross(mesh.positions[face[i]] - p0, mesh.positions[face[i + 1]] - p0));
            if (!(area > 0)) continue;
            total += area;
            triangles.push_back({face[0], face[i], face[i + 1]});
            cumulative.push_back(total);
        }
    }
    if (!(total > 0) || !std::isfinite(total))
        return make_error(ErrorCode::InvalidArgument, "the mesh has no area to sample (every face is degenerate)");

    PointCloud cloud;
    cloud.positions.reserve(options.count);
    cloud.normals.reserve(options.count);
    Random random(options.seed);
    for (std::size_t s = 0; s < options.count; ++s) {
        if (s % kPollEvery == 0 && options.cancel.requested())
            return make_error(ErrorCode::Cancelled, "mesh sampling was cancelled");
        // triangle by area: the first whose cumulative area exceeds u * total
        const double u = random.uniform() * total;
        std::size_t t =
            static_cast<std::size_t>(std::upper_bound(cumulative.begin(), cumulative.end(), u) - cumulative.begin());
        t = std::min(t, triangles.size() - 1);
        const Triangle& tri = triangles[t];
        const Vec3 &a = mesh.positions[tri.a], &b = mesh.positions[tri.b], &c = mesh.positions[tri.c];
        // uniform in the triangle: sqrt maps the first variate so that area, not parameter, is uniform
        const double r1 = std::sqrt(random.uniform()), r2 = random.uniform();
        // relative to a corner, so that a coordinate the three corners share is reproduced exactly
        cloud.positions.push_back(a + (b - a) * (r1 * (1.0 - r2)) + (c - a) * (r1 * r2));
        const Vec3 n = cross(b - a, c - a);
        cloud.normals.push_back(n * (1.0 / norm(n)));
    }
    return cloud;
}

Result<PointCloud> sample_field(const implicit::Field& field, const Box3& bounds, const FieldSamplingOptions& options) {
    if (bounds.empty() || !is_finite(bounds.min) || !is_finite(bounds.max) || !(bounds.diagonal() > 0))
        return make_error(ErrorCode::InvalidArgument, "sampling bounds must be a finite box with min < max");
    for (int i = 0; i < 3; ++i)
        if (!(bounds.max[i] > bounds.min[i]))
            return make_error(ErrorCode::InvalidArgument, "sampling bounds must have min < max on every axis");
    if (options.newton_steps < 1 || options.newton_steps > 100)
        return make_error(ErrorCode::InvalidArgument,
                          "newton_steps = " + std::to_string(options.newton_steps) + " is out of range 1..100");
    if (!(options.tolerance >= 0) || !std::isfinite(options.tolerance))
        return make_error(ErrorCode::InvalidArgument, "tolerance must be a finite number >= 0");
    if (options.max_attempts_per_point < 1 || options.max_attempts_per_point > 1000)
        return make_error(ErrorCode::InvalidArgument, "max_attempts_per_point is out of range 1..1000");
    const double tolerance = options.tolerance > 0 ? options.tolerance : 1e-6 * bounds.diagonal();
    const Vec3 extent = bounds.max - bounds.min;
    auto inside = [&](const Vec3& p) {
        for (int i = 0; i < 3; ++i)
            if (!(p[i] >= bounds.min[i] && p[i] <= bounds.max[i])) return false;
        return true;
    };

    PointCloud cloud;
    Random random(options.seed);
    const std::size_t attempts = options.count * options.max_attempts_per_point;
    for (std::size_t attempt = 0; attempt < attempts && cloud.size() < options.count; ++attempt) {
        if (attempt % kPollEvery == 0 && options.cancel.requested())
            return make_error(ErrorCode::Cancelled, "implicit sampling was cancelled");
        Vec3 p{bounds.min.x + extent.x * random.uniform(), bounds.min.y + extent.y * random.uniform(),
               bounds.min.z + extent.z * random.uniform()};
        double f = field.value(p);
        for (int step = 0; step < options.newton_steps && std::isfinite(f) && std::fabs(f) > tolerance; ++step) {
            const Vec3 g = field.gradient(p);
            const double g2 = dot(g, g);
            if (!(g2 > 0) || !std::isfinite(g2)) break;
            p -= g * (f / g2);
            if (!inside(p)) break;
            f = field.value(p);
        }
        if (!(std::fabs(f) <= tolerance) || !inside(p)) continue;
        const Vec3 g = field.gradient(p);
        const double len = norm(g);
        if (!(len > 0) || !std::isfinite(len)) continue;  // no direction to give the normal
        cloud.positions.push_back(p);
        cloud.normals.push_back(g * (1.0 / len));
    }
    if (cloud.empty())
        return make_error(ErrorCode::InvalidArgument,
                          "no point of the surface f = 0 was found inside the bounds after " +
                              std::to_string(attempts) + " attempts");
    return cloud;
}

}  // namespace surfaced
