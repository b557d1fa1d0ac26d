// Meshes and output checks shared by the simplification and mesh-as-solid tests (geometry, api, server). Header-only on purpose:
// test_support stays as it is and each test binary compiles only what it uses.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include "geometry/mesh/polygon_mesh.h"
#include "geometry/mesh/shapes.h"
#include "geometry/simplify/mesh_distance.h"
#include "geometry/subdivision/subdivide.h"

namespace surfaced::testing {

//! The cube [-1, 1]^3 as 12 outward triangles (volume 8; the mesh-as-solid tests' analytic reference).
inline PolygonMesh triangle_cube() {
    PolygonMesh mesh;
    for (int i = 0; i < 8; ++i) mesh.positions.push_back({i & 1 ? 1.0 : -1.0, i & 2 ? 1.0 : -1.0, i & 4 ? 1.0 : -1.0});
    const Index quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) {
        mesh.add_face({q[0], q[1], q[2]});
        mesh.add_face({q[0], q[2], q[3]});
    }
    return mesh;
}

//! Icosahedron Loop-subdivided `levels` times, vertices projected onto the sphere of `radius`: 20 * 4^levels faces.
inline PolygonMesh icosphere(int levels, double radius = 1.0) {
    SubdivisionOptions options;
    options.scheme = SubdivisionScheme::Loop;
    options.levels = levels;
    PolygonMesh mesh = subdivide(shapes::icosahedron(), options).value();
    for (Vec3& p : mesh.positions) p *= radius / norm(p);
    return mesh;
}

//! Open cylinder around z (radius 1, height 2) with face-varying uvs (u = angle / 2 pi, v = z / 2 + 1/2). The seam
//! at angle 0 uses u = 0 on one side and u = 1 on the other: the vertices there have two uv indices.
inline PolygonMesh uv_cylinder(int around, int along) {
    PolygonMesh mesh;
    for (int j = 0; j <= along; ++j)
        for (int i = 0; i < around; ++i) {
            const double a = 2 * std::numbers::pi * i / around;
            mesh.positions.push_back({std::cos(a), std::sin(a), -1.0 + 2.0 * j / along});
        }
    for (int j = 0; j <= along; ++j)
        for (int i = 0; i <= around; ++i) mesh.uvs.push_back({double(i) / around, double(j) / along});
    auto vid = [&](int i, int j) { return static_cast<Index>(j * around + (i % around)); };
    auto uvid = [&](int i, int j) { return static_cast<Index>(j * (around + 1) + i); };
    for (int j = 0; j < along; ++j)
        for (int i = 0; i < around; ++i) {
            mesh.add_face({vid(i, j), vid(i + 1, j), vid(i + 1, j + 1)});
            mesh.uv_indices.insert(mesh.uv_indices.end(), {uvid(i, j), uvid(i + 1, j), uvid(i + 1, j + 1)});
            mesh.add_face({vid(i, j), vid(i + 1, j + 1), vid(i, j + 1)});
            mesh.uv_indices.insert(mesh.uv_indices.end(), {uvid(i, j), uvid(i + 1, j + 1), uvid(i, j + 1)});
        }
    return mesh;
}

//! A cylinder as CAD programs export it to STL: radius 1, height 2, `around` segments; each end a fan from one rim
//! vertex (needles down to 360/around degrees) unless `open`, the side one strip of full-height triangles. Then `caps`
//! edges get a T-junction closed the way exporters close them: the edge (a, b) is split at a point m on one side only,
//! and the slit left on the other side is filled by the zero-area face (a, b, m) (on a boundary edge, the cap's long
//! edge is the boundary).
inline PolygonMesh cad_cylinder(int around, int caps, bool open = false) {
    PolygonMesh m;
    for (int z = 0; z < 2; ++z)
        for (int i = 0; i < around; ++i) {
            const double a = 2 * std::numbers::pi * i / around;
            m.positions.push_back({std::cos(a), std::sin(a), 2.0 * z});
        }
    auto id = [&](int i, int z) { return static_cast<Index>(z * around + (i % around)); };
    for (int i = 0; i < around; ++i) {
        m.add_face({id(i, 0), id(i + 1, 0), id(i + 1, 1)});
        m.add_face({id(i, 0), id(i + 1, 1), id(i, 1)});
    }
    for (int i = 1; i + 1 < around && !open; ++i) {
        m.add_face({id(0, 1), id(i, 1), id(i + 1, 1)});
        m.add_face({id(0, 0), id(i + 1, 0), id(i, 0)});
    }
    // T-junctions on every (faces / caps)-th face's first edge
    const std::size_t faces = m.face_count();
    for (int k = 0; k < caps; ++k) {
        const std::size_t f = (k * 7919) % faces;
        auto t = m.face(f);
        const Index a = t[0], b = t[1], x = t[2];
        const double s = 0.25 + 0.5 * ((k * 37) % 10) / 10.0;
        const auto mid = static_cast<Index>(m.positions.size());
        m.positions.push_back(m.positions[a] + (m.positions[b] - m.positions[a]) * s);
        PolygonMesh next;
        next.positions = m.positions;
        for (std::size_t g = 0; g < m.face_count(); ++g)
            if (g == f) {
                next.add_face({a, mid, x});
                next.add_face({mid, b, x});
            } else {
                auto u = m.face(g);
                next.add_face({u[0], u[1], u[2]});
            }
        next.add_face({a, b, mid});  // a -> b against the neighbour's b -> a
        m = std::move(next);
    }
    return m;
}

//! 2 area / longest edge^2 of a triangle: 0 for a degenerate one, sqrt(3)/2 for an equilateral one.
inline double triangle_thinness(const Vec3& a, const Vec3& b, const Vec3& c) {
    const double l = std::max({dot(b - a, b - a), dot(c - b, c - b), dot(a - c, a - c)});
    return l > 0 ? norm(cross(b - a, c - a)) / l : 0.0;
}

inline Vec3 face_normal(const PolygonMesh& mesh, std::size_t f) {
    auto t = mesh.face(f);
    const Vec3& a = mesh.positions[t[0]];
    return cross(mesh.positions[t[1]] - a, mesh.positions[t[2]] - a);
}

//! Triangles with thinness below 1e-6 or a repeated vertex.
inline std::size_t degenerate_faces(const PolygonMesh& mesh) {
    std::size_t count = 0;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        auto t = mesh.face(f);
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2] ||
            triangle_thinness(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]) < 1e-6)
            ++count;
    }
    return count;
}

//! Faces on the same vertex set as an earlier face (either orientation).
inline std::size_t duplicate_faces(const PolygonMesh& mesh) {
    std::set<std::vector<Index>> seen;
    std::size_t count = 0;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        auto t = mesh.face(f);
        std::vector<Index> key(t.begin(), t.end());
        std::sort(key.begin(), key.end());
        if (!seen.insert(key).second) ++count;
    }
    return count;
}

//! Output faces that face away from the input: the face normal against the sum of the unit normals of the input
//! triangles nearest to its centroid and to three points towards its corners. (One probe alone is fooled by scan
//! noise: a bunny face can have one nearly perpendicular input triangle under its centroid.)
inline std::size_t flipped_faces(const PolygonMesh& output, const PolygonMesh& input) {
    const SurfaceDistance surface(input);
    // unit normals of the input's fan triangles, in face order as SurfaceDistance numbers them
    std::vector<Vec3> normals;
    for (std::size_t f = 0; f < input.face_count(); ++f) {
        auto t = input.face(f);
        for (std::size_t j = 1; j + 1 < t.size(); ++j) {
            Vec3 n =
                cross(input.positions[t[j]] - input.positions[t[0]], input.positions[t[j + 1]] - input.positions[t[0]]);
            const double len = norm(n);
            normals.push_back(len > 0 ? n * (1.0 / len) : n);
        }
    }
    std::size_t count = 0;
    for (std::size_t f = 0; f < output.face_count(); ++f) {
        auto t = output.face(f);
        // the centroid and a point towards each corner, inside the face: a probe on an input vertex or edge (an
        // output vertex that never moved) would take whichever of the faces there the search meets first
        const Vec3 centroid = (output.positions[t[0]] + output.positions[t[1]] + output.positions[t[2]]) * (1.0 / 3.0);
        const Vec3 probes[4] = {centroid, (output.positions[t[0]] * 2.0 + centroid) * (1.0 / 3.0),
                                (output.positions[t[1]] * 2.0 + centroid) * (1.0 / 3.0),
                                (output.positions[t[2]] * 2.0 + centroid) * (1.0 / 3.0)};
        Vec3 reference;
        for (const Vec3& p : probes) {
            std::size_t nearest = 0;
            surface.closest_point(p, &nearest);
            reference += normals[nearest];
        }
        if (dot(face_normal(output, f), reference) < 0) ++count;
    }
    return count;
}

//! Positions of the vertices on boundary edges, sorted.
inline std::vector<std::array<double, 3>> boundary_positions(const PolygonMesh& mesh) {
    std::map<std::pair<Index, Index>, int> edges;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        auto t = mesh.face(f);
        for (std::size_t j = 0; j < t.size(); ++j) {
            const Index a = t[j], b = t[(j + 1) % t.size()];
            ++edges[{std::min(a, b), std::max(a, b)}];
        }
    }
    std::set<Index> vertices;
    for (const auto& [e, n] : edges)
        if (n == 1) vertices.insert({e.first, e.second});
    std::vector<std::array<double, 3>> out;
    for (Index v : vertices) out.push_back({mesh.positions[v].x, mesh.positions[v].y, mesh.positions[v].z});
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace surfaced::testing
