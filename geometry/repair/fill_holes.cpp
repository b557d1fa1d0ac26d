// Hole filling: boundary loops followed along the half-edges that have no neighbour, projected on their best-fit
// plane, tested for simplicity and ear clipped (D. Eberly, "Triangulation by Ear Clipping", Geometric Tools, 2002).
#include "geometry/repair/fill_holes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "geometry/repair/face_checks.h"
#include "geometry/repair/mesh_edges.h"

namespace surfaced::repair_detail {

namespace {

struct Point2 {
    double x = 0, y = 0;
};
using Triangle = std::array<std::size_t, 3>;  // positions within the loop

double orient(const Point2& a, const Point2& b, const Point2& c) {
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

//! The polygon projected on the plane perpendicular to its Newell normal (counter-clockwise seen from the normal);
//! false when it has no area.
bool project(const std::vector<Vec3>& positions, const std::vector<Index>& polygon, std::vector<Point2>& out) {
    const std::size_t n = polygon.size();
    const Vec3& origin = positions[polygon[0]];
    Vec3 normal;
    for (std::size_t i = 0; i < n; ++i)
        normal += cross(positions[polygon[i]] - origin, positions[polygon[(i + 1) % n]] - origin);
    const double len = norm(normal);
    if (!(len > 0) || !std::isfinite(len)) return false;
    normal *= 1.0 / len;
    const Vec3 seed = std::fabs(normal.x) < 0.6 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    Vec3 u = cross(seed, normal);
    u *= 1.0 / norm(u);
    const Vec3 v = cross(normal, u);
    out.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3 d = positions[polygon[i]] - origin;
        out[i] = {dot(d, u), dot(d, v)};
    }
    return true;
}

bool segments_touch(const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
    const double d1 = orient(c, d, a), d2 = orient(c, d, b), d3 = orient(a, b, c), d4 = orient(a, b, d);
    if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) return true;
    auto on = [](const Point2& p, const Point2& q, const Point2& r, double o) {  // r on segment pq, given orient
        return o == 0 && std::fmin(p.x, q.x) <= r.x && r.x <= std::fmax(p.x, q.x) && std::fmin(p.y, q.y) <= r.y &&
               r.y <= std::fmax(p.y, q.y);
    };
    return on(c, d, a, d1) || on(c, d, b, d2) || on(a, b, c, d3) || on(a, b, d, d4);
}

//! No two edges meet except consecutive ones at their shared corner. O(n^2).
bool is_simple(const std::vector<Point2>& pts) {
    const std::size_t n = pts.size();
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 2; j < n; ++j) {
            if (i == 0 && j == n - 1) continue;  // consecutive around the end
            if (segments_touch(pts[i], pts[i + 1], pts[j], pts[(j + 1) % n])) return false;
        }
    return true;
}

bool in_triangle(const Point2& p, const Point2& a, const Point2& b, const Point2& c) {
    return orient(a, b, p) >= 0 && orient(b, c, p) >= 0 && orient(c, a, p) >= 0;
}

//! Ear clipping of a simple counter-clockwise polygon; only strictly convex ears with no other corner inside or on
//! them are cut. False when no such ear is left before the end (collinear runs, rounding).
bool ear_clip(const std::vector<Point2>& pts, std::vector<Triangle>& tris) {
    const std::size_t n = pts.size();
    std::vector<std::size_t> prev(n), next(n);
    for (std::size_t i = 0; i < n; ++i) {
        prev[i] = (i + n - 1) % n;
        next[i] = (i + 1) % n;
    }
    auto is_ear = [&](std::size_t i) {
        const std::size_t a = prev[i], c = next[i];
        if (!(orient(pts[a], pts[i], pts[c]) > 0)) return false;
        for (std::size_t j = next[c]; j != a; j = next[j])
            if (in_triangle(pts[j], pts[a], pts[i], pts[c])) return false;
        return true;
    };
    std::size_t remaining = n, i = 0, misses = 0;
    while (remaining > 3) {
        if (!is_ear(i)) {
            i = next[i];
            if (++misses > remaining) return false;
            continue;
        }
        tris.push_back({prev[i], i, next[i]});
        next[prev[i]] = next[i];
        prev[next[i]] = prev[i];
        i = next[i];
        --remaining;
        misses = 0;
    }
    if (!(orient(pts[prev[i]], pts[i], pts[next[i]]) > 0)) return false;
    tris.push_back({prev[i], i, next[i]});
    return true;
}

class HoleFiller {
public:
    HoleFiller(PolygonMesh& mesh, std::span<const Index> place)
        : mesh_(mesh),
          place_(place),
          table_(make_corner_table(mesh.face_offsets, mesh.face_indices)),
          edges_(group_edges(table_, mesh.vertex_count())) {
        Index places = 0;
        for (Index p : place) places = std::max(places, p + 1);
        placed_indices_.reserve(mesh.face_indices.size());
        for (Index v : mesh.face_indices) placed_indices_.push_back(place[v]);
        placed_table_ = make_corner_table(mesh.face_offsets, placed_indices_);
        placed_edges_ = group_edges(placed_table_, places);
    }

    HoleFill run(std::size_t max_edges);

private:
    //! The boundary loop through boundary corner `start`, in the faces' direction; marks its corners visited.
    void follow(Index start, const std::vector<Index>& boundary_from, std::vector<std::uint8_t>& visited,
                std::vector<Index>& loop) const;
    //! Triangulates the hole behind `loop` into new_faces_; false (nothing added) when it is left open.
    bool close(const std::vector<Index>& loop);

    //! Faces of the mesh on the edge between the places of a and b.
    std::size_t faces_on(Index a, Index b) const {
        const Index e = placed_edges_.find(placed_table_, place_[a], place_[b]);
        return e == kInvalidIndex ? 0 : placed_edges_.size(e);
    }

    PolygonMesh& mesh_;
    std::span<const Index> place_;
    CornerTable table_;
    EdgeGroups edges_;
    std::vector<Index> placed_indices_;  // face_indices by place
    CornerTable placed_table_;
    EdgeGroups placed_edges_;
    std::vector<Index> new_faces_, new_uvs_;
};

void HoleFiller::follow(Index start, const std::vector<Index>& boundary_from, std::vector<std::uint8_t>& visited,
                        std::vector<Index>& loop) const {
    loop.clear();
    for (Index c = start; c != kInvalidIndex && !visited[c];) {
        visited[c] = 1;
        loop.push_back(c);
        c = boundary_from[table_.indices[table_.next(c)]];
    }
}

bool HoleFiller::close(const std::vector<Index>& loop) {
    const std::size_t n = loop.size();
    if (n < 3 || table_.indices[table_.next(loop.back())] != table_.indices[loop.front()]) return false;
    if (n == 3 && table_.face(loop[0]) == table_.face(loop[1]) && table_.face(loop[1]) == table_.face(loop[2]))
        return false;
    // the hole's polygon winds against the loop: loop corners 0, n-1, ..., 1
    std::vector<Index> polygon(n), corner(n);
    for (std::size_t i = 0; i < n; ++i) {
        corner[i] = loop[(n - i) % n];
        polygon[i] = table_.indices[corner[i]];
    }
    std::vector<Point2> pts;
    std::vector<Triangle> tris;
    if (!project(mesh_.positions, polygon, pts) || !is_simple(pts) || !ear_clip(pts, tris)) return false;
    for (const Triangle& t : tris) {
        const std::array<Index, 3> face{polygon[t[0]], polygon[t[1]], polygon[t[2]]};
        if (has_zero_area(mesh_.positions, face)) return false;
        for (int k = 0; k < 3; ++k) {
            const std::size_t a = t[k], b = t[(k + 1) % 3];
            const bool on_loop = (a + 1) % n == b || (b + 1) % n == a;
            if (faces_on(polygon[a], polygon[b]) != (on_loop ? 1u : 0u)) return false;
        }
    }
    for (const Triangle& t : tris)
        for (std::size_t k : t) {
            new_faces_.push_back(polygon[k]);
            if (mesh_.has_uvs()) new_uvs_.push_back(mesh_.uv_indices[corner[k]]);
        }
    return true;
}

HoleFill HoleFiller::run(std::size_t max_edges) {
    std::vector<Index> boundary_from(mesh_.vertex_count(), kInvalidIndex);
    for (std::size_t e = 0; e < edges_.edge_count(); ++e)
        if (edges_.size(e) == 1) boundary_from[table_.indices[edges_.of(e)[0]]] = edges_.of(e)[0];
    HoleFill result;
    std::vector<std::uint8_t> visited(table_.corner_count(), 0);
    std::vector<Index> loop;
    for (std::size_t e = 0; e < edges_.edge_count(); ++e) {
        const Index start = edges_.of(e)[0];
        if (edges_.size(e) != 1 || visited[start]) continue;
        follow(start, boundary_from, visited, loop);
        if (loop.size() > max_edges || !close(loop)) continue;
        ++result.holes;
    }
    result.faces = new_faces_.size() / 3;
    for (std::size_t i = 0; i < new_faces_.size(); i += 3)
        mesh_.add_face(std::span<const Index>(new_faces_.data() + i, 3));
    mesh_.uv_indices.insert(mesh_.uv_indices.end(), new_uvs_.begin(), new_uvs_.end());
    return result;
}

}  // namespace

HoleFill fill_holes(PolygonMesh& mesh, std::size_t max_edges, std::span<const Index> place) {
    if (max_edges < 3 || mesh.face_count() == 0) return {};
    HoleFiller filler(mesh, place);
    return filler.run(max_edges);
}

}  // namespace surfaced::repair_detail
