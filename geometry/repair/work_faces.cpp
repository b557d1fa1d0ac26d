// Degenerate faces dropped while the welded faces are copied; duplicate polygons (4 or more corners) by a table of
// vertex sets; duplicate triangles on the edges, which the joining steps group anyway.
#include "geometry/repair/work_faces.h"

#include <algorithm>
#include <cstdint>
#include <optional>
#include <utility>

#include "geometry/repair/face_checks.h"

namespace surfaced::repair_detail {

namespace {

//! Per working face: 1 when it is a triangle with the vertex set of an earlier triangle. Two triangles on one edge
//! have the same vertex set exactly when their corners off the edge are the same vertex.
std::vector<std::uint8_t> duplicate_triangles(const CornerTable& table, const EdgeGroups& edges, std::size_t& count) {
    const std::size_t faces = table.offsets.size() - 1;
    std::vector<std::uint8_t> duplicate(faces, 0);
    auto is_triangle = [&](Index f) { return table.offsets[f + 1] - table.offsets[f] == 3; };
    auto third = [&](Index c) { return table.indices[table.prev(c)]; };
    std::vector<std::pair<Index, Index>> keyed;  // (third vertex, face) of an edge of more than two triangles
    for (std::size_t e = 0; e < edges.edge_count(); ++e) {
        const auto corners = edges.of(e);
        if (corners.size() < 2) continue;
        if (corners.size() == 2) {
            const Index a = table.face(corners[0]), b = table.face(corners[1]);  // a < b: corners in order
            if (is_triangle(a) && is_triangle(b) && third(corners[0]) == third(corners[1])) duplicate[b] = 1;
            continue;
        }
        keyed.clear();
        for (Index c : corners)
            if (is_triangle(table.face(c))) keyed.emplace_back(third(c), table.face(c));
        std::sort(keyed.begin(), keyed.end());
        for (std::size_t i = 1; i < keyed.size(); ++i)
            if (keyed[i].first == keyed[i - 1].first) duplicate[keyed[i].second] = 1;
    }
    count = 0;
    for (std::uint8_t d : duplicate) count += d;
    return duplicate;
}

//! The edges of the faces not dropped, renumbered as when the dropped faces' corners are taken out: a few dropped
//! faces cost a pass over the edges instead of grouping them again.
EdgeGroups without_faces(const EdgeGroups& edges, const CornerTable& table, const std::vector<std::uint8_t>& drop,
                         std::size_t vertex_count) {
    // first corner of every dropped face, and the corners dropped before it
    std::vector<std::pair<Index, Index>> dropped;
    Index removed = 0;
    for (Index f = 0; f < drop.size(); ++f)
        if (drop[f]) {
            dropped.emplace_back(table.offsets[f], removed);
            removed += table.offsets[f + 1] - table.offsets[f];
        }
    auto renumbered = [&](Index c) {  // c is not dropped: the dropped corners before it are whole faces before it
        auto it = std::upper_bound(dropped.begin(), dropped.end(), std::pair{c, kInvalidIndex});
        if (it == dropped.begin()) return c;
        --it;
        return c - it->second - (table.offsets[table.face(it->first) + 1] - it->first);
    };
    EdgeGroups out;
    out.corners.reserve(edges.corners.size() - removed);
    out.begin.reserve(edges.begin.size());
    out.vertex_edge.resize(vertex_count + 1);
    for (std::size_t v = 0; v < vertex_count; ++v) {
        out.vertex_edge[v] = static_cast<Index>(out.begin.size());
        for (Index e = edges.vertex_edge[v]; e < edges.vertex_edge[v + 1]; ++e) {
            const auto start = static_cast<Index>(out.corners.size());
            for (Index c : edges.of(e))
                if (!drop[table.face(c)]) out.corners.push_back(renumbered(c));
            if (out.corners.size() > start) out.begin.push_back(start);
        }
    }
    out.vertex_edge[vertex_count] = static_cast<Index>(out.begin.size());
    out.begin.push_back(static_cast<Index>(out.corners.size()));
    return out;
}

}  // namespace

WorkFaces clean_faces(const PolygonMesh& mesh, std::span<const Index> weld) {
    WorkFaces work;
    const std::size_t faces = mesh.face_count();
    work.source.reserve(faces);
    work.offsets.reserve(faces + 1);
    work.indices.resize(mesh.face_indices.size());
    std::optional<FaceSets> polygons;  // vertex sets of the kept faces of 4 or more corners
    Index* out = work.indices.data();
    Index at = 0;
    for (std::size_t f = 0; f < faces; ++f) {
        const Index begin = mesh.face_offsets[f], n = mesh.face_offsets[f + 1] - begin;
        for (Index i = 0; i < n; ++i) {
            const Index v = mesh.face_indices[begin + i];
            out[at + i] = weld.empty() ? v : weld[v];
        }
        const std::span<const Index> face(out + at, n);
        if (has_repeated_index(face) || has_zero_area(mesh.positions, face)) {
            ++work.degenerate;
            continue;
        }
        if (n > 3) {
            if (!polygons) polygons.emplace(faces);
            if (!polygons->insert(face)) {
                ++work.duplicate;
                continue;
            }
        }
        at += n;
        work.offsets.push_back(at);
        work.source.push_back(static_cast<Index>(f));
    }
    work.indices.resize(at);
    work.table = make_corner_table(work.offsets, work.indices);
    work.edges = group_edges(work.table, mesh.vertex_count());

    std::size_t duplicates = 0;
    const std::vector<std::uint8_t> drop = duplicate_triangles(work.table, work.edges, duplicates);
    if (duplicates == 0) return work;
    work.duplicate += duplicates;
    WorkFaces kept;
    kept.degenerate = work.degenerate;
    kept.duplicate = work.duplicate;
    kept.source.reserve(work.source.size() - duplicates);
    kept.indices.reserve(work.indices.size());
    for (std::size_t f = 0; f < drop.size(); ++f) {
        if (drop[f]) continue;
        kept.indices.insert(kept.indices.end(), work.indices.begin() + work.offsets[f],
                            work.indices.begin() + work.offsets[f + 1]);
        kept.offsets.push_back(static_cast<Index>(kept.indices.size()));
        kept.source.push_back(work.source[f]);
    }
    kept.table = make_corner_table(kept.offsets, kept.indices);
    if (duplicates * 8 > drop.size())
        kept.edges = group_edges(kept.table, mesh.vertex_count());
    else
        kept.edges = without_faces(work.edges, work.table, drop, mesh.vertex_count());
    return kept;
}

}  // namespace surfaced::repair_detail
