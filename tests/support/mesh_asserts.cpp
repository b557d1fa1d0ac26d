#include "tests/support/mesh_asserts.h"

#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <sstream>
#include <vector>

namespace surfaced::testing {

namespace {
// directed edge (a, b) -> count; undirected key (min, max) -> (faces, same-direction count)
struct EdgeInfo {
    int faces = 0;
    int forward = 0;  // traversals lo -> hi
};
std::map<std::pair<Index, Index>, EdgeInfo> edge_map(const PolygonMesh& mesh) {
    std::map<std::pair<Index, Index>, EdgeInfo> edges;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        auto face = mesh.face(f);
        for (std::size_t j = 0; j < face.size(); ++j) {
            Index a = face[j], b = face[(j + 1) % face.size()];
            auto& info = edges[{std::min(a, b), std::max(a, b)}];
            ++info.faces;
            if (a < b) ++info.forward;
        }
    }
    return edges;
}
}  // namespace

EdgeStats edge_stats(const PolygonMesh& mesh) {
    EdgeStats s;
    for (const auto& [key, info] : edge_map(mesh)) {
        ++s.edges;
        if (info.faces == 1) ++s.boundary_edges;
        if (info.faces > 2) ++s.non_manifold_edges;
        if (info.faces == 2 && info.forward != 1) ++s.inconsistent_edges;
    }
    return s;
}

std::int64_t euler_characteristic(const PolygonMesh& mesh) {
    return static_cast<std::int64_t>(mesh.vertex_count()) - static_cast<std::int64_t>(edge_stats(mesh).edges) +
           static_cast<std::int64_t>(mesh.face_count());
}

std::size_t boundary_loop_count(const PolygonMesh& mesh) {
    // union-find over vertices joined by boundary edges; count components that contain boundary edges
    std::vector<Index> parent(mesh.vertex_count());
    for (Index i = 0; i < parent.size(); ++i) parent[i] = i;
    auto find = [&](Index x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    std::vector<char> on_boundary(mesh.vertex_count(), 0);
    for (const auto& [key, info] : edge_map(mesh))
        if (info.faces == 1) {
            parent[find(key.first)] = find(key.second);
            on_boundary[key.first] = on_boundary[key.second] = 1;
        }
    std::size_t loops = 0;
    for (Index v = 0; v < parent.size(); ++v)
        if (on_boundary[v] && find(v) == v) ++loops;
    return loops;
}

bool is_watertight(const PolygonMesh& mesh) {
    const EdgeStats s = edge_stats(mesh);
    return s.boundary_edges == 0 && s.non_manifold_edges == 0 && s.inconsistent_edges == 0;
}

double signed_volume(const PolygonMesh& mesh) {
    double v = 0;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        auto face = mesh.face(f);
        const Vec3& a = mesh.positions[face[0]];
        for (std::size_t j = 1; j + 1 < face.size(); ++j)
            v += dot(a, cross(mesh.positions[face[j]], mesh.positions[face[j + 1]])) / 6.0;
    }
    return v;
}

std::size_t non_manifold_vertices(const PolygonMesh& mesh) {
    std::vector<std::vector<std::size_t>> faces_of(mesh.vertex_count());
    for (std::size_t f = 0; f < mesh.face_count(); ++f)
        for (Index v : mesh.face(f)) faces_of[v].push_back(f);
    std::size_t bad = 0;
    for (Index v = 0; v < mesh.vertex_count(); ++v) {
        const auto& around = faces_of[v];
        if (around.empty()) {
            ++bad;
            continue;
        }
        // the face after each one around v: the face whose edge (v, next) is this one's (previous, v)
        std::map<Index, std::size_t> by_next;
        std::size_t start = around[0];
        for (std::size_t f : around) {
            const auto t = mesh.face(f);
            for (std::size_t j = 0; j < t.size(); ++j)
                if (t[j] == v) by_next[t[(j + 1) % t.size()]] = f;
        }
        // an open fan (at a boundary) is walked from its first face: the one no other face leads to, whose edge
        // (v, next) is no face's (previous, v)
        std::map<Index, std::size_t> by_previous;
        for (std::size_t f : around) {
            const auto t = mesh.face(f);
            for (std::size_t j = 0; j < t.size(); ++j)
                if (t[j] == v) by_previous[t[(j + t.size() - 1) % t.size()]] = f;
        }
        for (const auto& [next, f] : by_next)
            if (!by_previous.count(next)) start = f;
        std::size_t f = start, steps = 0;
        do {
            ++steps;
            const auto t = mesh.face(f);
            Index previous = kInvalidIndex;
            for (std::size_t j = 0; j < t.size(); ++j)
                if (t[j] == v) previous = t[(j + t.size() - 1) % t.size()];
            const auto it = by_next.find(previous);
            if (it == by_next.end()) break;
            f = it->second;
        } while (f != start && steps <= around.size());
        if (steps != around.size()) ++bad;
    }
    return bad;
}

std::string read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        ADD_FAILURE() << "cannot open " << path;
        return {};
    }
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

}  // namespace surfaced::testing
