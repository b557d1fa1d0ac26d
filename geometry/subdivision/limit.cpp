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

}  // namespace

void evaluate_limit(const Level& level, const std::vector<float>& edge_sharpness,
                    const std::vector<float>& vertex_sharpness, bool loop, bool warren, const Vec3* points, Index count,
                    Vec3* limit_positions, Vec3* limit_normals) {
    const Index ne = level.edge_count(), nf = level.face_count();
    // the (up to two) face slots of each edge; a slot is the corner where the edge starts in its face
    std::vector<Index> slot0(ne, kInvalidIndex), slot1(ne, kInvalidIndex);
    std::vector<std::uint8_t> edge_uses(ne, 0);
    std::vector<Index> slot_face(level.face_verts.size());
    for (Index f = 0; f < nf; ++f)
        for (Index s = level.face_offsets[f]; s < level.face_offsets[f + 1]; ++s) {
            slot_face[s] = f;
            const Index e = level.face_edges[s];
            if (edge_uses[e] == 0)
                slot0[e] = s;
            else
                slot1[e] = s;
            if (edge_uses[e] < 255) ++edge_uses[e];
        }
    // the slots of each vertex < count, in face order (so the first is in the lowest face)
    std::vector<Index> vs_offsets(static_cast<std::size_t>(count) + 1, 0);
    for (Index v : level.face_verts)
        if (v < count) ++vs_offsets[v + 1];
    for (Index v = 0; v < count; ++v) vs_offsets[v + 1] += vs_offsets[v];
    std::vector<Index> vs_slots(vs_offsets[count]);
    {
        std::vector<Index> fill(vs_offsets.begin(), vs_offsets.end() - 1);
        for (Index s = 0; s < level.face_verts.size(); ++s)
            if (level.face_verts[s] < count) vs_slots[fill[level.face_verts[s]]++] = s;
    }
    auto prev_slot = [&](Index s) {
        const Index f = slot_face[s];
        return s == level.face_offsets[f] ? level.face_offsets[f + 1] - 1 : s - 1;
    };
    auto next_slot = [&](Index s) {
        const Index f = slot_face[s];
        return s + 1 == level.face_offsets[f + 1] ? level.face_offsets[f] : s + 1;
    };
    auto other_end = [&](Index e, Index v) {
        return level.edge_verts[2 * e] == v ? level.edge_verts[2 * e + 1] : level.edge_verts[2 * e];
    };
    // vertex -> incident edges (unordered), for positions where no ordered ring exists
    std::vector<Index> ve_offsets(static_cast<std::size_t>(count) + 1, 0);
    for (Index e = 0; e < ne; ++e)
        for (int k = 0; k < 2; ++k)
            if (level.edge_verts[2 * e + k] < count) ++ve_offsets[level.edge_verts[2 * e + k] + 1];
    for (Index v = 0; v < count; ++v) ve_offsets[v + 1] += ve_offsets[v];
    std::vector<Index> ve_edges(ve_offsets[count]);
    {
        std::vector<Index> fill(ve_offsets.begin(), ve_offsets.end() - 1);
        for (Index e = 0; e < ne; ++e)
            for (int k = 0; k < 2; ++k)
                if (level.edge_verts[2 * e + k] < count) ve_edges[fill[level.edge_verts[2 * e + k]]++] = e;
    }
    // Non-manifold vertices are corners or creases (OpenSubdiv sharpens them), whose limit positions need only the
    // sharp neighbours; their normal is the area-weighted one of the incident faces.
    auto fallback = [&](Index v) {
        int sharp = 0;
        Vec3 ends{};
        for (Index k = ve_offsets[v]; k < ve_offsets[v + 1]; ++k) {
            const Index e = ve_edges[k];
            if (edge_sharpness[e] > 0.0f) {
                if (sharp < 2) ends += points[other_end(e, v)];
                ++sharp;
            }
        }
        const bool crease = vertex_sharpness[v] <= 0.0f && sharp == 2;
        limit_positions[v] = crease ? (2.0 / 3.0) * points[v] + (1.0 / 6.0) * ends : points[v];
        Vec3 n{};
        for (Index k = vs_offsets[v]; k < vs_offsets[v + 1]; ++k) {
            const Index s = vs_slots[k];
            // the nearest corners before and after that are somewhere else: a face that repeats a vertex, or a
            // degenerate edge's descendants (which stay on top of their vertex), would give no area
            Index before = prev_slot(s), after = next_slot(s);
            while (before != s && points[level.face_verts[before]] == points[v]) before = prev_slot(before);
            while (after != s && points[level.face_verts[after]] == points[v]) after = next_slot(after);
            n += cross(points[v] - points[level.face_verts[before]], points[level.face_verts[after]] - points[v]);
        }
        limit_normals[v] = normalized(n);
    };

    Ring ring;
    std::vector<Index> ring_edges;
    for (Index v = 0; v < count; ++v) {
        const Index slot_count = vs_offsets[v + 1] - vs_offsets[v];
        if (slot_count == 0) {  // isolated vertex
            limit_positions[v] = points[v];
            limit_normals[v] = Vec3{};
            continue;
        }
        // find the start: a slot whose leading edge is a boundary edge, else the lowest face
        Index start = vs_slots[vs_offsets[v]];
        bool manifold = true;
        ring.boundary = false;
        {
            Index boundary_starts = 0;
            for (Index k = vs_offsets[v]; k < vs_offsets[v + 1]; ++k) {
                const Index s = vs_slots[k];
                const Index lead = level.face_edges[s];
                if (edge_uses[lead] > 2 || edge_uses[level.face_edges[prev_slot(s)]] > 2) manifold = false;
                if (edge_uses[lead] == 1) {
                    if (boundary_starts++ == 0) start = s;
                    ring.boundary = true;
                }
            }
            if (boundary_starts > 1) manifold = false;
        }
        // walk counter-clockwise: face of slot s lies between its leading edge and its trailing edge
        ring.edge_points.clear();
        ring.edge_sharpness.clear();
        ring.face_points.clear();
        ring_edges.clear();
        Index s = start, steps = 0;
        while (manifold) {
            const Index lead = level.face_edges[s];
            ring_edges.push_back(lead);
            const Index f = slot_face[s];
            if (!loop) {
                // opposite corner of a quad (Catmull-Clark levels >= 1 are all quads)
                if (level.face_offsets[f + 1] - level.face_offsets[f] != 4) {
                    manifold = false;
                    break;
                }
                ring.face_points.push_back(points[level.face_verts[next_slot(next_slot(s))]]);
            } else {
                ring.face_points.push_back(Vec3{});
            }
            const Index trail_slot = prev_slot(s);
            const Index trail = level.face_edges[trail_slot];
            ++steps;
            if (edge_uses[trail] == 1) {
                ring_edges.push_back(trail);
                break;
            }
            const Index next = slot0[trail] == trail_slot ? slot1[trail] : slot0[trail];
            if (next == start) break;
            if (next == kInvalidIndex || steps > slot_count || level.face_verts[next] != v) {
                manifold = false;
                break;
            }
            s = next;
        }
        if (!manifold || steps != slot_count) {
            fallback(v);
            continue;
        }
        int sharp_count = 0, c0 = -1, c1 = -1;
        for (std::size_t i = 0; i < ring_edges.size(); ++i) {
            const Index e = ring_edges[i];
            ring.edge_points.push_back(points[other_end(e, v)]);
            const float sh = edge_sharpness[e];
            ring.edge_sharpness.push_back(sh);
            if (sh > 0.0f) {
                if (sharp_count == 0)
                    c0 = static_cast<int>(i);
                else if (sharp_count == 1)
                    c1 = static_cast<int>(i);
                ++sharp_count;
            }
        }
        const bool corner = vertex_sharpness[v] > 0.0f || sharp_count > 2;
        if (sharp_count != 2) c0 = c1 = -1;
        const LimitPoint lp =
            loop ? loop_limit(points[v], ring, corner, c0, c1, warren) : catmark_limit(points[v], ring, corner, c0, c1);
        limit_positions[v] = lp.position;
        const Vec3 n = normalized(cross(lp.tan1, lp.tan2));
        if (n.x == 0 && n.y == 0 && n.z == 0) {
            fallback(v);
            limit_positions[v] = lp.position;
        } else {
            limit_normals[v] = n;
        }
    }
}

}  // namespace surfaced::subdivision
