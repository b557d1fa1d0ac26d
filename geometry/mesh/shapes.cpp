#include "geometry/mesh/shapes.h"

#include <cmath>
#include <numbers>

namespace surfaced::shapes {

PolygonMesh cube() {
    PolygonMesh m;
    m.positions = {{-0.5, -0.5, -0.5}, {0.5, -0.5, -0.5}, {0.5, 0.5, -0.5}, {-0.5, 0.5, -0.5},
                   {-0.5, -0.5, 0.5},  {0.5, -0.5, 0.5},  {0.5, 0.5, 0.5},  {-0.5, 0.5, 0.5}};
    m.add_face({0, 3, 2, 1});  // -z
    m.add_face({4, 5, 6, 7});  // +z
    m.add_face({0, 1, 5, 4});  // -y
    m.add_face({2, 3, 7, 6});  // +y
    m.add_face({1, 2, 6, 5});  // +x
    m.add_face({0, 4, 7, 3});  // -x
    return m;
}

PolygonMesh tetrahedron() {
    PolygonMesh m;
    m.positions = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
    m.add_face({0, 1, 2});
    m.add_face({0, 3, 1});
    m.add_face({0, 2, 3});
    m.add_face({1, 3, 2});
    return m;
}

PolygonMesh octahedron() {
    PolygonMesh m;
    m.positions = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    m.add_face({0, 2, 4});
    m.add_face({2, 1, 4});
    m.add_face({1, 3, 4});
    m.add_face({3, 0, 4});
    m.add_face({2, 0, 5});
    m.add_face({1, 2, 5});
    m.add_face({3, 1, 5});
    m.add_face({0, 3, 5});
    return m;
}

PolygonMesh icosahedron() {
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    const double s = 1.0 / std::sqrt(1.0 + t * t);
    PolygonMesh m;
    m.positions = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                   {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
    for (Vec3& p : m.positions) p *= s;
    const Index faces[20][3] = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                                {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                                {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    for (const auto& f : faces) m.add_face({f[0], f[1], f[2]});
    return m;
}

PolygonMesh grid(int nx, int ny, bool triangles) {
    PolygonMesh m;
    for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i) m.positions.push_back({double(i) / nx, double(j) / ny, 0.0});
    auto id = [&](int i, int j) { return static_cast<Index>(j * (nx + 1) + i); };
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            if (triangles) {
                m.add_face({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
                m.add_face({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
            } else {
                m.add_face({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
            }
        }
    return m;
}

PolygonMesh torus(int n, int m_count, double R, double r) {
    PolygonMesh m;
    for (int i = 0; i < n; ++i) {
        const double u = 2.0 * std::numbers::pi * i / n;
        for (int j = 0; j < m_count; ++j) {
            const double v = 2.0 * std::numbers::pi * j / m_count;
            m.positions.push_back(
                {(R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u), r * std::sin(v)});
        }
    }
    auto id = [&](int i, int j) { return static_cast<Index>(((i + n) % n) * m_count + (j + m_count) % m_count); };
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < m_count; ++j) m.add_face({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
    return m;
}

namespace {

// Rotates the edge shared by quads a = (v0 v1 v2 v3) and b = (v3 v2 v4 v5) inside their hexagon: the shared edge's
// ends drop to valence 3 and the new diagonal's ends rise to valence 5.
void rotate_shared_edge(PolygonMesh& m, std::size_t a, std::size_t b) {
    auto fa = m.face(a), fb = m.face(b);
    // find the shared edge oriented fa[j] -> fa[j+1] and fb[k] -> fb[k+1] reversed
    for (std::size_t j = 0; j < 4; ++j)
        for (std::size_t k = 0; k < 4; ++k)
            if (fa[j] == fb[(k + 1) % 4] && fa[(j + 1) % 4] == fb[k]) {
                const Index v0 = fa[(j + 2) % 4], v1 = fa[(j + 3) % 4], v2 = fa[j], v3 = fa[(j + 1) % 4];
                const Index v4 = fb[(k + 2) % 4], v5 = fb[(k + 3) % 4];
                // hexagon v0 v1 v2 v4 v5 v3 (the shared edge was v2-v3 in quad a = v0 v1 v2 v3)
                const Index qa[4] = {v1, v2, v4, v5}, qb[4] = {v5, v3, v0, v1};
                Index* pa = &m.face_indices[m.face_offsets[a]];
                Index* pb = &m.face_indices[m.face_offsets[b]];
                for (int i = 0; i < 4; ++i) {
                    pa[i] = qa[i];
                    pb[i] = qb[i];
                }
                return;
            }
}

}  // namespace

PolygonMesh irregular_torus() {
    PolygonMesh m = torus(8, 6);
    // faces (i, j) are numbered i * 6 + j; (0,0)/(1,0) share an edge, as do (4,3)/(4,4)
    rotate_shared_edge(m, 0 * 6 + 0, 1 * 6 + 0);
    rotate_shared_edge(m, 4 * 6 + 3, 4 * 6 + 4);
    return m;
}

PolygonMesh mixed_polygons() {
    // A gable-roofed house: pentagon gable walls, quad walls/roof/floor, one wall split into two triangles.
    PolygonMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},     {0, 0, 1},
                   {1, 0, 1}, {1, 1, 1}, {0, 1, 1}, {0.5, 0, 1.5}, {0.5, 1, 1.5}};
    m.add_face({0, 1, 5, 8, 4});  // front gable
    m.add_face({2, 3, 7, 9, 6});  // back gable
    m.add_face({0, 3, 2, 1});     // floor
    m.add_face({1, 2, 6});        // right wall, two triangles
    m.add_face({1, 6, 5});
    m.add_face({0, 4, 7, 3});  // left wall
    m.add_face({5, 6, 9, 8});  // roof
    m.add_face({4, 8, 9, 7});
    return m;
}

PolygonMesh grid_with_holes() {
    PolygonMesh full = grid(6, 6);
    PolygonMesh m;
    m.positions = full.positions;
    for (std::size_t f = 0; f < full.face_count(); ++f) {
        const std::size_t i = f % 6, j = f / 6;
        if ((i == 1 && j == 1) || (i == 4 && j == 3)) continue;  // two separated one-quad holes
        m.add_face(full.face(f));
    }
    return m;
}

}  // namespace surfaced::shapes
