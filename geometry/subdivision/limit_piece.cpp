// Local pieces of refinement levels (limit_piece.h).
#include "geometry/subdivision/limit_piece.h"

#include <algorithm>
#include <utility>

#include "geometry/subdivision/interpolate.h"

namespace surfaced::subdivision {

void vertex_faces(const Level& level, std::vector<Index>& offsets, std::vector<Index>& faces) {
    offsets.assign(static_cast<std::size_t>(level.vertex_count) + 1, 0);
    for (Index v : level.face_verts) ++offsets[v + 1];
    for (Index v = 0; v < level.vertex_count; ++v) offsets[v + 1] += offsets[v];
    faces.resize(offsets[level.vertex_count]);
    std::vector<Index> fill(offsets.begin(), offsets.end() - 1);
    for (Index f = 0; f < level.face_count(); ++f)
        for (Index s = level.face_offsets[f]; s < level.face_offsets[f + 1]; ++s)
            faces[fill[level.face_verts[s]]++] = f;
}

Piece extract(const Piece& src, const std::vector<Index>& vf_offsets, const std::vector<Index>& vf_faces, Index face) {
    const Level& L = src.level;
    // a local piece is small: marks per face and vertex; the base mesh may be large: sorted lists
    const bool dense = L.face_count() <= 4096;
    std::vector<Index> faces{face};
    if (dense) {
        std::vector<std::uint8_t> in(L.face_count(), 0);
        in[face] = 1;
        for (int ring = 0; ring < 2; ++ring) {
            const std::size_t count = faces.size();
            for (std::size_t i = 0; i < count; ++i)
                for (Index s = L.face_offsets[faces[i]]; s < L.face_offsets[faces[i] + 1]; ++s) {
                    const Index v = L.face_verts[s];
                    for (Index k = vf_offsets[v]; k < vf_offsets[v + 1]; ++k)
                        if (!in[vf_faces[k]]) {
                            in[vf_faces[k]] = 1;
                            faces.push_back(vf_faces[k]);
                        }
                }
        }
        std::sort(faces.begin(), faces.end());
    } else {
        for (int ring = 0; ring < 2; ++ring) {
            const std::size_t count = faces.size();
            std::vector<Index> next;
            for (std::size_t i = 0; i < count; ++i) {
                const Index f = faces[i];
                for (Index s = L.face_offsets[f]; s < L.face_offsets[f + 1]; ++s) {
                    const Index v = L.face_verts[s];
                    next.insert(next.end(), vf_faces.begin() + vf_offsets[v], vf_faces.begin() + vf_offsets[v + 1]);
                }
            }
            std::sort(next.begin(), next.end());
            next.erase(std::unique(next.begin(), next.end()), next.end());
            faces.swap(next);
        }
    }
    // faces in source order; vertices: the face's distinct corners first (in face order), then the rest

    std::vector<Index> order;
    for (Index s = L.face_offsets[face]; s < L.face_offsets[face + 1]; ++s)
        if (std::find(order.begin(), order.end(), L.face_verts[s]) == order.end()) order.push_back(L.face_verts[s]);
    std::vector<Index> dense_local;
    std::vector<std::pair<Index, Index>> map;  // (source, local), sorted by source
    if (dense) {
        dense_local.assign(L.vertex_count, kInvalidIndex);
        for (Index i = 0; i < order.size(); ++i) dense_local[order[i]] = i;
        for (Index f : faces)
            for (Index s = L.face_offsets[f]; s < L.face_offsets[f + 1]; ++s)
                if (dense_local[L.face_verts[s]] == kInvalidIndex) {
                    dense_local[L.face_verts[s]] = static_cast<Index>(order.size());
                    order.push_back(L.face_verts[s]);
                }
    } else {
        const std::size_t corner_count = order.size();
        std::vector<Index> rest;
        for (Index f : faces)
            for (Index s = L.face_offsets[f]; s < L.face_offsets[f + 1]; ++s) rest.push_back(L.face_verts[s]);
        std::sort(rest.begin(), rest.end());
        rest.erase(std::unique(rest.begin(), rest.end()), rest.end());
        for (Index v : rest)
            if (std::find(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(corner_count), v) ==
                order.begin() + static_cast<std::ptrdiff_t>(corner_count))
                order.push_back(v);
        map.reserve(order.size());
        for (Index i = 0; i < order.size(); ++i) map.push_back({order[i], i});
        std::sort(map.begin(), map.end());
    }
    auto local = [&](Index v) {
        if (dense) return dense_local[v];
        return std::lower_bound(map.begin(), map.end(), std::pair<Index, Index>{v, 0})->second;
    };

    Piece out;
    out.points.resize(order.size());
    out.sharp.vertex.resize(order.size());
    for (Index l = 0; l < order.size(); ++l) {
        out.points[l] = src.points[order[l]];
        out.sharp.vertex[l] = src.sharp.vertex[order[l]];
    }
    // the topology is copied, edges included (not rebuilt from the faces: two edges may join the same two vertices,
    // as on small closed meshes and next to faces that use a vertex twice, and must stay two)
    std::vector<Index> edges;  // the source edges, in order of first appearance
    std::vector<Index> dense_edge;
    std::vector<std::pair<Index, Index>> edge_map;  // (source, local), sorted by source
    if (dense) dense_edge.assign(L.edge_count(), kInvalidIndex);
    for (Index f : faces)
        for (Index s = L.face_offsets[f]; s < L.face_offsets[f + 1]; ++s) {
            const Index e = L.face_edges[s];
            if (dense) {
                if (dense_edge[e] != kInvalidIndex) continue;
                dense_edge[e] = static_cast<Index>(edges.size());
            }
            edges.push_back(e);
        }
    if (!dense) {
        std::sort(edges.begin(), edges.end());
        edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
        edge_map.reserve(edges.size());
        for (Index i = 0; i < edges.size(); ++i) edge_map.push_back({edges[i], i});
    }
    auto local_edge = [&](Index e) {
        if (dense) return dense_edge[e];
        return std::lower_bound(edge_map.begin(), edge_map.end(), std::pair<Index, Index>{e, 0})->second;
    };
    Level& level = out.level;
    level.vertex_count = static_cast<Index>(order.size());
    level.face_offsets.assign(1, 0);
    for (Index f : faces)
        for (Index s = L.face_offsets[f]; s < L.face_offsets[f + 1]; ++s) {
            level.face_verts.push_back(local(L.face_verts[s]));
            level.face_edges.push_back(local_edge(L.face_edges[s]));
        }
    for (Index f : faces)
        level.face_offsets.push_back(level.face_offsets.back() + L.face_offsets[f + 1] - L.face_offsets[f]);
    level.edge_verts.resize(2 * edges.size());
    out.sharp.edge.resize(edges.size());
    for (Index i = 0; i < edges.size(); ++i) {
        level.edge_verts[2 * i] = local(L.edge_verts[2 * edges[i]]);
        level.edge_verts[2 * i + 1] = local(L.edge_verts[2 * edges[i] + 1]);
        out.sharp.edge[i] = src.sharp.edge[edges[i]];
    }
    out.target = static_cast<Index>(std::lower_bound(faces.begin(), faces.end(), face) - faces.begin());
    if (!src.sharp.hole.empty()) {
        out.sharp.hole.resize(faces.size());
        for (Index i = 0; i < faces.size(); ++i) out.sharp.hole[i] = src.sharp.hole[faces[i]];
    }
    return out;
}

Piece refine(const Piece& p, const SubdivisionOptions& options, bool first_level) {
    const bool loop = options.scheme == SubdivisionScheme::Loop;
    const Neighbourhood n = neighbourhood(p.level, p.sharp, options.crease_method);
    Piece c;
    c.level = loop ? refine_triangles(p.level, true, false) : refine_quads(p.level, true, false);
    c.points.assign(c.level.vertex_count, Vec3{});
    const LevelInput in{p.level,
                        p.sharp,
                        options.crease_method,
                        first_level ? options.triangle_rule : TriangleRule::Catmark,
                        options.loop_weights,
                        false};
    if (loop)
        interpolate_loop(in, n, p.points.data(), c.points.data());
    else
        interpolate_catmark(in, n, p.points.data(), c.points.data());
    c.sharp = refine_sharpness(p.level, c.level, p.sharp, n, options.crease_method, loop);
    return c;
}

Adjacency::Adjacency(const Level& L) {
    const Index ne = L.edge_count();
    edge_face0.assign(ne, kInvalidIndex);
    edge_face1.assign(ne, kInvalidIndex);
    edge_uses.assign(ne, 0);
    for (Index f = 0; f < L.face_count(); ++f)
        for (Index s = L.face_offsets[f]; s < L.face_offsets[f + 1]; ++s) {
            const Index e = L.face_edges[s];
            (edge_uses[e] == 0 ? edge_face0 : edge_face1)[e] = f;
            ++edge_uses[e];
        }
    vertex_faces(L, vf_offsets, vf_faces);
}

Index slot_of(const Level& L, Index f, Index v) {
    for (Index s = L.face_offsets[f]; s < L.face_offsets[f + 1]; ++s)
        if (L.face_verts[s] == v) return s - L.face_offsets[f];
    return kInvalidIndex;
}

}  // namespace surfaced::subdivision
