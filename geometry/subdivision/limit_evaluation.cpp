// Limit surface evaluation (limit_evaluation.h): regular patches as bicubic B-splines (with phantom points at
// infinitely sharp edges), everything else by local refinement of the face's 2-ring until the point's child face is
// regular.
#include "geometry/subdivision/limit_evaluation.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <utility>

#include "geometry/subdivision/creases.h"
#include "geometry/subdivision/interpolate.h"
#include "geometry/subdivision/limit.h"
#include "geometry/subdivision/limit_piece.h"
#include "geometry/subdivision/loop_patch.h"
#include "geometry/subdivision/topology.h"

namespace surfaced {

namespace {

using subdivision::Adjacency;
using subdivision::extract;
using subdivision::face_vert;
using subdivision::is_infinite;
using subdivision::is_semi_sharp;
using subdivision::is_sharp;
using subdivision::Level;
using subdivision::Piece;
using subdivision::refine;
using subdivision::slot_of;
using subdivision::vertex_faces;

//! The distinct edges at vertex v of a level: each face's two edges at its corner v.
std::vector<Index> edges_at(const Level& L, const Adjacency& adj, Index v) {
    std::vector<Index> edges;
    for (Index k = adj.vf_offsets[v]; k < adj.vf_offsets[v + 1]; ++k) {
        const Index g = adj.vf_faces[k], n = L.face_offsets[g + 1] - L.face_offsets[g];
        const Index s = slot_of(L, g, v);
        edges.push_back(L.face_edges[L.face_offsets[g] + s]);
        edges.push_back(L.face_edges[L.face_offsets[g] + (s + n - 1) % n]);
    }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    return edges;
}

//! Corner j of quad f: whether the limit surface over f near it is the tensor-product B-spline (smooth valence 4,
//! a straight infinitely sharp crease or boundary with the face's side holding two quads, or a corner with the face
//! alone between two infinitely sharp edges), given which of f's edges are infinitely sharp. `semi_sharp` is set
//! when a semi-sharp vertex or edge at the corner is what prevents it (it decays with refinement).
bool corner_regular(const Piece& p, const Adjacency& adj, Index f, int j, const bool sharp_edge[4],
                    bool* semi_sharp = nullptr) {
    const Level& L = p.level;
    const Index begin = L.face_offsets[f];
    const Index v = L.face_verts[begin + j];
    const float vs = p.sharp.vertex[v];
    if (semi_sharp) *semi_sharp = false;
    bool quads = true;
    for (Index k = adj.vf_offsets[v]; k < adj.vf_offsets[v + 1]; ++k) {
        const Index g = adj.vf_faces[k];
        if (L.face_offsets[g + 1] - L.face_offsets[g] != 4) quads = false;
    }
    // the edges at v: each face's edges leaving and arriving at v
    const std::vector<Index> edges = quads ? edges_at(L, adj, v) : std::vector<Index>{};
    bool semi = is_semi_sharp(vs);
    for (Index ed : edges) semi = semi || is_semi_sharp(p.sharp.edge[ed]);
    if (semi_sharp) *semi_sharp = semi;
    if (semi || !quads) return false;
    const Index face_count = adj.vf_offsets[v + 1] - adj.vf_offsets[v];
    int sharp_count = 0, edge_count = 0;
    for (Index ed : edges) {
        const float s = p.sharp.edge[ed];
        if (L.edge_verts[2 * ed] == L.edge_verts[2 * ed + 1] || adj.edge_uses[ed] > 2) return false;
        if (is_sharp(s))
            ++sharp_count;
        else if (adj.edge_uses[ed] != 2)
            return false;
        ++edge_count;
    }
    const Index e_out = L.face_edges[begin + j], e_in = L.face_edges[begin + (j + 3) % 4];
    const bool in = sharp_edge[(j + 3) % 4], out = sharp_edge[j];
    if (!in && !out) return vs == 0.0f && sharp_count == 0 && face_count == 4 && edge_count == 4;
    if (in && out) return is_infinite(vs) || sharp_count >= 3;
    if (vs != 0.0f || sharp_count != 2) return false;
    // the face's sector is f and the neighbour across its smooth edge at v, closed by a sharp edge
    const Index smooth = in ? e_out : e_in;
    const Index g = adj.across(smooth, f);
    if (g == kInvalidIndex) return false;
    const Index s = slot_of(L, g, v);
    const Index leave = L.face_edges[L.face_offsets[g] + s], arrive = L.face_edges[L.face_offsets[g] + (s + 3) % 4];
    return is_infinite(p.sharp.edge[leave == smooth ? arrive : leave]);
}

//! Which of quad f's edges are infinitely sharp.
void sharp_edges_of(const Piece& p, Index f, bool sharp_edge[4]) {
    for (int j = 0; j < 4; ++j)
        sharp_edge[j] = is_infinite(p.sharp.edge[p.level.face_edges[p.level.face_offsets[f] + j]]);
}

//! The 16 control points of face `f` of `p` when its limit surface is one bicubic B-spline patch (see the header
//! for the cases), false otherwise. Face f's corners must have all their faces in the piece.
bool regular_patch(const Piece& p, const Adjacency& adj, Index f, std::array<Vec3, 16>& grid) {
    const Level& L = p.level;
    const Index begin = L.face_offsets[f];
    if (L.face_offsets[f + 1] - begin != 4) return false;
    Index c[4], e[4];
    for (int j = 0; j < 4; ++j) {
        c[j] = L.face_verts[begin + j];
        e[j] = L.face_edges[begin + j];
    }
    for (int j = 0; j < 4; ++j)
        for (int k = j + 1; k < 4; ++k)
            if (c[j] == c[k]) return false;
    bool sharp_edge[4];
    sharp_edges_of(p, f, sharp_edge);
    for (int j = 0; j < 4; ++j)
        if (!corner_regular(p, adj, f, j, sharp_edge)) return false;
    // gather: P[r][col], r along v, col along u; corner j of F at pos[j]
    Vec3 P[4][4];
    bool known[4][4] = {};
    const int pos[4][2] = {{1, 1}, {1, 2}, {2, 2}, {2, 1}};
    const int out_dir[4][2] = {{-1, 0}, {0, 1}, {1, 0}, {0, -1}};  // beyond edge j
    auto set = [&](int r, int col, Index v) {
        P[r][col] = p.points[v];
        known[r][col] = true;
    };
    for (int j = 0; j < 4; ++j) set(pos[j][0], pos[j][1], c[j]);
    for (int j = 0; j < 4; ++j) {
        if (sharp_edge[j]) continue;
        const Index g = adj.across(e[j], f);
        if (g == kInvalidIndex) return false;
        const Index k = slot_of(L, g, c[(j + 1) % 4]);
        if (face_vert(L, g, k + 1) != c[j]) return false;
        const int j1 = (j + 1) % 4;
        set(pos[j][0] + out_dir[j][0], pos[j][1] + out_dir[j][1], face_vert(L, g, k + 2));
        set(pos[j1][0] + out_dir[j][0], pos[j1][1] + out_dir[j][1], face_vert(L, g, k + 3));
    }
    for (int j = 0; j < 4; ++j) {
        const int jp = (j + 3) % 4;
        if (sharp_edge[j] || sharp_edge[jp]) continue;
        const Index ga = adj.across(e[j], f), gb = adj.across(e[jp], f);
        Index diagonal = kInvalidIndex;
        for (Index k = adj.vf_offsets[c[j]]; k < adj.vf_offsets[c[j] + 1]; ++k) {
            const Index g = adj.vf_faces[k];
            if (g != f && g != ga && g != gb) diagonal = g;
        }
        if (diagonal == kInvalidIndex) return false;
        set(pos[j][0] + out_dir[j][0] + out_dir[jp][0], pos[j][1] + out_dir[j][1] + out_dir[jp][1],
            face_vert(L, diagonal, slot_of(L, diagonal, c[j]) + 2));
    }
    // phantoms: columns first (edges 3 and 1), then rows (edges 0 and 2), which also fills the grid's corners
    for (int r = 0; r < 4; ++r) {
        if (sharp_edge[3] && known[r][1] && known[r][2]) {
            P[r][0] = 2.0 * P[r][1] - P[r][2];
            known[r][0] = true;
        }
        if (sharp_edge[1] && known[r][1] && known[r][2]) {
            P[r][3] = 2.0 * P[r][2] - P[r][1];
            known[r][3] = true;
        }
    }
    for (int col = 0; col < 4; ++col) {
        if (sharp_edge[0]) {
            P[0][col] = 2.0 * P[1][col] - P[2][col];
            known[0][col] = known[1][col] && known[2][col];
        }
        if (sharp_edge[2]) {
            P[3][col] = 2.0 * P[2][col] - P[1][col];
            known[3][col] = known[1][col] && known[2][col];
        }
    }
    for (int r = 0; r < 4; ++r)
        for (int col = 0; col < 4; ++col) {
            if (!known[r][col]) return false;
            grid[4 * r + col] = P[r][col];
        }
    return true;
}

//! Uniform cubic B-spline basis and its first (and when `Second`, second) derivatives at t in [0, 1].
template <bool Second>
inline void bspline_basis(double t, double b[4], double d[4], double dd[4]) {
    const double s = 1.0 - t, t2 = t * t, t3 = t2 * t;
    b[0] = s * s * s / 6.0;
    b[1] = (3.0 * t3 - 6.0 * t2 + 4.0) / 6.0;
    b[2] = (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) / 6.0;
    b[3] = t3 / 6.0;
    d[0] = -0.5 * s * s;
    d[1] = 0.5 * (3.0 * t2 - 4.0 * t);
    d[2] = 0.5 * (-3.0 * t2 + 2.0 * t + 1.0);
    d[3] = 0.5 * t2;
    if constexpr (Second) {
        dd[0] = s;
        dd[1] = 3.0 * t - 2.0;
        dd[2] = 1.0 - 3.0 * t;
        dd[3] = t;
    }
}

inline Vec3 unit(const Vec3& v) {
    const double len = norm(v);
    return len > 0 ? v * (1.0 / len) : Vec3{};
}

//! The patch at local (s, t) into `out` (default-initialized); derivatives multiplied by `scale` (d(local)/d(u, v))
//! once per order. Tensor form: each row's sums along s (with the values and the derivatives of the s basis) are
//! combined along t, in registers.
template <bool Second>
void evaluate_patch(const std::array<Vec3, 16>& grid, double s, double t, double scale, LimitSample& out) {
    double bu[4], du[4], ddu[4], bv[4], dv[4], ddv[4];
    bspline_basis<Second>(s, bu, du, ddu);
    bspline_basis<Second>(t, bv, dv, ddv);
    Vec3 position{}, d_u{}, d_v{}, d_uu{}, d_uv{}, d_vv{};
    for (int r = 0; r < 4; ++r) {
        const Vec3* row = &grid[4 * static_cast<std::size_t>(r)];
        Vec3 row_b{}, row_d{}, row_dd{};
        for (int col = 0; col < 4; ++col) {
            row_b += bu[col] * row[col];
            row_d += du[col] * row[col];
            if constexpr (Second) row_dd += ddu[col] * row[col];
        }
        position += bv[r] * row_b;
        d_u += bv[r] * row_d;
        d_v += dv[r] * row_b;
        if constexpr (Second) {
            d_uu += bv[r] * row_dd;
            d_uv += dv[r] * row_d;
            d_vv += ddv[r] * row_b;
        }
    }
    d_u = scale * d_u;
    d_v = scale * d_v;
    out.position = position;
    out.du = d_u;
    out.dv = d_v;
    out.normal = unit(cross(d_u, d_v));
    if constexpr (Second) {
        out.duu = (scale * scale) * d_uu;
        out.duv = (scale * scale) * d_uv;
        out.dvv = (scale * scale) * d_vv;
    }
}

//! The Loop patch (its polynomial, loop_patch.h) at local (s, t), as evaluate_patch.
void evaluate_loop_patch(const std::array<Vec3, 16>& coefficients, double s, double t, double scale, bool second,
                         LimitSample& out) {
    Vec3 d[6];
    subdivision::evaluate_loop_polynomial(coefficients, s, t, second, d);
    const Vec3 d_u = scale * d[1], d_v = scale * d[2];
    out.position = d[0];
    out.du = d_u;
    out.dv = d_v;
    out.normal = unit(cross(d_u, d_v));
    if (second) {
        out.duu = (scale * scale) * d[3];
        out.duv = (scale * scale) * d[4];
        out.dvv = (scale * scale) * d[5];
    }
}

//! A regular patch of either scheme at local (s, t), into `out` (default-initialized).
inline void evaluate_any(bool loop, const std::array<Vec3, 16>& points, double s, double t, double scale, bool second,
                         LimitSample& out) {
    if (loop)
        evaluate_loop_patch(points, s, t, scale, second, out);
    else if (second)
        evaluate_patch<true>(points, s, t, scale, out);
    else
        evaluate_patch<false>(points, s, t, scale, out);
}

//! The patch of face f of `p` when it is regular under the scheme: Catmull-Clark's 16 control points, or Loop's
//! polynomial coefficients (from its 12 control points, converted once so that each evaluation is cheap).
bool regular(bool loop, const Piece& p, const Adjacency& adj, Index f, std::array<Vec3, 16>& points) {
    if (!loop) return regular_patch(p, adj, f, points);
    std::array<Vec3, 12> triangle;
    if (!subdivision::loop_regular_patch(p, adj, f, triangle)) return false;
    subdivision::loop_patch_polynomial(triangle, points);
    return true;
}

//! The corner of the domain (the unit square; Loop: the unit triangle) at (s, t), or -1.
int corner_at(bool loop, double s, double t) {
    if ((s != 0.0 && s != 1.0) || (t != 0.0 && t != 1.0)) return -1;
    if (loop) return s == 0.0 ? (t == 0.0 ? 0 : 2) : (t == 0.0 ? 1 : -1);
    return t == 0.0 ? (s == 0.0 ? 0 : 1) : (s == 0.0 ? 3 : 2);
}

//! Whether every face at local vertex v is a quad (the limit masks of limit.h need that).
bool all_quads_at(const Piece& p, const Adjacency& adj, Index v) {
    for (Index k = adj.vf_offsets[v]; k < adj.vf_offsets[v + 1]; ++k) {
        const Index g = adj.vf_faces[k];
        if (p.level.face_offsets[g + 1] - p.level.face_offsets[g] != 4) return false;
    }
    return true;
}

//! Whether local vertex v is a dart: one sharp edge at it, no vertex sharpness. The smooth limit mask there is not
//! the limit (the sharp edge's points follow the crease rule as the vertex is refined, which the smooth mask does not
//! model): it is off by a fraction of the ring's size that falls with each level (measured on catmark_inf_crease0:
//! Far's limit at a dart moves by 0.013 of a unit edge from level 0 to 5, converging).
bool dart_at(const Piece& p, const Adjacency& adj, Index v) {
    if (is_sharp(p.sharp.vertex[v])) return false;
    int sharp = 0;
    for (Index e : edges_at(p.level, adj, v)) sharp += is_sharp(p.sharp.edge[e]) ? 1 : 0;
    return sharp == 1;
}

//! Whether local vertex v is a smooth Catmull-Clark vertex of two faces (faces glued back to back, as in
//! catmark_val2_back2back). limit.h gives it the corner mask (the point itself), as OpenSubdiv's Sdc does, but the
//! surface around it converges elsewhere: to (4 v + 4 sum(edge neighbours) + sum(opposite corners)) / 14, the smooth
//! mask's formula at valence 2, which has no tangent plane to go with it (its two subdominant eigenvalues are 1/4).
bool valence_two_at(const Piece& p, const Adjacency& adj, Index v) {
    if (adj.vf_offsets[v + 1] - adj.vf_offsets[v] != 2 || is_sharp(p.sharp.vertex[v])) return false;
    const auto edges = edges_at(p.level, adj, v);
    if (edges.size() != 2) return false;
    for (Index e : edges)
        if (is_sharp(p.sharp.edge[e]) || adj.edge_uses[e] != 2) return false;
    return true;
}

//! Whether corner j of the piece's target face stays irregular under refinement: it is not regular, no semi-sharp
//! feature at it is what prevents it, and the limit masks of limit.h apply there (not at a dart or a smooth
//! Catmull-Clark vertex of valence 2: there the descent goes on to max_level, where the mask's error has shrunk with
//! the ring).
bool irregular_for_good(bool loop, const Piece& p, const Adjacency& adj, int j) {
    const Index v = subdivision::face_vert(p.level, p.target, static_cast<Index>(j));
    if (dart_at(p, adj, v) || (!loop && valence_two_at(p, adj, v))) return false;
    bool semi = false;
    if (loop) return !subdivision::loop_corner_regular(p, adj, p.target, j, &semi) && !semi;
    bool sharp_edge[4];
    sharp_edges_of(p, p.target, sharp_edge);
    return !corner_regular(p, adj, p.target, j, sharp_edge, &semi) && !semi &&
           all_quads_at(p, adj, subdivision::face_vert(p.level, p.target, static_cast<Index>(j)));
}

//! One step down: the child of the face (quad or triangle) containing local (s, t), the point's coordinates in it,
//! and d(child coordinates)/d(parent coordinates) (Loop's middle child is turned half round: -2).
struct Step {
    int child;
    double s, t, factor;
};
Step descend(bool loop, double s, double t) {
    if (loop) {
        if (s >= 0.5) return {1, 2.0 * s - 1.0, 2.0 * t, 2.0};
        if (t >= 0.5) return {2, 2.0 * s, 2.0 * t - 1.0, 2.0};
        if (s + t <= 0.5) return {0, 2.0 * s, 2.0 * t, 2.0};
        return {3, 1.0 - 2.0 * s, 1.0 - 2.0 * t, -2.0};
    }
    const int col = s > 0.5 ? 1 : 0, row = t > 0.5 ? 1 : 0;
    static constexpr int kCorner[2][2] = {{0, 1}, {3, 2}};
    return {kCorner[row][col], 2.0 * s - col, 2.0 * t - row, 2.0};
}

//! Near an irregular vertex: the limit positions (limit.h) at the corners of the piece's target face, blended
//! bilinearly (Loop: linearly), with the limit normal exactly at a corner.
LimitSample blend_corner_limits(bool loop, bool warren, const Piece& piece, double s, double t, double scale,
                                int corner) {
    const int n = loop ? 3 : 4;
    Vec3 limit_p[4], limit_n[4], lp[4], ln[4];
    const Index count = std::min<Index>(n, piece.level.vertex_count);
    subdivision::evaluate_limit(piece.level, piece.sharp.edge, piece.sharp.vertex, loop, warren, piece.points.data(),
                                count, limit_p, limit_n);
    for (int k = 0; k < n; ++k) {
        const Index v = subdivision::face_vert(piece.level, piece.target, static_cast<Index>(k));
        lp[k] = limit_p[v];
        ln[k] = limit_n[v];
    }
    LimitSample out;
    if (loop) {
        out.position = (1 - s - t) * lp[0] + s * lp[1] + t * lp[2];
        out.du = scale * (lp[1] - lp[0]);
        out.dv = scale * (lp[2] - lp[0]);
    } else {
        out.position = (1 - s) * (1 - t) * lp[0] + s * (1 - t) * lp[1] + s * t * lp[2] + (1 - s) * t * lp[3];
        out.du = scale * ((1 - t) * (lp[1] - lp[0]) + t * (lp[2] - lp[3]));
        out.dv = scale * ((1 - s) * (lp[3] - lp[0]) + s * (lp[2] - lp[1]));
    }
    out.normal = unit(cross(out.du, out.dv));
    if (corner >= 0 && norm(ln[corner]) > 0) out.normal = ln[corner];
    out.exact = false;
    return out;
}

//! The quad sub-face tile width of an N-gon in Bfr's parameterization.
int subface_columns(Index n) {
    return n < 10 ? 2 + (n > 4 ? 1 : 0) : 1 + static_cast<int>(std::sqrt(static_cast<float>(n - 1)));
}

}  // namespace

//! What an evaluator shares with its copies and its face surfaces: the base level, its sharpness and points, its
//! vertex-face lists and the patches of its regular faces.
struct LimitSurfaceEvaluator::Data {
    SubdivisionOptions options;
    bool loop = false;
    int max_level = 24;
    Piece base;
    std::vector<Index> vf_offsets, vf_faces;
    std::vector<std::int32_t> patch_of_face;    //!< index into patches, -1 when the face is not regular
    std::vector<std::array<Vec3, 16>> patches;  //!< Catmull-Clark: control points; Loop: polynomial coefficients
};

//! The pieces of a face surface's leaves without a patch, by node (a few per irregular corner).
struct LimitFaceSurface::Unresolved {
    std::vector<std::int32_t> node;
    std::vector<Piece> pieces;
    int find(std::size_t n) const {
        for (std::size_t i = 0; i < node.size(); ++i)
            if (node[i] == static_cast<std::int32_t>(n)) return static_cast<int>(i);
        return -1;
    }
};

std::size_t LimitSurfaceEvaluator::face_count() const { return data_->base.level.face_count(); }

SubdivisionScheme LimitSurfaceEvaluator::scheme() const { return data_->options.scheme; }

int LimitSurfaceEvaluator::max_level() const { return data_->max_level; }

bool LimitSurfaceEvaluator::is_hole(std::size_t face) const {
    return !data_->base.sharp.hole.empty() && data_->base.sharp.hole[static_cast<Index>(face)];
}

Result<LimitSurfaceEvaluator> LimitSurfaceEvaluator::create(const PolygonMesh& mesh, const SubdivisionOptions& options,
                                                            const LimitEvaluationOptions& evaluation) {
    if (evaluation.max_level < 12 || evaluation.max_level > 40)
        return make_error(ErrorCode::InvalidArgument,
                          "max_level must be in [12, 40], got " + std::to_string(evaluation.max_level));
    if (Status valid = validate_for_subdivision(mesh); !valid) return valid.error();
    const bool loop = options.scheme == SubdivisionScheme::Loop;
    if (loop)
        for (std::size_t f = 0; f < mesh.face_count(); ++f)
            if (mesh.face_size(f) != 3)
                return element_error(ErrorCode::NotTriangleMesh,
                                     "face " + std::to_string(f) + " has " + std::to_string(mesh.face_size(f)) +
                                         " vertices; Loop subdivision needs triangles",
                                     ElementKind::Face, static_cast<std::int64_t>(f));
    auto data = std::make_shared<Data>();
    Data& d = *data;
    d.options = options;
    d.loop = loop;
    d.max_level = evaluation.max_level;
    const BoundaryInterpolation boundary =
        options.use_mesh_boundary_tag && mesh.tags.boundary ? *mesh.tags.boundary : options.boundary;
    d.base.level = subdivision::build_base_level(mesh);
    auto sharp = subdivision::base_sharpness(mesh, d.base.level, boundary, options.use_mesh_tags);
    if (!sharp) return sharp.error();
    d.base.sharp = std::move(sharp).value();
    d.base.points = mesh.positions;
    vertex_faces(d.base.level, d.vf_offsets, d.vf_faces);
    // regular base faces keep their patch (the base level holds every face's neighbourhood: no piece is cut)
    const Index nf = d.base.level.face_count();
    d.patch_of_face.assign(nf, -1);
    const Adjacency adj(d.base.level);
    for (Index f = 0; f < nf; ++f) {
        if (d.base.level.face_offsets[f + 1] - d.base.level.face_offsets[f] != (loop ? 3 : 4)) continue;
        std::array<Vec3, 16> points;
        if (regular(loop, d.base, adj, f, points)) {
            d.patch_of_face[f] = static_cast<std::int32_t>(d.patches.size());
            d.patches.push_back(points);
        }
    }
    LimitSurfaceEvaluator e;
    e.data_ = std::move(data);
    return e;
}

Result<LimitSurfaceEvaluator::Start> LimitSurfaceEvaluator::locate(std::size_t face, double u, double v) const {
    if (face >= face_count())
        return element_error(
            ErrorCode::IndexOutOfRange,
            "face " + std::to_string(face) + " is out of range (" + std::to_string(face_count()) + " faces)",
            ElementKind::Face, static_cast<std::int64_t>(face));
    if (!std::isfinite(u) || !std::isfinite(v))
        return element_error(ErrorCode::NonFinite, "(u, v) must be finite", ElementKind::Face,
                             static_cast<std::int64_t>(face));
    const Index f = static_cast<Index>(face);
    if (!data_->base.sharp.hole.empty() && data_->base.sharp.hole[f])
        return element_error(ErrorCode::InvalidArgument,
                             "face " + std::to_string(face) + " is a hole: it has no limit surface", ElementKind::Face,
                             static_cast<std::int64_t>(face));
    const Index n = data_->base.level.face_offsets[f + 1] - data_->base.level.face_offsets[f];
    auto outside = [&](const std::string& domain) {
        return element_error(ErrorCode::InvalidArgument,
                             "(u, v) = (" + std::to_string(u) + ", " + std::to_string(v) + ") is outside the " + domain,
                             ElementKind::Face, static_cast<std::int64_t>(face));
    };
    if (data_->loop) {
        if (u < 0.0 || v < 0.0 || u + v > 1.0) return outside("triangle's domain u, v >= 0, u + v <= 1");
        return Start{-1, u, v};
    }
    if (n == 4) {
        if (u < 0.0 || u > 1.0 || v < 0.0 || v > 1.0) return outside("quad's domain [0, 1] x [0, 1]");
        return Start{-1, u, v};
    }
    const int columns = subface_columns(n);
    const double x = std::floor(u), y = std::floor(v);
    const bool inside = u >= 0.0 && v >= 0.0 && x < columns && u - x <= 0.5 && v - y <= 0.5 &&
                        static_cast<double>(y * columns + x) < static_cast<double>(n);
    if (!inside) return outside(std::to_string(n) + "-gon's domain (its quad sub-faces)");
    return Start{static_cast<int>(y) * columns + static_cast<int>(x), 2.0 * (u - x), 2.0 * (v - y)};
}

namespace {

//! The descent of evaluate() from `piece` (its target face `level` refinements below the base face; `subface` >= 0:
//! the target is an N-gon and the point lies in that sub-face) at local (s, t), derivatives scaled by `scale`.
LimitSample descend_from(const LimitSurfaceEvaluator::Data& d, const Piece& start, int level, int subface, double s,
                         double t, double scale, bool second) {
    std::vector<Index> offsets, faces;
    Piece refined;
    const Piece* current = &start;
    for (;; ++level) {
        const Piece& piece = *current;
        const bool at_patch_shape = subface < 0;  // a quad (Loop: a triangle), not an N-gon
        if (at_patch_shape) {
            const Adjacency adj(piece.level);
            std::array<Vec3, 16> points;
            if (regular(d.loop, piece, adj, piece.target, points)) {
                LimitSample out;
                evaluate_any(d.loop, points, s, t, scale, second, out);
                out.level = level;
                return out;
            }
            // exactly at an irregular vertex whose sharpness has decayed: refining changes nothing there
            const int corner = corner_at(d.loop, s, t);
            const bool at_irregular_vertex = corner >= 0 && irregular_for_good(d.loop, piece, adj, corner);
            if (at_irregular_vertex || level >= d.max_level) {
                LimitSample out = blend_corner_limits(d.loop, d.options.loop_weights == LoopWeights::Warren, piece, s,
                                                      t, scale, corner);
                out.level = level;
                return out;
            }
        }
        const Piece child = refine(piece, d.options, level == 0);
        Index next;
        if (at_patch_shape) {
            const Step step = descend(d.loop, s, t);
            next = subdivision::child_face(piece.level, piece.target, step.child, d.loop);
            s = step.s;
            t = step.t;
            scale *= step.factor;
        } else {
            next = subdivision::child_face(piece.level, piece.target, subface, false);
            subface = -1;
            scale *= 2.0;
        }
        vertex_faces(child.level, offsets, faces);
        refined = extract(child, offsets, faces, next);
        current = &refined;
    }
}

}  // namespace

Result<LimitSample> LimitSurfaceEvaluator::evaluate(std::size_t face, double u, double v, bool second) const {
    auto start = locate(face, u, v);
    if (!start) return start.error();
    const Data& d = *data_;
    const Index f = static_cast<Index>(face);
    if (start->subface < 0 && d.patch_of_face[f] >= 0) {
        Result<LimitSample> out{LimitSample{}};
        evaluate_any(d.loop, d.patches[d.patch_of_face[f]], start->s, start->t, 1.0, second, *out);
        return out;
    }
    // local refinement: the face with its 2-ring, refined around the point until its face there is regular
    return descend_from(d, extract(d.base, d.vf_offsets, d.vf_faces, f), 0, start->subface, start->s, start->t, 1.0,
                        second);
}

namespace {

//! The children of `piece`'s target face (a quad, an N-gon's quad sub-faces at level 0, or a triangle under Loop),
//! `level` + 1 refinements below the base face, as the nodes from `first` on (in corner order; Loop: the middle one
//! last): a leaf with a patch where a child is regular, its own children below it otherwise, and where `level` + 1
//! reaches `levels`, a leaf without a patch whose piece is kept in `unresolved`, where the descent of a point there
//! resumes. Regularity is checked on the refined piece itself (it holds the children's corners' faces), so that only
//! the irregular children are cut out of it; patches are numbered depth first, in the order of leaves().
void build_children(const Piece& piece, const SubdivisionOptions& options, int level, int levels, std::size_t first,
                    std::vector<LimitFaceSurface::Node>& nodes, std::vector<std::array<Vec3, 16>>& patches,
                    LimitFaceSurface::Unresolved& unresolved) {
    const bool loop = options.scheme == SubdivisionScheme::Loop;
    const Piece child = refine(piece, options, level == 0);
    const Adjacency adj(child.level);
    const Index n = piece.level.face_offsets[piece.target + 1] - piece.level.face_offsets[piece.target];
    const Index count = loop ? 4 : n;
    for (Index j = 0; j < count; ++j) {
        const std::size_t node = first + j;
        const Index face = subdivision::child_face(piece.level, piece.target, static_cast<int>(j), loop);
        std::array<Vec3, 16> points;
        if (regular(loop, child, adj, face, points)) {
            nodes[node].patch = static_cast<std::int32_t>(patches.size());
            patches.push_back(points);
            continue;
        }
        Piece sub = extract(child, adj.vf_offsets, adj.vf_faces, face);
        if (level + 1 >= levels) {
            unresolved.node.push_back(static_cast<std::int32_t>(node));
            unresolved.pieces.push_back(std::move(sub));
            continue;
        }
        const std::size_t grandchildren = nodes.size();
        nodes[node].first_child = static_cast<std::int32_t>(grandchildren);
        nodes.resize(grandchildren + 4);
        build_children(sub, options, level + 1, levels, grandchildren, nodes, patches, unresolved);
    }
}

}  // namespace

Result<LimitFaceSurface> LimitSurfaceEvaluator::face_surface(std::size_t face, int levels) const {
    if (levels < 0 || levels > data_->max_level)
        return make_error(ErrorCode::InvalidArgument, "levels must be in [0, " + std::to_string(data_->max_level) +
                                                          "], got " + std::to_string(levels));
    // the domain check of a point inside the face (its first sub-face for N-gons) checks the face itself
    auto start = locate(face, 0.0, 0.0);
    if (!start) return start.error();
    LimitFaceSurface out;
    out.owner_ = *this;
    out.face_ = face;
    const Index f = static_cast<Index>(face);
    const Index n = data_->base.level.face_offsets[f + 1] - data_->base.level.face_offsets[f];
    const bool patch_shape = n == (data_->loop ? 3 : 4);
    out.nodes_.resize(1);
    if (patch_shape && data_->patch_of_face[f] >= 0) {
        out.nodes_[0].patch = 0;
        out.patches_.push_back(data_->patches[data_->patch_of_face[f]]);
        return out;
    }
    // the face is not one patch (an N-gon, or a quad or triangle that is not regular): its children, recursively
    auto unresolved = std::make_shared<LimitFaceSurface::Unresolved>();
    Piece piece = extract(data_->base, data_->vf_offsets, data_->vf_faces, f);
    if (levels == 0) {
        if (patch_shape) {
            unresolved->node.push_back(0);
            unresolved->pieces.push_back(std::move(piece));
            out.unresolved_ = std::move(unresolved);
        }
        return out;
    }
    const Index children = patch_shape ? 4 : n;  // Loop: three corner triangles and the middle one
    out.nodes_[0].first_child = 1;
    out.nodes_.resize(1 + children);
    build_children(piece, data_->options, 0, levels, 1, out.nodes_, out.patches_, *unresolved);
    if (!unresolved->node.empty()) out.unresolved_ = std::move(unresolved);
    return out;
}

Result<LimitSample> LimitFaceSurface::evaluate(double u, double v, bool second_derivatives) const {
    auto start = owner_.locate(face_, u, v);
    if (!start) return start.error();
    const bool loop = owner_.data_->loop;
    double s = start->s, t = start->t, scale = 1.0;
    std::size_t node = 0;
    int level = 0;
    if (start->subface >= 0) {
        if (nodes_[0].first_child < 0) return owner_.evaluate(face_, u, v, second_derivatives);
        node = static_cast<std::size_t>(nodes_[0].first_child + start->subface);
        scale = 2.0;
        level = 1;
    }
    for (;;) {
        const Node& current = nodes_[node];
        if (current.patch >= 0) {
            Result<LimitSample> out{LimitSample{}};
            evaluate_any(loop, patches_[current.patch], s, t, scale, second_derivatives, *out);
            out->level = level;
            return out;
        }
        if (current.first_child < 0) {
            // not resolved within the prepared levels: the evaluator's descent, resumed from the leaf's piece (the
            // one it would reach from the base face). At a corner of the leaf the descent may stop above it (exactly
            // at an irregular vertex): from the base face then, as evaluate() answers.
            const int at = unresolved_ && corner_at(loop, s, t) < 0 ? unresolved_->find(node) : -1;
            if (at < 0) return owner_.evaluate(face_, u, v, second_derivatives);
            return descend_from(*owner_.data_, unresolved_->pieces[static_cast<std::size_t>(at)], level, -1, s, t,
                                scale, second_derivatives);
        }
        const Step step = descend(loop, s, t);
        node = static_cast<std::size_t>(current.first_child + step.child);
        s = step.s;
        t = step.t;
        scale *= step.factor;
        ++level;
    }
}

std::vector<LimitFaceSurface::Leaf> LimitFaceSurface::leaves(int max_level) const {
    std::vector<Leaf> out;
    if (owner_.scheme() != SubdivisionScheme::CatmullClark) return out;
    // (node, square) pairs still to visit; a node's four children are its corner quadrants in corner order
    struct Pending {
        std::size_t node;
        Leaf square;
    };
    std::vector<Pending> stack;
    const Index f = static_cast<Index>(face_);
    const Index n = owner_.data_->base.level.face_offsets[f + 1] - owner_.data_->base.level.face_offsets[f];
    if (n != 4 && nodes_[0].first_child >= 0 && max_level >= 1) {
        const int columns = subface_columns(n);
        for (Index j = n; j-- > 0;)
            stack.push_back({static_cast<std::size_t>(nodes_[0].first_child) + j,
                             Leaf{static_cast<double>(j % columns), static_cast<double>(j / columns), 0.5, 1, nullptr,
                                  nodes_[0].first_child + static_cast<std::int32_t>(j)}});
    } else if (n != 4) {
        // an N-gon prepared to level 0: its sub-faces, none of them a patch
        const int columns = subface_columns(n);
        for (Index j = 0; j < n; ++j)
            out.push_back(Leaf{static_cast<double>(j % columns), static_cast<double>(j / columns), 0.5, 1, nullptr});
        return out;
    } else {
        stack.push_back({0, Leaf{0, 0, 1, 0, nullptr, 0}});
    }
    static constexpr double kColumn[4] = {0, 1, 1, 0}, kRow[4] = {0, 0, 1, 1};
    while (!stack.empty()) {
        const Pending current = stack.back();
        stack.pop_back();
        const Node& node = nodes_[current.node];
        if (node.first_child < 0 || current.square.level >= max_level) {
            Leaf leaf = current.square;
            if (node.patch >= 0) leaf.bspline = &patches_[static_cast<std::size_t>(node.patch)];
            out.push_back(leaf);
            continue;
        }
        const double half = 0.5 * current.square.size;
        for (int j = 3; j >= 0; --j)
            stack.push_back({static_cast<std::size_t>(node.first_child) + static_cast<std::size_t>(j),
                             Leaf{current.square.u0 + kColumn[j] * half, current.square.v0 + kRow[j] * half, half,
                                  current.square.level + 1, nullptr, node.first_child + j}});
    }
    return out;
}

namespace {

//! The points of the faces that share a vertex with the piece's target face: the limit surface over the target is
//! a convex combination of them (each child face's such points are computed from its parent's alone).
std::vector<Vec3> one_ring_points(const Piece& piece) {
    const Level& L = piece.level;
    std::vector<Index> offsets, faces;
    vertex_faces(L, offsets, faces);
    std::vector<char> used(L.vertex_count, 0);
    for (Index i = L.face_offsets[piece.target]; i < L.face_offsets[piece.target + 1]; ++i) {
        const Index v = L.face_verts[i];
        for (Index k = offsets[v]; k < offsets[v + 1]; ++k)
            for (Index j = L.face_offsets[faces[k]]; j < L.face_offsets[faces[k] + 1]; ++j) used[L.face_verts[j]] = 1;
    }
    std::vector<Vec3> out;
    for (Index v = 0; v < L.vertex_count; ++v)
        if (used[v]) out.push_back(piece.points[v]);
    return out;
}

}  // namespace

std::vector<Vec3> LimitFaceSurface::hull_points(const Leaf& leaf) const {
    if (leaf.bspline) return {};
    const int at = unresolved_ && leaf.node >= 0 ? unresolved_->find(static_cast<std::size_t>(leaf.node)) : -1;
    if (at >= 0) return one_ring_points(unresolved_->pieces[static_cast<std::size_t>(at)]);
    const LimitSurfaceEvaluator::Data& d = *owner_.data_;
    return one_ring_points(extract(d.base, d.vf_offsets, d.vf_faces, static_cast<Index>(face_)));
}

}  // namespace surfaced
