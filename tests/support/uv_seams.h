// A mesh given texture coordinates with seams and junctions, for the face-varying limit tests.
#pragma once

#include <array>
#include <vector>

#include "geometry/mesh/polygon_mesh.h"

namespace surfaced::testing {

//! `mesh` with texture coordinates cut into three UV regions by face centroid (x <= 0; x > 0 and y <= 0; x > 0 and
//! y > 0): seams where regions meet, junctions where three do, UVs a skewed projection offset per region.
inline PolygonMesh with_seams(PolygonMesh mesh) {
    std::vector<int> region(mesh.face_count());
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        Vec3 c{0, 0, 0};
        for (Index v : mesh.face(f)) c = c + mesh.positions[v];
        region[f] = c.x <= 0 ? 0 : c.y <= 0 ? 1 : 2;
    }
    std::vector<std::array<Index, 3>> value(mesh.vertex_count(), {kInvalidIndex, kInvalidIndex, kInvalidIndex});
    mesh.uvs.clear();
    mesh.uv_indices.clear();
    for (std::size_t f = 0; f < mesh.face_count(); ++f)
        for (Index v : mesh.face(f)) {
            Index& id = value[v][static_cast<std::size_t>(region[f])];
            if (id == kInvalidIndex) {
                id = static_cast<Index>(mesh.uvs.size());
                const Vec3& p = mesh.positions[v];
                mesh.uvs.push_back({0.5 * p.x + 0.1 * p.z + 0.3 * region[f], 0.5 * p.y - 0.2 * p.z + 0.1 * region[f]});
            }
            mesh.uv_indices.push_back(id);
        }
    return mesh;
}

}  // namespace surfaced::testing
