// Child points of one level. Three scatter passes (face points, edge points, vertex points) with the smooth rules;
// then the points that sharpness governs are overwritten: crease and corner vertex rules, creased edges, and
// OpenSubdiv's fractional blend where a semi-sharp feature decays to smooth between this level and the next.
#include "geometry/subdivision/interpolate.h"

#include <memory>
#include <vector>

#include "geometry/core/two_parts.h"
#include "geometry/subdivision/parallel.h"
#include "geometry/subdivision/rules.h"

namespace surfaced::subdivision {

namespace {

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
            return kCreaseVertexWeight * src[v] + kCreaseNeighbourWeight * sum;
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
// vertices) on entry. `smooth_weights(e)` gives the smooth rule's {end vertex, face contribution} weights of edge e.
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

// The scatter pass of both schemes, into the caller's accumulators, which must be all zero on entry: vertex_acc[v]
// gets the sum of v's edge neighbours, and face_pass(f_begin, f_end, vacc, eacc) adds each face's terms to its
// vertices and edges (Catmull-Clark: its face point to both; Loop: the opposite vertex to each edge). Large levels
// are cut into two fixed parts whose partial sums are added in a fixed order, so the result does not depend on the
// thread count.
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
    if (nf < kSplitMinimum) {
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

}  // namespace

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
            const auto w = catmark_smooth_vertex(static_cast<int>(n.vertex_faces[v]));
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
        return {kCatmarkEdgeWeight, kCatmarkEdgeWeight};
    };
    for_range(ne, in.threaded,
              [&](Index b, Index e) { finish_edge_points(p, in.sharp, n, in.method, src, edge_pts, weights, b, e); });
    for_range(nv, in.threaded,
              [&](Index b, Index e) { apply_vertex_rules(p, in.sharp, n, in.method, src, dst, b, e); });
}

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
            const auto w =
                in.loop_weights == LoopWeights::Warren ? loop_warren_vertex(valence) : loop_smooth_vertex(valence);
            dst[v] = w.vertex * src[v] + w.edge * dst[v];
        }
    });
    struct W {
        double vertex, face;
    };
    auto weights = [](Index) -> W { return {kLoopEdgeEndWeight, kLoopEdgeOppositeWeight}; };
    for_range(ne, in.threaded,
              [&](Index b, Index e) { finish_edge_points(p, in.sharp, n, in.method, src, edge_pts, weights, b, e); });
    for_range(nv, in.threaded,
              [&](Index b, Index e) { apply_vertex_rules(p, in.sharp, n, in.method, src, dst, b, e); });
}

}  // namespace surfaced::subdivision
