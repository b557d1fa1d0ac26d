#include "tests/support/repair_asserts.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>

#include "tests/support/mesh_asserts.h"

namespace surfaced::testing {
namespace {

struct FaceGroups {  // union-find over faces
    std::vector<std::size_t> parent;
    explicit FaceGroups(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
    std::size_t find(std::size_t x) { return parent[x] == x ? x : parent[x] = find(parent[x]); }
    void unite(std::size_t a, std::size_t b) { parent[find(a)] = find(b); }
};

}  // namespace

EdgeFaces faces_by_edge(const PolygonMesh& mesh) {
    EdgeFaces edges;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const auto face = mesh.face(f);
        for (std::size_t j = 0; j < face.size(); ++j) {
            const Index a = face[j], b = face[(j + 1) % face.size()];
            edges[{std::min(a, b), std::max(a, b)}].push_back(f);
        }
    }
    return edges;
}

std::size_t multi_fan_vertices(const PolygonMesh& mesh, const EdgeFaces& edges) {
    std::vector<std::vector<std::size_t>> around(mesh.vertex_count());
    for (std::size_t f = 0; f < mesh.face_count(); ++f)
        for (Index v : mesh.face(f)) around[v].push_back(f);
    std::size_t bad = 0;
    for (Index v = 0; v < mesh.vertex_count(); ++v) {
        FaceGroups local(mesh.face_count());
        for (const auto& [key, faces] : edges)
            if (key.first == v || key.second == v)
                for (std::size_t i = 1; i < faces.size(); ++i) local.unite(faces[0], faces[i]);
        std::set<std::size_t> fans;
        for (std::size_t f : around[v]) fans.insert(local.find(f));
        if (fans.size() > 1) ++bad;
    }
    return bad;
}

std::size_t zero_area_faces(const PolygonMesh& mesh) {
    std::size_t bad = 0;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const auto face = mesh.face(f);
        std::set<Index> distinct(face.begin(), face.end());
        Vec3 area;
        for (std::size_t j = 1; j + 1 < face.size(); ++j)
            area += cross(mesh.positions[face[j]] - mesh.positions[face[0]],
                          mesh.positions[face[j + 1]] - mesh.positions[face[0]]);
        if (distinct.size() != face.size() || norm(area) == 0) ++bad;
    }
    return bad;
}

std::size_t same_vertex_set_faces(const PolygonMesh& mesh) {
    std::set<std::vector<Index>> seen;
    std::size_t bad = 0;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        std::vector<Index> key(mesh.face(f).begin(), mesh.face(f).end());
        std::sort(key.begin(), key.end());
        if (!seen.insert(key).second) ++bad;
    }
    return bad;
}

std::size_t repeated_directed_edges(const PolygonMesh& mesh) {
    std::map<std::pair<Index, Index>, std::size_t> uses;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const auto face = mesh.face(f);
        for (std::size_t j = 0; j < face.size(); ++j) ++uses[{face[j], face[(j + 1) % face.size()]}];
    }
    return static_cast<std::size_t>(
        std::count_if(uses.begin(), uses.end(), [](const auto& entry) { return entry.second > 1; }));
}

std::vector<double> closed_component_volumes(const PolygonMesh& mesh, const EdgeFaces& edges) {
    FaceGroups groups(mesh.face_count());
    for (const auto& [key, faces] : edges)
        for (std::size_t i = 1; i < faces.size(); ++i) groups.unite(faces[0], faces[i]);
    std::map<std::size_t, bool> open;
    for (const auto& [key, faces] : edges) open[groups.find(faces[0])] |= faces.size() == 1;
    std::map<std::size_t, double> volume;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const auto face = mesh.face(f);
        for (std::size_t j = 1; j + 1 < face.size(); ++j)
            volume[groups.find(f)] +=
                dot(mesh.positions[face[0]], cross(mesh.positions[face[j]], mesh.positions[face[j + 1]])) / 6.0;
    }
    std::vector<double> closed;
    for (const auto& [root, v] : volume)
        if (!open[root]) closed.push_back(v);
    return closed;
}

void expect_repaired(const PolygonMesh& mesh, bool oriented) {
    ASSERT_TRUE(validate(mesh).ok()) << validate(mesh).error().message;
    const auto stats = edge_stats(mesh);
    EXPECT_EQ(stats.non_manifold_edges, 0u);
    EXPECT_EQ(stats.inconsistent_edges, 0u);
    EXPECT_EQ(repeated_directed_edges(mesh), 0u);
    const EdgeFaces edges = faces_by_edge(mesh);
    EXPECT_EQ(multi_fan_vertices(mesh, edges), 0u);
    EXPECT_EQ(zero_area_faces(mesh), 0u);
    EXPECT_EQ(same_vertex_set_faces(mesh), 0u);
    if (oriented) {
        for (double v : closed_component_volumes(mesh, edges))
            EXPECT_GT(v, -1e-12) << "a closed component is inside out";
    }
    EXPECT_FALSE(needs_repair(mesh));
    const auto audit = audit_mesh(mesh);
    ASSERT_TRUE(audit.ok());
    if (oriented) {
        EXPECT_EQ(audit->inverted_components, 0u);
    }
}

void expect_counts_add_up(const PolygonMesh& in, const RepairResult& result) {
    const RepairReport& s = result.report;
    EXPECT_EQ(result.mesh.vertex_count(), in.vertex_count() - s.welded - s.unreferenced + s.nonmanifold_split);
    EXPECT_EQ(result.mesh.face_count(), in.face_count() - s.degenerate - s.duplicate - s.removed_faces + s.fill_faces);
}

FaceCorners corner_positions(const PolygonMesh& mesh, std::size_t f) {
    FaceCorners pts;
    for (Index v : mesh.face(f)) pts.push_back({mesh.positions[v].x, mesh.positions[v].y, mesh.positions[v].z});
    std::rotate(pts.begin(), std::min_element(pts.begin(), pts.end()), pts.end());
    return pts;
}

std::multiset<FaceCorners> surface_faces(const PolygonMesh& mesh, bool ignore_winding) {
    std::multiset<FaceCorners> faces;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        FaceCorners pts = corner_positions(mesh, f);
        if (ignore_winding && pts.size() > 2) {
            FaceCorners reversed = pts;
            std::reverse(reversed.begin() + 1, reversed.end());  // the same start corner, the other direction
            pts = std::min(pts, reversed);
        }
        faces.insert(std::move(pts));
    }
    return faces;
}

}  // namespace surfaced::testing
