// Uniform Catmull-Clark and Loop refinement.
//
// Each level: build the child topology (topology.cpp), classify the parent's edges and vertices (smooth, crease,
// corner), then compute child positions in three passes that only scatter into arrays: face points, edge points,
// vertex points. The weights are OpenSubdiv's (rules.h); the output is numbered as OpenSubdiv Far numbers it.
#include "geometry/subdivision/subdivide.h"

#include <limits>
#include <string>

#include "geometry/subdivision/rules.h"
#include "geometry/subdivision/topology.h"

namespace surfaced {

namespace {

using subdivision::Level;

// Edge and vertex classification of one level.
struct Classification {
    std::vector<std::uint8_t> edge_sharp;      // boundary or non-manifold: infinitely sharp
    std::vector<std::uint32_t> vertex_faces;   // incident faces
    std::vector<std::uint32_t> vertex_edges;   // incident edges
    std::vector<std::uint8_t> vertex_sharp_edges;  // incident sharp edges (saturating)
    std::vector<std::uint8_t> vertex_corner;   // corner rule: position kept
};

Classification classify(const Level& level, BoundaryInterpolation boundary) {
    const Index nv = level.vertex_count, ne = level.edge_count();
    Classification c;
    std::vector<std::uint32_t> edge_faces(ne, 0);
    for (Index e : level.face_edges) ++edge_faces[e];
    c.edge_sharp.resize(ne);
    for (Index e = 0; e < ne; ++e) c.edge_sharp[e] = edge_faces[e] != 2;

    c.vertex_faces.assign(nv, 0);
    for (Index v : level.face_verts) ++c.vertex_faces[v];
    c.vertex_edges.assign(nv, 0);
    c.vertex_sharp_edges.assign(nv, 0);
    for (Index e = 0; e < ne; ++e) {
        for (int k = 0; k < 2; ++k) {
            const Index v = level.edge_verts[2 * e + k];
            ++c.vertex_edges[v];
            if (c.edge_sharp[e] && c.vertex_sharp_edges[v] < 255) ++c.vertex_sharp_edges[v];
        }
    }
    c.vertex_corner.resize(nv);
    for (Index v = 0; v < nv; ++v) {
        const bool boundary_corner =
            boundary == BoundaryInterpolation::EdgeAndCorner && c.vertex_faces[v] == 1 && c.vertex_sharp_edges[v] > 0;
        // OpenSubdiv's vertex-vertex rule: more than two sharp edges, or a sharp vertex, is a corner.
        c.vertex_corner[v] = c.vertex_edges[v] == 0 || c.vertex_sharp_edges[v] > 2 || boundary_corner;
    }
    return c;
}

// Vertex points of either scheme: `dst` already holds, for smooth vertices, the weighted neighbourhood sums the
// scheme computed. Crease vertices (exactly two sharp edges) and corners are overwritten here.
void apply_sharp_vertex_rules(const Level& p, const Classification& c, const Vec3* src, Vec3* dst) {
    const Index nv = p.vertex_count, ne = p.edge_count();
    bool any_crease = false;
    for (Index v = 0; v < nv; ++v) {
        if (c.vertex_corner[v]) {
            dst[v] = src[v];
        } else if (c.vertex_sharp_edges[v] == 2) {
            dst[v] = subdivision::kCreaseVertexWeight * src[v];
            any_crease = true;
        }
    }
    if (!any_crease) return;
    for (Index e = 0; e < ne; ++e) {
        if (!c.edge_sharp[e]) continue;
        const Index a = p.edge_verts[2 * e], b = p.edge_verts[2 * e + 1];
        if (!c.vertex_corner[a] && c.vertex_sharp_edges[a] == 2) dst[a] += subdivision::kCreaseNeighbourWeight * src[b];
        if (!c.vertex_corner[b] && c.vertex_sharp_edges[b] == 2) dst[b] += subdivision::kCreaseNeighbourWeight * src[a];
    }
}

// One Catmull-Clark level: src has p.vertex_count points, dst gets nv + nf + ne.
void interpolate_catmark(const Level& p, const Classification& c, const Vec3* src, Vec3* dst) {
    const Index nv = p.vertex_count, nf = p.face_count(), ne = p.edge_count();
    Vec3* face_pts = dst + nv;
    Vec3* edge_pts = dst + nv + nf;

    // face points, and the sums they contribute to vertex points
    for (Index v = 0; v < nv; ++v) dst[v] = Vec3{};
    for (Index e = 0; e < ne; ++e) {
        const Index a = p.edge_verts[2 * e], b = p.edge_verts[2 * e + 1];
        edge_pts[e] = c.edge_sharp[e] ? 0.5 * (src[a] + src[b]) : subdivision::kCatmarkEdgeWeight * (src[a] + src[b]);
        dst[a] += src[b];
        dst[b] += src[a];
    }
    for (Index f = 0; f < nf; ++f) {
        const Index begin = p.face_offsets[f], end = p.face_offsets[f + 1];
        Vec3 sum{};
        for (Index i = begin; i < end; ++i) sum += src[p.face_verts[i]];
        const Vec3 fp = sum * (1.0 / static_cast<double>(end - begin));
        face_pts[f] = fp;
        const Vec3 quarter = subdivision::kCatmarkEdgeWeight * fp;
        for (Index i = begin; i < end; ++i) {
            dst[p.face_verts[i]] += fp;
            const Index e = p.face_edges[i];
            if (!c.edge_sharp[e]) edge_pts[e] += quarter;
        }
    }
    // smooth vertex points from the sums (edge neighbours + face points share the weight 1/n^2)
    for (Index v = 0; v < nv; ++v) {
        if (c.vertex_corner[v] || c.vertex_sharp_edges[v] >= 2) continue;
        const auto w = subdivision::catmark_smooth_vertex(static_cast<int>(c.vertex_faces[v]));
        dst[v] = w.vertex * src[v] + w.edge * dst[v];
    }
    apply_sharp_vertex_rules(p, c, src, dst);
}

// One Loop level: src has p.vertex_count points, dst gets nv + ne.
void interpolate_loop(const Level& p, const Classification& c, const Vec3* src, Vec3* dst) {
    const Index nv = p.vertex_count, nf = p.face_count(), ne = p.edge_count();
    Vec3* edge_pts = dst + nv;

    for (Index v = 0; v < nv; ++v) dst[v] = Vec3{};
    for (Index e = 0; e < ne; ++e) {
        const Index a = p.edge_verts[2 * e], b = p.edge_verts[2 * e + 1];
        edge_pts[e] = c.edge_sharp[e] ? 0.5 * (src[a] + src[b]) : subdivision::kLoopEdgeEndWeight * (src[a] + src[b]);
        dst[a] += src[b];
        dst[b] += src[a];
    }
    for (Index f = 0; f < nf; ++f) {
        const Index b = p.face_offsets[f];
        for (Index j = 0; j < 3; ++j) {
            const Index e = p.face_edges[b + j];
            if (!c.edge_sharp[e])
                edge_pts[e] += subdivision::kLoopEdgeOppositeWeight * src[p.face_verts[b + (j + 2) % 3]];
        }
    }
    for (Index v = 0; v < nv; ++v) {
        if (c.vertex_corner[v] || c.vertex_sharp_edges[v] >= 2) continue;
        const auto w = subdivision::loop_smooth_vertex(static_cast<int>(c.vertex_edges[v]));
        dst[v] = w.vertex * src[v] + w.edge * dst[v];
    }
    apply_sharp_vertex_rules(p, c, src, dst);
}

std::uint64_t saturating_mul(std::uint64_t a, std::uint64_t b) {
    if (a != 0 && b > std::numeric_limits<std::uint64_t>::max() / a) return std::numeric_limits<std::uint64_t>::max();
    return a * b;
}

std::uint64_t count_edges(const PolygonMesh& mesh) { return subdivision::build_base_level(mesh).edge_count(); }

}  // namespace

std::uint64_t predicted_face_count(const PolygonMesh& mesh, SubdivisionScheme scheme, int levels) {
    if (levels <= 0) return mesh.face_count();
    std::uint64_t faces = scheme == SubdivisionScheme::CatmullClark ? mesh.face_indices.size() : 4 * mesh.face_count();
    for (int l = 1; l < levels; ++l) faces = saturating_mul(faces, 4);
    return faces;
}

std::uint64_t predicted_vertex_count(const PolygonMesh& mesh, SubdivisionScheme scheme, int levels) {
    std::uint64_t v = mesh.vertex_count(), e = count_edges(mesh), f = mesh.face_count();
    std::uint64_t corners = mesh.face_indices.size();
    constexpr std::uint64_t kMax = std::numeric_limits<std::uint64_t>::max() / 8;
    for (int l = 0; l < levels; ++l) {
        if (v > kMax || e > kMax || f > kMax || corners > kMax) return std::numeric_limits<std::uint64_t>::max();
        if (scheme == SubdivisionScheme::CatmullClark) {
            const std::uint64_t nv = v + f + e, ne = 2 * e + corners, nf = corners;
            v = nv; e = ne; f = nf; corners = 4 * nf;
        } else {
            const std::uint64_t nv = v + e, ne = 2 * e + 3 * f, nf = 4 * f;
            v = nv; e = ne; f = nf; corners = 3 * nf;
        }
    }
    return v;
}

Result<PolygonMesh> subdivide(const PolygonMesh& mesh, const SubdivisionOptions& options) {
    if (options.levels < 0)
        return make_error(ErrorCode::InvalidArgument, "levels must be >= 0, got " + std::to_string(options.levels));
    if (Status valid = validate(mesh); !valid) return valid.error();
    const bool loop = options.scheme == SubdivisionScheme::Loop;
    if (loop) {
        for (std::size_t f = 0; f < mesh.face_count(); ++f)
            if (mesh.face_size(f) != 3)
                return make_error(ErrorCode::NotTriangleMesh,
                                  "face " + std::to_string(f) + " has " + std::to_string(mesh.face_size(f)) +
                                      " vertices; Loop subdivision needs triangles",
                                  -1, -1, static_cast<std::int64_t>(f));
    }
    if (options.levels == 0) {
        PolygonMesh out;
        out.positions = mesh.positions;
        out.face_offsets = mesh.face_offsets;
        out.face_indices = mesh.face_indices;
        return out;
    }
    constexpr std::uint64_t kIndexLimit = std::numeric_limits<Index>::max() - 1;
    const auto scheme = options.scheme;
    if (predicted_face_count(mesh, scheme, options.levels) * 4 > kIndexLimit ||
        predicted_vertex_count(mesh, scheme, options.levels) > kIndexLimit)
        return make_error(ErrorCode::BudgetExceeded, "the refined mesh would exceed 2^32 indices");

    const BoundaryInterpolation boundary =
        options.use_mesh_boundary_tag && mesh.tags.boundary ? *mesh.tags.boundary : options.boundary;

    Level level = subdivision::build_base_level(mesh);
    std::vector<Vec3> src = mesh.positions, dst;
    for (int l = 0; l < options.levels; ++l) {
        const bool last = l + 1 == options.levels;
        const Classification c = classify(level, boundary);
        Level child = loop ? subdivision::refine_triangles(level, !last) : subdivision::refine_quads(level, !last);
        dst.resize(child.vertex_count);
        if (loop)
            interpolate_loop(level, c, src.data(), dst.data());
        else
            interpolate_catmark(level, c, src.data(), dst.data());
        level = std::move(child);
        src.swap(dst);
    }

    PolygonMesh out;
    out.positions = std::move(src);
    out.face_offsets = std::move(level.face_offsets);
    out.face_indices = std::move(level.face_verts);
    return out;
}

}  // namespace surfaced
