// Remesher::build and Remesher::output: the halfedge mesh made from the input triangles (refusing non-manifold
// edges and vertices, with the error naming the element) and the compacted triangle mesh written back at the end.
#include "geometry/remesh/remesher.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

namespace surfaced::remesh_detail {

//! Halfedges from a triangle mesh; refuses edges with more than two faces or traversed twice in one direction, and
//! vertices where several fans of faces meet.
Status Remesher::build(const PolygonMesh& mesh) {
    const std::size_t nv = mesh.vertex_count(), nf = mesh.face_count();
    pos_ = mesh.positions;
    v_out_.assign(nv, kNone);
    v_kind_.assign(nv, kFree);
    v_dead_.assign(nv, 0);
    h_to_.reserve(6 * nf);
    std::unordered_map<std::uint64_t, Index> edge_of;
    edge_of.reserve(3 * nf);
    std::vector<Index> faces_at(nv, 0);
    for (Index f = 0; f < nf; ++f) {
        auto t = mesh.face(f);
        const Index fh = new_face();
        std::array<Index, 3> hs{};
        for (int j = 0; j < 3; ++j) {
            const Index u = t[j], w = t[(j + 1) % 3];
            ++faces_at[u];
            const std::uint64_t key = (std::uint64_t{std::min(u, w)} << 32) | std::max(u, w);
            auto [it, inserted] = edge_of.try_emplace(key, kNone);
            if (inserted) it->second = new_edge(u, w);
            const Index e = it->second;
            const Index h = h_to_[2 * e] == w ? 2 * e : 2 * e + 1;
            if (h_face_[h] != kNone) {
                const std::string edge = "(" + std::to_string(u) + ", " + std::to_string(w) + ")";
                return element_error(
                    ErrorCode::NonManifold,
                    h_face_[h ^ 1] == kNone
                        ? "edge " + edge + " is traversed in the same direction by face " + std::to_string(f) +
                              " and another face (inconsistent orientation or a duplicate face)"
                        : "edge " + edge + " is shared by more than two faces (face " + std::to_string(f) + " is one)",
                    ElementKind::Face, f);
            }
            h_face_[h] = fh;
            hs[j] = h;
        }
        for (int j = 0; j < 3; ++j) link(hs[j], hs[(j + 1) % 3]);
        f_h_[fh] = hs[0];
    }
    // boundary halfedges: linked to the boundary halfedge leaving their end vertex, which must be unique
    std::vector<Index> boundary_out(nv, kNone);
    for (Index h = 0; h < h_to_.size(); ++h) {
        const Index from = h_to_[h ^ 1];
        if (v_out_[from] == kNone) v_out_[from] = h;
        if (h_face_[h] != kNone) continue;
        if (boundary_out[from] != kNone)
            return element_error(
                ErrorCode::NonManifold,
                "vertex " + std::to_string(from) + " joins several fans of faces (a non-manifold vertex)",
                ElementKind::Vertex, from);
        boundary_out[from] = h;
    }
    for (Index h = 0; h < h_to_.size(); ++h)
        if (h_face_[h] == kNone) link(h, boundary_out[h_to_[h]]);
    for (Index v = 0; v < nv; ++v) {
        if (boundary_out[v] != kNone) v_out_[v] = boundary_out[v];
        if (v_out_[v] == kNone) {
            v_dead_[v] = 1;  // in no face: not part of the surface, dropped from the output
            continue;
        }
        // one fan: walking around v meets every face that uses it
        Index count = 0, guard = 0;
        const Index h0 = v_out_[v];
        Index h = h0;
        do {
            if (h_face_[h] != kNone) ++count;
            h = h_next_[h ^ 1];
        } while (h != h0 && ++guard <= faces_at[v] + 1);
        if (count != faces_at[v])
            return element_error(ErrorCode::NonManifold,
                                 "vertex " + std::to_string(v) + " joins several fans of faces (a non-manifold vertex)",
                                 ElementKind::Vertex, v);
    }
    live_faces_ = nf;
    return Ok{};
}

PolygonMesh Remesher::output() const {
    PolygonMesh out;
    std::vector<Index> map(pos_.size(), kNone);
    for (Index v = 0; v < pos_.size(); ++v) {
        if (v_dead_[v]) continue;
        map[v] = static_cast<Index>(out.positions.size());
        out.positions.push_back(pos_[v]);
    }
    out.face_indices.reserve(3 * live_faces_);
    out.face_offsets.reserve(live_faces_ + 1);
    for (Index f = 0; f < f_h_.size(); ++f) {
        if (f_dead_[f]) continue;
        const Index h = f_h_[f];
        out.add_face({map[h_to_[h]], map[h_to_[h_next_[h]]], map[h_to_[h_next_[h_next_[h]]]]});
    }
    return out;
}

}  // namespace surfaced::remesh_detail
