#include "geometry/subdivision/topology.h"

#include "geometry/subdivision/parallel.h"

#include <cassert>

namespace surfaced::subdivision {

Level build_base_level(const PolygonMesh& mesh) {
    Level level;
    level.vertex_count = static_cast<Index>(mesh.vertex_count());
    level.face_offsets = mesh.face_offsets;
    level.face_verts = mesh.face_indices;
    level.face_edges.resize(mesh.face_indices.size());

    // Bucket candidate edges by their lower vertex. Every half-edge reserves one slot, so a bucket can never
    // overflow; lookups scan the few edges already found at that vertex.
    const std::size_t nv = mesh.vertex_count();
    std::vector<Index> bucket_start(nv + 1, 0);
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        auto face = mesh.face(f);
        for (std::size_t j = 0; j < face.size(); ++j) {
            Index a = face[j], b = face[(j + 1) % face.size()];
            ++bucket_start[std::min(a, b) + 1];
        }
    }
    for (std::size_t v = 0; v < nv; ++v) bucket_start[v + 1] += bucket_start[v];
    std::vector<Index> bucket_fill(nv, 0);
    std::vector<Index> bucket_edges(bucket_start[nv]);
    level.edge_verts.reserve(mesh.face_indices.size());  // at most one edge per half-edge
    std::vector<Index> last_face;                        // per edge: the last face found using it
    last_face.reserve(mesh.face_indices.size());
    std::vector<Index> tagged;  // edges OpenSubdiv tags non-manifold as it builds them

    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const Index begin = mesh.face_offsets[f];
        const std::size_t n = mesh.face_size(f);
        for (std::size_t j = 0; j < n; ++j) {
            const Index a = mesh.face_indices[begin + j];
            const Index b = mesh.face_indices[begin + (j + 1) % n];
            const Index lo = std::min(a, b), hi = std::max(a, b);
            Index* slots = bucket_edges.data() + bucket_start[lo];
            Index found = kInvalidIndex;
            if (a != b) {  // a degenerate edge (a corner followed by the same vertex) is always new
                for (Index k = 0; k < bucket_fill[lo]; ++k) {
                    const Index e = slots[k];
                    const Index u = level.edge_verts[2 * e], w = level.edge_verts[2 * e + 1];
                    if (u != w && (u == hi || w == hi)) {
                        found = e;
                        break;
                    }
                }
                if (found != kInvalidIndex && last_face[found] == static_cast<Index>(f)) {
                    // this face uses the edge a second time: a new instance, and both are non-manifold
                    tagged.push_back(found);
                    tagged.push_back(static_cast<Index>(level.edge_verts.size() / 2));
                    found = kInvalidIndex;
                }
            } else {
                tagged.push_back(static_cast<Index>(level.edge_verts.size() / 2));
            }
            if (found == kInvalidIndex) {
                found = static_cast<Index>(level.edge_verts.size() / 2);
                level.edge_verts.push_back(a);
                level.edge_verts.push_back(b);
                last_face.push_back(static_cast<Index>(f));
                slots[bucket_fill[lo]++] = found;
            } else {
                last_face[found] = static_cast<Index>(f);
            }
            level.face_edges[begin + j] = found;
        }
    }
    if (!tagged.empty()) {
        level.non_manifold_edge.assign(level.edge_verts.size() / 2, 0);
        for (Index e : tagged) level.non_manifold_edge[e] = 1;
    }
    return level;
}

// Union-find over face corners (a corner is one slot of face_verts).
std::vector<std::uint32_t> count_fans(const Level& level, const std::vector<std::uint32_t>& edge_faces,
                                      const std::vector<std::uint8_t>& non_manifold_edge) {
    const Index corners = static_cast<Index>(level.face_verts.size()), ne = level.edge_count();
    std::vector<Index> parent(corners);
    for (Index i = 0; i < corners; ++i) parent[i] = i;
    auto find = [&](Index x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    // the corner after `slot` in face f (the other end of the edge that starts at `slot`)
    auto next_corner = [&](Index f, Index slot) {
        return slot + 1 < level.face_offsets[f + 1] ? slot + 1 : level.face_offsets[f];
    };
    // first face-edge slot (and its face) seen for each manifold interior edge
    std::vector<Index> first_slot(ne, kInvalidIndex), first_face(ne, kInvalidIndex);
    for (Index f = 0; f < level.face_count(); ++f) {
        for (Index slot = level.face_offsets[f]; slot < level.face_offsets[f + 1]; ++slot) {
            const Index e = level.face_edges[slot];
            if (edge_faces[e] != 2 || non_manifold_edge[e]) continue;
            if (first_slot[e] == kInvalidIndex) {
                first_slot[e] = slot;
                first_face[e] = f;
                continue;
            }
            // the two faces meet along e: join their corners at each end vertex of e
            const Index ours[2] = {slot, next_corner(f, slot)};
            const Index theirs[2] = {first_slot[e], next_corner(first_face[e], first_slot[e])};
            for (Index x : ours)
                for (Index y : theirs)
                    if (level.face_verts[x] == level.face_verts[y]) parent[find(x)] = find(y);
        }
    }
    std::vector<std::uint32_t> fans(level.vertex_count, 0);
    for (Index i = 0; i < corners; ++i)
        if (find(i) == i) ++fans[level.face_verts[i]];
    return fans;
}

namespace {

// The two children of every parent edge, (edge point, child of end 0) and (edge point, child of end 1), numbered
// after the face-interior edges; the same for both schemes.
void emit_edge_children(const Level& p, Index first_edge_vert, Index first_edge_edge, Level& c, bool threaded) {
    for_range(p.edge_count(), threaded, [&](Index e_begin, Index e_end) {
        for (Index e = e_begin; e < e_end; ++e) {
            const Index ce = first_edge_vert + e;
            Index* ev = &c.edge_verts[2 * (static_cast<std::size_t>(first_edge_edge) + 2 * e)];
            ev[0] = ce;
            ev[1] = p.edge_verts[2 * e];
            ev[2] = ce;
            ev[3] = p.edge_verts[2 * e + 1];
        }
    });
}

}  // namespace

Level refine_quads(const Level& p, bool with_edges, bool threaded) {
    const Index nv = p.vertex_count, nf = p.face_count(), ne = p.edge_count();
    const Index first_face_vert = nv, first_edge_vert = nv + nf;
    const Index corners = static_cast<Index>(p.face_verts.size());

    Level c;
    c.vertex_count = nv + nf + ne;
    c.face_offsets.resize(static_cast<std::size_t>(corners) + 1);
    for_range(corners + 1, threaded, [&](Index b, Index e) {
        for (Index i = b; i < e; ++i) c.face_offsets[i] = 4 * i;
    });
    c.face_verts.resize(4 * static_cast<std::size_t>(corners));
    if (with_edges) {
        c.face_edges.resize(4 * static_cast<std::size_t>(corners));
        c.edge_verts.resize(2 * (static_cast<std::size_t>(corners) + 2 * ne));
    }
    // child edges: first `corners` from faces (face f's j-th at face_offsets[f] + j), then 2 per parent edge
    const Index first_edge_edge = corners;

    for_range(nf, threaded, [&](Index f_begin, Index f_end) {
        for (Index f = f_begin; f < f_end; ++f) {
            const Index begin = p.face_offsets[f];
            const Index n = p.face_offsets[f + 1] - begin;
            const Index cf = first_face_vert + f;
            for (Index j = 0; j < n; ++j) {
                const Index jp = j == 0 ? n - 1 : j - 1;
                const Index v = p.face_verts[begin + j];
                const Index e_next = p.face_edges[begin + j], e_prev = p.face_edges[begin + jp];
                // Quads keep the parent's parametric orientation: the corner's child vertex sits at position j.
                const Index rot = n == 4 ? j : 0;
                Index* fv = &c.face_verts[4 * (static_cast<std::size_t>(begin) + j)];
                fv[rot] = v;
                fv[(rot + 1) & 3] = first_edge_vert + e_next;
                fv[(rot + 2) & 3] = cf;
                fv[(rot + 3) & 3] = first_edge_vert + e_prev;
                if (with_edges) {
                    Index* fe = &c.face_edges[4 * (static_cast<std::size_t>(begin) + j)];
                    fe[rot] = first_edge_edge + 2 * e_next + edge_child_at(p, e_next, v, false);
                    fe[(rot + 1) & 3] = begin + j;
                    fe[(rot + 2) & 3] = begin + jp;
                    fe[(rot + 3) & 3] = first_edge_edge + 2 * e_prev + edge_child_at(p, e_prev, v, true);
                    c.edge_verts[2 * (begin + j)] = cf;
                    c.edge_verts[2 * (begin + j) + 1] = first_edge_vert + e_next;
                }
            }
        }
    });
    if (with_edges) emit_edge_children(p, first_edge_vert, first_edge_edge, c, threaded);
    return c;
}

Level refine_triangles(const Level& p, bool with_edges, bool threaded) {
    const Index nv = p.vertex_count, nf = p.face_count(), ne = p.edge_count();
    const Index first_edge_vert = nv;

    Level c;
    c.vertex_count = nv + ne;
    c.face_offsets.resize(4 * static_cast<std::size_t>(nf) + 1);
    for_range(4 * nf + 1, threaded, [&](Index b, Index e) {
        for (Index i = b; i < e; ++i) c.face_offsets[i] = 3 * i;
    });
    c.face_verts.resize(12 * static_cast<std::size_t>(nf));
    if (with_edges) {
        c.face_edges.resize(12 * static_cast<std::size_t>(nf));
        c.edge_verts.resize(2 * (3 * static_cast<std::size_t>(nf) + 2 * ne));
    }
    const Index first_edge_edge = 3 * nf;

    for_range(nf, threaded, [&](Index f_begin, Index f_end) {
        for (Index f = f_begin; f < f_end; ++f) {
            const Index b = p.face_offsets[f];
            assert(p.face_offsets[f + 1] - b == 3);
            const Index v[3] = {p.face_verts[b], p.face_verts[b + 1], p.face_verts[b + 2]};
            const Index e[3] = {p.face_edges[b], p.face_edges[b + 1], p.face_edges[b + 2]};
            const Index ce[3] = {first_edge_vert + e[0], first_edge_vert + e[1], first_edge_vert + e[2]};
            Index* fv = &c.face_verts[12 * static_cast<std::size_t>(f)];
            const Index tri[4][3] = {
                {v[0], ce[0], ce[2]}, {ce[0], v[1], ce[1]}, {ce[2], ce[1], v[2]}, {ce[1], ce[2], ce[0]}};
            for (int t = 0; t < 4; ++t)
                for (int k = 0; k < 3; ++k) fv[3 * t + k] = tri[t][k];
            if (with_edges) {
                // interior edges of face f: j-th joins edge points j and j-1
                const Index ie = 3 * f;
                for (Index j = 0; j < 3; ++j) {
                    c.edge_verts[2 * (ie + j)] = ce[j];
                    c.edge_verts[2 * (ie + j) + 1] = ce[(j + 2) % 3];
                }
                // half of edge e_j at its start v_j (out), or of e_{j-1} at its end v_j (in)
                auto out = [&](Index j) { return first_edge_edge + 2 * e[j] + edge_child_at(p, e[j], v[j], false); };
                auto in = [&](Index j) {
                    const Index jp = (j + 2) % 3;
                    return first_edge_edge + 2 * e[jp] + edge_child_at(p, e[jp], v[j], true);
                };
                Index* fe = &c.face_edges[12 * static_cast<std::size_t>(f)];
                // corner triangles: (v_j, ce_j) is half of e_j, (ce_j, ce_{j-1}) interior j, (ce_{j-1}, v_j) half of e_{j-1}
                fe[0] = out(0);
                fe[1] = ie + 0;
                fe[2] = in(0);
                fe[3] = in(1);
                fe[4] = out(1);
                fe[5] = ie + 1;
                fe[6] = ie + 2;
                fe[7] = in(2);
                fe[8] = out(2);
                // middle triangle (ce1, ce2, ce0)
                fe[9] = ie + 2;
                fe[10] = ie + 0;
                fe[11] = ie + 1;
            }
        }
    });
    if (with_edges) emit_edge_children(p, first_edge_vert, first_edge_edge, c, threaded);
    return c;
}

}  // namespace surfaced::subdivision
