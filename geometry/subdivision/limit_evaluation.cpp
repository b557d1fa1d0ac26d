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
#include "geometry/subdivision/topology.h"

namespace surfaced {

namespace {

using subdivision::is_infinite;
using subdivision::is_semi_sharp;
using subdivision::is_sharp;
using subdivision::Level;
//! A piece of one refinement level: topology, sharpness and points, cut around one face.
struct Piece {
    Level level;
    subdivision::Sharpness sharp;
    std::vector<Vec3> points;
    Index target = 0;  //!< the face the piece was cut around
};

//! Vertex -> faces lists of a level.
void vertex_faces(const Level& level, std::vector<Index>& offsets, std::vector<Index>& faces) {
    offsets.assign(static_cast<std::size_t>(level.vertex_count) + 1, 0);
    for (Index v : level.face_verts) ++offsets[v + 1];
    for (Index v = 0; v < level.vertex_count; ++v) offsets[v + 1] += offsets[v];
    faces.resize(offsets[level.vertex_count]);
    std::vector<Index> fill(offsets.begin(), offsets.end() - 1);
    for (Index f = 0; f < level.face_count(); ++f)
        for (Index s = level.face_offsets[f]; s < level.face_offsets[f + 1]; ++s)
            faces[fill[level.face_verts[s]]++] = f;
}

//! The faces of `src` within two vertex rings of `face` (face first, its corners first among the vertices): enough
//! for one Catmull-Clark step to give exact points, sharpness and topology on the child faces' 2-rings. Sharpness is
//! copied, not recomputed, so that the piece's cut edges keep their true (usually smooth) rule.
Piece extract(const Piece& src, const std::vector<Index>& vf_offsets, const std::vector<Index>& vf_faces, Index face) {
    const Level& L = src.level;
    // a local piece is small: marks per face and vertex; the base mesh may be large: sorted lists
    const bool dense = L.face_count() <= 4096;
    std::vector<Index> faces{face};
    if (dense) {
        std::vector<std::uint8_t> in(L.face_count(), 0);
        in[face] = 1;
        for (int ring = 0; ring < 2; ++ring) {
            const std::size_t count = faces.size();
            for (std::size_t i = 0; i < count; ++i)
                for (Index s = L.face_offsets[faces[i]]; s < L.face_offsets[faces[i] + 1]; ++s) {
                    const Index v = L.face_verts[s];
                    for (Index k = vf_offsets[v]; k < vf_offsets[v + 1]; ++k)
                        if (!in[vf_faces[k]]) {
                            in[vf_faces[k]] = 1;
                            faces.push_back(vf_faces[k]);
                        }
                }
        }
        std::sort(faces.begin(), faces.end());
    } else {
        for (int ring = 0; ring < 2; ++ring) {
            const std::size_t count = faces.size();
            std::vector<Index> next;
            for (std::size_t i = 0; i < count; ++i) {
                const Index f = faces[i];
                for (Index s = L.face_offsets[f]; s < L.face_offsets[f + 1]; ++s) {
                    const Index v = L.face_verts[s];
                    next.insert(next.end(), vf_faces.begin() + vf_offsets[v], vf_faces.begin() + vf_offsets[v + 1]);
                }
            }
            std::sort(next.begin(), next.end());
            next.erase(std::unique(next.begin(), next.end()), next.end());
            faces.swap(next);
        }
    }
    // faces keep their source order (which decides, as in build_base_level, which instance of a repeated edge is
    // found first); vertices: the face's distinct corners first (in face order), then the rest
    std::vector<Index> order;
    for (Index s = L.face_offsets[face]; s < L.face_offsets[face + 1]; ++s)
        if (std::find(order.begin(), order.end(), L.face_verts[s]) == order.end()) order.push_back(L.face_verts[s]);
    std::vector<Index> dense_local;
    std::vector<std::pair<Index, Index>> map;  // (source, local), sorted by source
    if (dense) {
        dense_local.assign(L.vertex_count, kInvalidIndex);
        for (Index i = 0; i < order.size(); ++i) dense_local[order[i]] = i;
        for (Index f : faces)
            for (Index s = L.face_offsets[f]; s < L.face_offsets[f + 1]; ++s)
                if (dense_local[L.face_verts[s]] == kInvalidIndex) {
                    dense_local[L.face_verts[s]] = static_cast<Index>(order.size());
                    order.push_back(L.face_verts[s]);
                }
    } else {
        const std::size_t corner_count = order.size();
        std::vector<Index> rest;
        for (Index f : faces)
            for (Index s = L.face_offsets[f]; s < L.face_offsets[f + 1]; ++s) rest.push_back(L.face_verts[s]);
        std::sort(rest.begin(), rest.end());
        rest.erase(std::unique(rest.begin(), rest.end()), rest.end());
        for (Index v : rest)
            if (std::find(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(corner_count), v) ==
                order.begin() + static_cast<std::ptrdiff_t>(corner_count))
                order.push_back(v);
        map.reserve(order.size());
        for (Index i = 0; i < order.size(); ++i) map.push_back({order[i], i});
        std::sort(map.begin(), map.end());
    }
    auto local = [&](Index v) {
        if (dense) return dense_local[v];
        return std::lower_bound(map.begin(), map.end(), std::pair<Index, Index>{v, 0})->second;
    };

    PolygonMesh mesh;
    mesh.positions.resize(order.size());
    Piece out;
    out.points.resize(order.size());
    out.sharp.vertex.resize(order.size());
    for (Index l = 0; l < order.size(); ++l) {
        out.points[l] = src.points[order[l]];
        out.sharp.vertex[l] = src.sharp.vertex[order[l]];
    }
    std::vector<Index> corner_ids;
    for (Index f : faces) {
        corner_ids.clear();
        for (Index s = L.face_offsets[f]; s < L.face_offsets[f + 1]; ++s) corner_ids.push_back(local(L.face_verts[s]));
        mesh.add_face(corner_ids);
    }
    out.level = subdivision::build_base_level(mesh);
    out.sharp.edge.assign(out.level.edge_count(), 0.0f);
    for (Index i = 0; i < faces.size(); ++i) {
        const Index f = faces[i];
        const Index n = L.face_offsets[f + 1] - L.face_offsets[f];
        for (Index k = 0; k < n; ++k)
            out.sharp.edge[out.level.face_edges[out.level.face_offsets[i] + k]] =
                src.sharp.edge[L.face_edges[L.face_offsets[f] + k]];
    }
    out.target = static_cast<Index>(std::lower_bound(faces.begin(), faces.end(), face) - faces.begin());
    if (!src.sharp.hole.empty()) {
        out.sharp.hole.resize(faces.size());
        for (Index i = 0; i < faces.size(); ++i) out.sharp.hole[i] = src.sharp.hole[faces[i]];
    }
    return out;
}

//! One Catmull-Clark step of a whole piece, with subdivide()'s rules.
Piece refine(const Piece& p, const SubdivisionOptions& options, bool first_level) {
    const subdivision::Neighbourhood n = subdivision::neighbourhood(p.level, p.sharp, options.crease_method);
    Piece c;
    c.level = subdivision::refine_quads(p.level, true, false);
    c.points.assign(c.level.vertex_count, Vec3{});
    const subdivision::LevelInput in{p.level,
                                     p.sharp,
                                     options.crease_method,
                                     first_level ? options.triangle_rule : TriangleRule::Catmark,
                                     options.loop_weights,
                                     false};
    subdivision::interpolate_catmark(in, n, p.points.data(), c.points.data());
    c.sharp = subdivision::refine_sharpness(p.level, c.level, p.sharp, n, options.crease_method, false);
    return c;
}

//! Edge -> faces (up to two recorded, and the count) and vertex -> edges of a small level.
struct Adjacency {
    std::vector<Index> edge_face0, edge_face1;
    std::vector<std::uint32_t> edge_uses;
    std::vector<Index> vf_offsets, vf_faces;
    explicit Adjacency(const Level& L) {
        const Index ne = L.edge_count();
        edge_face0.assign(ne, kInvalidIndex);
        edge_face1.assign(ne, kInvalidIndex);
        edge_uses.assign(ne, 0);
        for (Index f = 0; f < L.face_count(); ++f)
            for (Index s = L.face_offsets[f]; s < L.face_offsets[f + 1]; ++s) {
                const Index e = L.face_edges[s];
                (edge_uses[e] == 0 ? edge_face0 : edge_face1)[e] = f;
                ++edge_uses[e];
            }
        vertex_faces(L, vf_offsets, vf_faces);
    }
    Index across(Index e, Index f) const { return edge_face0[e] == f ? edge_face1[e] : edge_face0[e]; }
};

Index slot_of(const Level& L, Index f, Index v) {
    for (Index s = L.face_offsets[f]; s < L.face_offsets[f + 1]; ++s)
        if (L.face_verts[s] == v) return s - L.face_offsets[f];
    return kInvalidIndex;
}

Index face_vert(const Level& L, Index f, Index k) {
    const Index n = L.face_offsets[f + 1] - L.face_offsets[f];
    return L.face_verts[L.face_offsets[f] + k % n];
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
    std::vector<Index> edges;
    if (quads)
        for (Index k = adj.vf_offsets[v]; k < adj.vf_offsets[v + 1]; ++k) {
            const Index g = adj.vf_faces[k];
            const Index s = slot_of(L, g, v);
            edges.push_back(L.face_edges[L.face_offsets[g] + s]);
            edges.push_back(L.face_edges[L.face_offsets[g] + (s + 3) % 4]);
        }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
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

//! Uniform cubic B-spline basis and its first two derivatives at t in [0, 1].
void bspline_basis(double t, double b[4], double d[4], double dd[4]) {
    const double s = 1.0 - t, t2 = t * t, t3 = t2 * t;
    b[0] = s * s * s / 6.0;
    b[1] = (3.0 * t3 - 6.0 * t2 + 4.0) / 6.0;
    b[2] = (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) / 6.0;
    b[3] = t3 / 6.0;
    d[0] = -0.5 * s * s;
    d[1] = 0.5 * (3.0 * t2 - 4.0 * t);
    d[2] = 0.5 * (-3.0 * t2 + 2.0 * t + 1.0);
    d[3] = 0.5 * t2;
    dd[0] = s;
    dd[1] = 3.0 * t - 2.0;
    dd[2] = 1.0 - 3.0 * t;
    dd[3] = t;
}

Vec3 unit(const Vec3& v) {
    const double len = norm(v);
    return len > 0 ? v * (1.0 / len) : Vec3{};
}

//! The patch at local (s, t); derivatives multiplied by `scale` (d(local)/d(u, v)) once per order.
LimitSample evaluate_patch(const std::array<Vec3, 16>& grid, double s, double t, double scale, bool second) {
    double bu[4], du[4], ddu[4], bv[4], dv[4], ddv[4];
    bspline_basis(s, bu, du, ddu);
    bspline_basis(t, bv, dv, ddv);
    LimitSample out;
    for (int r = 0; r < 4; ++r) {
        Vec3 row_b{}, row_d{}, row_dd{};
        for (int col = 0; col < 4; ++col) {
            const Vec3& p = grid[4 * r + col];
            row_b += bu[col] * p;
            row_d += du[col] * p;
            if (second) row_dd += ddu[col] * p;
        }
        out.position += bv[r] * row_b;
        out.du += bv[r] * row_d;
        out.dv += dv[r] * row_b;
        if (second) {
            out.duu += bv[r] * row_dd;
            out.duv += dv[r] * row_d;
            out.dvv += ddv[r] * row_b;
        }
    }
    out.du = scale * out.du;
    out.dv = scale * out.dv;
    out.normal = unit(cross(out.du, out.dv));
    if (second) {
        out.duu = (scale * scale) * out.duu;
        out.duv = (scale * scale) * out.duv;
        out.dvv = (scale * scale) * out.dvv;
    }
    return out;
}

//! The corner of the unit square at (s, t), or -1.
int corner_at(double s, double t) {
    if ((s != 0.0 && s != 1.0) || (t != 0.0 && t != 1.0)) return -1;
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

//! The quad sub-face tile width of an N-gon in Bfr's parameterization.
int subface_columns(Index n) {
    return n < 10 ? 2 + (n > 4 ? 1 : 0) : 1 + static_cast<int>(std::sqrt(static_cast<float>(n - 1)));
}

}  // namespace

//! What an evaluator shares with its copies and its face surfaces: the base level, its sharpness and points, its
//! vertex-face lists and the patches of its regular faces.
struct LimitSurfaceEvaluator::Data {
    SubdivisionOptions options;
    int max_level = 24;
    Piece base;
    std::vector<Index> vf_offsets, vf_faces;
    std::vector<std::int32_t> patch_of_face;  //!< index into patches, -1 when the face is not regular
    std::vector<std::array<Vec3, 16>> patches;
};

std::size_t LimitSurfaceEvaluator::face_count() const { return data_->base.level.face_count(); }

bool LimitSurfaceEvaluator::is_hole(std::size_t face) const {
    return !data_->base.sharp.hole.empty() && data_->base.sharp.hole[static_cast<Index>(face)];
}

Result<LimitSurfaceEvaluator> LimitSurfaceEvaluator::create(const PolygonMesh& mesh, const SubdivisionOptions& options,
                                                            const LimitEvaluationOptions& evaluation) {
    if (options.scheme != SubdivisionScheme::CatmullClark)
        return make_error(ErrorCode::Unsupported, "limit evaluation supports the catmull-clark scheme only");
    if (evaluation.max_level < 12 || evaluation.max_level > 40)
        return make_error(ErrorCode::InvalidArgument,
                          "max_level must be in [12, 40], got " + std::to_string(evaluation.max_level));
    if (Status valid = validate_for_subdivision(mesh); !valid) return valid.error();
    auto data = std::make_shared<Data>();
    Data& d = *data;
    d.options = options;
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
        if (d.base.level.face_offsets[f + 1] - d.base.level.face_offsets[f] != 4) continue;
        std::array<Vec3, 16> grid;
        if (regular_patch(d.base, adj, f, grid)) {
            d.patch_of_face[f] = static_cast<std::int32_t>(d.patches.size());
            d.patches.push_back(grid);
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
    for (Index a = 0; a < n; ++a)
        for (Index b = a + 1; b < n; ++b)
            if (data_->base.level.face_verts[data_->base.level.face_offsets[f] + a] ==
                data_->base.level.face_verts[data_->base.level.face_offsets[f] + b])
                return element_error(ErrorCode::Unsupported,
                                     "face " + std::to_string(face) +
                                         " uses a vertex twice: limit evaluation does not support such faces",
                                     ElementKind::Face, static_cast<std::int64_t>(face));
    int subface = -1;
    double s = u, t = v;
    if (n == 4) {
        if (u < 0.0 || u > 1.0 || v < 0.0 || v > 1.0)
            return element_error(ErrorCode::InvalidArgument,
                                 "(u, v) = (" + std::to_string(u) + ", " + std::to_string(v) +
                                     ") is outside the quad's domain [0, 1] x [0, 1]",
                                 ElementKind::Face, static_cast<std::int64_t>(face));
    } else {
        const int columns = subface_columns(n);
        const double x = std::floor(u), y = std::floor(v);
        const bool inside = u >= 0.0 && v >= 0.0 && x < columns && u - x <= 0.5 && v - y <= 0.5 &&
                            static_cast<double>(y * columns + x) < static_cast<double>(n);
        if (!inside)
            return element_error(ErrorCode::InvalidArgument,
                                 "(u, v) = (" + std::to_string(u) + ", " + std::to_string(v) + ") is outside the " +
                                     std::to_string(n) + "-gon's domain (its quad sub-faces)",
                                 ElementKind::Face, static_cast<std::int64_t>(face));
        subface = static_cast<int>(y) * columns + static_cast<int>(x);
        s = 2.0 * (u - x);
        t = 2.0 * (v - y);
    }
    return Start{subface, s, t};
}

Result<LimitSample> LimitSurfaceEvaluator::evaluate(std::size_t face, double u, double v, bool second) const {
    auto start = locate(face, u, v);
    if (!start) return start.error();
    const Index f = static_cast<Index>(face);
    int subface = start->subface;
    double s = start->s, t = start->t;
    if (subface < 0 && data_->patch_of_face[f] >= 0)
        return evaluate_patch(data_->patches[data_->patch_of_face[f]], s, t, 1.0, second);

    // local refinement: `piece` holds the current face (index 0) with its 2-ring; (s, t) are its local coordinates
    Piece piece = extract(data_->base, data_->vf_offsets, data_->vf_faces, f);
    double scale = 1.0;
    std::vector<Index> offsets, faces;
    for (int level = 0;; ++level) {
        const bool at_quad = subface < 0;
        if (at_quad) {
            const Adjacency adj(piece.level);
            std::array<Vec3, 16> grid;
            if (regular_patch(piece, adj, piece.target, grid)) {
                LimitSample out = evaluate_patch(grid, s, t, scale, second);
                out.level = level;
                return out;
            }
            // exactly at an irregular vertex whose sharpness has decayed: refining changes nothing there
            bool at_irregular_vertex = false;
            const int corner = corner_at(s, t);
            if (corner >= 0) {
                bool sharp_edge[4], semi = false;
                sharp_edges_of(piece, piece.target, sharp_edge);
                at_irregular_vertex =
                    !corner_regular(piece, adj, piece.target, corner, sharp_edge, &semi) && !semi &&
                    all_quads_at(piece, adj, piece.level.face_verts[piece.level.face_offsets[piece.target] + corner]);
            }
            if (at_irregular_vertex || level >= data_->max_level) {
                // the limit positions at the face's corners (the piece's first vertices), blended bilinearly
                Vec3 limit_p[4], limit_n[4], lp[4], ln[4];
                const Index count = std::min<Index>(4, piece.level.vertex_count);
                subdivision::evaluate_limit(piece.level, piece.sharp.edge, piece.sharp.vertex, false, false,
                                            piece.points.data(), count, limit_p, limit_n);
                for (int k = 0; k < 4; ++k) {
                    lp[k] = limit_p[piece.level.face_verts[piece.level.face_offsets[piece.target] + k]];
                    ln[k] = limit_n[piece.level.face_verts[piece.level.face_offsets[piece.target] + k]];
                }
                LimitSample out;
                out.position = (1 - s) * (1 - t) * lp[0] + s * (1 - t) * lp[1] + s * t * lp[2] + (1 - s) * t * lp[3];
                out.du = scale * ((1 - t) * (lp[1] - lp[0]) + t * (lp[2] - lp[3]));
                out.dv = scale * ((1 - s) * (lp[3] - lp[0]) + s * (lp[2] - lp[1]));
                out.normal = unit(cross(out.du, out.dv));
                if (corner >= 0 && norm(ln[corner]) > 0) out.normal = ln[corner];
                out.level = level;
                out.exact = false;
                return out;
            }
        }
        const Piece child = refine(piece, data_->options, level == 0);
        Index child_face;
        if (at_quad) {
            const int col = s > 0.5 ? 1 : 0, row = t > 0.5 ? 1 : 0;
            static constexpr int kCorner[2][2] = {{0, 1}, {3, 2}};
            child_face = piece.level.face_offsets[piece.target] + static_cast<Index>(kCorner[row][col]);
            s = 2.0 * s - col;
            t = 2.0 * t - row;
        } else {
            child_face = piece.level.face_offsets[piece.target] + static_cast<Index>(subface);
            subface = -1;
        }
        scale *= 2.0;
        vertex_faces(child.level, offsets, faces);
        piece = extract(child, offsets, faces, child_face);
    }
}

namespace {

//! The patch tree below `piece`'s target face (a quad), at `level` refinements below the base face: a node per
//! sub-face, a leaf with a patch where the sub-face is regular, a leaf without one where `level` reaches `levels`.
void build_tree(const Piece& piece, const SubdivisionOptions& options, int level, int levels, std::size_t node,
                std::vector<LimitFaceSurface::Node>& nodes, std::vector<std::array<Vec3, 16>>& patches) {
    const Adjacency adj(piece.level);
    std::array<Vec3, 16> grid;
    if (regular_patch(piece, adj, piece.target, grid)) {
        nodes[node].patch = static_cast<std::int32_t>(patches.size());
        patches.push_back(grid);
        return;
    }
    if (level >= levels) return;
    const Piece child = refine(piece, options, level == 0);
    std::vector<Index> offsets, faces;
    vertex_faces(child.level, offsets, faces);
    const std::size_t first = nodes.size();
    nodes[node].first_child = static_cast<std::int32_t>(first);
    nodes.resize(first + 4);
    for (Index j = 0; j < 4; ++j)
        build_tree(extract(child, offsets, faces, piece.level.face_offsets[piece.target] + j), options, level + 1,
                   levels, first + j, nodes, patches);
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
    out.nodes_.resize(1);
    if (n == 4 && data_->patch_of_face[f] >= 0) {
        out.nodes_[0].patch = 0;
        out.patches_.push_back(data_->patches[data_->patch_of_face[f]]);
        return out;
    }
    const Piece piece = extract(data_->base, data_->vf_offsets, data_->vf_faces, f);
    if (n == 4) {
        build_tree(piece, data_->options, 0, levels, 0, out.nodes_, out.patches_);
        return out;
    }
    if (levels == 0) return out;
    // an N-gon: its children are its sub-faces, in corner order
    const Piece child = refine(piece, data_->options, true);
    std::vector<Index> offsets, faces;
    vertex_faces(child.level, offsets, faces);
    out.nodes_[0].first_child = 1;
    out.nodes_.resize(1 + n);
    for (Index j = 0; j < n; ++j)
        build_tree(extract(child, offsets, faces, piece.level.face_offsets[piece.target] + j), data_->options, 1,
                   levels, 1 + j, out.nodes_, out.patches_);
    return out;
}

Result<LimitSample> LimitFaceSurface::evaluate(double u, double v, bool second_derivatives) const {
    auto start = owner_.locate(face_, u, v);
    if (!start) return start.error();
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
            LimitSample out = evaluate_patch(patches_[current.patch], s, t, scale, second_derivatives);
            out.level = level;
            return out;
        }
        if (current.first_child < 0) return owner_.evaluate(face_, u, v, second_derivatives);
        const int col = s > 0.5 ? 1 : 0, row = t > 0.5 ? 1 : 0;
        static constexpr int kCorner[2][2] = {{0, 1}, {3, 2}};
        node = static_cast<std::size_t>(current.first_child + kCorner[row][col]);
        s = 2.0 * s - col;
        t = 2.0 * t - row;
        scale *= 2.0;
        ++level;
    }
}

std::vector<LimitFaceSurface::Leaf> LimitFaceSurface::leaves(int max_level) const {
    std::vector<Leaf> out;
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
            stack.push_back(
                {static_cast<std::size_t>(nodes_[0].first_child) + j,
                 Leaf{static_cast<double>(j % columns), static_cast<double>(j / columns), 0.5, 1, nullptr}});
    } else if (n != 4) {
        // an N-gon prepared to level 0: its sub-faces, none of them a patch
        const int columns = subface_columns(n);
        for (Index j = 0; j < n; ++j)
            out.push_back(Leaf{static_cast<double>(j % columns), static_cast<double>(j / columns), 0.5, 1, nullptr});
        return out;
    } else {
        stack.push_back({0, Leaf{}});
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
                                  current.square.level + 1, nullptr}});
    }
    return out;
}

}  // namespace surfaced
