// Area-weighted vertex normals. Newell's method gives each polygon's vector area (direction = normal, length =
// area) even for non-planar or concave polygons, so summing it over incident faces weights large faces more and
// needs no triangulation.
#include "geometry/mesh/normals.h"

namespace surfaced {

namespace {

//! Newell's vector area: half the sum of cross products of consecutive corners (exact for planar polygons).
Vec3 vector_area(const PolygonMesh& mesh, std::span<const Index> face) {
    Vec3 sum;
    const std::size_t n = face.size();
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3& a = mesh.positions[face[i]];
        const Vec3& b = mesh.positions[face[(i + 1) % n]];
        // (a - c) x (b - c) with c = first corner keeps the terms small for faces far from the origin.
        sum += cross(a - mesh.positions[face[0]], b - mesh.positions[face[0]]);
    }
    return sum * 0.5;
}

}  // namespace

std::vector<Vec3> compute_vertex_normals(const PolygonMesh& mesh) {
    const std::size_t nv = mesh.vertex_count();
    std::vector<Vec3> normals(nv);
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const auto face = mesh.face(f);
        bool in_range = true;
        for (Index v : face) in_range = in_range && v < nv;
        // Callers validate first; skipping a broken face keeps this function total instead of reading out of bounds.
        if (!in_range || face.size() < 3) continue;
        const Vec3 area = vector_area(mesh, face);
        for (Index v : face) normals[v] += area;
    }
    for (Vec3& n : normals) {
        const double len = norm(n);
        // A tiny or non-finite sum has no meaningful direction; the header promises +z then.
        if (std::isfinite(len) && len > 1e-300)
            n *= 1.0 / len;
        else
            n = Vec3{0, 0, 1};
    }
    return normals;
}

}  // namespace surfaced
