// Crease rules: the sharpness of the base level, its decay from level to level, and the fractional weight of a
// vertex whose rule changes (see creases.h).
#include "geometry/subdivision/creases.h"

#include <string>

namespace surfaced::subdivision {

Neighbourhood neighbourhood(const Level& level, const Sharpness& sharp, CreaseMethod method) {
    const Index nv = level.vertex_count, ne = level.edge_count();
    Neighbourhood n;
    n.vertex_faces.assign(nv, 0);
    for (Index v : level.face_verts) ++n.vertex_faces[v];
    n.vertex_edges.assign(nv, 0);
    n.sharp_offsets.assign(nv + 1, 0);
    for (Index e = 0; e < ne; ++e) {
        const Index a = level.edge_verts[2 * e], b = level.edge_verts[2 * e + 1];
        ++n.vertex_edges[a];
        ++n.vertex_edges[b];
        if (is_sharp(sharp.edge[e])) {
            ++n.sharp_offsets[a + 1];
            ++n.sharp_offsets[b + 1];
        }
    }
    for (Index v = 0; v < nv; ++v) n.sharp_offsets[v + 1] += n.sharp_offsets[v];
    n.sharp_edges.resize(n.sharp_offsets[nv]);
    std::vector<Index> fill(n.sharp_offsets.begin(), n.sharp_offsets.end() - 1);
    for (Index e = 0; e < ne; ++e)
        if (is_sharp(sharp.edge[e])) {
            n.sharp_edges[fill[level.edge_verts[2 * e]]++] = e;
            n.sharp_edges[fill[level.edge_verts[2 * e + 1]]++] = e;
        }
    for (Index v = 0; v < nv; ++v)
        if (is_sharp(sharp.vertex[v])) n.any_sharp_vertex = true;
    if (method == CreaseMethod::Chaikin) {
        n.semi_sum.assign(nv, 0.0f);
        n.semi_count.assign(nv, 0);
        for (Index v = 0; v < nv; ++v)
            for (Index i = n.sharp_offsets[v]; i < n.sharp_offsets[v + 1]; ++i) {
                const float s = sharp.edge[n.sharp_edges[i]];
                if (is_semi_sharp(s)) {
                    n.semi_sum[v] += s;
                    ++n.semi_count[v];
                }
            }
    }
    return n;
}

float fractional_weight(float parent_vertex, float child_vertex, const float* parent_edges, const float* child_edges,
                        Index count) {
    int transitions = 0;
    float sum = 0.0f;
    if (is_sharp(parent_vertex) && !is_sharp(child_vertex)) {
        transitions = 1;
        sum = parent_vertex;
    }
    for (Index i = 0; i < count; ++i)
        if (is_sharp(parent_edges[i]) && !is_sharp(child_edges[i])) {
            sum += parent_edges[i];
            ++transitions;
        }
    if (transitions == 0) return 0.0f;
    const float w = sum / static_cast<float>(transitions);
    return w > 1.0f ? 1.0f : w;
}

Sharpness refine_sharpness(const Level& p, const Level& child, const Sharpness& sharp, const Neighbourhood& n,
                           CreaseMethod method, bool loop, bool holes_only) {
    Sharpness c;
    if (!sharp.hole.empty()) {
        c.hole.assign(child.face_count(), 0);
        for (Index f = 0; f < p.face_count(); ++f) {
            if (!sharp.hole[f]) continue;
            const Index first = loop ? 4 * f : p.face_offsets[f];
            const Index count = loop ? 4 : p.face_offsets[f + 1] - p.face_offsets[f];
            for (Index i = 0; i < count; ++i) c.hole[first + i] = 1;
        }
    }
    if (holes_only) return c;
    c.vertex.assign(child.vertex_count, 0.0f);
    for (Index v = 0; v < p.vertex_count; ++v) c.vertex[v] = decrement(sharp.vertex[v]);
    const Index interior = loop ? 3 * p.face_count() : static_cast<Index>(p.face_verts.size());
    c.edge.assign(interior + 2 * static_cast<std::size_t>(p.edge_count()), 0.0f);
    for (Index e = 0; e < p.edge_count(); ++e) {
        const float s = sharp.edge[e];
        if (!is_sharp(s)) continue;
        c.edge[interior + 2 * e] = child_edge_sharpness(s, p.edge_verts[2 * e], n, method);
        c.edge[interior + 2 * e + 1] = child_edge_sharpness(s, p.edge_verts[2 * e + 1], n, method);
    }
    return c;
}

namespace {

// The mesh tags: crease sharpness on the edges they name, corner sharpness, holes. Fails on a crease between
// vertices that share no edge.
Status apply_tags(const PolygonMesh& mesh, const Level& level, Sharpness& s) {
    const Index nv = level.vertex_count, ne = level.edge_count();
    // vertex -> incident edges, to find the edge a crease names
    std::vector<Index> offsets(nv + 1, 0), edges(2 * static_cast<std::size_t>(ne));
    for (Index e = 0; e < ne; ++e) {
        ++offsets[level.edge_verts[2 * e] + 1];
        ++offsets[level.edge_verts[2 * e + 1] + 1];
    }
    for (Index v = 0; v < nv; ++v) offsets[v + 1] += offsets[v];
    std::vector<Index> fill(offsets.begin(), offsets.end() - 1);
    for (Index e = 0; e < ne; ++e) {
        edges[fill[level.edge_verts[2 * e]]++] = e;
        edges[fill[level.edge_verts[2 * e + 1]]++] = e;
    }
    for (std::size_t i = 0; i < mesh.tags.creases.size(); ++i) {
        const Crease& crease = mesh.tags.creases[i];
        // the first instance, as OpenSubdiv's FindEdge (an edge a face uses twice has two)
        Index found = kInvalidIndex;
        for (Index k = offsets[crease.v0]; k < offsets[crease.v0 + 1] && found == kInvalidIndex; ++k)
            if (other_end(level, edges[k], crease.v0) == crease.v1) found = edges[k];
        if (found == kInvalidIndex)
            return element_error(ErrorCode::InvalidArgument,
                                 "crease " + std::to_string(i) + ": vertices " + std::to_string(crease.v0) + " and " +
                                     std::to_string(crease.v1) + " share no edge",
                                 ElementKind::Crease, static_cast<std::int64_t>(i));
        s.edge[found] = static_cast<float>(crease.sharpness);
    }
    for (const Corner& corner : mesh.tags.corners) s.vertex[corner.vertex] = static_cast<float>(corner.sharpness);
    if (!mesh.tags.holes.empty()) {
        s.hole.assign(level.face_count(), 0);
        for (Index h : mesh.tags.holes) s.hole[h] = 1;
    }
    return Ok{};
}

}  // namespace

Result<Sharpness> base_sharpness(const PolygonMesh& mesh, const Level& level, BoundaryInterpolation boundary,
                                 bool use_tags) {
    const Index nv = level.vertex_count, ne = level.edge_count();
    Sharpness s;
    s.edge.assign(ne, 0.0f);
    s.vertex.assign(nv, 0.0f);

    std::vector<std::uint32_t> edge_faces(ne, 0), edge_forward(ne, 0);
    for (Index f = 0; f < level.face_count(); ++f) {
        const Index b = level.face_offsets[f], n = level.face_offsets[f + 1] - b;
        for (Index j = 0; j < n; ++j) {
            const Index e = level.face_edges[b + j];
            ++edge_faces[e];
            if (level.edge_verts[2 * e] == level.face_verts[b + j]) ++edge_forward[e];
        }
    }
    if (use_tags) {
        if (Status tagged = apply_tags(mesh, level, s); !tagged) return tagged.error();
    }
    std::vector<std::uint8_t> non_manifold_edge(ne, 0);
    // for "boundary none": boundary vertices with a boundary edge that the tags did not make infinitely sharp
    std::vector<std::uint8_t> open_boundary_vertex(nv, 0);
    for (Index e = 0; e < ne; ++e)
        if (edge_faces[e] < 2 && !is_infinite(s.edge[e]))
            open_boundary_vertex[level.edge_verts[2 * e]] = open_boundary_vertex[level.edge_verts[2 * e + 1]] = 1;
    for (Index e = 0; e < ne; ++e) {
        non_manifold_edge[e] = edge_faces[e] > 2 || (edge_faces[e] == 2 && edge_forward[e] != 1) ||
                               (!level.non_manifold_edge.empty() && level.non_manifold_edge[e]);
        if (edge_faces[e] < 2 || non_manifold_edge[e]) s.edge[e] = kInfiniteSharpness;
    }
    std::vector<std::uint32_t> vertex_faces(nv, 0), vertex_edges(nv, 0), vertex_boundary(nv, 0), vertex_nm(nv, 0);
    for (Index v : level.face_verts) ++vertex_faces[v];
    for (Index e = 0; e < ne; ++e)
        for (int k = 0; k < 2; ++k) {
            const Index v = level.edge_verts[2 * e + k];
            ++vertex_edges[v];
            vertex_boundary[v] += edge_faces[e] == 1;
            vertex_nm[v] += non_manifold_edge[e];
        }
    if (boundary == BoundaryInterpolation::None) {
        // OpenSubdiv's "boundary none": a face touching the boundary has no limit surface (it shapes its
        // neighbours, like a hole) unless every boundary edge at its boundary vertices was tagged infinitely sharp.
        bool any = false;
        std::vector<std::uint8_t> hole(level.face_count(), 0);
        for (Index f = 0; f < level.face_count(); ++f)
            for (Index i = level.face_offsets[f]; i < level.face_offsets[f + 1]; ++i)
                if (open_boundary_vertex[level.face_verts[i]]) {
                    hole[f] = 1;
                    any = true;
                    break;
                }
        if (any) {
            if (s.hole.empty()) s.hole.assign(level.face_count(), 0);
            for (Index f = 0; f < level.face_count(); ++f) s.hole[f] |= hole[f];
        }
    }
    const std::vector<std::uint32_t> fans = count_fans(level, edge_faces, non_manifold_edge);
    for (Index v = 0; v < nv; ++v) {
        const bool topological_corner = vertex_faces[v] == 1 && vertex_edges[v] == 2;
        // a manifold vertex is one fan of faces joined by manifold edges: closed (faces == edges) or open with two
        // boundary edges (faces == edges - 1)
        const bool fan = vertex_nm[v] == 0 && fans[v] == 1 &&
                         ((vertex_boundary[v] == 0 && vertex_faces[v] == vertex_edges[v]) ||
                          (vertex_boundary[v] == 2 && vertex_faces[v] + 1 == vertex_edges[v]));
        const bool non_manifold = vertex_edges[v] > 0 && !fan;
        if (topological_corner && boundary == BoundaryInterpolation::EdgeAndCorner) {
            s.vertex[v] = kInfiniteSharpness;
        } else if (non_manifold) {
            const bool simple_crease =
                vertex_nm[v] == 2 && vertex_boundary[v] == 0 && vertex_faces[v] > vertex_edges[v];
            if (!simple_crease) s.vertex[v] = kInfiniteSharpness;
        }
    }
    return s;
}

}  // namespace surfaced::subdivision
