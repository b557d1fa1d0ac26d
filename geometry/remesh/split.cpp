// The split pass (Remesher::split_long_edges): edges longer than 4/3 of the working target are split at their
// midpoints, longest first; Remesher::split is the halfedge operation it (and degenerate.cpp) uses.
#include "geometry/remesh/remesher.h"

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

namespace surfaced::remesh_detail {

//! Splits edge e at p; the new vertex is returned. Both faces (where present) become two.
Index Remesher::split(Index e, const Vec3& p) {
    const Index h0 = 2 * e, o0 = 2 * e + 1;
    const Index b = h_to_[h0];
    const Index v = new_vertex(p, e_constrained_[e] ? kCurve : kFree);
    v_ref_.push_back(unit(v_ref_[h_to_[h0]] + v_ref_[h_to_[o0]]));
    const Index e1 = new_edge(v, b);
    const Index h1 = 2 * e1, o1 = 2 * e1 + 1;  // v -> b, b -> v
    e_constrained_[e1] = e_constrained_[e];
    h_to_[h0] = v;  // h0: a -> v; o0 becomes v -> a
    if (!boundary_h(h0)) {
        const Index f0 = h_face_[h0], n0 = h_next_[h0], p0 = h_next_[n0];  // b -> c, c -> a
        const Index c = h_to_[n0];
        const Index e2 = new_edge(v, c);
        const Index x = 2 * e2, y = 2 * e2 + 1;  // v -> c, c -> v
        const Index f2 = new_face();
        link(h0, x), link(x, p0), link(p0, h0);
        h_face_[x] = f0;
        f_h_[f0] = h0;
        link(h1, n0), link(n0, y), link(y, h1);
        h_face_[h1] = h_face_[n0] = h_face_[y] = f2;
        f_h_[f2] = h1;
    } else {
        const Index hn = h_next_[h0];
        link(h0, h1), link(h1, hn);
    }
    if (!boundary_h(o0)) {
        const Index f1 = h_face_[o0], n1 = h_next_[o0], p1 = h_next_[n1];  // a -> d, d -> b
        const Index d = h_to_[n1];
        const Index e3 = new_edge(v, d);
        const Index s = 2 * e3, t = 2 * e3 + 1;  // v -> d, d -> v
        const Index f3 = new_face();
        link(o0, n1), link(n1, t), link(t, o0);
        h_face_[t] = f1;
        f_h_[f1] = o0;
        link(o1, s), link(s, p1), link(p1, o1);
        h_face_[o1] = h_face_[s] = h_face_[p1] = f3;
        f_h_[f3] = o1;
    } else {
        const Index op = h_prev_[o0];
        link(op, o1), link(o1, o0);
    }
    v_out_[v] = h1;
    if (v_out_[b] == o0) v_out_[b] = o1;
    adjust_out(v);
    return v;
}

//! Longest edge first (Rivara's longest-edge bisection): splitting in index order can keep making thinner
//! triangles on coarse input (a cube's two triangles per side split towards L << side) and never finish.
Status Remesher::split_long_edges(double high, const RemeshOptions& options) {
    const double high2 = high * high;
    std::vector<std::pair<double, Index>> heap;
    for (Index e = 0; e < e_dead_.size(); ++e)
        if (!e_dead_[e] && length2(e) > high2) heap.push_back({length2(e), e});
    std::make_heap(heap.begin(), heap.end());
    std::size_t done = 0;
    while (!heap.empty()) {
        std::pop_heap(heap.begin(), heap.end());
        const auto [stored, e] = heap.back();
        heap.pop_back();
        if (++done % kPollEvery == 0 && options.cancel.requested()) return cancelled();
        const double l2 = length2(e);
        if (l2 <= high2) continue;
        if (l2 < stored) {  // split since it was pushed: its current length is queued again
            heap.push_back({l2, e});
            std::push_heap(heap.begin(), heap.end());
            continue;
        }
        const Index v = split(e, (pos_[h_to_[2 * e]] + pos_[h_to_[2 * e + 1]]) * 0.5);
        if (options.max_faces != 0 && live_faces_ > options.max_faces)
            return make_error(
                ErrorCode::BudgetExceeded,
                "remeshing needs more than " + std::to_string(options.max_faces) + " faces at this edge length");
        for_out(v, [&](Index h) {
            const Index f = h >> 1;
            if (length2(f) > high2) {
                heap.push_back({length2(f), f});
                std::push_heap(heap.begin(), heap.end());
            }
        });
    }
    return Ok{};
}

}  // namespace surfaced::remesh_detail
