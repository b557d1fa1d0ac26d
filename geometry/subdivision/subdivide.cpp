// Uniform Catmull-Clark and Loop refinement.
//
// Each level: build the child topology (topology.cpp); compute child positions in three scatter passes (face points,
// edge points, vertex points) with the smooth rules; then overwrite the points that sharpness governs (crease and
// corner vertex rules, creased edges, and OpenSubdiv's fractional blend where a semi-sharp feature decays to smooth
// between this level and the next); finally subdivide the sharpness values for the child level. Weights are
// OpenSubdiv's (rules.h); sharpness arithmetic is done in float, as OpenSubdiv does, so results agree to the last bits.
#include "geometry/subdivision/subdivide.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <thread>
#include <string>
#include <unordered_map>

#include "geometry/subdivision/limit.h"
#include "geometry/subdivision/parallel.h"
#include "geometry/subdivision/rules.h"
#include "geometry/subdivision/topology.h"

namespace surfaced {

namespace {

using subdivision::for_range;
using subdivision::Level;

bool is_sharp(float s) { return s > 0.0f; }
bool is_infinite(float s) { return s >= kInfiniteSharpness; }
bool is_semi_sharp(float s) { return s > 0.0f && s < kInfiniteSharpness; }
float decrement(float s) {
    if (is_infinite(s)) return kInfiniteSharpness;
    return s > 1.0f ? s - 1.0f : 0.0f;
}

enum class Rule { Smooth, Dart, Crease, Corner };
Rule vertex_rule(float vertex_sharpness, int sharp_edges) {
    if (is_sharp(vertex_sharpness)) return Rule::Corner;
    switch (sharp_edges) {
        case 0: return Rule::Smooth;
        case 1: return Rule::Dart;
        case 2: return Rule::Crease;
        default: return Rule::Corner;
    }
}

// Sharpness state of one level.
struct Sharpness {
    std::vector<float> edge;         // per edge; boundary and non-manifold edges are infinite
    std::vector<float> vertex;       // per vertex
    std::vector<std::uint8_t> hole;  // per face; empty when there are no holes
};

// What the rules need to know about a level's vertices.
struct Neighbourhood {
    std::vector<std::uint32_t> vertex_faces, vertex_edges;
    std::vector<Index> sharp_offsets;  // per vertex, into sharp_edges: incident edges with sharpness > 0
    std::vector<Index> sharp_edges;
    std::vector<float> semi_sum;  // Chaikin: sum of incident semi-sharp sharpness
    std::vector<std::uint16_t> semi_count;
    bool any_sharp_vertex = false;
};

Neighbourhood neighbourhood(const Level& level, const Sharpness& sharp, CreaseMethod method) {
    const Index nv = level.vertex_count, ne = level.edge_count();
    Neighbourhood n;
    n.vertex_faces.assign(nv, 0);
    for (Index v : level.face_verts) ++n.vertex_faces[v];
    n.vertex_edges.assign(nv, 0);
    n.sharp_offsets.assign(nv + 1, 0);
    for (Index e = 0; e < ne; ++e) {
        const Index a = level.edge_verts[2 * e], b = level.edge_verts[2 * e + 1];
        ++n.vertex_edges[a];
        ++n.vertex_edges[b];
        if (is_sharp(sharp.edge[e])) {
            ++n.sharp_offsets[a + 1];
            ++n.sharp_offsets[b + 1];
        }
    }
    for (Index v = 0; v < nv; ++v) n.sharp_offsets[v + 1] += n.sharp_offsets[v];
    n.sharp_edges.resize(n.sharp_offsets[nv]);
    std::vector<Index> fill(n.sharp_offsets.begin(), n.sharp_offsets.end() - 1);
    for (Index e = 0; e < ne; ++e)
        if (is_sharp(sharp.edge[e])) {
            n.sharp_edges[fill[level.edge_verts[2 * e]]++] = e;
            n.sharp_edges[fill[level.edge_verts[2 * e + 1]]++] = e;
        }
    for (Index v = 0; v < nv; ++v)
        if (is_sharp(sharp.vertex[v])) n.any_sharp_vertex = true;
    if (method == CreaseMethod::Chaikin) {
        n.semi_sum.assign(nv, 0.0f);
        n.semi_count.assign(nv, 0);
        for (Index v = 0; v < nv; ++v)
            for (Index i = n.sharp_offsets[v]; i < n.sharp_offsets[v + 1]; ++i) {
                const float s = sharp.edge[n.sharp_edges[i]];
                if (is_semi_sharp(s)) {
                    n.semi_sum[v] += s;
                    ++n.semi_count[v];
                }
            }
    }
    return n;
}

// Sharpness of the child of an edge (sharpness s) at its end vertex v (OpenSubdiv's Crease::
// SubdivideEdgeSharpnessAtVertex).
float child_edge_sharpness(float s, Index v, const Neighbourhood& n, CreaseMethod method) {
    if (method == CreaseMethod::Uniform || n.vertex_edges[v] < 2) return decrement(s);
    if (!is_sharp(s)) return 0.0f;
    if (is_infinite(s)) return kInfiniteSharpness;
    if (n.semi_count[v] > 1) {
        const float others = (n.semi_sum[v] - s) / static_cast<float>(n.semi_count[v] - 1);
        s = 0.75f * s + 0.25f * others;
    }
    s -= 1.0f;
    return is_sharp(s) ? s : 0.0f;
}

// Fraction of the parent rule in a vertex whose rule changes between levels (Crease::ComputeFractionalWeightAtVertex).
float fractional_weight(float parent_vertex, float child_vertex, const float* parent_edges, const float* child_edges,
                        Index count) {
    int transitions = 0;
    float sum = 0.0f;
    if (is_sharp(parent_vertex) && !is_sharp(child_vertex)) {
        transitions = 1;
        sum = parent_vertex;
    }
    for (Index i = 0; i < count; ++i)
        if (is_sharp(parent_edges[i]) && !is_sharp(child_edges[i])) {
            sum += parent_edges[i];
            ++transitions;
        }
    if (transitions == 0) return 0.0f;
    const float w = sum / static_cast<float>(transitions);
    return w > 1.0f ? 1.0f : w;
}

Index other_end(const Level& level, Index e, Index v) {
    return level.edge_verts[2 * e] == v ? level.edge_verts[2 * e + 1] : level.edge_verts[2 * e];
}

// Vertex points for every vertex whose rule is not smooth. On entry dst[v] holds the smooth result for every vertex.
void apply_vertex_rules(const Level& p, const Sharpness& sharp, const Neighbourhood& n, CreaseMethod method,
                        const Vec3* src, Vec3* dst, Index v_begin, Index v_end) {
    std::vector<float> parent_sharp, child_sharp;
    for (Index v = v_begin; v < v_end; ++v) {
        const Index begin = n.sharp_offsets[v], count = n.sharp_offsets[v + 1] - begin;
        const float pv = sharp.vertex[v];
        if (count <= 1 && !is_sharp(pv)) continue;  // smooth or dart, at this level and the next
        const Index* edges = n.sharp_edges.data() + begin;
        const Rule parent_rule = vertex_rule(pv, static_cast<int>(count));
        if (parent_rule == Rule::Smooth || parent_rule == Rule::Dart) continue;

        auto crease_point = [&](const float* edge_sharpness) {
            Vec3 sum{};
            int found = 0;
            for (Index i = 0; i < count && found < 2; ++i)
                if (is_sharp(edge_sharpness[i])) {
                    sum += src[other_end(p, edges[i], v)];
                    ++found;
                }
            return subdivision::kCreaseVertexWeight * src[v] + subdivision::kCreaseNeighbourWeight * sum;
        };
        parent_sharp.resize(count);
        child_sharp.resize(count);
        int child_sharp_count = 0;
        for (Index i = 0; i < count; ++i) {
            parent_sharp[i] = sharp.edge[edges[i]];
            child_sharp[i] = child_edge_sharpness(parent_sharp[i], v, n, method);
            child_sharp_count += is_sharp(child_sharp[i]);
        }
        const Vec3 parent_point = parent_rule == Rule::Corner ? src[v] : crease_point(parent_sharp.data());
        const float cv = decrement(pv);
        const Rule child_rule = vertex_rule(cv, child_sharp_count);
        if (child_rule == parent_rule) {
            dst[v] = parent_point;
            continue;
        }
        Vec3 child_point;
        if (child_rule == Rule::Smooth || child_rule == Rule::Dart)
            child_point = dst[v];
        else if (child_rule == Rule::Crease)
            child_point = crease_point(child_sharp.data());
        else
            child_point = src[v];
        const double pw = fractional_weight(pv, cv, parent_sharp.data(), child_sharp.data(), count);
        const double cw = 1.0 - pw;
        dst[v] = pw * parent_point + cw * child_point;
    }
}

// Edge points: dst_edges[e] holds the sum of the smooth rule's face contributions (CC: face points; Loop: opposite
// vertices) on entry. `face_weight(e)`/`vertex_weight(e)` are the smooth weights.
template <class Weights>
void finish_edge_points(const Level& p, const Sharpness& sharp, const Neighbourhood& n, CreaseMethod method,
                        const Vec3* src, Vec3* dst_edges, Weights&& smooth_weights, Index e_begin, Index e_end) {
    for (Index e = e_begin; e < e_end; ++e) {
        const Index a = p.edge_verts[2 * e], b = p.edge_verts[2 * e + 1];
        const float s = sharp.edge[e];
        const Vec3 ends = src[a] + src[b];
        if (!is_sharp(s)) {
            const auto [vw, fw] = smooth_weights(e);
            dst_edges[e] = vw * ends + fw * dst_edges[e];
            continue;
        }
        // the child edge point is a crease vertex when both halves stay sharp: then the crease mask alone applies
        if (is_infinite(s) ||
            (is_sharp(child_edge_sharpness(s, a, n, method)) && is_sharp(child_edge_sharpness(s, b, n, method)))) {
            dst_edges[e] = 0.5 * ends;
            continue;
        }
        // crease decaying to smooth: blend the crease mask (1/2, 1/2) into the smooth one by the sharpness
        const auto [vw, fw] = smooth_weights(e);
        const double pw = s, cw = 1.0 - pw;
        dst_edges[e] = (pw * 0.5 + cw * vw) * ends + (cw * fw) * dst_edges[e];
    }
}

struct LevelInput {
    const Level& topology;
    const Sharpness& sharp;
    CreaseMethod method;
    TriangleRule triangle_rule;
    LoopWeights loop_weights;
    bool threaded;
};

// The scatter pass of both schemes, into zeroed accumulators (the caller's, which must be all zero on entry): vertex_acc[v] = sum of v's edge neighbours plus
// face_term(f) of each face around v (Catmull-Clark adds face points; Loop nothing); edge_acc[e] = sum of
// face_to_edge(f, corner) over e's faces. Large levels are cut into two fixed parts whose partial sums are added
// in a fixed order, so the result does not depend on the thread count.
template <class FacePass>
void scatter_level(const Level& p, const Vec3* src, Vec3* vertex_acc, Vec3* edge_acc, bool threaded,
                   FacePass&& face_pass) {
    const Index nv = p.vertex_count, ne = p.edge_count(), nf = p.face_count();
    auto edges = [&](Index begin, Index end, Vec3* vacc) {
        for (Index e = begin; e < end; ++e) {
            const Index a = p.edge_verts[2 * e], b = p.edge_verts[2 * e + 1];
            vacc[a] += src[b];
            vacc[b] += src[a];
        }
    };
    // the accumulators arrive zeroed (a freshly sized std::vector<Vec3>): zeroing them again would cost a pass
    if (nf < subdivision::kSplitMinimum) {
        edges(0, ne, vertex_acc);
        face_pass(Index{0}, nf, vertex_acc, edge_acc);
        return;
    }
    // The second part's accumulators: raw storage that part 1 zeroes itself, so that with two threads the zeroing
    // overlaps part 0 and the pages are first touched by the thread that writes them.
    const std::size_t second_count = static_cast<std::size_t>(nv) + ne;
    struct Storage {  // Vec3 is trivially destructible: freeing is all there is to do
        Vec3* data;
        std::size_t count;
        ~Storage() { std::allocator<Vec3>().deallocate(data, count); }
    } storage{std::allocator<Vec3>().allocate(second_count), second_count};
    Vec3* const second = storage.data;
    run_two_parts(threaded, [&](int part) {
        if (part == 1) std::uninitialized_value_construct_n(second, second_count);
        Vec3* vacc = part == 0 ? vertex_acc : second;
        Vec3* eacc = part == 0 ? edge_acc : second + nv;
        edges(part == 0 ? 0 : ne / 2, part == 0 ? ne / 2 : ne, vacc);
        face_pass(part == 0 ? 0 : nf / 2, part == 0 ? nf / 2 : nf, vacc, eacc);
    });
    for_range(nv, threaded, [&](Index b, Index e) {
        for (Index v = b; v < e; ++v) vertex_acc[v] += second[v];
    });
    for_range(ne, threaded, [&](Index b, Index e) {
        for (Index k = b; k < e; ++k) edge_acc[k] += second[nv + k];
    });
}

// One Catmull-Clark level: src has p.vertex_count points, dst gets nv + nf + ne.
void interpolate_catmark(const LevelInput& in, const Neighbourhood& n, const Vec3* src, Vec3* dst) {
    const Level& p = in.topology;
    const Index nv = p.vertex_count, nf = p.face_count(), ne = p.edge_count();
    Vec3* face_pts = dst + nv;
    Vec3* edge_pts = dst + nv + nf;

    const bool smooth_triangles = in.triangle_rule == TriangleRule::Smooth;
    std::vector<std::uint8_t> edge_triangles;  // incident triangles per edge, for the smooth triangle rule
    if (smooth_triangles) {
        edge_triangles.assign(ne, 0);
        for (Index f = 0; f < nf; ++f)
            if (p.face_offsets[f + 1] - p.face_offsets[f] == 3)
                for (Index i = p.face_offsets[f]; i < p.face_offsets[f + 1]; ++i) ++edge_triangles[p.face_edges[i]];
    }
    // face points, and their sums around vertices and edges
    scatter_level(p, src, dst, edge_pts, in.threaded, [&](Index f_begin, Index f_end, Vec3* vacc, Vec3* eacc) {
        for (Index f = f_begin; f < f_end; ++f) {
            const Index begin = p.face_offsets[f], end = p.face_offsets[f + 1];
            Vec3 sum{};
            for (Index i = begin; i < end; ++i) sum += src[p.face_verts[i]];
            const Vec3 fp = sum * (1.0 / static_cast<double>(end - begin));
            face_pts[f] = fp;
            for (Index i = begin; i < end; ++i) {
                vacc[p.face_verts[i]] += fp;
                eacc[p.face_edges[i]] += fp;
            }
        }
    });
    // smooth vertex points (edge neighbours and face points share the weight 1/n^2)
    for_range(nv, in.threaded, [&](Index b, Index e) {
        for (Index v = b; v < e; ++v) {
            const auto w = subdivision::catmark_smooth_vertex(static_cast<int>(n.vertex_faces[v]));
            dst[v] = w.vertex * src[v] + w.edge * dst[v];
        }
    });
    struct W {
        double vertex, face;
    };
    auto weights = [&](Index e) -> W {
        if (smooth_triangles && edge_triangles[e] > 0) {
            // OpenSubdiv's TRI_SUB_SMOOTH weights (from Hbr): 0.47 for a triangle side, 0.25 for a quad side
            const double tri = 0.470;
            const double f0 = tri, f1 = edge_triangles[e] == 2 ? tri : 0.25;
            const double fw = 0.5 * (f0 + f1);
            return {0.5 * (1.0 - 2.0 * fw), fw};
        }
        return {subdivision::kCatmarkEdgeWeight, subdivision::kCatmarkEdgeWeight};
    };
    for_range(ne, in.threaded,
              [&](Index b, Index e) { finish_edge_points(p, in.sharp, n, in.method, src, edge_pts, weights, b, e); });
    for_range(nv, in.threaded,
              [&](Index b, Index e) { apply_vertex_rules(p, in.sharp, n, in.method, src, dst, b, e); });
}

// One Loop level: src has p.vertex_count points, dst gets nv + ne.
void interpolate_loop(const LevelInput& in, const Neighbourhood& n, const Vec3* src, Vec3* dst) {
    const Level& p = in.topology;
    const Index nv = p.vertex_count, ne = p.edge_count();
    Vec3* edge_pts = dst + nv;

    // edge neighbours around vertices; opposite vertices around edges
    scatter_level(p, src, dst, edge_pts, in.threaded, [&](Index f_begin, Index f_end, Vec3*, Vec3* eacc) {
        for (Index f = f_begin; f < f_end; ++f) {
            const Index b = p.face_offsets[f];
            for (Index j = 0; j < 3; ++j) eacc[p.face_edges[b + j]] += src[p.face_verts[b + (j + 2) % 3]];
        }
    });
    for_range(nv, in.threaded, [&](Index b, Index e) {
        for (Index v = b; v < e; ++v) {
            const int valence = static_cast<int>(n.vertex_edges[v]);
            const auto w = in.loop_weights == LoopWeights::Warren ? subdivision::loop_warren_vertex(valence)
                                                                  : subdivision::loop_smooth_vertex(valence);
            dst[v] = w.vertex * src[v] + w.edge * dst[v];
        }
    });
    struct W {
        double vertex, face;
    };
    auto weights = [](Index) -> W { return {subdivision::kLoopEdgeEndWeight, subdivision::kLoopEdgeOppositeWeight}; };
    for_range(ne, in.threaded,
              [&](Index b, Index e) { finish_edge_points(p, in.sharp, n, in.method, src, edge_pts, weights, b, e); });
    for_range(nv, in.threaded,
              [&](Index b, Index e) { apply_vertex_rules(p, in.sharp, n, in.method, src, dst, b, e); });
}

// Sharpness of the child level (vertices: children of vertices first; edges: face-interior edges first, then two
// per parent edge), and holes carried to child faces. `holes_only`: the last level, where nothing refines the
// sharpness further; only the holes are needed (for the output), and the rest would be written for nothing.
Sharpness refine_sharpness(const Level& p, const Level& child, const Sharpness& sharp, const Neighbourhood& n,
                           CreaseMethod method, bool loop, bool holes_only = false) {
    Sharpness c;
    if (!sharp.hole.empty()) {
        c.hole.assign(child.face_count(), 0);
        for (Index f = 0; f < p.face_count(); ++f) {
            if (!sharp.hole[f]) continue;
            const Index first = loop ? 4 * f : p.face_offsets[f];
            const Index count = loop ? 4 : p.face_offsets[f + 1] - p.face_offsets[f];
            for (Index i = 0; i < count; ++i) c.hole[first + i] = 1;
        }
    }
    if (holes_only) return c;
    c.vertex.assign(child.vertex_count, 0.0f);
    for (Index v = 0; v < p.vertex_count; ++v) c.vertex[v] = decrement(sharp.vertex[v]);
    const Index interior = loop ? 3 * p.face_count() : static_cast<Index>(p.face_verts.size());
    c.edge.assign(interior + 2 * static_cast<std::size_t>(p.edge_count()), 0.0f);
    for (Index e = 0; e < p.edge_count(); ++e) {
        const float s = sharp.edge[e];
        if (!is_sharp(s)) continue;
        c.edge[interior + 2 * e] = child_edge_sharpness(s, p.edge_verts[2 * e], n, method);
        c.edge[interior + 2 * e + 1] = child_edge_sharpness(s, p.edge_verts[2 * e + 1], n, method);
    }
    return c;
}

// Number of face fans at each vertex: faces around a vertex are in one fan when a chain of manifold edges at the
// vertex joins them. Union-find over face corners (a corner is one slot of face_verts).
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

// Base-level sharpness from the mesh tags and the topology, as OpenSubdiv's factory assigns it: boundary and
// non-manifold edges are infinitely sharp; corners of one face are with edge-and-corner; non-manifold vertices are,
// except on a simple non-manifold crease.
Result<Sharpness> base_sharpness(const PolygonMesh& mesh, const Level& level, BoundaryInterpolation boundary,
                                 bool use_tags) {
    const Index nv = level.vertex_count, ne = level.edge_count();
    Sharpness s;
    s.edge.assign(ne, 0.0f);
    s.vertex.assign(nv, 0.0f);

    std::vector<std::uint32_t> edge_faces(ne, 0), edge_forward(ne, 0);
    for (Index f = 0; f < level.face_count(); ++f) {
        const Index b = level.face_offsets[f], n = level.face_offsets[f + 1] - b;
        for (Index j = 0; j < n; ++j) {
            const Index e = level.face_edges[b + j];
            ++edge_faces[e];
            if (level.edge_verts[2 * e] == level.face_verts[b + j]) ++edge_forward[e];
        }
    }
    if (use_tags) {
        // vertex -> incident edges, to find the edge a crease names
        std::vector<Index> offsets(nv + 1, 0), edges(2 * static_cast<std::size_t>(ne));
        for (Index e = 0; e < ne; ++e) {
            ++offsets[level.edge_verts[2 * e] + 1];
            ++offsets[level.edge_verts[2 * e + 1] + 1];
        }
        for (Index v = 0; v < nv; ++v) offsets[v + 1] += offsets[v];
        std::vector<Index> fill(offsets.begin(), offsets.end() - 1);
        for (Index e = 0; e < ne; ++e) {
            edges[fill[level.edge_verts[2 * e]]++] = e;
            edges[fill[level.edge_verts[2 * e + 1]]++] = e;
        }
        for (std::size_t i = 0; i < mesh.tags.creases.size(); ++i) {
            const Crease& crease = mesh.tags.creases[i];
            // the first instance, as OpenSubdiv's FindEdge (an edge a face uses twice has two)
            Index found = kInvalidIndex;
            for (Index k = offsets[crease.v0]; k < offsets[crease.v0 + 1] && found == kInvalidIndex; ++k)
                if (other_end(level, edges[k], crease.v0) == crease.v1) found = edges[k];
            if (found == kInvalidIndex)
                return element_error(ErrorCode::InvalidArgument,
                                     "crease " + std::to_string(i) + ": vertices " + std::to_string(crease.v0) +
                                         " and " + std::to_string(crease.v1) + " share no edge",
                                     ElementKind::Crease, static_cast<std::int64_t>(i));
            s.edge[found] = static_cast<float>(crease.sharpness);
        }
        for (const Corner& corner : mesh.tags.corners) s.vertex[corner.vertex] = static_cast<float>(corner.sharpness);
        if (!mesh.tags.holes.empty()) {
            s.hole.assign(level.face_count(), 0);
            for (Index h : mesh.tags.holes) s.hole[h] = 1;
        }
    }
    std::vector<std::uint8_t> non_manifold_edge(ne, 0);
    // for "boundary none": boundary vertices with a boundary edge that the tags did not make infinitely sharp
    std::vector<std::uint8_t> open_boundary_vertex(nv, 0);
    for (Index e = 0; e < ne; ++e)
        if (edge_faces[e] < 2 && !is_infinite(s.edge[e]))
            open_boundary_vertex[level.edge_verts[2 * e]] = open_boundary_vertex[level.edge_verts[2 * e + 1]] = 1;
    for (Index e = 0; e < ne; ++e) {
        non_manifold_edge[e] = edge_faces[e] > 2 || (edge_faces[e] == 2 && edge_forward[e] != 1) ||
                               (!level.non_manifold_edge.empty() && level.non_manifold_edge[e]);
        if (edge_faces[e] < 2 || non_manifold_edge[e]) s.edge[e] = kInfiniteSharpness;
    }
    std::vector<std::uint32_t> vertex_faces(nv, 0), vertex_edges(nv, 0), vertex_boundary(nv, 0), vertex_nm(nv, 0);
    for (Index v : level.face_verts) ++vertex_faces[v];
    for (Index e = 0; e < ne; ++e)
        for (int k = 0; k < 2; ++k) {
            const Index v = level.edge_verts[2 * e + k];
            ++vertex_edges[v];
            vertex_boundary[v] += edge_faces[e] == 1;
            vertex_nm[v] += non_manifold_edge[e];
        }
    if (boundary == BoundaryInterpolation::None) {
        // OpenSubdiv's "boundary none": a face touching the boundary has no limit surface (it shapes its
        // neighbours, like a hole) unless every boundary edge at its boundary vertices was tagged infinitely sharp.
        bool any = false;
        std::vector<std::uint8_t> hole(level.face_count(), 0);
        for (Index f = 0; f < level.face_count(); ++f)
            for (Index i = level.face_offsets[f]; i < level.face_offsets[f + 1]; ++i)
                if (open_boundary_vertex[level.face_verts[i]]) {
                    hole[f] = 1;
                    any = true;
                    break;
                }
        if (any) {
            if (s.hole.empty()) s.hole.assign(level.face_count(), 0);
            for (Index f = 0; f < level.face_count(); ++f) s.hole[f] |= hole[f];
        }
    }
    const std::vector<std::uint32_t> fans = count_fans(level, edge_faces, non_manifold_edge);
    for (Index v = 0; v < nv; ++v) {
        const bool topological_corner = vertex_faces[v] == 1 && vertex_edges[v] == 2;
        // a manifold vertex is one fan of faces joined by manifold edges: closed (faces == edges) or open with two
        // boundary edges (faces == edges - 1)
        const bool fan = vertex_nm[v] == 0 && fans[v] == 1 &&
                         ((vertex_boundary[v] == 0 && vertex_faces[v] == vertex_edges[v]) ||
                          (vertex_boundary[v] == 2 && vertex_faces[v] + 1 == vertex_edges[v]));
        const bool non_manifold = vertex_edges[v] > 0 && !fan;
        if (topological_corner && boundary == BoundaryInterpolation::EdgeAndCorner) {
            s.vertex[v] = kInfiniteSharpness;
        } else if (non_manifold) {
            const bool simple_crease =
                vertex_nm[v] == 2 && vertex_boundary[v] == 0 && vertex_faces[v] > vertex_edges[v];
            if (!simple_crease) s.vertex[v] = kInfiniteSharpness;
        }
    }
    return s;
}

bool use_threads(const SubdivisionOptions& options) {
    return options.threads != 1 && std::thread::hardware_concurrency() > 1;
}

// One refinable set of values on its own topology: the mesh's positions, or a face-varying channel (UVs), whose
// "value mesh" has the mesh's faces but a vertex per distinct (vertex, value) pair, so that seams are its boundaries.
//
// A "dependent-sharp" value (OpenSubdiv's FVarLevel::ValueTag::_depSharp, corners-plus1/2) follows OpenSubdiv's tags
// rather than the value mesh's own rule: of the two values at a vertex, the one without semi-sharp edges inside its
// span stays a corner while its sibling (which has them) is semi-sharp, then becomes a crease with the sibling's
// fractional weight. `ends` are the value mesh's two edges along which it is a crease (refined with it).
struct UvOverride {
    Index value;
    Index ends[2];
    Index sibling;  //!< the semi-sharp value it depends on
};
struct Channel {
    Level level;
    Sharpness sharp;
    std::vector<Vec3> values;
    std::vector<UvOverride> overrides;
};

// Applies the overrides to one refined level (dst: the child values; p/n: the parent level) and carries them to the
// child level's edges. Values that have become creases are dropped (the value mesh then smooths them as it should).
void apply_uv_overrides(Channel& c, const Level& p, const Neighbourhood& n, CreaseMethod method, bool loop,
                        std::vector<Vec3>& dst) {
    const Vec3* src = c.values.data();
    const Index interior = loop ? 3 * p.face_count() : static_cast<Index>(p.face_verts.size());
    std::vector<float> parent_sharp, child_sharp;
    std::vector<UvOverride> kept;
    for (UvOverride o : c.overrides) {
        const Index v = o.value;
        const Vec3 ends = src[other_end(p, o.ends[0], v)] + src[other_end(p, o.ends[1], v)];
        bool keep = true;
        {
            // the sibling's semi-sharp edges (its span's interior edges: the value mesh's sharp edges at it that are
            // not infinite) and the vertex sharpness decide
            const Index w = o.sibling;
            parent_sharp.clear();
            child_sharp.clear();
            bool still_sharp = is_sharp(decrement(c.sharp.vertex[w]));
            for (Index i = n.sharp_offsets[w]; i < n.sharp_offsets[w + 1]; ++i) {
                const float s = c.sharp.edge[n.sharp_edges[i]];
                if (!is_semi_sharp(s)) continue;
                parent_sharp.push_back(s);
                child_sharp.push_back(child_edge_sharpness(s, w, n, method));
                still_sharp |= is_sharp(child_sharp.back());
            }
            if (still_sharp) {
                dst[v] = src[v];
            } else {
                const double corner =
                    fractional_weight(c.sharp.vertex[w], decrement(c.sharp.vertex[w]), parent_sharp.data(),
                                      child_sharp.data(), static_cast<Index>(parent_sharp.size()));
                const double crease = 1.0 - corner;
                dst[v] = (crease * subdivision::kCreaseNeighbourWeight) * ends +
                         (crease * subdivision::kCreaseVertexWeight + corner) * src[v];
                keep = false;
            }
        }
        if (!keep) continue;
        for (Index& e : o.ends) e = interior + 2 * e + subdivision::edge_child_at(p, e, v, false);
        kept.push_back(o);
    }
    c.overrides = std::move(kept);
}

// Refines a channel by one level (the same topology step and rules as positions).
void refine_channel(Channel& c, const SubdivisionOptions& options, bool first_level, bool loop, bool with_edges) {
    const Neighbourhood n = neighbourhood(c.level, c.sharp, options.crease_method);
    Level child = loop ? subdivision::refine_triangles(c.level, with_edges, use_threads(options))
                       : subdivision::refine_quads(c.level, with_edges, use_threads(options));
    std::vector<Vec3> dst(child.vertex_count);
    const bool threaded = use_threads(options);
    const LevelInput in{c.level,
                        c.sharp,
                        options.crease_method,
                        first_level ? options.triangle_rule : TriangleRule::Catmark,
                        options.loop_weights,
                        threaded};
    if (loop)
        interpolate_loop(in, n, c.values.data(), dst.data());
    else
        interpolate_catmark(in, n, c.values.data(), dst.data());
    Sharpness child_sharp = refine_sharpness(c.level, child, c.sharp, n, options.crease_method, loop);
    if (!c.overrides.empty()) apply_uv_overrides(c, c.level, n, options.crease_method, loop, dst);
    c.level = std::move(child);
    c.sharp = std::move(child_sharp);
    c.values = std::move(dst);
}

std::vector<std::uint32_t> edge_face_counts(const Level& level) {
    std::vector<std::uint32_t> counts(level.edge_count(), 0);
    for (Index e : level.face_edges) ++counts[e];
    return counts;
}

// The linear UV modes at every level: "all" is bilinear (every value a corner, every edge sharp); "boundaries" keeps
// every value on a seam or boundary a corner (its edges are boundary edges of the value mesh, already sharp).
void sharpen_linear_uvs(Channel& c, UvInterpolation mode) {
    if (mode == UvInterpolation::All) {
        std::fill(c.sharp.edge.begin(), c.sharp.edge.end(), kInfiniteSharpness);
        std::fill(c.sharp.vertex.begin(), c.sharp.vertex.end(), kInfiniteSharpness);
    } else if (mode == UvInterpolation::Boundaries) {
        const auto faces = edge_face_counts(c.level);
        for (Index e = 0; e < c.level.edge_count(); ++e)
            if (faces[e] < 2)
                c.sharp.vertex[c.level.edge_verts[2 * e]] = c.sharp.vertex[c.level.edge_verts[2 * e + 1]] =
                    kInfiniteSharpness;
    }
}

// Vertices OpenSubdiv tags non-manifold: not one fan of faces joined by manifold edges (as in base_sharpness).
std::vector<std::uint8_t> non_manifold_vertices(const Level& level) {
    const Index nv = level.vertex_count, ne = level.edge_count();
    std::vector<std::uint32_t> edge_faces(ne, 0), edge_forward(ne, 0);
    for (Index f = 0; f < level.face_count(); ++f)
        for (Index slot = level.face_offsets[f]; slot < level.face_offsets[f + 1]; ++slot) {
            const Index e = level.face_edges[slot];
            ++edge_faces[e];
            if (level.edge_verts[2 * e] == level.face_verts[slot]) ++edge_forward[e];
        }
    std::vector<std::uint8_t> non_manifold_edge(ne, 0);
    for (Index e = 0; e < ne; ++e)
        non_manifold_edge[e] = edge_faces[e] > 2 || (edge_faces[e] == 2 && edge_forward[e] != 1) ||
                               (!level.non_manifold_edge.empty() && level.non_manifold_edge[e]);
    std::vector<std::uint32_t> vertex_faces(nv, 0), vertex_edges(nv, 0), vertex_boundary(nv, 0), vertex_nm(nv, 0);
    for (Index v : level.face_verts) ++vertex_faces[v];
    for (Index e = 0; e < ne; ++e)
        for (int k = 0; k < 2; ++k) {
            const Index v = level.edge_verts[2 * e + k];
            ++vertex_edges[v];
            vertex_boundary[v] += edge_faces[e] == 1;
            vertex_nm[v] += non_manifold_edge[e];
        }
    const std::vector<std::uint32_t> fans = count_fans(level, edge_faces, non_manifold_edge);
    std::vector<std::uint8_t> out(nv, 0);
    for (Index v = 0; v < nv; ++v) {
        const bool fan = vertex_nm[v] == 0 && fans[v] == 1 &&
                         ((vertex_boundary[v] == 0 && vertex_faces[v] == vertex_edges[v]) ||
                          (vertex_boundary[v] == 2 && vertex_faces[v] + 1 == vertex_edges[v]));
        out[v] = vertex_edges[v] > 0 && !fan;
    }
    return out;
}

// OpenSubdiv numbers the values around a vertex ("siblings") walking its faces in order, and a quirk of that walk
// (Vtr::FVarLevel::completeTopologyFromFaceValues: with two distinct values found so far, a value is only looked up
// among the earlier ones when it differs from the first) gives a run of the second value that comes back after the
// first value a sibling of its own: a separate value, with its own span (a crease in "none", a corner of one face
// in the other rules). Per face corner: that sibling number where the walk does this, kInvalidIndex elsewhere.
// Only manifold vertices are walked (OpenSubdiv sharpens every value of a non-manifold vertex anyway).
std::vector<Index> duplicate_value_runs(const PolygonMesh& mesh, const Level& ml) {
    const Index corners = static_cast<Index>(ml.face_verts.size()), ne = ml.edge_count(), nv = ml.vertex_count;
    std::vector<Index> duplicate(corners, kInvalidIndex);
    std::vector<Index> edge_slots(2 * static_cast<std::size_t>(ne), kInvalidIndex);
    std::vector<std::uint32_t> edge_faces(ne, 0);
    for (Index s = 0; s < corners; ++s) {
        const Index e = ml.face_edges[s];
        if (edge_faces[e] < 2) edge_slots[2 * e + edge_faces[e]] = s;
        ++edge_faces[e];
    }
    std::vector<Index> offsets(nv + 1, 0), slots(corners);
    for (Index s = 0; s < corners; ++s) ++offsets[ml.face_verts[s] + 1];
    for (Index v = 0; v < nv; ++v) offsets[v + 1] += offsets[v];
    {
        std::vector<Index> fill(offsets.begin(), offsets.end() - 1);
        for (Index s = 0; s < corners; ++s) slots[fill[ml.face_verts[s]]++] = s;  // increasing face order
    }
    std::vector<Index> face_of(corners);
    for (Index f = 0; f < ml.face_count(); ++f)
        for (Index s = ml.face_offsets[f]; s < ml.face_offsets[f + 1]; ++s) face_of[s] = f;
    const auto prev = [&](Index s) {
        const Index f = face_of[s];
        return s > ml.face_offsets[f] ? s - 1 : ml.face_offsets[f + 1] - 1;
    };
    const auto manifold = [&](Index e) {
        return edge_faces[e] == 2 && ml.edge_verts[2 * e] != ml.edge_verts[2 * e + 1] &&
               (ml.non_manifold_edge.empty() || !ml.non_manifold_edge[e]);
    };
    std::vector<Index> ring, unique;
    std::vector<Index> sibling;
    for (Index v = 0; v < nv; ++v) {
        const Index count = offsets[v + 1] - offsets[v];
        if (count < 3) continue;  // the quirk needs at least three runs
        // the first face: the lowest, or at a boundary the one whose edge leaving v is a boundary
        Index start = slots[offsets[v]];
        int boundary_edges = 0;
        for (Index k = offsets[v]; k < offsets[v + 1]; ++k) {
            const Index s = slots[k];
            if (edge_faces[ml.face_edges[s]] == 1) {
                if (boundary_edges == 0) start = s;
                ++boundary_edges;
            }
            if (edge_faces[ml.face_edges[prev(s)]] == 1) ++boundary_edges;
        }
        if (boundary_edges != 0 && boundary_edges != 2) continue;
        // walk: the next face is the one across the edge arriving at v
        ring.clear();
        Index s = start;
        bool ok = true;
        while (ring.size() <= count) {
            ring.push_back(s);
            const Index e = ml.face_edges[prev(s)];
            if (!manifold(e)) {
                ok = boundary_edges == 2 && edge_faces[e] == 1;
                break;
            }
            const Index t = edge_slots[2 * e] == prev(s) ? edge_slots[2 * e + 1] : edge_slots[2 * e];
            if (ml.face_verts[t] != v) {
                ok = false;
                break;
            }
            s = t;
            if (s == start) break;
        }
        if (!ok || ring.size() != count) continue;
        // OpenSubdiv's sibling assignment, and the true one
        unique.assign(1, mesh.uv_indices[ring[0]]);
        sibling.assign(1, 0);
        for (Index i = 1; i < count; ++i) {
            const Index value = mesh.uv_indices[ring[i]];
            if (value == mesh.uv_indices[ring[i - 1]]) {
                sibling.push_back(sibling.back());
                continue;
            }
            Index sib = static_cast<Index>(unique.size());
            if (unique.size() == 1 || (unique.size() == 2 && unique[0] != value)) {
                unique.push_back(value);
            } else {
                const auto found = std::find(unique.begin(), unique.end(), value);
                if (found == unique.end())
                    unique.push_back(value);
                else
                    sib = static_cast<Index>(found - unique.begin());
            }
            sibling.push_back(sib);
        }
        for (Index i = 0; i < count; ++i) {
            const Index first =
                static_cast<Index>(std::find(unique.begin(), unique.end(), unique[sibling[i]]) - unique.begin());
            if (first != sibling[i]) duplicate[ring[i]] = sibling[i];
        }
    }
    return duplicate;
}

// The two value-mesh edges that bound the span (the fan of faces joined by manifold value edges) of the value at
// `slot`, walking around it both ways; false when the span is closed or crosses a sharp edge (then the value mesh's
// own corner rule is what OpenSubdiv does too).
bool span_ends(const Level& vl, const std::vector<std::uint32_t>& edge_faces,
               const std::vector<std::uint8_t>& non_manifold_edge, const std::vector<Index>& edge_slots,
               const Sharpness& sharp, Index slot, Index ends[2]) {
    const auto face_of = [&](Index s) {
        return static_cast<Index>(std::upper_bound(vl.face_offsets.begin(), vl.face_offsets.end(), s) -
                                  vl.face_offsets.begin() - 1);
    };
    const auto next = [&](Index f, Index s) { return s + 1 < vl.face_offsets[f + 1] ? s + 1 : vl.face_offsets[f]; };
    const auto prev = [&](Index f, Index s) { return s > vl.face_offsets[f] ? s - 1 : vl.face_offsets[f + 1] - 1; };
    const auto open = [&](Index e) { return edge_faces[e] != 2 || non_manifold_edge[e]; };
    const auto across = [&](Index e, Index s) {
        return edge_slots[2 * e] == s ? edge_slots[2 * e + 1] : edge_slots[2 * e];
    };
    const Index limit = static_cast<Index>(vl.face_verts.size());
    for (int dir = 0; dir < 2; ++dir) {
        Index s = slot, f = face_of(slot);
        for (Index steps = 0;; ++steps) {
            if (steps > limit) return false;
            // dir 0: the edge leaving the value in this face; dir 1: the edge arriving at it
            const Index es = dir == 0 ? s : prev(f, s);
            const Index e = vl.face_edges[es];
            if (open(e)) {
                ends[dir] = e;
                break;
            }
            if (is_sharp(sharp.edge[e])) return false;
            const Index t = across(e, es);
            f = face_of(t);
            // the neighbour runs along e the other way: the value is at the end of its slot t (dir 0) or at t
            s = dir == 0 ? next(f, t) : t;
            if (s == slot) return false;  // closed around
        }
    }
    return true;
}

// corners-plus1/2: OpenSubdiv's value tags that the value mesh does not express (see UvOverride), and both values
// of a two-value vertex sharpened when either has an infinitely sharp edge inside its span.
template <class Split>
void add_uv_overrides(Channel& c, const std::vector<Index>& vertex_of, const std::vector<std::uint32_t>& edge_faces,
                      const std::vector<std::uint8_t>& non_manifold_edge, const Sharpness& mesh_sharp,
                      UvInterpolation mode, Split&& split, const std::vector<std::uint32_t>& values_at,
                      const std::vector<std::uint8_t>& any_corner) {
    const Level& vl = c.level;
    const Index nvals = vl.vertex_count, ne = vl.edge_count();
    std::vector<Index> edge_slots(2 * static_cast<std::size_t>(ne), kInvalidIndex);
    for (Index s = 0; s < static_cast<Index>(vl.face_edges.size()); ++s) {
        const Index e = vl.face_edges[s];
        edge_slots[2 * e + (edge_slots[2 * e] == kInvalidIndex ? 0 : 1)] = s;
    }
    std::vector<Index> first_slot(nvals, kInvalidIndex);
    for (Index s = static_cast<Index>(vl.face_verts.size()); s-- > 0;) first_slot[vl.face_verts[s]] = s;
    // semi-sharp and infinitely sharp interior edges of each value's span
    std::vector<std::uint32_t> semi(nvals, 0), inf(nvals, 0);
    for (Index e = 0; e < ne; ++e) {
        if (edge_faces[e] != 2 || non_manifold_edge[e] || !is_sharp(c.sharp.edge[e])) continue;
        auto& count = is_infinite(c.sharp.edge[e]) ? inf : semi;
        ++count[vl.edge_verts[2 * e]];
        ++count[vl.edge_verts[2 * e + 1]];
    }
    // two values at a vertex, exactly one with semi-sharp edges inside its span
    std::vector<Index> first_value(values_at.size(), kInvalidIndex), second_value(values_at.size(), kInvalidIndex);
    for (Index v = 0; v < nvals; ++v)
        (first_value[vertex_of[v]] == kInvalidIndex ? first_value : second_value)[vertex_of[v]] = v;
    for (std::size_t mv = 0; mv < values_at.size(); ++mv) {
        if (values_at[mv] != 2) continue;
        const Index a = first_value[mv], b = second_value[mv];
        if (split(a) || split(b) || is_sharp(mesh_sharp.vertex[mv])) continue;
        if (mode == UvInterpolation::CornersPlus2 && any_corner[mv]) continue;
        if (inf[a] || inf[b]) {  // OpenSubdiv sharpens both values
            c.sharp.vertex[a] = c.sharp.vertex[b] = kInfiniteSharpness;
            continue;
        }
        if ((semi[a] > 0) == (semi[b] > 0)) continue;
        const Index dep = semi[a] > 0 ? b : a, sibling = semi[a] > 0 ? a : b;
        if (is_infinite(c.sharp.vertex[dep])) continue;  // a corner anyway
        UvOverride o{dep, {kInvalidIndex, kInvalidIndex}, sibling};
        if (span_ends(vl, edge_faces, non_manifold_edge, edge_slots, c.sharp, first_slot[dep], o.ends))
            c.overrides.push_back(o);
    }
}

// The base UV channel, sharpened as OpenSubdiv's face-varying channel is (Vtr::FVarLevel): a value on a seam keeps
// the mesh's sharpness and is smoothed as a boundary of its UV region, except where the mode makes it a corner:
// regions with one face at the vertex (all modes but "none"), junctions of three or more regions (corners-plus1/2),
// darts (corners-plus2), values whose region is split at the vertex (always).
Channel base_uv_channel(const PolygonMesh& mesh, const Level& mesh_level, const Sharpness& mesh_sharp,
                        UvInterpolation mode) {
    const std::size_t corners = mesh.face_indices.size();
    std::vector<Index> corner_value(corners);
    std::vector<Index> vertex_of;
    std::vector<Vec3> values;
    {
        const std::vector<Index> duplicate = duplicate_value_runs(mesh, mesh_level);
        std::unordered_map<std::uint64_t, Index> ids, duplicate_ids;
        ids.reserve(corners);
        for (std::size_t i = 0; i < corners; ++i) {
            const bool dup = duplicate[i] != kInvalidIndex;
            const std::uint64_t key =
                (std::uint64_t{mesh.face_indices[i]} << 32) | (dup ? duplicate[i] : mesh.uv_indices[i]);
            auto [it, added] = (dup ? duplicate_ids : ids).emplace(key, static_cast<Index>(vertex_of.size()));
            if (added) {
                vertex_of.push_back(mesh.face_indices[i]);
                const Vec2& uv = mesh.uvs[mesh.uv_indices[i]];
                values.push_back({uv.x, uv.y, 0.0});
            }
            corner_value[i] = it->second;
        }
    }
    PolygonMesh value_mesh;
    value_mesh.positions.resize(values.size());
    value_mesh.face_offsets = mesh.face_offsets;
    value_mesh.face_indices = corner_value;

    Channel c;
    c.level = subdivision::build_base_level(value_mesh);
    c.values = std::move(values);
    const Level& vl = c.level;
    const Index nvals = vl.vertex_count, ne = vl.edge_count();

    // value edges inherit the sharpness of the mesh edge in the same face slot; seams and boundaries are infinite
    c.sharp.edge.assign(ne, 0.0f);
    for (std::size_t slot = 0; slot < corners; ++slot)
        c.sharp.edge[vl.face_edges[slot]] = mesh_sharp.edge[mesh_level.face_edges[slot]];
    std::vector<std::uint32_t> edge_faces(ne, 0), edge_forward(ne, 0);
    for (Index f = 0; f < vl.face_count(); ++f)
        for (Index slot = vl.face_offsets[f]; slot < vl.face_offsets[f + 1]; ++slot) {
            ++edge_faces[vl.face_edges[slot]];
            if (vl.edge_verts[2 * vl.face_edges[slot]] == vl.face_verts[slot]) ++edge_forward[vl.face_edges[slot]];
        }
    std::vector<std::uint8_t> non_manifold_edge(ne, 0);
    for (Index e = 0; e < ne; ++e) {
        non_manifold_edge[e] = edge_faces[e] > 2 || (edge_faces[e] == 2 && edge_forward[e] != 1) ||
                               (!vl.non_manifold_edge.empty() && vl.non_manifold_edge[e]);
        if (edge_faces[e] < 2 || non_manifold_edge[e]) c.sharp.edge[e] = kInfiniteSharpness;
    }
    c.sharp.vertex.resize(nvals);
    for (Index v = 0; v < nvals; ++v) c.sharp.vertex[v] = mesh_sharp.vertex[vertex_of[v]];
    c.sharp.hole = mesh_sharp.hole;
    if (mode == UvInterpolation::All || mode == UvInterpolation::Boundaries) {
        sharpen_linear_uvs(c, mode);
        if (mode == UvInterpolation::All) return c;
    }

    // topology of each value, and of each mesh vertex's set of values
    std::vector<std::uint32_t> vfaces(nvals, 0), vedges(nvals, 0), vboundary(nvals, 0), vnm(nvals, 0);
    for (Index v : vl.face_verts) ++vfaces[v];
    for (Index e = 0; e < ne; ++e)
        for (int k = 0; k < 2; ++k) {
            const Index v = vl.edge_verts[2 * e + k];
            ++vedges[v];
            vboundary[v] += edge_faces[e] < 2;
            vnm[v] += non_manifold_edge[e];
        }
    const std::vector<std::uint32_t> fans = count_fans(vl, edge_faces, non_manifold_edge);
    std::vector<std::uint32_t> values_at(mesh_level.vertex_count, 0);
    for (Index v = 0; v < nvals; ++v) ++values_at[vertex_of[v]];
    std::vector<std::uint8_t> mesh_boundary(mesh_level.vertex_count, 0);
    {
        const auto mesh_faces = edge_face_counts(mesh_level);
        for (Index e = 0; e < mesh_level.edge_count(); ++e)
            if (mesh_faces[e] < 2)
                mesh_boundary[mesh_level.edge_verts[2 * e]] = mesh_boundary[mesh_level.edge_verts[2 * e + 1]] = 1;
    }
    auto split = [&](Index v) {  // the value's region is not one fan at the vertex ("disjoint" span)
        const bool fan =
            vnm[v] == 0 && fans[v] == 1 &&
            ((vboundary[v] == 0 && vfaces[v] == vedges[v]) || (vboundary[v] == 2 && vfaces[v] + 1 == vedges[v]));
        return !fan;
    };
    const bool plus = mode == UvInterpolation::CornersPlus1 || mode == UvInterpolation::CornersPlus2;
    const std::vector<std::uint8_t> mesh_non_manifold = non_manifold_vertices(mesh_level);
    // per mesh vertex: whether any of its values is split, or a one-face corner
    std::vector<std::uint8_t> any_split(mesh_level.vertex_count, 0), any_corner(mesh_level.vertex_count, 0);
    for (Index v = 0; v < nvals; ++v) {
        any_split[vertex_of[v]] |= split(v);
        any_corner[vertex_of[v]] |= vfaces[v] == 1;
    }
    for (Index v = 0; v < nvals; ++v) {
        const Index mv = vertex_of[v];
        bool sharp = split(v) || (mode != UvInterpolation::None && vfaces[v] == 1);
        if (mesh_non_manifold[mv] && values_at[mv] > 1) sharp = true;  // OpenSubdiv sharpens them all
        if (plus && values_at[mv] > 2) sharp = true;                   // junction
        if (plus && values_at[mv] == 2 && any_split[mv]) sharp = true;
        if (mode == UvInterpolation::CornersPlus2 && values_at[mv] == 2 && any_corner[mv]) sharp = true;
        if (mode == UvInterpolation::CornersPlus2 && values_at[mv] == 1 && !mesh_boundary[mv] && vboundary[v] > 0)
            sharp = true;  // dart: a seam ending inside the region
        if (sharp) c.sharp.vertex[v] = kInfiniteSharpness;
    }
    if (plus)
        add_uv_overrides(c, vertex_of, edge_faces, non_manifold_edge, mesh_sharp, mode, split, values_at, any_corner);
    return c;
}

std::uint64_t saturating_mul(std::uint64_t a, std::uint64_t b) {
    if (a != 0 && b > std::numeric_limits<std::uint64_t>::max() / a) return std::numeric_limits<std::uint64_t>::max();
    return a * b;
}

}  // namespace

Status validate_for_subdivision(const PolygonMesh& mesh) {
    ValidateOptions options;
    options.allow_repeated_vertices = true;
    return validate(mesh, options);
}

std::uint64_t predicted_face_count(const PolygonMesh& mesh, SubdivisionScheme scheme, int levels) {
    if (levels <= 0) return mesh.face_count();
    std::uint64_t faces = scheme == SubdivisionScheme::CatmullClark ? mesh.face_indices.size() : 4 * mesh.face_count();
    for (int l = 1; l < levels; ++l) faces = saturating_mul(faces, 4);
    return faces;
}

std::uint64_t predicted_vertex_count(const PolygonMesh& mesh, SubdivisionScheme scheme, int levels) {
    std::uint64_t v = mesh.vertex_count(), e = subdivision::build_base_level(mesh).edge_count(), f = mesh.face_count();
    std::uint64_t corners = mesh.face_indices.size();
    constexpr std::uint64_t kMax = std::numeric_limits<std::uint64_t>::max() / 8;
    for (int l = 0; l < levels; ++l) {
        if (v > kMax || e > kMax || f > kMax || corners > kMax) return std::numeric_limits<std::uint64_t>::max();
        if (scheme == SubdivisionScheme::CatmullClark) {
            const std::uint64_t nv = v + f + e, ne = 2 * e + corners, nf = corners;
            v = nv;
            e = ne;
            f = nf;
            corners = 4 * nf;
        } else {
            const std::uint64_t nv = v + e, ne = 2 * e + 3 * f, nf = 4 * f;
            v = nv;
            e = ne;
            f = nf;
            corners = 3 * nf;
        }
    }
    return v;
}

Result<PolygonMesh> subdivide(const PolygonMesh& mesh, const SubdivisionOptions& options) {
    if (options.levels < 0)
        return make_error(ErrorCode::InvalidArgument, "levels must be >= 0, got " + std::to_string(options.levels));
    if (Status valid = validate_for_subdivision(mesh); !valid) return valid.error();
    const bool loop = options.scheme == SubdivisionScheme::Loop;
    if (loop) {
        for (std::size_t f = 0; f < mesh.face_count(); ++f)
            if (mesh.face_size(f) != 3)
                return element_error(ErrorCode::NotTriangleMesh,
                                     "face " + std::to_string(f) + " has " + std::to_string(mesh.face_size(f)) +
                                         " vertices; Loop subdivision needs triangles",
                                     ElementKind::Face, static_cast<std::int64_t>(f));
    }
    constexpr std::uint64_t kIndexLimit = std::numeric_limits<Index>::max() - 1;
    const auto scheme = options.scheme;
    if (options.levels > 0 && (predicted_face_count(mesh, scheme, options.levels) > kIndexLimit / 4 ||
                               predicted_vertex_count(mesh, scheme, options.levels) > kIndexLimit))
        return make_error(ErrorCode::BudgetExceeded, "the refined mesh would exceed 2^32 indices");

    const BoundaryInterpolation boundary =
        options.use_mesh_boundary_tag && mesh.tags.boundary ? *mesh.tags.boundary : options.boundary;

    Level level = subdivision::build_base_level(mesh);
    auto base = base_sharpness(mesh, level, boundary, options.use_mesh_tags);
    if (!base) return base.error();
    Sharpness sharp = std::move(base).value();

    const int extra = options.limit_surface ? limit_extra_levels(mesh, options) : 0;
    const int total = options.levels + extra;
    if (extra > 0 && (predicted_face_count(mesh, scheme, total) > kIndexLimit / 4 ||
                      predicted_vertex_count(mesh, scheme, total) > kIndexLimit))
        return make_error(ErrorCode::BudgetExceeded, "evaluating the limit surface would exceed 2^32 indices");

    // Texture coordinates: refined alongside, to the requested level.
    std::optional<Channel> uv;
    if (mesh.has_uvs()) uv = base_uv_channel(mesh, level, sharp, options.uv_interpolation);
    for (int l = 0; uv && l < options.levels; ++l) {
        refine_channel(*uv, options, l == 0, loop, l + 1 < options.levels);
        sharpen_linear_uvs(*uv, options.uv_interpolation);
    }

    const bool threaded = use_threads(options);
    int level_done = 0;
    std::vector<Vec3> src = mesh.positions, dst;
    Level output_level;  // the requested level, when refinement continues past it for the limit
    Sharpness output_sharp;
    const auto cancelled = [&] {
        return make_error(ErrorCode::Cancelled, "subdivision cancelled at level " + std::to_string(level_done) +
                                                    " of " + std::to_string(total) + " (deadline or shutdown)");
    };
    for (int l = 0; l < total; ++l, ++level_done) {
        if (options.cancel.requested()) return cancelled();
        const bool last = l + 1 == total;
        const Neighbourhood n = neighbourhood(level, sharp, options.crease_method);
        Level child = loop ? subdivision::refine_triangles(level, !last || options.limit_surface, threaded)
                           : subdivision::refine_quads(level, !last || options.limit_surface, threaded);
        if (options.cancel.requested()) return cancelled();
        dst.clear();  // every point is written below: growing need not copy the stale ones
        dst.resize(child.vertex_count);
        const LevelInput in{level,
                            sharp,
                            options.crease_method,
                            l == 0 ? options.triangle_rule : TriangleRule::Catmark,
                            options.loop_weights,
                            threaded};
        if (loop)
            interpolate_loop(in, n, src.data(), dst.data());
        else
            interpolate_catmark(in, n, src.data(), dst.data());
        if (options.cancel.requested()) return cancelled();
        Sharpness child_sharp =
            refine_sharpness(level, child, sharp, n, options.crease_method, loop, last && !options.limit_surface);
        if (l + 1 == options.levels && extra > 0) {
            output_level = child;
            output_sharp = child_sharp;
        }
        level = std::move(child);
        sharp = std::move(child_sharp);
        src.swap(dst);
    }
    if (options.levels == 0 && extra > 0) {
        output_level = subdivision::build_base_level(mesh);
        output_sharp = base_sharpness(mesh, output_level, boundary, options.use_mesh_tags).value();
    }

    PolygonMesh out;
    if (options.limit_surface) {
        // vertices of the requested level are the first ones of every finer level (children of vertices first)
        const Index count = extra > 0 ? output_level.vertex_count : level.vertex_count;
        out.positions.resize(count);
        out.normals.resize(count);
        subdivision::evaluate_limit(level, sharp.edge, sharp.vertex, loop, options.loop_weights == LoopWeights::Warren,
                                    src.data(), count, out.positions.data(), out.normals.data());
        if (extra > 0) {
            level = std::move(output_level);
            sharp = std::move(output_sharp);
        }
    } else {
        out.positions = std::move(src);
    }
    if (uv) {
        out.uvs.reserve(uv->values.size());
        for (const Vec3& value : uv->values) out.uvs.push_back({value.x, value.y});
    }
    if (sharp.hole.empty()) {
        out.face_offsets = std::move(level.face_offsets);
        out.face_indices = std::move(level.face_verts);
        if (uv) out.uv_indices = std::move(uv->level.face_verts);
    } else {
        for (Index f = 0; f < level.face_count(); ++f) {
            if (sharp.hole[f]) continue;
            const Index begin = level.face_offsets[f], size = level.face_offsets[f + 1] - begin;
            out.add_face({level.face_verts.data() + begin, size});
            if (uv)
                out.uv_indices.insert(out.uv_indices.end(), uv->level.face_verts.begin() + begin,
                                      uv->level.face_verts.begin() + begin + size);
        }
    }
    return out;
}

int limit_extra_levels(const PolygonMesh& mesh, const SubdivisionOptions& options) {
    if (!options.limit_surface) return 0;
    // sharpness decays by at least 1 per level with either crease method
    float max_semi = 0.0f;
    if (options.use_mesh_tags) {
        for (const Crease& c : mesh.tags.creases)
            if (is_semi_sharp(static_cast<float>(c.sharpness)))
                max_semi = std::max(max_semi, static_cast<float>(c.sharpness));
        for (const Corner& c : mesh.tags.corners)
            if (is_semi_sharp(static_cast<float>(c.sharpness)))
                max_semi = std::max(max_semi, static_cast<float>(c.sharpness));
    }
    const int decay = std::max(0, static_cast<int>(std::ceil(max_semi)) - options.levels);
    const bool needs_quads =
        options.scheme == SubdivisionScheme::CatmullClark && options.levels == 0 && !mesh.is_triangle_mesh() && [&] {
            for (std::size_t f = 0; f < mesh.face_count(); ++f)
                if (mesh.face_size(f) != 4) return true;
            return false;
        }();
    return std::max(decay, needs_quads ? 1 : 0);
}

}  // namespace surfaced
