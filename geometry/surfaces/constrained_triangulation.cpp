#include "geometry/surfaces/constrained_triangulation.h"

#include <algorithm>
#include <cmath>
#include <deque>

namespace surfaced::detail {

double orient(Vec2 a, Vec2 b, Vec2 c) { return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x); }

namespace {

//! > 0 when d lies inside the circle through a, b, c (counter-clockwise), beyond a relative rounding margin: points
//! that are cocircular up to rounding (the corners of a grid cell) are not flipped back and forth.
bool in_circle(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
    const double adx = a.x - d.x, ady = a.y - d.y, bdx = b.x - d.x, bdy = b.y - d.y, cdx = c.x - d.x, cdy = c.y - d.y;
    const double alift = adx * adx + ady * ady, blift = bdx * bdx + bdy * bdy, clift = cdx * cdx + cdy * cdy;
    const double bc = bdx * cdy - cdx * bdy, ca = cdx * ady - adx * cdy, ab = adx * bdy - bdx * ady;
    const double det = alift * bc + blift * ca + clift * ab;
    const double magnitude = alift * std::fabs(bc) + blift * std::fabs(ca) + clift * std::fabs(ab);
    return det > 1e-12 * magnitude;
}

bool segments_cross(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
    const double o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
    return ((o1 < 0 && o2 > 0) || (o1 > 0 && o2 < 0)) && ((o3 < 0 && o4 > 0) || (o3 > 0 && o4 < 0));
}

}  // namespace

ConstrainedTriangulation::ConstrainedTriangulation(Vec2 lo, Vec2 hi) : lo_(lo), hi_(hi) {
    points_ = {lo, {hi.x, lo.y}, hi, {lo.x, hi.y}};
    triangles_.push_back({{0, 1, 2}, {-1, 1, -1}});
    triangles_.push_back({{0, 2, 3}, {-1, -1, 0}});
    vertex_triangle_ = {0, 0, 0, 1};
}

int ConstrainedTriangulation::opposite_index(int t, int neighbor) const {
    const CdtTriangle& tri = triangles_[static_cast<std::size_t>(t)];
    for (int j = 0; j < 3; ++j)
        if (tri.n[static_cast<std::size_t>(j)] == neighbor) return j;
    return -1;
}

void ConstrainedTriangulation::set_neighbor(int t, int old_neighbor, int new_neighbor) {
    if (t < 0) return;
    for (int& n : triangles_[static_cast<std::size_t>(t)].n)
        if (n == old_neighbor) {
            n = new_neighbor;
            return;
        }
}

ConstrainedTriangulation::Location ConstrainedTriangulation::locate(Vec2 p, int start, bool stop_at_constraints) const {
    int t = start >= 0 && start < static_cast<int>(triangles_.size()) ? start : 0;
    int rotation = 0;
    const std::size_t limit = 4 * triangles_.size() + 16;
    for (std::size_t step = 0; step <= limit; ++step) {
        const CdtTriangle& tri = triangles_[static_cast<std::size_t>(t)];
        bool moved = false;
        for (int k = 0; k < 3 && !moved; ++k) {
            const auto i = static_cast<std::size_t>((k + rotation) % 3);
            const int a = tri.v[(i + 1) % 3], b = tri.v[(i + 2) % 3];
            if (orient(points_[static_cast<std::size_t>(a)], points_[static_cast<std::size_t>(b)], p) < 0) {
                if (tri.n[i] < 0 || (stop_at_constraints && constrained(a, b)))
                    return {t, static_cast<int>(i), -1, true};
                t = tri.n[i];
                moved = true;
            }
        }
        rotation = (rotation + 1) % 3;
        if (moved) continue;
        Location at{t, -1, -1, false};
        for (int i = 0; i < 3; ++i) {
            const Vec2 q = points_[static_cast<std::size_t>(tri.v[static_cast<std::size_t>(i)])];
            if (q.x == p.x && q.y == p.y) at.vertex = tri.v[static_cast<std::size_t>(i)];
        }
        if (at.vertex < 0)
            for (int i = 0; i < 3; ++i) {
                const int a = tri.v[static_cast<std::size_t>((i + 1) % 3)],
                          b = tri.v[static_cast<std::size_t>((i + 2) % 3)];
                if (orient(points_[static_cast<std::size_t>(a)], points_[static_cast<std::size_t>(b)], p) == 0)
                    at.edge = i;
            }
        return at;
    }
    // The walk cycled (possible in a triangulation that is not Delaunay): scan every triangle.
    for (std::size_t t2 = 0; t2 < triangles_.size(); ++t2) {
        const CdtTriangle& tri = triangles_[t2];
        const Vec2 a = points_[static_cast<std::size_t>(tri.v[0])], b = points_[static_cast<std::size_t>(tri.v[1])],
                   c = points_[static_cast<std::size_t>(tri.v[2])];
        if (orient(a, b, p) >= 0 && orient(b, c, p) >= 0 && orient(c, a, p) >= 0)
            return locate(p, static_cast<int>(t2), stop_at_constraints);
    }
    return {t, -1, -1, true};
}

void ConstrainedTriangulation::split_triangle(int t, int p) {
    const CdtTriangle old = triangles_[static_cast<std::size_t>(t)];
    const int a = old.v[0], b = old.v[1], c = old.v[2];
    const int t1 = static_cast<int>(triangles_.size()), t2 = t1 + 1;
    triangles_[static_cast<std::size_t>(t)] = {{a, b, p}, {t1, t2, old.n[2]}};
    triangles_.push_back({{b, c, p}, {t2, t, old.n[0]}});
    triangles_.push_back({{c, a, p}, {t, t1, old.n[1]}});
    set_neighbor(old.n[0], t, t1);
    set_neighbor(old.n[1], t, t2);
    vertex_triangle_[static_cast<std::size_t>(a)] = t;
    vertex_triangle_[static_cast<std::size_t>(b)] = t;
    vertex_triangle_[static_cast<std::size_t>(c)] = t1;
    vertex_triangle_[static_cast<std::size_t>(p)] = t;
    std::vector<std::pair<int, int>> stack{{t, 2}, {t1, 2}, {t2, 2}};
    legalize(stack);
}

void ConstrainedTriangulation::split_edge(int t, int i, int p) {
    const auto is = static_cast<std::size_t>(i);
    const CdtTriangle old_t = triangles_[static_cast<std::size_t>(t)];
    const int a = old_t.v[is], b = old_t.v[(is + 1) % 3], c = old_t.v[(is + 2) % 3];
    const int t_nb = old_t.n[(is + 1) % 3], t_nc = old_t.n[(is + 2) % 3];
    const int u = old_t.n[is];
    const bool was_constrained = constrained(b, c);
    const int t1 = static_cast<int>(triangles_.size());
    int u1 = -1;
    if (u >= 0) u1 = t1 + 1;
    triangles_[static_cast<std::size_t>(t)] = {{a, b, p}, {u1, t1, t_nc}};
    triangles_.push_back({{a, p, c}, {u, t_nb, t}});
    set_neighbor(t_nb, t, t1);
    vertex_triangle_[static_cast<std::size_t>(a)] = t;
    vertex_triangle_[static_cast<std::size_t>(b)] = t;
    vertex_triangle_[static_cast<std::size_t>(c)] = t1;
    vertex_triangle_[static_cast<std::size_t>(p)] = t;
    std::vector<std::pair<int, int>> stack{{t, 2}, {t1, 1}};
    if (u >= 0) {
        const CdtTriangle old_u = triangles_[static_cast<std::size_t>(u)];
        const auto j = static_cast<std::size_t>(opposite_index(u, t));
        const int d = old_u.v[j];
        const int u_nc = old_u.n[(j + 1) % 3], u_nb = old_u.n[(j + 2) % 3];
        triangles_[static_cast<std::size_t>(u)] = {{d, c, p}, {t1, u1, u_nb}};
        triangles_.push_back({{d, p, b}, {t, u_nc, u}});
        set_neighbor(u_nc, u, u1);
        vertex_triangle_[static_cast<std::size_t>(d)] = u;
        stack.push_back({u, 2});
        stack.push_back({u1, 1});
    }
    if (was_constrained) {
        constraints_.erase(key(b, c));
        constraints_.insert(key(b, p));
        constraints_.insert(key(p, c));
    }
    legalize(stack);
}

bool ConstrainedTriangulation::flip(int t, int i) {
    const auto is = static_cast<std::size_t>(i);
    const CdtTriangle old_t = triangles_[static_cast<std::size_t>(t)];
    const int u = old_t.n[is];
    if (u < 0) return false;
    const CdtTriangle old_u = triangles_[static_cast<std::size_t>(u)];
    const auto j = static_cast<std::size_t>(opposite_index(u, t));
    const int a = old_t.v[is], b = old_t.v[(is + 1) % 3], c = old_t.v[(is + 2) % 3], d = old_u.v[j];
    const auto P = [&](int k) { return points_[static_cast<std::size_t>(k)]; };
    if (!(orient(P(a), P(b), P(d)) > 0 && orient(P(a), P(d), P(c)) > 0)) return false;
    const int t_nca = old_t.n[(is + 1) % 3], t_nab = old_t.n[(is + 2) % 3];
    const int u_nbd = old_u.n[(j + 1) % 3], u_ndc = old_u.n[(j + 2) % 3];
    triangles_[static_cast<std::size_t>(t)] = {{a, b, d}, {u_nbd, u, t_nab}};
    triangles_[static_cast<std::size_t>(u)] = {{a, d, c}, {u_ndc, t_nca, t}};
    set_neighbor(u_nbd, u, t);
    set_neighbor(t_nca, t, u);
    vertex_triangle_[static_cast<std::size_t>(a)] = t;
    vertex_triangle_[static_cast<std::size_t>(b)] = t;
    vertex_triangle_[static_cast<std::size_t>(d)] = t;
    vertex_triangle_[static_cast<std::size_t>(c)] = u;
    return true;
}

void ConstrainedTriangulation::legalize(std::vector<std::pair<int, int>>& stack) {
    std::size_t budget = 64 * triangles_.size() + 1024;  // rounding could otherwise cycle
    while (!stack.empty() && budget-- > 0) {
        const auto [t, i] = stack.back();
        stack.pop_back();
        const CdtTriangle& tri = triangles_[static_cast<std::size_t>(t)];
        const auto is = static_cast<std::size_t>(i);
        const int u = tri.n[is];
        const int b = tri.v[(is + 1) % 3], c = tri.v[(is + 2) % 3];
        if (u < 0 || constrained(b, c)) continue;
        const int j = opposite_index(u, t);
        const int d = triangles_[static_cast<std::size_t>(u)].v[static_cast<std::size_t>(j)];
        const auto P = [&](int k) { return points_[static_cast<std::size_t>(k)]; };
        if (!in_circle(P(tri.v[0]), P(tri.v[1]), P(tri.v[2]), P(d))) continue;
        if (!flip(t, i)) continue;
        stack.push_back({t, 0});
        stack.push_back({t, 2});
        stack.push_back({u, 0});
        stack.push_back({u, 1});
    }
}

void ConstrainedTriangulation::restore_delaunay() {
    std::vector<std::pair<int, int>> stack;
    for (std::size_t t = 0; t < triangles_.size(); ++t)
        for (int i = 0; i < 3; ++i) stack.push_back({static_cast<int>(t), i});
    legalize(stack);
}

int ConstrainedTriangulation::add_point(Vec2 p, const Location& at) {
    if (at.vertex >= 0) return at.vertex;
    const int index = static_cast<int>(points_.size());
    points_.push_back(p);
    vertex_triangle_.push_back(at.triangle);
    if (at.edge >= 0)
        split_edge(at.triangle, at.edge, index);
    else
        split_triangle(at.triangle, index);
    last_ = vertex_triangle_[static_cast<std::size_t>(index)];
    return index;
}

int ConstrainedTriangulation::insert(Vec2 p) {
    const Location at = locate(p, last_, false);
    if (at.blocked) return -1;  // outside the rectangle
    return add_point(p, at);
}

int ConstrainedTriangulation::insert_free(Vec2 p, int from, bool check_encroachment) {
    refused_side_ = {-1, -1};
    const Location at = locate(p, from, true);
    if (at.blocked) {
        const CdtTriangle& tri = triangles_[static_cast<std::size_t>(at.triangle)];
        const auto i = static_cast<std::size_t>(at.edge);
        if (tri.n[i] < 0) refused_side_ = {tri.v[(i + 1) % 3], tri.v[(i + 2) % 3]};
        return -1;
    }
    if (!(p.x > lo_.x && p.x < hi_.x && p.y > lo_.y && p.y < hi_.y)) return -1;
    if (at.vertex >= 0 || at.edge >= 0) return -1;
    const CdtTriangle& tri = triangles_[static_cast<std::size_t>(at.triangle)];
    for (std::size_t i = 0; i < 3 && check_encroachment; ++i) {
        const int a = tri.v[(i + 1) % 3], b = tri.v[(i + 2) % 3];
        if (tri.n[i] >= 0 && !constrained(a, b)) continue;
        const Vec2 pa = points_[static_cast<std::size_t>(a)], pb = points_[static_cast<std::size_t>(b)];
        if ((pa.x - p.x) * (pb.x - p.x) + (pa.y - p.y) * (pb.y - p.y) <= 0) {  // encroaches a-b
            if (tri.n[i] < 0) refused_side_ = {a, b};
            return -1;
        }
    }
    return add_point(p, at);
}

bool ConstrainedTriangulation::find_edge(int a, int b, int& t, int& i) const {
    const int first = vertex_triangle_[static_cast<std::size_t>(a)];
    // counter-clockwise around a, then clockwise from the start if the rectangle's side stopped us
    for (int direction = 0; direction < 2; ++direction) {
        int cur = first;
        for (std::size_t guard = 0; cur >= 0 && guard <= triangles_.size(); ++guard) {
            const CdtTriangle& tri = triangles_[static_cast<std::size_t>(cur)];
            int k = 0;
            while (tri.v[static_cast<std::size_t>(k)] != a) ++k;
            const auto ks = static_cast<std::size_t>(k);
            if (tri.v[(ks + 1) % 3] == b) {
                t = cur;
                i = static_cast<int>((ks + 2) % 3);
                return true;
            }
            if (tri.v[(ks + 2) % 3] == b) {
                t = cur;
                i = static_cast<int>((ks + 1) % 3);
                return true;
            }
            cur = direction == 0 ? tri.n[(ks + 1) % 3] : tri.n[(ks + 2) % 3];
            if (cur == first) return false;
        }
    }
    return false;
}

bool ConstrainedTriangulation::constrain(int a, int b) {
    const auto P = [&](int k) { return points_[static_cast<std::size_t>(k)]; };
    for (int round = 0; a != b; ++round) {
        if (round > 1'000'000) return false;
        int t = -1, i = -1;
        if (find_edge(a, b, t, i)) {
            constraints_.insert(key(a, b));
            return true;
        }
        const Vec2 A = P(a), B = P(b);
        // the triangle around a whose wedge holds the direction to b, or a neighbour lying on the segment
        int start = -1, right = -1, left = -1, on_segment = -1;
        const int first = vertex_triangle_[static_cast<std::size_t>(a)];
        for (int direction = 0; direction < 2 && start < 0 && on_segment < 0; ++direction) {
            int cur = first;
            for (std::size_t guard = 0; cur >= 0 && guard <= triangles_.size(); ++guard) {
                const CdtTriangle& tri = triangles_[static_cast<std::size_t>(cur)];
                std::size_t k = 0;
                while (tri.v[k] != a) ++k;
                const int p = tri.v[(k + 1) % 3], q = tri.v[(k + 2) % 3];
                const double op = orient(A, B, P(p)), oq = orient(A, B, P(q));
                const auto ahead = [&](int x) {
                    return (P(x).x - A.x) * (B.x - A.x) + (P(x).y - A.y) * (B.y - A.y) > 0;
                };
                if (op == 0 && ahead(p)) on_segment = p;
                if (oq == 0 && ahead(q)) on_segment = q;
                if (on_segment >= 0) break;
                if (op < 0 && oq > 0) {
                    start = cur;
                    right = p;
                    left = q;
                    break;
                }
                cur = direction == 0 ? tri.n[(k + 1) % 3] : tri.n[(k + 2) % 3];
                if (cur == first) break;
            }
        }
        if (on_segment >= 0) {  // a vertex on the segment: constrain up to it, continue from it
            constraints_.insert(key(a, on_segment));
            a = on_segment;
            continue;
        }
        if (start < 0) return false;
        // walk along the segment, collecting the edges it crosses
        std::deque<std::pair<int, int>> crossed;
        int target = b;
        for (int cur = start;;) {
            if (constrained(right, left)) return false;
            crossed.push_back({right, left});
            const CdtTriangle& tri = triangles_[static_cast<std::size_t>(cur)];
            std::size_t k = 0;
            while (tri.v[k] == right || tri.v[k] == left) ++k;
            const int next = tri.n[k];
            if (next < 0) return false;
            const int r =
                triangles_[static_cast<std::size_t>(next)].v[static_cast<std::size_t>(opposite_index(next, cur))];
            if (r == b) break;
            const double o = orient(A, B, P(r));
            if (o == 0) {
                target = r;
                break;
            }
            (o < 0 ? right : left) = r;
            cur = next;
        }
        // Sloan: flip crossing edges whose quadrilateral is convex until none crosses
        const Vec2 T = P(target);
        const std::size_t limit = 64 * crossed.size() * crossed.size() + 1024;
        for (std::size_t iteration = 0; !crossed.empty(); ++iteration) {
            if (iteration > limit) return false;
            const auto [x, y] = crossed.front();
            crossed.pop_front();
            int et = -1, ei = -1;
            if (!find_edge(x, y, et, ei)) continue;
            const int c = triangles_[static_cast<std::size_t>(et)].v[static_cast<std::size_t>(ei)];
            if (!flip(et, ei)) {
                crossed.push_back({x, y});
                continue;
            }
            // after the flip, triangle et is (c, x or y, d): d is its third vertex
            const CdtTriangle& now = triangles_[static_cast<std::size_t>(et)];
            const int d = now.v[2];
            if (c != a && c != target && d != a && d != target && segments_cross(A, T, P(c), P(d)))
                crossed.push_back({c, d});
        }
        constraints_.insert(key(a, target));
        a = target;
    }
    return true;
}

int ConstrainedTriangulation::components(std::vector<int>& label) const {
    label.assign(triangles_.size(), -1);
    int count = 0;
    std::vector<int> stack;
    for (std::size_t s = 0; s < triangles_.size(); ++s) {
        if (label[s] >= 0) continue;
        label[s] = count;
        stack.push_back(static_cast<int>(s));
        while (!stack.empty()) {
            const auto t = static_cast<std::size_t>(stack.back());
            stack.pop_back();
            const CdtTriangle& tri = triangles_[t];
            for (std::size_t i = 0; i < 3; ++i) {
                const int n = tri.n[i];
                if (n < 0 || label[static_cast<std::size_t>(n)] >= 0) continue;
                if (constrained(tri.v[(i + 1) % 3], tri.v[(i + 2) % 3])) continue;
                label[static_cast<std::size_t>(n)] = count;
                stack.push_back(n);
            }
        }
        ++count;
    }
    return count;
}

}  // namespace surfaced::detail
