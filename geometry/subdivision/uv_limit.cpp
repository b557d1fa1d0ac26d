// The UVs' limit (uv_limit.h): the face-varying value mesh, with its sharpness as tags, under LimitSurfaceEvaluator.
#include "geometry/subdivision/uv_limit.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "geometry/subdivision/creases.h"
#include "geometry/subdivision/face_varying.h"
#include "geometry/subdivision/topology.h"

namespace surfaced {

namespace {

//! The value mesh of `c` as a PolygonMesh: the UVs as positions (u, v, 0), the channel's sharpness as tags.
PolygonMesh value_mesh(const subdivision::Channel& c) {
    const subdivision::Level& level = c.level;
    PolygonMesh out;
    out.positions = c.values;
    out.face_offsets = level.face_offsets;
    out.face_indices = level.face_verts;
    for (Index e = 0; e < level.edge_count(); ++e)
        if (subdivision::is_sharp(c.sharp.edge[e]))
            out.tags.creases.push_back({level.edge_verts[2 * e], level.edge_verts[2 * e + 1],
                                        std::min<double>(c.sharp.edge[e], kInfiniteSharpness)});
    for (Index v = 0; v < level.vertex_count; ++v)
        if (subdivision::is_sharp(c.sharp.vertex[v]))
            out.tags.corners.push_back({v, std::min<double>(c.sharp.vertex[v], kInfiniteSharpness)});
    for (Index f = 0; f < static_cast<Index>(c.sharp.hole.size()); ++f)
        if (c.sharp.hole[f]) out.tags.holes.push_back(f);
    return out;
}

//! Bfr's quad sub-face tiling of an N-gon (limit_evaluation.h): tiles per row.
int tiles_per_row(std::size_t n) {
    return n < 10 ? 2 + (n > 4 ? 1 : 0) : 1 + static_cast<int>(std::floor(std::sqrt(static_cast<double>(n - 1))));
}

//! The tile of an N-gon's domain holding (u, v) (a point on a tile's far edge, x + 1/2, belongs to it), or -1.
long subface_of(std::size_t n, double u, double v) {
    if (!(u >= 0) || !(v >= 0)) return -1;
    const double fx = std::floor(u), fy = std::floor(v);
    if (u - fx > 0.5 || v - fy > 0.5) return -1;
    const double d = tiles_per_row(n);
    if (fx >= d) return -1;
    const double index = fx + d * fy;
    return index < static_cast<double>(n) ? static_cast<long>(index) : -1;
}

}  // namespace

bool limit_domain_contains(std::size_t face_size, double u, double v) {
    if (face_size == 4) return u >= 0 && u <= 1 && v >= 0 && v <= 1;
    return subface_of(face_size, u, v) >= 0;
}

Result<UvLimitEvaluator> UvLimitEvaluator::create(const PolygonMesh& mesh, const SubdivisionOptions& options,
                                                  const LimitEvaluationOptions& evaluation) {
    if (!mesh.has_uvs()) return make_error(ErrorCode::InvalidArgument, "the mesh has no texture coordinates");
    // the position evaluator checks the mesh, the scheme and the options the same way
    auto positions = LimitSurfaceEvaluator::create(mesh, options, evaluation);
    if (!positions) return positions.error();

    UvLimitEvaluator out;
    out.approximated_.assign(mesh.face_count(), 0);
    if (options.uv_interpolation == UvInterpolation::All) {
        out.face_offsets_ = mesh.face_offsets;
        out.corner_uvs_.reserve(mesh.uv_indices.size());
        for (const Index i : mesh.uv_indices) out.corner_uvs_.push_back(mesh.uvs[i]);
        return out;
    }
    const BoundaryInterpolation boundary =
        options.use_mesh_boundary_tag && mesh.tags.boundary ? *mesh.tags.boundary : options.boundary;
    const subdivision::Level level = subdivision::build_base_level(mesh);
    auto sharp = subdivision::base_sharpness(mesh, level, boundary, options.use_mesh_tags);
    if (!sharp) return sharp.error();
    SubdivisionOptions base = options;
    base.levels = 0;
    const subdivision::Channel channel = subdivision::refine_uvs(mesh, level, sharp.value(), base, false);

    // OpenSubdiv's dependent sharpness (UvOverride): the value is a corner until its sibling's semi-sharp edges have
    // decayed, then a crease with the fractional weight of the edges that decay last. When their sharpness at the
    // sibling decays by one per level (uniform creasing, or Chaikin's with a single semi-sharp edge there) and one
    // edge decays last, that is the value's vertex sharpness (the same last level, the same weight; measured equal
    // to Bfr). Otherwise (Chaikin with several semi-sharp edges, several edges decaying last) the faces using the
    // value are reported inexact.
    subdivision::Channel tagged = channel;
    for (const subdivision::UvOverride& o : channel.overrides) {
        std::vector<float> semi;
        for (Index e = 0; e < channel.level.edge_count(); ++e) {
            const float s = channel.sharp.edge[e];
            if ((channel.level.edge_verts[2 * e] == o.sibling || channel.level.edge_verts[2 * e + 1] == o.sibling) &&
                subdivision::is_semi_sharp(s))
                semi.push_back(s);
        }
        const float sharpest = semi.empty() ? 0.0f : *std::max_element(semi.begin(), semi.end());
        const auto last =
            std::count_if(semi.begin(), semi.end(), [&](float s) { return std::ceil(s) == std::ceil(sharpest); });
        if (last == 1 && (options.crease_method == CreaseMethod::Uniform || semi.size() == 1)) {
            tagged.sharp.vertex[o.value] = std::max(tagged.sharp.vertex[o.value], sharpest);
            continue;
        }
        for (std::size_t f = 0; f < mesh.face_count(); ++f)
            for (Index s = channel.level.face_offsets[f]; s < channel.level.face_offsets[f + 1]; ++s)
                if (channel.level.face_verts[s] == o.value) out.approximated_[f] = 1;
    }

    // the sharpness is all in the tags: edge-only adds nothing to the value mesh's own boundary edges, which are
    // tagged infinitely sharp already
    SubdivisionOptions value_options = options;
    value_options.boundary = BoundaryInterpolation::EdgeOnly;
    value_options.use_mesh_boundary_tag = false;
    value_options.use_mesh_tags = true;
    auto values = LimitSurfaceEvaluator::create(value_mesh(tagged), value_options, evaluation);
    if (!values) return values.error();
    out.values_ = std::move(values).value();
    return out;
}

Result<UvSample> UvLimitEvaluator::bilinear(std::size_t face, double u, double v) const {
    if (face + 1 >= face_offsets_.size())
        return make_error(ErrorCode::IndexOutOfRange, "face " + std::to_string(face) + " out of range (" +
                                                          std::to_string(face_offsets_.size() - 1) + " faces)");
    if (!std::isfinite(u) || !std::isfinite(v)) return make_error(ErrorCode::NonFinite, "u and v must be finite");
    const Vec2* c = corner_uvs_.data() + face_offsets_[face];
    const std::size_t n = face_offsets_[face + 1] - face_offsets_[face];
    const auto lerp = [](const Vec2& a, const Vec2& b, double t) {
        return Vec2{a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t};
    };
    const auto outside = [&] {
        return make_error(ErrorCode::InvalidArgument, "(u, v) = (" + std::to_string(u) + ", " + std::to_string(v) +
                                                          ") is outside face " + std::to_string(face) + "'s domain");
    };
    if (n == 4) {
        if (u < 0 || u > 1 || v < 0 || v > 1) return outside();
        return UvSample{lerp(lerp(c[0], c[1], u), lerp(c[3], c[2], u), v), true};
    }
    // an N-gon: sub-face i is the tile [x, x + 1/2] x [y, y + 1/2] with corner i, the midpoint of edge i, the centroid
    // and the midpoint of edge i - 1 at its corners (the first refinement's quad; linear refinement keeps it bilinear)
    const long i = subface_of(n, u, v);
    if (i < 0) return outside();
    const int d = tiles_per_row(n);
    const double x = static_cast<double>(i % d), y = static_cast<double>(i / d);
    Vec2 centre{0, 0};
    for (std::size_t k = 0; k < n; ++k) centre = Vec2{centre.x + c[k].x / double(n), centre.y + c[k].y / double(n)};
    const std::size_t k = static_cast<std::size_t>(i);
    const Vec2 corner = c[k], next_mid = lerp(c[k], c[(k + 1) % n], 0.5),
               prev_mid = lerp(c[k], c[(k + n - 1) % n], 0.5);
    const double s = 2 * (u - x), t = 2 * (v - y);
    return UvSample{lerp(lerp(corner, next_mid, s), lerp(prev_mid, centre, s), t), true};
}

Result<UvSample> UvLimitEvaluator::evaluate(std::size_t face, double u, double v) const {
    if (!values_) return bilinear(face, u, v);
    auto sample = values_->evaluate(face, u, v);
    if (!sample) return sample.error();
    return UvSample{Vec2{sample->position.x, sample->position.y}, sample->exact && !approximated_[face]};
}

Result<UvFaceSurface> UvLimitEvaluator::face_surface(std::size_t face, int levels) const {
    UvFaceSurface out;
    out.owner_ = this;
    out.face_ = face;
    if (!values_) {
        if (face + 1 >= face_offsets_.size())
            return make_error(ErrorCode::IndexOutOfRange, "face " + std::to_string(face) + " out of range (" +
                                                              std::to_string(face_offsets_.size() - 1) + " faces)");
        return out;
    }
    auto surface = values_->face_surface(face, levels);
    if (!surface) return surface.error();
    out.surface_ = std::move(surface).value();
    return out;
}

std::size_t UvLimitEvaluator::approximated_face_count() const {
    return static_cast<std::size_t>(std::count(approximated_.begin(), approximated_.end(), std::uint8_t{1}));
}

Result<UvSample> UvFaceSurface::evaluate(double u, double v) const {
    if (!surface_) return owner_->bilinear(face_, u, v);
    auto sample = surface_->evaluate(u, v);
    if (!sample) return sample.error();
    return UvSample{Vec2{sample->position.x, sample->position.y}, sample->exact && !owner_->approximated_[face_]};
}

}  // namespace surfaced
