#include "geometry/repair/open_seams.h"

#include <algorithm>
#include <cstdint>
#include <vector>

#include "geometry/repair/weld.h"

namespace surfaced {

std::size_t count_open_seam_vertices(const PolygonMesh& mesh) {
    const std::vector<Index> target = repair_detail::weld_targets(mesh.positions, 0.0);
    const std::size_t nv = mesh.vertex_count();
    std::vector<std::uint8_t> coincident(nv, 0);
    bool any = false;
    for (Index v = 0; v < nv; ++v)
        if (target[v] != v) coincident[v] = coincident[target[v]] = 1, any = true;
    if (!any) return 0;
    // undirected edges with a coincident end: only the faces around those vertices can hold them
    std::vector<std::uint64_t> edges;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const auto face = mesh.face(f);
        for (std::size_t j = 0; j < face.size(); ++j) {
            const Index u = face[j], w = face[(j + 1) % face.size()];
            if (coincident[u] || coincident[w]) edges.push_back(std::uint64_t{std::min(u, w)} << 32 | std::max(u, w));
        }
    }
    std::sort(edges.begin(), edges.end());
    std::vector<std::uint8_t> on_boundary(nv, 0);
    for (std::size_t i = 0; i < edges.size();) {
        std::size_t j = i + 1;
        while (j < edges.size() && edges[j] == edges[i]) ++j;
        if (j - i == 1) on_boundary[edges[i] >> 32] = on_boundary[edges[i] & 0xffffffffu] = 1;
        i = j;
    }
    // per position group (its lowest vertex, the weld target), the members on boundary edges beyond the first
    std::vector<Index> boundary_members(nv, 0);
    for (Index v = 0; v < nv; ++v)
        if (coincident[v] && on_boundary[v]) ++boundary_members[target[v]];
    std::size_t count = 0;
    for (Index v = 0; v < nv; ++v)
        if (boundary_members[v] > 1) count += boundary_members[v] - 1;
    return count;
}

}  // namespace surfaced
