// Face-varying refinement: the base UV channel with OpenSubdiv's value tags, and its refinement level by level.
#include "geometry/subdivision/face_varying.h"

#include <algorithm>
#include <cstdint>
#include <unordered_map>
#include <utility>

#include "geometry/subdivision/interpolate.h"
#include "geometry/subdivision/rules.h"

namespace surfaced::subdivision {

namespace {

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
                dst[v] = (crease * kCreaseNeighbourWeight) * ends + (crease * kCreaseVertexWeight + corner) * src[v];
                keep = false;
            }
        }
        if (!keep) continue;
        for (Index& e : o.ends) e = interior + 2 * e + edge_child_at(p, e, v, false);
        kept.push_back(o);
    }
    c.overrides = std::move(kept);
}

// Refines a channel by one level (the same topology step and rules as positions).
void refine_channel(Channel& c, const SubdivisionOptions& options, bool first_level, bool loop, bool with_edges,
                    bool threaded) {
    const Neighbourhood n = neighbourhood(c.level, c.sharp, options.crease_method);
    Level child = loop ? refine_triangles(c.level, with_edges, threaded) : refine_quads(c.level, with_edges, threaded);
    std::vector<Vec3> dst(child.vertex_count);
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

// Vertices OpenSubdiv tags non-manifold: not one fan of faces joined by manifold edges (as base_sharpness finds them).
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

// The channel's value mesh and values, not yet sharpened: a value per distinct (mesh vertex, UV index) pair, and a
// separate one per corner that duplicate_value_runs gives a sibling of its own. `vertex_of`: each value's mesh vertex.
Channel value_channel(const PolygonMesh& mesh, const Level& mesh_level, std::vector<Index>& vertex_of) {
    const std::size_t corners = mesh.face_indices.size();
    std::vector<Index> corner_value(corners);
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
    c.level = build_base_level(value_mesh);
    c.values = std::move(values);
    return c;
}

// The base UV channel, sharpened as OpenSubdiv's face-varying channel is (Vtr::FVarLevel): a value on a seam keeps
// the mesh's sharpness and is smoothed as a boundary of its UV region, except where the mode makes it a corner:
// regions with one face at the vertex (all modes but "none"), junctions of three or more regions (corners-plus1/2),
// darts (corners-plus2), values whose region is split at the vertex (always).
Channel base_uv_channel(const PolygonMesh& mesh, const Level& mesh_level, const Sharpness& mesh_sharp,
                        UvInterpolation mode) {
    const std::size_t corners = mesh.face_indices.size();
    std::vector<Index> vertex_of;
    Channel c = value_channel(mesh, mesh_level, vertex_of);
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

}  // namespace

Channel refine_uvs(const PolygonMesh& mesh, const Level& mesh_level, const Sharpness& mesh_sharp,
                   const SubdivisionOptions& options, bool threaded) {
    const bool loop = options.scheme == SubdivisionScheme::Loop;
    Channel c = base_uv_channel(mesh, mesh_level, mesh_sharp, options.uv_interpolation);
    for (int l = 0; l < options.levels; ++l) {
        refine_channel(c, options, l == 0, loop, l + 1 < options.levels, threaded);
        sharpen_linear_uvs(c, options.uv_interpolation);
    }
    return c;
}

}  // namespace surfaced::subdivision
