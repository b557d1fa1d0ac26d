// Regular Loop patches (loop_patch.h): the corners' rings on the triangular lattice, phantom points across straight
// infinitely sharp creases, and the quartic box-spline basis.
#include "geometry/subdivision/loop_patch.h"

#include <algorithm>
#include <vector>

namespace surfaced::subdivision {

namespace {

//! The six lattice directions around a point, counter-clockwise from +u.
constexpr int kDirection[6][2] = {{1, 0}, {0, 1}, {-1, 1}, {-1, 0}, {0, -1}, {1, -1}};
//! The triangle's corners on the lattice; corner j's ring starts (at its next corner) with direction 2j.
constexpr int kCornerAt[3][2] = {{0, 0}, {1, 0}, {0, 1}};

//! 12 times the basis polynomials: coefficient k of point i multiplies u^a v^b, (a, b) = kMonomial[k].
constexpr int kMonomial[15][2] = {{0, 0}, {0, 1}, {0, 2}, {0, 3}, {0, 4}, {1, 0}, {1, 1}, {1, 2},
                                  {1, 3}, {2, 0}, {2, 1}, {2, 2}, {3, 0}, {3, 1}, {4, 0}};
constexpr int kBasis[12][15] = {
    {6, 0, -12, 8, -1, 0, -12, 12, -2, -12, 12, 0, 8, -2, -1},  // (0, 0)
    {1, 2, 0, -4, 2, 4, 6, -12, 4, 6, -6, 0, -4, -2, -1},       // (1, 0)
    {1, 4, 6, -4, -1, 2, 6, -6, -2, 0, -12, 0, -4, 4, 2},       // (0, 1)
    {1, 2, 0, -4, 2, -2, -6, 0, 4, 0, 6, 0, 2, -2, -1},         // (-1, 1)
    {1, -2, 0, 2, -1, -4, 6, 0, -2, 6, -6, 0, -4, 2, 1},        // (-1, 0)
    {1, -4, 6, -4, 1, -2, 6, -6, 2, 0, 0, 0, 2, -2, -1},        // (0, -1)
    {1, -2, 0, 2, -1, 2, -6, 6, -2, 0, 0, 0, -4, 4, 2},         // (1, -1)
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 2, -2, -1},            // (2, -1)
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 2, 1},              // (2, 0)
    {0, 0, 0, 2, -1, 0, 0, 6, -2, 0, 6, 0, 2, -2, -1},          // (1, 1)
    {0, 0, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0, 0, 0, 0},              // (0, 2)
    {0, 0, 0, 2, -1, 0, 0, 0, -2, 0, 0, 0, 0, 0, 0},            // (-1, 2)
};

//! Whether kMonomial is a-major with b ascending (the offsets evaluate_loop_polynomial's nested form reads).
constexpr bool monomials_a_major() {
    int k = 0;
    for (int a = 0; a <= 4; ++a)
        for (int b = 0; a + b <= 4; ++b, ++k)
            if (kMonomial[k][0] != a || kMonomial[k][1] != b) return false;
    return k == 15;
}
static_assert(monomials_a_major());

int cross(int ax, int ay, int bx, int by) { return ax * by - ay * bx; }

//! A corner's 1-ring on the lattice: the vertex at each direction (kInvalidIndex where the ring stops at a crease),
//! and for a crease corner the direction of its line.
struct CornerRing {
    Index at[6];
    int line = -1;
};

//! Corner j's ring when the corner is regular.
bool corner_ring(const Piece& p, const Adjacency& adj, Index f, int j, CornerRing& ring, bool* semi_sharp) {
    const Level& L = p.level;
    const Index v = face_vert(L, f, static_cast<Index>(j));
    const float vs = p.sharp.vertex[v];
    if (semi_sharp) *semi_sharp = false;
    // the edges at v, from its faces (each face's edges leaving and arriving at v)
    std::vector<Index> edges;
    for (Index k = adj.vf_offsets[v]; k < adj.vf_offsets[v + 1]; ++k) {
        const Index g = adj.vf_faces[k];
        const Index begin = L.face_offsets[g], n = L.face_offsets[g + 1] - begin;
        if (n != 3) return false;
        int uses = 0;
        for (Index s = 0; s < 3; ++s)
            if (L.face_verts[begin + s] == v) {
                ++uses;
                edges.push_back(L.face_edges[begin + s]);
                edges.push_back(L.face_edges[begin + (s + 2) % 3]);
            }
        if (uses != 1) return false;
    }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    bool semi = is_semi_sharp(vs);
    for (Index e : edges) semi = semi || is_semi_sharp(p.sharp.edge[e]);
    if (semi_sharp) *semi_sharp = semi;
    if (semi || vs != 0.0f) return false;
    int sharp_count = 0;
    for (Index e : edges) {
        if (L.edge_verts[2 * e] == L.edge_verts[2 * e + 1] || adj.edge_uses[e] > 2) return false;
        if (is_sharp(p.sharp.edge[e]))
            ++sharp_count;
        else if (adj.edge_uses[e] != 2)
            return false;
    }
    const Index face_count = adj.vf_offsets[v + 1] - adj.vf_offsets[v];
    if (sharp_count == 0 && (face_count != 6 || edges.size() != 6)) return false;
    if (sharp_count != 0 && sharp_count != 2) return false;

    std::fill(ring.at, ring.at + 6, kInvalidIndex);
    ring.line = -1;
    const Index k0 = slot_of(L, f, v);
    ring.at[(2 * j) % 6] = face_vert(L, f, k0 + 1);
    ring.at[(2 * j + 1) % 6] = face_vert(L, f, k0 + 2);
    int faces = 1;
    // counter-clockwise: across the edge (prev, v) of each face
    Index g = f, k = k0;
    bool closed = false;
    for (int step = 1;; ++step) {
        const Index e = L.face_edges[L.face_offsets[g] + (k + 2) % 3];
        if (is_sharp(p.sharp.edge[e])) {
            ring.line = (2 * j + step) % 6;
            break;
        }
        const Index h = adj.across(e, g);
        if (h == kInvalidIndex) return false;
        const Index kh = slot_of(L, h, v);
        if (face_vert(L, h, kh + 1) != face_vert(L, g, k + 2)) return false;
        if (h == f) {
            closed = true;
            break;
        }
        if (step > 5) return false;
        ring.at[(2 * j + 1 + step) % 6] = face_vert(L, h, kh + 2);
        ++faces;
        g = h;
        k = kh;
    }
    if (sharp_count == 0) return closed && faces == 6;
    if (closed) return false;
    // clockwise: across the edge (v, next) of each face
    g = f;
    k = k0;
    for (int step = 1;; ++step) {
        const Index e = L.face_edges[L.face_offsets[g] + k];
        if (is_sharp(p.sharp.edge[e])) break;
        const Index h = adj.across(e, g);
        if (h == kInvalidIndex) return false;
        const Index kh = slot_of(L, h, v);
        if (face_vert(L, h, kh + 2) != face_vert(L, g, k + 1)) return false;
        if (step > 5 || h == f) return false;
        ring.at[(2 * j - step + 12) % 6] = face_vert(L, h, kh + 1);
        ++faces;
        g = h;
        k = kh;
    }
    return faces == 3;
}

//! Lattice points of the patch neighbourhood: coordinates in [-2, 3]^2.
struct LatticeMap {
    Index at[6][6];
    LatticeMap() {
        for (auto& row : at) std::fill(row, row + 6, kInvalidIndex);
    }
    static bool inside(int x, int y) { return x >= -2 && x <= 3 && y >= -2 && y <= 3; }
    Index get(int x, int y) const { return inside(x, y) ? at[y + 2][x + 2] : kInvalidIndex; }
    //! false when the point already holds another vertex
    bool set(int x, int y, Index v) {
        if (!inside(x, y)) return false;
        Index& slot = at[y + 2][x + 2];
        if (slot != kInvalidIndex && slot != v) return false;
        slot = v;
        return true;
    }
};

}  // namespace

bool loop_corner_regular(const Piece& p, const Adjacency& adj, Index f, int j, bool* semi_sharp) {
    CornerRing ring;
    return corner_ring(p, adj, f, j, ring, semi_sharp);
}

bool loop_regular_patch(const Piece& p, const Adjacency& adj, Index f, std::array<Vec3, 12>& points) {
    const Level& L = p.level;
    if (L.face_offsets[f + 1] - L.face_offsets[f] != 3) return false;
    CornerRing rings[3];
    LatticeMap map;
    for (int j = 0; j < 3; ++j) {
        if (!corner_ring(p, adj, f, j, rings[j], nullptr)) return false;
        if (!map.set(kCornerAt[j][0], kCornerAt[j][1], face_vert(L, f, static_cast<Index>(j)))) return false;
    }
    for (int j = 0; j < 3; ++j)
        for (int d = 0; d < 6; ++d)
            if (rings[j].at[d] != kInvalidIndex &&
                !map.set(kCornerAt[j][0] + kDirection[d][0], kCornerAt[j][1] + kDirection[d][1], rings[j].at[d]))
                return false;
    for (int i = 0; i < 12; ++i) {
        const int x = kLoopPatchLattice[i][0], y = kLoopPatchLattice[i][1];
        const Index known = map.get(x, y);
        if (known != kInvalidIndex) {
            points[i] = p.points[known];
            continue;
        }
        // a phantom: beyond the line of a crease corner (the face's centre, times 3, is (1, 1))
        int line_corner = -1;
        for (int j = 0; j < 3; ++j) {
            if (rings[j].line < 0) continue;
            const int dx = kDirection[rings[j].line][0], dy = kDirection[rings[j].line][1];
            const int cx = kCornerAt[j][0], cy = kCornerAt[j][1];
            const int side = cross(dx, dy, x - cx, y - cy), face_side = cross(dx, dy, 1 - 3 * cx, 1 - 3 * cy);
            if (side == 0 || (side > 0) == (face_side > 0)) continue;
            if (line_corner >= 0) {
                // beyond two crease lines: only when they are the same line
                const int lj = line_corner;
                const bool same = rings[lj].line % 3 == rings[j].line % 3 &&
                                  cross(dx, dy, kCornerAt[lj][0] - cx, kCornerAt[lj][1] - cy) == 0;
                if (!same) return false;
                continue;
            }
            if (side != 1 && side != -1) return false;
            line_corner = j;
        }
        if (line_corner < 0) return false;
        const int dx = kDirection[rings[line_corner].line][0], dy = kDirection[rings[line_corner].line][1];
        const int cx = kCornerAt[line_corner][0], cy = kCornerAt[line_corner][1];
        // the two line points next to X, and the point C across the line: X = A + B - C
        int ax[2], ay[2], found = 0;
        for (int d = 0; d < 6 && found < 2; ++d) {
            const int nx = x + kDirection[d][0], ny = y + kDirection[d][1];
            if (cross(dx, dy, nx - cx, ny - cy) == 0) {
                ax[found] = nx;
                ay[found] = ny;
                ++found;
            }
        }
        if (found != 2) return false;
        const Index a = map.get(ax[0], ay[0]), b = map.get(ax[1], ay[1]);
        const Index c = map.get(ax[0] + ax[1] - x, ay[0] + ay[1] - y);
        if (a == kInvalidIndex || b == kInvalidIndex || c == kInvalidIndex) return false;
        points[i] = p.points[a] + p.points[b] - p.points[c];
    }
    return true;
}

void loop_patch_polynomial(const std::array<Vec3, 12>& points, std::array<Vec3, 16>& coefficients) {
    for (int k = 0; k < 15; ++k) {
        Vec3 sum{};
        for (int i = 0; i < 12; ++i)
            if (kBasis[i][k] != 0) sum += static_cast<double>(kBasis[i][k]) * points[i];
        coefficients[k] = sum * (1.0 / 12.0);
    }
    coefficients[15] = Vec3{};
}

void evaluate_loop_polynomial(const std::array<Vec3, 16>& coefficients, double u, double v, bool second, Vec3 out[6]) {
    // nested (Horner) form: the patch is sum_a u^a Q_a(v), Q_a of degree 4 - a with the coefficients of u^a v^b at
    // kMonomial's a-major offsets 0, 5, 9, 12, 14; Q_a and its v-derivatives first, then the sums over a in u
    const Vec3* c = coefficients.data();
    const Vec3 q0 = c[0] + v * (c[1] + v * (c[2] + v * (c[3] + v * c[4])));
    const Vec3 q1 = c[5] + v * (c[6] + v * (c[7] + v * c[8]));
    const Vec3 q2 = c[9] + v * (c[10] + v * c[11]);
    const Vec3 q3 = c[12] + v * c[13];
    const Vec3& q4 = c[14];
    const Vec3 q0v = c[1] + v * (2.0 * c[2] + v * (3.0 * c[3] + v * (4.0 * c[4])));
    const Vec3 q1v = c[6] + v * (2.0 * c[7] + v * (3.0 * c[8]));
    const Vec3 q2v = c[10] + v * (2.0 * c[11]);
    const Vec3& q3v = c[13];
    out[0] = q0 + u * (q1 + u * (q2 + u * (q3 + u * q4)));
    out[1] = q1 + u * (2.0 * q2 + u * (3.0 * q3 + u * (4.0 * q4)));
    out[2] = q0v + u * (q1v + u * (q2v + u * q3v));
    if (!second) {
        out[3] = out[4] = out[5] = Vec3{};
        return;
    }
    const Vec3 q0vv = 2.0 * c[2] + v * (6.0 * c[3] + v * (12.0 * c[4]));
    const Vec3 q1vv = 2.0 * c[7] + v * (6.0 * c[8]);
    const Vec3 q2vv = 2.0 * c[11];
    out[3] = 2.0 * q2 + u * (6.0 * q3 + u * (12.0 * q4));
    out[4] = q1v + u * (2.0 * q2v + u * (3.0 * q3v));
    out[5] = q0vv + u * (q1vv + u * q2vv);
}

}  // namespace surfaced::subdivision
