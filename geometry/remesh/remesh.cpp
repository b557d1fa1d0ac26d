// remesh(), the public entry point: checks the options, triangulates the input, picks the target edge length, and
// runs Remesher (remesher.h) through its iteration loop, Remesher::run, which steers the working target towards L.
// The operations the loop calls live in their own files: halfedges.cpp, constraints.cpp, split.cpp, collapse.cpp,
// flip.cpp, relax.cpp, degenerate.cpp; the quality report in quality.cpp.
#include "geometry/remesh/remesh.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "geometry/mesh/triangulate.h"
#include "geometry/remesh/remesher.h"
#include "geometry/simplify/mesh_distance.h"

namespace surfaced::remesh_detail {

// Bounds of the working target edge length that run() steers the mean edge length to L with, in L.
constexpr double kMinWorking = 0.8, kMaxWorking = 1.25;
// Within this share of L the mean edge length is left alone; kFinalRelaxations rounds of flips and relaxation end run().
constexpr double kSettled = 0.02;
constexpr int kFinalRelaxations = 3;

//! The (4/5, 4/3) band leaves a mesh stable whose edges average anywhere in it (longest-edge bisection of a coarse
//! grid lands at 1.13 L, of a finer one at 0.88 L), so the thresholds follow a working target that is corrected
//! after every iteration by the ratio of L to the mean edge length reached (unless within kSettled of L), within
//! [kMinWorking, kMaxWorking] L; when the mean crosses L the working target goes half way back to L (the mesh
//! answers a correction over several iterations, and a pure integral correction would overshoot). Then
//! kFinalRelaxations rounds of flips and relaxation smooth the last splits and collapses.
Status Remesher::run(const RemeshOptions& options, double length) {
    double working = length;
    double last_error = 0;
    for (int it = 0; it < options.iterations; ++it) {
        if (options.cancel.requested()) return cancelled();
        const double high = 4.0 / 3.0 * working, low = 4.0 / 5.0 * working;
        if (auto s = split_long_edges(high, options); !s) return s;
        if (auto s = collapse_short_edges(low, high, options); !s) return s;
        if (auto s = equalize_valences(options); !s) return s;
        if (auto s = relax(options); !s) return s;
        const double mean = mean_live_edge_length();
        const double error = mean - length;
        // the mean crossed L: the corrections so far overshoot, take half of them back (in ratio)
        if (error * last_error < 0) working = std::sqrt(working * length);
        last_error = error;
        if (mean > 0 && std::abs(error) > kSettled * length)
            working = std::clamp(working * length / mean, kMinWorking * length, kMaxWorking * length);
    }
    // the last corrections leave fresh splits and collapses: relax them without changing the vertex count
    for (int it = 0; it < std::min(options.iterations, kFinalRelaxations); ++it) {
        if (options.cancel.requested()) return cancelled();
        if (auto s = equalize_valences(options); !s) return s;
        if (auto s = relax(options); !s) return s;
    }
    if (options.iterations > 0) remove_caps();
    remove_degenerate_faces();
    return Ok{};
}

}  // namespace surfaced::remesh_detail

namespace surfaced {
namespace {

using remesh_detail::cancelled;
using remesh_detail::Remesher;

double mean_edge_length(const PolygonMesh& mesh) {
    double sum = 0;
    std::size_t n = 0;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        auto t = mesh.face(f);
        for (std::size_t j = 0; j < t.size(); ++j) {
            sum += norm(mesh.positions[t[(j + 1) % t.size()]] - mesh.positions[t[j]]);
            ++n;
        }
    }
    return n ? sum / static_cast<double>(n) : 0.0;
}

}  // namespace

Result<RemeshResult> remesh(const PolygonMesh& mesh, const RemeshOptions& options) {
    if (auto valid = validate(mesh); !valid) return valid.error();
    if (options.iterations < 0)
        return make_error(ErrorCode::InvalidArgument,
                          "iterations must be >= 0, got " + std::to_string(options.iterations));
    if (!(options.feature_angle_degrees >= 0 && options.feature_angle_degrees <= 180))
        return make_error(ErrorCode::InvalidArgument, "the feature angle must be in [0, 180] degrees");
    if (mesh.face_count() == 0) return make_error(ErrorCode::InvalidArgument, "the mesh has no faces");

    RemeshResult result;
    result.triangulated = !mesh.is_triangle_mesh();
    PolygonMesh input = result.triangulated ? triangulate(mesh) : mesh;
    input.uvs.clear();
    input.uv_indices.clear();
    input.normals.clear();
    input.tags = {};

    double length = 0;
    if (options.target_edge_length)
        length = *options.target_edge_length;
    else if (options.relative_edge_length)
        length = *options.relative_edge_length * input.bounds().diagonal();
    else
        length = mean_edge_length(input);
    if (!(std::isfinite(length) && length > 0))
        return make_error(ErrorCode::InvalidArgument, "the target edge length must be finite and > 0");
    result.target_edge_length = length;

    Remesher remesher;
    if (auto built = remesher.build(input); !built) return built.error();
    remesher.remove_degenerate_faces();
    remesher.set_constraints(input, options, length);
    result.feature_edges = remesher.feature_edges();
    result.boundary_edges = remesher.boundary_edges();
    if (auto ran = remesher.run(options, length); !ran) return ran.error();
    result.mesh = remesher.output();
    result.before = measure_quality(input);
    result.after = measure_quality(result.mesh);
    if (options.measure_hausdorff) {
        if (options.cancel.requested()) return cancelled();
        result.hausdorff = mesh_distance(input, result.mesh).hausdorff;
    }
    return result;
}

}  // namespace surfaced
