// Uniform Catmull-Clark and Loop refinement: the public entry points (subdivide.h).
//
// Each level: build the child topology (topology.cpp); compute the child points (interpolate.cpp), with the smooth
// weights (rules.h) and the crease rules (creases.cpp); finally subdivide the sharpness values for the child level
// (creases.cpp). Texture coordinates are refined the same way on a topology of their own (face_varying.cpp); the
// limit surface, when asked for, is evaluated on the last level (limit.cpp).
#include "geometry/subdivision/subdivide.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <thread>
#include <string>

#include "geometry/subdivision/creases.h"
#include "geometry/subdivision/face_varying.h"
#include "geometry/subdivision/interpolate.h"
#include "geometry/subdivision/limit.h"
#include "geometry/subdivision/topology.h"

namespace surfaced {

namespace {

using subdivision::Channel;
using subdivision::Level;
using subdivision::LevelInput;
using subdivision::Neighbourhood;
using subdivision::Sharpness;

bool use_threads(const SubdivisionOptions& options) {
    return options.threads != 1 && std::thread::hardware_concurrency() > 1;
}

std::uint64_t saturating_mul(std::uint64_t a, std::uint64_t b) {
    if (a != 0 && b > std::numeric_limits<std::uint64_t>::max() / a) return std::numeric_limits<std::uint64_t>::max();
    return a * b;
}

}  // namespace

Status validate_for_subdivision(const PolygonMesh& mesh) {
    ValidateOptions options;
    options.allow_repeated_vertices = true;
    return validate(mesh, options);
}

std::uint64_t predicted_face_count(const PolygonMesh& mesh, SubdivisionScheme scheme, int levels) {
    if (levels <= 0) return mesh.face_count();
    std::uint64_t faces = scheme == SubdivisionScheme::CatmullClark ? mesh.face_indices.size() : 4 * mesh.face_count();
    for (int l = 1; l < levels; ++l) faces = saturating_mul(faces, 4);
    return faces;
}

std::uint64_t predicted_vertex_count(const PolygonMesh& mesh, SubdivisionScheme scheme, int levels) {
    std::uint64_t v = mesh.vertex_count(), e = subdivision::build_base_level(mesh).edge_count(), f = mesh.face_count();
    std::uint64_t corners = mesh.face_indices.size();
    constexpr std::uint64_t kMax = std::numeric_limits<std::uint64_t>::max() / 8;
    for (int l = 0; l < levels; ++l) {
        if (v > kMax || e > kMax || f > kMax || corners > kMax) return std::numeric_limits<std::uint64_t>::max();
        if (scheme == SubdivisionScheme::CatmullClark) {
            const std::uint64_t nv = v + f + e, ne = 2 * e + corners, nf = corners;
            v = nv;
            e = ne;
            f = nf;
            corners = 4 * nf;
        } else {
            const std::uint64_t nv = v + e, ne = 2 * e + 3 * f, nf = 4 * f;
            v = nv;
            e = ne;
            f = nf;
            corners = 3 * nf;
        }
    }
    return v;
}

namespace {

constexpr std::uint64_t kIndexLimit = std::numeric_limits<Index>::max() - 1;

// Whether `levels` levels of refinement keep every face and vertex index within 32 bits.
bool fits_indices(const PolygonMesh& mesh, SubdivisionScheme scheme, int levels) {
    return predicted_face_count(mesh, scheme, levels) <= kIndexLimit / 4 &&
           predicted_vertex_count(mesh, scheme, levels) <= kIndexLimit;
}

// The checks subdivide() makes before refining: options, mesh, Loop's triangles, the index budget.
Status check_input(const PolygonMesh& mesh, const SubdivisionOptions& options) {
    if (options.levels < 0)
        return make_error(ErrorCode::InvalidArgument, "levels must be >= 0, got " + std::to_string(options.levels));
    if (Status valid = validate_for_subdivision(mesh); !valid) return valid.error();
    if (options.scheme == SubdivisionScheme::Loop) {
        for (std::size_t f = 0; f < mesh.face_count(); ++f)
            if (mesh.face_size(f) != 3)
                return element_error(ErrorCode::NotTriangleMesh,
                                     "face " + std::to_string(f) + " has " + std::to_string(mesh.face_size(f)) +
                                         " vertices; Loop subdivision needs triangles",
                                     ElementKind::Face, static_cast<std::int64_t>(f));
    }
    if (options.levels > 0 && !fits_indices(mesh, options.scheme, options.levels))
        return make_error(ErrorCode::BudgetExceeded, "the refined mesh would exceed 2^32 indices");
    return Ok{};
}

// Refinement state: the finest level reached, with its sharpness and points; and the requested level, kept apart
// when refinement continues past it to evaluate the limit surface.
struct Refinement {
    Level level;
    Sharpness sharp;
    std::vector<Vec3> points;
    Level output_level;
    Sharpness output_sharp;
};

// Refines `r` (on entry: the base level) `total` times; the level after options.levels refinements is copied to
// r.output_level/output_sharp when `total` goes past it. Fails (Cancelled) only when options.cancel fires.
Status refine_levels(Refinement& r, const SubdivisionOptions& options, int total, bool threaded) {
    const bool loop = options.scheme == SubdivisionScheme::Loop;
    const bool past_output = total > options.levels;
    std::vector<Vec3> dst;
    int level_done = 0;
    const auto cancelled = [&] {
        return make_error(ErrorCode::Cancelled, "subdivision cancelled at level " + std::to_string(level_done) +
                                                    " of " + std::to_string(total) + " (deadline or shutdown)");
    };
    for (int l = 0; l < total; ++l, ++level_done) {
        if (options.cancel.requested()) return cancelled();
        const bool last = l + 1 == total;
        const Neighbourhood n = subdivision::neighbourhood(r.level, r.sharp, options.crease_method);
        Level child = loop ? subdivision::refine_triangles(r.level, !last || options.limit_surface, threaded)
                           : subdivision::refine_quads(r.level, !last || options.limit_surface, threaded);
        if (options.cancel.requested()) return cancelled();
        dst.clear();  // every point is written below: growing need not copy the stale ones
        dst.resize(child.vertex_count);
        const LevelInput in{r.level,
                            r.sharp,
                            options.crease_method,
                            l == 0 ? options.triangle_rule : TriangleRule::Catmark,
                            options.loop_weights,
                            threaded};
        if (loop)
            subdivision::interpolate_loop(in, n, r.points.data(), dst.data());
        else
            subdivision::interpolate_catmark(in, n, r.points.data(), dst.data());
        if (options.cancel.requested()) return cancelled();
        Sharpness child_sharp = subdivision::refine_sharpness(r.level, child, r.sharp, n, options.crease_method, loop,
                                                              last && !options.limit_surface);
        if (l + 1 == options.levels && past_output) {
            r.output_level = child;
            r.output_sharp = child_sharp;
        }
        r.level = std::move(child);
        r.sharp = std::move(child_sharp);
        r.points.swap(dst);
    }
    return Ok{};
}

// The output mesh from the refined state: positions (or, with options.limit_surface, limit positions and normals of
// the requested level's vertices, evaluated on the finest level), faces without holes, and the refined UVs.
PolygonMesh output_mesh(Refinement& r, std::optional<Channel>& uv, const SubdivisionOptions& options,
                        bool past_output) {
    PolygonMesh out;
    if (options.limit_surface) {
        // vertices of the requested level are the first ones of every finer level (children of vertices first)
        const Index count = past_output ? r.output_level.vertex_count : r.level.vertex_count;
        out.positions.resize(count);
        out.normals.resize(count);
        subdivision::evaluate_limit(r.level, r.sharp.edge, r.sharp.vertex, options.scheme == SubdivisionScheme::Loop,
                                    options.loop_weights == LoopWeights::Warren, r.points.data(), count,
                                    out.positions.data(), out.normals.data());
        if (past_output) {
            r.level = std::move(r.output_level);
            r.sharp = std::move(r.output_sharp);
        }
    } else {
        out.positions = std::move(r.points);
    }
    if (uv) {
        out.uvs.reserve(uv->values.size());
        for (const Vec3& value : uv->values) out.uvs.push_back({value.x, value.y});
    }
    const Level& level = r.level;
    if (r.sharp.hole.empty()) {
        out.face_offsets = std::move(r.level.face_offsets);
        out.face_indices = std::move(r.level.face_verts);
        if (uv) out.uv_indices = std::move(uv->level.face_verts);
    } else {
        for (Index f = 0; f < level.face_count(); ++f) {
            if (r.sharp.hole[f]) continue;
            const Index begin = level.face_offsets[f], size = level.face_offsets[f + 1] - begin;
            out.add_face({level.face_verts.data() + begin, size});
            if (uv)
                out.uv_indices.insert(out.uv_indices.end(), uv->level.face_verts.begin() + begin,
                                      uv->level.face_verts.begin() + begin + size);
        }
    }
    return out;
}

}  // namespace

Result<PolygonMesh> subdivide(const PolygonMesh& mesh, const SubdivisionOptions& options) {
    if (Status valid = check_input(mesh, options); !valid) return valid.error();
    const BoundaryInterpolation boundary =
        options.use_mesh_boundary_tag && mesh.tags.boundary ? *mesh.tags.boundary : options.boundary;

    Refinement r;
    r.level = subdivision::build_base_level(mesh);
    auto base = subdivision::base_sharpness(mesh, r.level, boundary, options.use_mesh_tags);
    if (!base) return base.error();
    r.sharp = std::move(base).value();

    const int extra = options.limit_surface ? limit_extra_levels(mesh, options) : 0;
    const int total = options.levels + extra;
    if (extra > 0 && !fits_indices(mesh, options.scheme, total))
        return make_error(ErrorCode::BudgetExceeded, "evaluating the limit surface would exceed 2^32 indices");

    const bool threaded = use_threads(options);
    // Texture coordinates: refined alongside, to the requested level.
    std::optional<Channel> uv;
    if (mesh.has_uvs()) uv = subdivision::refine_uvs(mesh, r.level, r.sharp, options, threaded);

    r.points = mesh.positions;
    if (Status refined = refine_levels(r, options, total, threaded); !refined) return refined.error();
    if (options.levels == 0 && extra > 0) {
        r.output_level = subdivision::build_base_level(mesh);
        r.output_sharp = subdivision::base_sharpness(mesh, r.output_level, boundary, options.use_mesh_tags).value();
    }
    return output_mesh(r, uv, options, extra > 0);
}

int limit_extra_levels(const PolygonMesh& mesh, const SubdivisionOptions& options) {
    if (!options.limit_surface) return 0;
    // sharpness decays by at least 1 per level with either crease method
    float max_semi = 0.0f;
    if (options.use_mesh_tags) {
        for (const Crease& c : mesh.tags.creases)
            if (subdivision::is_semi_sharp(static_cast<float>(c.sharpness)))
                max_semi = std::max(max_semi, static_cast<float>(c.sharpness));
        for (const Corner& c : mesh.tags.corners)
            if (subdivision::is_semi_sharp(static_cast<float>(c.sharpness)))
                max_semi = std::max(max_semi, static_cast<float>(c.sharpness));
    }
    const int decay = std::max(0, static_cast<int>(std::ceil(max_semi)) - options.levels);
    const bool needs_quads =
        options.scheme == SubdivisionScheme::CatmullClark && options.levels == 0 && !mesh.is_triangle_mesh() && [&] {
            for (std::size_t f = 0; f < mesh.face_count(); ++f)
                if (mesh.face_size(f) != 4) return true;
            return false;
        }();
    return std::max(decay, needs_quads ? 1 : 0);
}

}  // namespace surfaced
