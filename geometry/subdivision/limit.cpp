// Limit masks. Positions: Catmull-Clark (Halstead, Kass, DeRose 1993), Loop (Hoppe et al. 1994), B-spline crease
// (1/6, 2/3, 1/6). Tangents: cosine/sine masks for smooth vertices, Biermann, Levin, Zorin (2000) for creases and
// boundaries. Normalisations follow OpenSubdiv's Sdc so that results are comparable; only directions matter for
// the unit normals we return.
#include "geometry/subdivision/limit.h"

#include <cmath>
#include <numbers>

namespace surfaced::subdivision {

namespace {

constexpr double kPi = std::numbers::pi;

// One vertex's ordered neighbourhood: edges e[0..] counter-clockwise, face i between edges i and i+1.
struct Ring {
    std::vector<Vec3> edge_points;  // the other end of each edge
    std::vector<float> edge_sharpness;
    std::vector<Vec3> face_points;  // Catmull-Clark: the quad's corner opposite the vertex
    bool boundary = false;
};

struct LimitPoint {
    Vec3 position, tan1, tan2;
};

LimitPoint corner_limit(const Vec3& p, const Ring& r, double scale) {
    return {p, scale * (r.edge_points[0] - p), scale * (r.edge_points[1] - p)};
}

LimitPoint catmark_limit(const Vec3& p, const Ring& r, bool corner, int c0, int c1) {
    const int ne = static_cast<int>(r.edge_points.size()), nf = static_cast<int>(r.face_points.size());
    const auto& E = r.edge_points;
    const auto& F = r.face_points;
    if (corner) return corner_limit(p, r, 1.0);
    if (c0 >= 0) {
        LimitPoint out;
        out.position = (2.0 / 3.0) * p + (1.0 / 6.0) * (E[c0] + E[c1]);
        out.tan1 = 0.5 * (E[c0] - E[c1]);
        const int interior = c1 - c0 - 1;
        if (interior == 1) {
            out.tan2 = (-4.0 / 6.0) * p + (-1.0 / 6.0) * (E[c0] + E[c1]) + (4.0 / 6.0) * E[c0 + 1] +
                       (1.0 / 6.0) * (F[c0] + F[c0 + 1]);
        } else if (interior > 1) {
            const double k = interior + 1, theta = kPi / k;
            const double c = std::cos(theta), s = std::sin(theta);
            const double denom = 1.0 / (k * (3.0 + c));
            const double R = (c + 1.0) / s;
            Vec3 t = (4.0 * R * (c - 1.0)) * p + (-R * (1.0 + 2.0 * c)) * (E[c0] + E[c1]) + s * F[c0];
            for (int i = 1; i < k; ++i) {
                const double si = std::sin(i * theta), si1 = std::sin((i + 1) * theta);
                t += (4.0 * si) * E[c0 + i] + (si + si1) * F[c0 + i];
            }
            out.tan2 = denom * t;
        } else {
            out.tan2 = -6.0 * p + 3.0 * (E[c0] + E[c1]);
        }
        return out;
    }
    const int n = nf;
    if (n == 2) return corner_limit(p, r, 1.0);
    LimitPoint out;
    Vec3 esum{}, fsum{};
    for (int i = 0; i < n; ++i) {
        esum += E[i];
        fsum += F[i];
    }
    if (n == 4) {
        out.position = (4.0 / 9.0) * p + (1.0 / 9.0) * esum + (1.0 / 36.0) * fsum;
        out.tan1 = 4.0 * (E[0] - E[2]) + F[0] - F[1] - F[2] + F[3];
        out.tan2 = 4.0 * (E[1] - E[3]) + F[0] + F[1] - F[2] - F[3];
        return out;
    }
    const double dn = n;
    const double fw = 1.0 / (dn * (dn + 5.0)), ew = 4.0 * fw, vw = 1.0 - dn * (ew + fw);
    out.position = vw * p + ew * esum + fw * fsum;
    const double theta = 2.0 * kPi / dn, c = std::cos(theta), ch = std::cos(0.5 * theta);
    const double lambda = 5.0 / 16.0 + (1.0 / 16.0) * (c + ch * std::sqrt(2.0 * (9.0 + c)));
    const double fscale = 1.0 / (4.0 * lambda - 1.0);
    // tan2 uses tan1's weights rotated by one position
    for (int i = 0; i < n; ++i) {
        const double ci = std::cos(i * theta), ci1 = std::cos((i + 1) * theta);
        const double we = 4.0 * ci, wf = fscale * (ci + ci1);
        out.tan1 += we * E[i] + wf * F[i];
        out.tan2 += we * E[(i + 1) % n] + wf * F[(i + 1) % n];
    }
    (void)ne;
    return out;
}

LimitPoint loop_limit(const Vec3& p, const Ring& r, bool corner, int c0, int c1, bool warren) {
    const auto& E = r.edge_points;
    if (corner) return corner_limit(p, r, 3.0);
    if (c0 >= 0) {
        LimitPoint out;
        out.position = (2.0 / 3.0) * p + (1.0 / 6.0) * (E[c0] + E[c1]);
        out.tan1 = 1.5 * (E[c0] - E[c1]);
        const int interior = c1 - c0 - 1;
        const double root3 = std::sqrt(3.0);
        if (interior == 2) {
            out.tan2 = -root3 * p - (0.5 * root3) * (E[c0] + E[c1]) + root3 * (E[c0 + 1] + E[c0 + 2]);
        } else if (interior > 2) {
            const double theta = kPi / (interior + 1);
            Vec3 t = (-3.0 * std::sin(theta)) * (E[c0] + E[c1]);
            const double ecoeff = -6.0 * (std::cos(theta) - 1.0);
            for (int i = 1; i <= interior; ++i) t += (ecoeff * std::sin(i * theta)) * E[c0 + i];
            out.tan2 = t;
        } else if (interior == 1) {
            out.tan2 = -3.0 * p + 3.0 * E[c0 + 1];
        } else {
            out.tan2 = -6.0 * p + 3.0 * (E[c0] + E[c1]);
        }
        return out;
    }
    const int n = static_cast<int>(r.face_points.size());
    LimitPoint out;
    Vec3 esum{};
    for (int i = 0; i < n; ++i) esum += E[i];
    if (n == 6) {
        out.position = 0.5 * p + (1.0 / 12.0) * esum;
    } else {
        // limit weight per neighbour from the scheme's per-neighbour refinement weight gamma: 1 / (n + 3 / (8 gamma))
        const double dn = n;
        const double beta = 0.25 * std::cos(2.0 * kPi / dn) + 0.375;
        const double gamma = warren ? (n == 3 ? 3.0 / 16.0 : 3.0 / (8.0 * dn)) : (0.625 - beta * beta) / dn;
        const double ew = 1.0 / (dn + 3.0 / (8.0 * gamma));
        out.position = (1.0 - ew * dn) * p + ew * esum;
    }
    const double alpha = 2.0 * kPi / n;
    for (int i = 0; i < n; ++i) {
        out.tan1 += std::cos(alpha * i) * E[i];
        out.tan2 += std::sin(alpha * i) * E[i];
    }
    return out;
}

Vec3 normalized(const Vec3& v) {
    const double len = norm(v);
    return len > 0 ? v * (1.0 / len) : Vec3{0, 0, 0};
}

//! Limit positions and normals of one level's vertices: the vertex-to-face-slot adjacency built once, then each
//! vertex's ring walked in order and handed to the scheme's limit masks (non-manifold or unordered rings fall back to
//! the sharp-neighbour rule).
class LimitEvaluator {
public:
    LimitEvaluator(const Level& level, const std::vector<float>& edge_sharpness,
                   const std::vector<float>& vertex_sharpness, bool loop, bool warren, const Vec3* points, Index count,
                   Vec3* limit_positions, Vec3* limit_normals)
        : level_(level),
          edge_sharpness_(edge_sharpness),
          vertex_sharpness_(vertex_sharpness),
          loop_(loop),
          warren_(warren),
          points_(points),
          count_(count),
          limit_positions_(limit_positions),
          limit_normals_(limit_normals) {
        build_edge_slots();
        build_vertex_slots();
        build_vertex_edges();
    }

    void evaluate(Index v) {
        const Index slot_count = vs_offsets_[v + 1] - vs_offsets_[v];
        if (slot_count == 0) {  // isolated vertex
            limit_positions_[v] = points_[v];
            limit_normals_[v] = Vec3{};
            return;
        }
        if (!walk_ring(v, slot_count)) {
            fallback(v);
            return;
        }
        int sharp_count = 0, c0 = -1, c1 = -1;
        for (std::size_t i = 0; i < ring_edges_.size(); ++i) {
            const Index e = ring_edges_[i];
            ring_.edge_points.push_back(points_[other_end(e, v)]);
            const float sh = edge_sharpness_[e];
            ring_.edge_sharpness.push_back(sh);
            if (sh > 0.0f) {
                if (sharp_count == 0)
                    c0 = static_cast<int>(i);
                else if (sharp_count == 1)
                    c1 = static_cast<int>(i);
                ++sharp_count;
            }
        }
        const bool corner = vertex_sharpness_[v] > 0.0f || sharp_count > 2;
        if (sharp_count != 2) c0 = c1 = -1;
        const LimitPoint lp = loop_ ? loop_limit(points_[v], ring_, corner, c0, c1, warren_)
                                    : catmark_limit(points_[v], ring_, corner, c0, c1);
        limit_positions_[v] = lp.position;
        const Vec3 n = normalized(cross(lp.tan1, lp.tan2));
        if (n.x == 0 && n.y == 0 && n.z == 0) {
            fallback(v);
            limit_positions_[v] = lp.position;
        } else {
            limit_normals_[v] = n;
        }
    }

private:
    //! The (up to two) face slots of each edge; a slot is the corner where the edge starts in its face.
    void build_edge_slots() {
        const Index ne = level_.edge_count(), nf = level_.face_count();
        slot0_.assign(ne, kInvalidIndex);
        slot1_.assign(ne, kInvalidIndex);
        edge_uses_.assign(ne, 0);
        slot_face_.resize(level_.face_verts.size());
        for (Index f = 0; f < nf; ++f)
            for (Index s = level_.face_offsets[f]; s < level_.face_offsets[f + 1]; ++s) {
                slot_face_[s] = f;
                const Index e = level_.face_edges[s];
                if (edge_uses_[e] == 0)
                    slot0_[e] = s;
                else
                    slot1_[e] = s;
                if (edge_uses_[e] < 255) ++edge_uses_[e];
            }
    }

    //! The slots of each vertex < count, in face order (so the first is in the lowest face).
    void build_vertex_slots() {
        vs_offsets_.assign(static_cast<std::size_t>(count_) + 1, 0);
        for (Index v : level_.face_verts)
            if (v < count_) ++vs_offsets_[v + 1];
        for (Index v = 0; v < count_; ++v) vs_offsets_[v + 1] += vs_offsets_[v];
        vs_slots_.resize(vs_offsets_[count_]);
        std::vector<Index> fill(vs_offsets_.begin(), vs_offsets_.end() - 1);
        for (Index s = 0; s < level_.face_verts.size(); ++s)
            if (level_.face_verts[s] < count_) vs_slots_[fill[level_.face_verts[s]]++] = s;
    }

    //! Vertex -> incident edges (unordered), for vertices where no ordered ring exists.
    void build_vertex_edges() {
        const Index ne = level_.edge_count();
        ve_offsets_.assign(static_cast<std::size_t>(count_) + 1, 0);
        for (Index e = 0; e < ne; ++e)
            for (int k = 0; k < 2; ++k)
                if (level_.edge_verts[2 * e + k] < count_) ++ve_offsets_[level_.edge_verts[2 * e + k] + 1];
        for (Index v = 0; v < count_; ++v) ve_offsets_[v + 1] += ve_offsets_[v];
        ve_edges_.resize(ve_offsets_[count_]);
        std::vector<Index> fill(ve_offsets_.begin(), ve_offsets_.end() - 1);
        for (Index e = 0; e < ne; ++e)
            for (int k = 0; k < 2; ++k)
                if (level_.edge_verts[2 * e + k] < count_) ve_edges_[fill[level_.edge_verts[2 * e + k]]++] = e;
    }

    Index prev_slot(Index s) const {
        const Index f = slot_face_[s];
        return s == level_.face_offsets[f] ? level_.face_offsets[f + 1] - 1 : s - 1;
    }
    Index next_slot(Index s) const {
        const Index f = slot_face_[s];
        return s + 1 == level_.face_offsets[f + 1] ? level_.face_offsets[f] : s + 1;
    }
    Index other_end(Index e, Index v) const {
        return level_.edge_verts[2 * e] == v ? level_.edge_verts[2 * e + 1] : level_.edge_verts[2 * e];
    }

    //! Walks v's faces counter-clockwise (the face of slot s lies between its leading and its trailing edge) from a
    //! slot whose leading edge is a boundary edge, else from the lowest face, filling ring_.face_points and
    //! ring_edges_. False when the ring is not one manifold fan (or, for Catmull-Clark, holds a non-quad).
    bool walk_ring(Index v, Index slot_count) {
        Index start = vs_slots_[vs_offsets_[v]];
        bool manifold = true;
        ring_.boundary = false;
        Index boundary_starts = 0;
        for (Index k = vs_offsets_[v]; k < vs_offsets_[v + 1]; ++k) {
            const Index s = vs_slots_[k];
            const Index lead = level_.face_edges[s];
            if (edge_uses_[lead] > 2 || edge_uses_[level_.face_edges[prev_slot(s)]] > 2) manifold = false;
            if (edge_uses_[lead] == 1) {
                if (boundary_starts++ == 0) start = s;
                ring_.boundary = true;
            }
        }
        if (boundary_starts > 1) manifold = false;
        ring_.edge_points.clear();
        ring_.edge_sharpness.clear();
        ring_.face_points.clear();
        ring_edges_.clear();
        Index s = start, steps = 0;
        while (manifold) {
            const Index lead = level_.face_edges[s];
            ring_edges_.push_back(lead);
            const Index f = slot_face_[s];
            if (!loop_) {
                // opposite corner of a quad (Catmull-Clark levels >= 1 are all quads)
                if (level_.face_offsets[f + 1] - level_.face_offsets[f] != 4) return false;
                ring_.face_points.push_back(points_[level_.face_verts[next_slot(next_slot(s))]]);
            } else {
                ring_.face_points.push_back(Vec3{});
            }
            const Index trail_slot = prev_slot(s);
            const Index trail = level_.face_edges[trail_slot];
            ++steps;
            if (edge_uses_[trail] == 1) {
                ring_edges_.push_back(trail);
                break;
            }
            const Index next = slot0_[trail] == trail_slot ? slot1_[trail] : slot0_[trail];
            if (next == start) break;
            if (next == kInvalidIndex || steps > slot_count || level_.face_verts[next] != v) return false;
            s = next;
        }
        return manifold && steps == slot_count;
    }

    //! Non-manifold vertices are corners or creases (OpenSubdiv sharpens them), whose limit positions need only the
    //! sharp neighbours; their normal is the area-weighted one of the incident faces.
    void fallback(Index v) {
        int sharp = 0;
        Vec3 ends{};
        for (Index k = ve_offsets_[v]; k < ve_offsets_[v + 1]; ++k) {
            const Index e = ve_edges_[k];
            if (edge_sharpness_[e] > 0.0f) {
                if (sharp < 2) ends += points_[other_end(e, v)];
                ++sharp;
            }
        }
        const bool crease = vertex_sharpness_[v] <= 0.0f && sharp == 2;
        limit_positions_[v] = crease ? (2.0 / 3.0) * points_[v] + (1.0 / 6.0) * ends : points_[v];
        Vec3 n{};
        for (Index k = vs_offsets_[v]; k < vs_offsets_[v + 1]; ++k) {
            const Index s = vs_slots_[k];
            // the nearest corners before and after that are somewhere else: a face that repeats a vertex, or a
            // degenerate edge's descendants (which stay on top of their vertex), would give no area
            Index before = prev_slot(s), after = next_slot(s);
            while (before != s && points_[level_.face_verts[before]] == points_[v]) before = prev_slot(before);
            while (after != s && points_[level_.face_verts[after]] == points_[v]) after = next_slot(after);
            n += cross(points_[v] - points_[level_.face_verts[before]], points_[level_.face_verts[after]] - points_[v]);
        }
        limit_normals_[v] = normalized(n);
    }

    const Level& level_;
    const std::vector<float>& edge_sharpness_;
    const std::vector<float>& vertex_sharpness_;
    const bool loop_, warren_;
    const Vec3* points_;
    const Index count_;
    Vec3* limit_positions_;
    Vec3* limit_normals_;
    std::vector<Index> slot0_, slot1_, slot_face_, vs_offsets_, vs_slots_, ve_offsets_, ve_edges_;
    std::vector<std::uint8_t> edge_uses_;
    Ring ring_;
    std::vector<Index> ring_edges_;
};

}  // namespace

void evaluate_limit(const Level& level, const std::vector<float>& edge_sharpness,
                    const std::vector<float>& vertex_sharpness, bool loop, bool warren, const Vec3* points, Index count,
                    Vec3* limit_positions, Vec3* limit_normals) {
    LimitEvaluator evaluator(level, edge_sharpness, vertex_sharpness, loop, warren, points, count, limit_positions,
                             limit_normals);
    for (Index v = 0; v < count; ++v) evaluator.evaluate(v);
}

}  // namespace surfaced::subdivision
