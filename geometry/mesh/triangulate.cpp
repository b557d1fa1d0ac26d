// Polygon triangulation: fan for convex polygons (the common case: quads from subdivision, OBJ n-gons), ear
// clipping for concave ones. Ear clipping runs in the polygon's own plane (Newell normal), so a non-planar polygon is
// handled as its projection; the output always has n - 2 triangles even when the polygon self-intersects.
// Reference: D. Eberly, "Triangulation by Ear Clipping" (Geometric Tools, 2002).
#include "geometry/mesh/triangulate.h"

#include <array>
#include <cmath>

namespace surfaced {

namespace {

struct Point2 {
    double x = 0, y = 0;
};

//! Twice the signed area of triangle (a, b, c): > 0 when counter-clockwise.
double orient(const Point2& a, const Point2& b, const Point2& c) {
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

//! Inclusive test: a point on an edge blocks the ear too, otherwise clipping could produce overlapping triangles.
bool in_triangle(const Point2& p, const Point2& a, const Point2& b, const Point2& c) {
    return orient(a, b, p) >= 0 && orient(b, c, p) >= 0 && orient(c, a, p) >= 0;
}

//! The polygon projected onto the plane perpendicular to its Newell normal, counter-clockwise seen from the normal.
//! Returns false when the polygon has no area (no plane to work in).
bool project(const PolygonMesh& mesh, std::span<const Index> face, std::vector<Point2>& out) {
    const std::size_t n = face.size();
    const Vec3& origin = mesh.positions[face[0]];
    Vec3 normal;
    for (std::size_t i = 0; i < n; ++i)
        normal += cross(mesh.positions[face[i]] - origin, mesh.positions[face[(i + 1) % n]] - origin);
    const double len = norm(normal);
    if (!(len > 0) || !std::isfinite(len)) return false;
    normal *= 1.0 / len;
    // Any vector not parallel to the normal seeds the basis; pick the axis the normal is least aligned with.
    const Vec3 seed = std::fabs(normal.x) < 0.6 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    Vec3 u = cross(seed, normal);
    u *= 1.0 / norm(u);
    const Vec3 v = cross(normal, u);  // (u, v, normal) right-handed: CCW around the normal is CCW in (u, v)
    out.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3 d = mesh.positions[face[i]] - origin;
        out[i] = {dot(d, u), dot(d, v)};
    }
    return true;
}

bool is_convex(const std::vector<Point2>& pts) {
    const std::size_t n = pts.size();
    for (std::size_t i = 0; i < n; ++i)
        if (orient(pts[(i + n - 1) % n], pts[i], pts[(i + 1) % n]) < 0) return false;
    return true;
}

using Corner3 = std::array<std::size_t, 3>;  // corners of a triangle as positions within the polygon

void fan(std::size_t n, std::vector<Corner3>& tris) {
    for (std::size_t i = 1; i + 1 < n; ++i) tris.push_back({0, i, i + 1});
}

//! Ear clipping on a doubly linked list of the remaining corners. Only reflex corners can lie inside an ear, so
//! those are the only ones tested; once none is left the rest is convex and is fanned.
void ear_clip(const std::vector<Point2>& pts, std::vector<Corner3>& tris) {
    const std::size_t n = pts.size();
    std::vector<std::size_t> prev(n), next(n);
    for (std::size_t i = 0; i < n; ++i) {
        prev[i] = (i + n - 1) % n;
        next[i] = (i + 1) % n;
    }
    std::vector<char> removed(n, 0);
    auto reflex_at = [&](std::size_t i) { return orient(pts[prev[i]], pts[i], pts[next[i]]) <= 0; };
    std::vector<std::size_t> reflex;
    for (std::size_t i = 0; i < n; ++i)
        if (reflex_at(i)) reflex.push_back(i);

    auto is_ear = [&](std::size_t i) {
        const std::size_t a = prev[i], c = next[i];
        if (orient(pts[a], pts[i], pts[c]) <= 0) return false;
        for (std::size_t r : reflex) {
            if (removed[r] || r == a || r == i || r == c) continue;
            if (in_triangle(pts[r], pts[a], pts[i], pts[c])) return false;
        }
        return true;
    };
    auto clip = [&](std::size_t i) {
        const std::size_t a = prev[i], c = next[i];
        tris.push_back({a, i, c});
        removed[i] = 1;
        next[a] = c;
        prev[c] = a;
    };

    std::size_t remaining = n;
    std::size_t current = 0;
    while (remaining > 3) {
        // Drop corners that stopped being reflex (a reflex corner turns convex when a neighbour is clipped).
        std::erase_if(reflex, [&](std::size_t r) { return removed[r] || !reflex_at(r); });
        if (reflex.empty()) break;  // convex remainder
        std::size_t i = current;
        bool found = false;
        for (std::size_t step = 0; step < remaining; ++step, i = next[i]) {
            if (is_ear(i)) {
                found = true;
                break;
            }
        }
        if (!found) {
            // Self-intersecting or degenerate input has no ear; clip the most convex corner so the count stays n-2.
            double best = -INFINITY;
            std::size_t j = current;
            for (std::size_t step = 0; step < remaining; ++step, j = next[j]) {
                const double o = orient(pts[prev[j]], pts[j], pts[next[j]]);
                if (o > best) {
                    best = o;
                    i = j;
                }
            }
        }
        current = next[i];
        clip(i);
        --remaining;
    }
    // Fan the convex (or final triangle) remainder from `current`, keeping its cyclic order.
    const std::size_t start = current;
    for (std::size_t j = next[start]; next[j] != start; j = next[j]) tris.push_back({start, j, next[j]});
}

}  // namespace

PolygonMesh triangulate(const PolygonMesh& mesh) {
    PolygonMesh out;
    out.positions = mesh.positions;
    out.uvs = mesh.uvs;
    out.normals = mesh.normals;
    // A uv index array that does not parallel the faces is a broken mesh (validate() rejects it): drop the uvs
    // rather than read past the end.
    const bool with_uvs = mesh.has_uvs() && mesh.uv_indices.size() == mesh.face_indices.size();
    if (!with_uvs) out.uvs.clear();

    std::size_t triangle_count = 0;
    for (std::size_t f = 0; f < mesh.face_count(); ++f)
        if (mesh.face_size(f) >= 3) triangle_count += mesh.face_size(f) - 2;
    out.face_offsets.reserve(triangle_count + 1);
    out.face_indices.reserve(triangle_count * 3);
    if (with_uvs) out.uv_indices.reserve(triangle_count * 3);

    std::vector<Point2> pts;
    std::vector<Corner3> tris;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const auto face = mesh.face(f);
        const std::size_t n = face.size();
        if (n < 3) continue;  // not a polygon (validate() rejects these); nothing sensible to emit
        tris.clear();
        if (n == 3 || !project(mesh, face, pts) || is_convex(pts))
            fan(n, tris);
        else
            ear_clip(pts, tris);
        const std::size_t offset = mesh.face_offsets[f];
        for (const Corner3& t : tris) {
            for (std::size_t k : t) {
                out.face_indices.push_back(face[k]);
                if (with_uvs) out.uv_indices.push_back(mesh.uv_indices[offset + k]);
            }
            out.face_offsets.push_back(static_cast<Index>(out.face_indices.size()));
        }
    }
    return out;
}

}  // namespace surfaced
