#include "geometry/reconstruct/extract_surface.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <iterator>
#include <vector>

#include "geometry/core/two_parts.h"
#include "geometry/implicit/cell_faces.h"
#include "geometry/reconstruct/key_map.h"

namespace surfaced::reconstruct {
namespace {

constexpr std::uint64_t kStepJ = std::uint64_t{1} << 21;
constexpr std::uint64_t kStepK = std::uint64_t{1} << 42;
//! Cells between two polls of the cancel flag.
constexpr std::size_t kPollEvery = 4096;
//! Fewer cells than this are meshed on one thread (a second would cost more than it saves).
constexpr std::size_t kThreadedCells = 1 << 15;

// ---- cell-local numbering (cell_faces.h) ----------------------------------------------------------------------------
using cell_faces::bit;
using cell_faces::edge_start_corner;
using cell_faces::face_segments;
using cell_faces::Segment;

//! Orients a segment on face (a, s) so that, seen from outside the cell, the inside of the face is on its right;
//! then the segments of a cell chain into loops that turn counter-clockwise seen from outside the surface. Computed
//! on the cell's corners and edge midpoints in doubled integer coordinates, so it is exact.
Segment orient(const Segment& seg, const double v[8], int a, int s) {
    auto midpoint = [](int e, int m[3]) {
        const int c0 = edge_start_corner(e);
        for (int k = 0; k < 3; ++k) m[k] = 2 * bit(c0, k) + (k == e / 4 ? 1 : 0);
    };
    int m0[3], m1[3], p[3];
    midpoint(seg.e0, m0);
    midpoint(seg.e1, m1);
    const int c0 = edge_start_corner(seg.e0);
    const int in = v[c0] < 0 ? c0 : c0 | (1 << (seg.e0 / 4));  // the inside end of e0
    for (int k = 0; k < 3; ++k) p[k] = 2 * bit(in, k);
    const int d[3] = {m1[0] - m0[0], m1[1] - m0[1], m1[2] - m0[2]};
    const int q[3] = {p[0] - m0[0], p[1] - m0[1], p[2] - m0[2]};
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    const int normal_component = d[b] * q[c] - d[c] * q[b];  // (d x q)[a]
    const int side = (2 * s - 1) * normal_component;
    return side < 0 ? seg : Segment{seg.e1, seg.e0};
}

//! A coarse leaf: a support cell of some level without support children there, where chi is trilinear.
struct Leaf {
    double v[8];          //!< chi - iso at its corners
    std::int64_t lo[3];   //!< its origin in finest-grid units
    double inverse_size;  //!< 1 / its side in finest-grid units
    double margin;        //!< rounding margin on interpolated values
};

//! One part's meshing state: its node values off the finest support, its crossing vertices and its faces.
struct MeshPart {
    GrowingKeyMap memo;  //!< nodes off the finest level's support -> memo_values
    std::vector<double> memo_values;
    GrowingKeyMap edges;  //!< crossed grid edges (doubled midpoint coordinates) -> edge_vertices, edge_keys
    std::vector<Index> edge_vertices;
    std::vector<std::uint64_t> edge_keys;
    std::vector<Vec3> positions;
    PolygonMesh out;
    std::size_t surface = 0;  //!< cells the surface crosses
    bool broken = false;
    bool cancelled = false;

    std::size_t memory_bytes() const {
        return memo.memory_bytes() + memo_values.capacity() * 8 + edges.memory_bytes() + edge_vertices.capacity() * 4 +
               edge_keys.capacity() * 8;
    }
};

//! The mesh of two parts: the first's vertices and faces, then the second's, its vertices on edges the first
//! crossed too replaced by the first's.
PolygonMesh merge(MeshPart& first, MeshPart& second) {
    PolygonMesh out = std::move(first.out);
    out.positions = std::move(first.positions);
    constexpr Index kNew = ~Index{0};
    std::vector<Index> remap(second.positions.size(), kNew);
    for (std::size_t e = 0; e < second.edge_keys.size(); ++e) {
        const std::uint32_t shared = first.edges.find(second.edge_keys[e]);
        if (shared != GrowingKeyMap::kNone) remap[second.edge_vertices[e]] = first.edge_vertices[shared];
    }
    for (std::size_t v = 0; v < remap.size(); ++v)
        if (remap[v] == kNew) {
            remap[v] = static_cast<Index>(out.positions.size());
            out.positions.push_back(second.positions[v]);
        }
    out.face_offsets.reserve(out.face_offsets.size() + second.out.face_count());
    out.face_indices.reserve(out.face_indices.size() + second.out.face_indices.size());
    for (const Index v : second.out.face_indices) out.face_indices.push_back(remap[v]);
    const Index base = out.face_offsets.back();
    for (std::size_t f = 1; f < second.out.face_offsets.size(); ++f)
        out.face_offsets.push_back(base + second.out.face_offsets[f]);
    return out;
}

class Extractor {
public:
    Extractor(const PoissonOctree& tree, const IndicatorValues& chi, double iso, const Cancel& cancel)
        : tree_(tree),
          chi_(chi),
          finest_(tree.levels.back()),
          finest_values_(chi.values.back()),
          iso_(iso),
          cancel_(cancel),
          depth_(tree.max_depth),
          n_(std::int64_t{1} << tree.max_depth) {}

    //! Steps 1 and 2 below, concurrently when `threaded`, each collecting its own cells; then their union, sorted.
    Status find_cells(bool threaded) {
        KeyCollector found[2];
        Status status[2] = {Ok{}, Ok{}};
        run_two_parts(threaded,
                      [&](int part) { status[part] = part == 0 ? scan_finest(found[0]) : scan_leaves(found[1]); });
        for (const Status& s : status)
            if (!s) return s;
        collect_bytes_ = found[0].memory_bytes() + found[1].memory_bytes();
        const std::vector<std::uint64_t> a = found[0].take(), b = found[1].take();
        cells_.reserve(a.size() + b.size());
        std::set_union(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(cells_));
        return Ok{};
    }

    //! Meshes the cells found, as two parts (the first and second half of the cells in key order), concurrently
    //! when `threaded`; the second part's vertices on edges the first part also crossed are merged into the first's.
    //! The cut depends on the cells alone, so the mesh is the same either way.
    Result<PolygonMesh> mesh(ExtractionStats* stats, bool threaded) {
        const std::size_t collect_bytes = collect_bytes_;
        const std::vector<std::uint64_t> cells = std::move(cells_);
        const std::size_t middle = cells.size() / 2;
        MeshPart parts[2];
        run_two_parts(threaded && cells.size() >= kThreadedCells, [&](int p) {
            MeshPart& part = parts[p];
            const std::size_t begin = p == 0 ? 0 : middle, end = p == 0 ? middle : cells.size();
            part.out.face_offsets.reserve(2 * (end - begin) + 1);
            part.out.face_indices.reserve(6 * (end - begin));
            // the corners of cells taken in key order have increasing keys, corner by corner: found by cursors
            std::vector<SortedCursor> corners(8, SortedCursor(finest_.support_vertices.keys));
            for (std::size_t n = begin; n < end; ++n) {
                if ((n - begin) % kPollEvery == 0 && cancel_.requested()) {
                    part.cancelled = true;
                    return;
                }
                part.surface += mesh_cell(cells[n], corners, part) ? 1 : 0;
            }
        });
        if (parts[0].cancelled || parts[1].cancelled) return cancelled();
        if (parts[0].broken || parts[1].broken)
            return make_error(ErrorCode::Internal, "poisson: a marching-cubes loop did not close");
        if (stats) {
            stats->candidate_cells = cells.size();
            stats->surface_cells = parts[0].surface + parts[1].surface;
            stats->interpolated_nodes = parts[0].memo.size() + parts[1].memo.size();
            std::size_t mesh_bytes = cells.capacity() * 8;
            for (const MeshPart& part : parts) mesh_bytes += part.memory_bytes();
            stats->bytes = std::max(collect_bytes, mesh_bytes);
        }
        return merge(parts[0], parts[1]);
    }

private:
    static GeoError cancelled() { return make_error(ErrorCode::Cancelled, "poisson: cancelled while meshing"); }

    bool on_boundary(std::int64_t i, std::int64_t j, std::int64_t k) const {
        return i == 0 || j == 0 || k == 0 || i == n_ || j == n_ || k == n_;
    }

    //! chi - iso at a finest-grid node as meshed: nodes on the cube's faces count as outside (>= 0).
    double adjust(double value, std::int64_t i, std::int64_t j, std::int64_t k) const {
        return on_boundary(i, j, k) ? std::max(value, 0.0) : value;
    }

    // ---- finding the cells ------------------------------------------------------------------------------------

    void add_edge_cells(int axis, std::int64_t i, std::int64_t j, std::int64_t k, KeyCollector& found) const {
        const int b = (axis + 1) % 3, c = (axis + 2) % 3;
        for (int ob = 0; ob < 2; ++ob)
            for (int oc = 0; oc < 2; ++oc) {
                std::int64_t cell[3] = {i, j, k};
                cell[b] -= ob;
                cell[c] -= oc;
                if (cell[b] < 0 || cell[c] < 0 || cell[b] >= n_ || cell[c] >= n_) continue;
                found.insert(pack_key(static_cast<std::uint32_t>(cell[0]), static_cast<std::uint32_t>(cell[1]),
                                      static_cast<std::uint32_t>(cell[2])));
            }
    }

    //! 1. Edges between neighbouring support vertices of the finest level whose ends differ in sign. The keys are
    //! sorted by (k, j, i), so each neighbour is found by a pointer that only moves forward.
    Status scan_finest(KeyCollector& found) const {
        const std::vector<std::uint64_t>& keys = finest_.support_vertices.keys;
        const std::size_t count = keys.size();
        auto value = [&](std::size_t u) {
            const std::uint64_t key = keys[u];
            return adjust(finest_values_[u] - iso_, key_i(key), key_j(key), key_k(key));
        };
        std::size_t py = 0, pz = 0;
        for (std::size_t u = 0; u < count; ++u) {
            if (u % (16 * kPollEvery) == 0 && cancel_.requested()) return cancelled();
            const std::uint64_t key = keys[u];
            const bool inside = value(u) < 0;
            const std::int64_t i = key_i(key), j = key_j(key), k = key_k(key);
            if (u + 1 < count && keys[u + 1] == key + 1 && (value(u + 1) < 0) != inside)
                add_edge_cells(0, i, j, k, found);
            while (py < count && keys[py] < key + kStepJ) ++py;
            if (py < count && keys[py] == key + kStepJ && (value(py) < 0) != inside) add_edge_cells(1, i, j, k, found);
            while (pz < count && keys[pz] < key + kStepK) ++pz;
            if (pz < count && keys[pz] == key + kStepK && (value(pz) < 0) != inside) add_edge_cells(2, i, j, k, found);
        }
        return Ok{};
    }

    //! 2. The finest cells inside non-support children of coarser leaves whose sign may change.
    Status scan_leaves(KeyCollector& found) const {
        for (std::size_t li = 0; li + 1 < tree_.levels.size(); ++li) {
            const OctreeLevel& level = tree_.levels[li];
            const OctreeLevel& next = tree_.levels[li + 1];
            const std::vector<double>& values = chi_.values[li];
            const int shift = depth_ - level.depth;
            const std::int64_t level_n = std::int64_t{1} << level.depth;
            // children (2 key + corner) and corners (key + corner) of cells in key order have increasing keys,
            // corner by corner: found by cursors
            std::vector<SortedCursor> children(8, SortedCursor(next.support_cells.keys));
            std::vector<SortedCursor> corners(8, SortedCursor(level.support_vertices.keys));
            for (std::size_t n = 0; n < level.support_cells.size(); ++n) {
                if (n % kPollEvery == 0 && cancel_.requested()) return cancelled();
                const std::uint64_t key = level.support_cells.keys[n];
                const std::uint32_t i = key_i(key), j = key_j(key), k = key_k(key);
                int missing = 0;  // children that are not support cells of the next level
                for (int c = 0; c < 8; ++c)
                    if (children[static_cast<std::size_t>(c)].seek(
                            pack_key(2 * i + bit(c, 0), 2 * j + bit(c, 1), 2 * k + bit(c, 2))) == SortedCursor::kNone)
                        missing |= 1 << c;
                if (missing == 0) continue;
                Leaf leaf;
                double low = 0, high = 0, magnitude = std::fabs(iso_);
                for (int c = 0; c < 8; ++c) {
                    const std::uint32_t v = corners[static_cast<std::size_t>(c)].seek(
                        pack_key(i + bit(c, 0), j + bit(c, 1), k + bit(c, 2)));
                    assert(v != SortedCursor::kNone);
                    leaf.v[c] = values[v] - iso_;
                    magnitude = std::max(magnitude, std::fabs(values[v]));
                    low = c == 0 ? leaf.v[c] : std::min(low, leaf.v[c]);
                    high = c == 0 ? leaf.v[c] : std::max(high, leaf.v[c]);
                }
                leaf.margin = 1e-9 * magnitude;
                const bool touches =
                    i == 0 || j == 0 || k == 0 || i + 1 == level_n || j + 1 == level_n || k + 1 == level_n;
                if (low > leaf.margin || (high < -leaf.margin && !touches)) continue;
                leaf.lo[0] = std::int64_t{i} << shift;
                leaf.lo[1] = std::int64_t{j} << shift;
                leaf.lo[2] = std::int64_t{k} << shift;
                leaf.inverse_size = std::ldexp(1.0, -shift);
                const std::int64_t half = std::int64_t{1} << (shift - 1);
                for (int c = 0; c < 8; ++c)
                    if (missing & (1 << c))
                        descend(leaf,
                                {leaf.lo[0] + bit(c, 0) * half, leaf.lo[1] + bit(c, 1) * half,
                                 leaf.lo[2] + bit(c, 2) * half},
                                half, found);
            }
        }
        return Ok{};
    }

    //! The trilinear interpolant of a leaf at a finest-grid node.
    static double interpolate(const Leaf& leaf, const std::int64_t node[3]) {
        double t[3];
        for (int a = 0; a < 3; ++a) t[a] = static_cast<double>(node[a] - leaf.lo[a]) * leaf.inverse_size;
        double sum = 0;
        for (int c = 0; c < 8; ++c)
            sum += ((c & 1) ? t[0] : 1 - t[0]) * ((c & 2) ? t[1] : 1 - t[1]) * ((c & 4) ? t[2] : 1 - t[2]) * leaf.v[c];
        return sum;
    }

    //! Sub-cube [lo, lo + size) of a leaf: the finest cells in it whose sign may change.
    void descend(const Leaf& leaf, std::array<std::int64_t, 3> lo, std::int64_t size, KeyCollector& found) const {
        double low = 0, high = 0;
        for (int c = 0; c < 8; ++c) {
            const std::int64_t node[3] = {lo[0] + bit(c, 0) * size, lo[1] + bit(c, 1) * size, lo[2] + bit(c, 2) * size};
            const double v = interpolate(leaf, node);
            low = c == 0 ? v : std::min(low, v);
            high = c == 0 ? v : std::max(high, v);
        }
        const bool touches =
            lo[0] == 0 || lo[1] == 0 || lo[2] == 0 || lo[0] + size == n_ || lo[1] + size == n_ || lo[2] + size == n_;
        if (low > leaf.margin || (high < -leaf.margin && !touches)) return;
        if (size == 1) {
            found.insert(pack_key(static_cast<std::uint32_t>(lo[0]), static_cast<std::uint32_t>(lo[1]),
                                  static_cast<std::uint32_t>(lo[2])));
            return;
        }
        const std::int64_t half = size / 2;
        for (int c = 0; c < 8; ++c)
            descend(leaf, {lo[0] + bit(c, 0) * half, lo[1] + bit(c, 1) * half, lo[2] + bit(c, 2) * half}, half, found);
    }

    // ---- node values and crossings -----------------------------------------------------------------------------

    //! chi - iso at a node not stored on the finest level: the interpolant of the finest support cell containing
    //! it (the cell below-left of it on each level, clamped into the cube), as IndicatorField evaluates it.
    double interpolate_node(std::int64_t i, std::int64_t j, std::int64_t k) const {
        auto cell_at = [&](std::size_t l, int& shift) {
            const int depth = tree_.levels[l].depth;
            shift = depth_ - depth;
            const std::int64_t last = (std::int64_t{1} << depth) - 1;
            return pack_key(static_cast<std::uint32_t>(std::min(i >> shift, last)),
                            static_cast<std::uint32_t>(std::min(j >> shift, last)),
                            static_cast<std::uint32_t>(std::min(k >> shift, last)));
        };
        std::size_t l = 0;
        int shift = 0;
        while (l + 1 < tree_.levels.size() &&
               tree_.levels[l + 1].support_cells.find(cell_at(l + 1, shift)) != RowIndex::kNone)
            ++l;
        const std::uint64_t cell = cell_at(l, shift);
        const OctreeLevel& level = tree_.levels[l];
        const double scale = std::ldexp(1.0, -shift);
        const double t[3] = {static_cast<double>(i - (std::int64_t{key_i(cell)} << shift)) * scale,
                             static_cast<double>(j - (std::int64_t{key_j(cell)} << shift)) * scale,
                             static_cast<double>(k - (std::int64_t{key_k(cell)} << shift)) * scale};
        double sum = 0;
        for (std::uint32_t c = 0; c < 8; ++c) {
            const std::uint32_t v = level.support_vertices.find(
                pack_key(key_i(cell) + (c & 1), key_j(cell) + ((c >> 1) & 1), key_k(cell) + (c >> 2)));
            assert(v != RowIndex::kNone);
            sum += ((c & 1) ? t[0] : 1 - t[0]) * ((c & 2) ? t[1] : 1 - t[1]) * ((c & 4) ? t[2] : 1 - t[2]) *
                   chi_.values[l][v];
        }
        return sum - iso_;
    }

    //! The one value of a node that every cell around it uses; `cursor` seeks it among the finest support vertices.
    double node_value(std::int64_t i, std::int64_t j, std::int64_t k, SortedCursor& cursor, MeshPart& part) const {
        const std::uint64_t key =
            pack_key(static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j), static_cast<std::uint32_t>(k));
        const std::uint32_t u = cursor.seek(key);
        if (u != SortedCursor::kNone) return adjust(finest_values_[u] - iso_, i, j, k);
        bool inserted = false;
        const std::uint32_t m = part.memo.insert(key, inserted);
        if (inserted) part.memo_values.push_back(adjust(interpolate_node(i, j, k), i, j, k));
        return part.memo_values[m];
    }

    //! The vertex on cell edge e (corner values v): created by the first cell that asks, at the crossing of the
    //! linear interpolation of its end values.
    Index crossing_vertex(const std::int64_t cell[3], int e, const double v[8], MeshPart& part) const {
        const int axis = e / 4, c0 = edge_start_corner(e);
        std::int64_t node[3];
        for (int a = 0; a < 3; ++a) node[a] = cell[a] + bit(c0, a);
        const std::uint64_t key = pack_key(static_cast<std::uint32_t>(2 * node[0] + (axis == 0)),
                                           static_cast<std::uint32_t>(2 * node[1] + (axis == 1)),
                                           static_cast<std::uint32_t>(2 * node[2] + (axis == 2)));
        bool inserted = false;
        const std::uint32_t id = part.edges.insert(key, inserted);
        if (!inserted) return part.edge_vertices[id];
        const double v0 = v[c0], v1 = v[c0 | (1 << axis)];
        const double t = v0 / (v0 - v1);  // the ends differ in sign: v0 - v1 != 0, t in (0, 1]
        const double inverse_n = 1.0 / static_cast<double>(n_);
        Vec3 p{static_cast<double>(node[0]), static_cast<double>(node[1]), static_cast<double>(node[2])};
        p[axis] += t;
        const Index vertex = static_cast<Index>(part.positions.size());
        part.positions.push_back(p * inverse_n);
        part.edge_vertices.push_back(vertex);
        part.edge_keys.push_back(key);
        return vertex;
    }

    // ---- marching cubes ----------------------------------------------------------------------------------------

    bool mesh_cell(std::uint64_t key, std::vector<SortedCursor>& corners, MeshPart& part) const {
        const std::int64_t cell[3] = {key_i(key), key_j(key), key_k(key)};
        double v[8];
        int inside = 0;
        for (int c = 0; c < 8; ++c) {
            v[c] = node_value(cell[0] + bit(c, 0), cell[1] + bit(c, 1), cell[2] + bit(c, 2),
                              corners[static_cast<std::size_t>(c)], part);
            if (v[c] < 0) inside |= 1 << c;
        }
        if (inside == 0 || inside == 255) return false;
        int next[12];
        std::fill(next, next + 12, -1);
        for (int a = 0; a < 3; ++a)
            for (int s = 0; s < 2; ++s) {
                Segment seg[2];
                const int count = face_segments(v, a, s, seg);
                for (int q = 0; q < count; ++q) {
                    const Segment o = orient(seg[q], v, a, s);
                    next[o.e0] = o.e1;
                }
            }
        bool visited[12] = {};
        for (int start = 0; start < 12; ++start) {
            if (next[start] < 0 || visited[start]) continue;
            Index loop[12];
            int length = 0;
            for (int e = start; !visited[e]; e = next[e]) {
                if (next[e] < 0) {  // cannot happen: the segments around the inside corners form closed loops
                    part.broken = true;
                    return true;
                }
                visited[e] = true;
                loop[length++] = crossing_vertex(cell, e, v, part);
            }
            triangulate(loop, length, part);
        }
        return true;
    }

    static void triangulate(const Index* loop, int length, MeshPart& part) {
        PolygonMesh& out = part.out;
        std::vector<Vec3>& positions = part.positions;
        if (length == 3) {
            out.add_face({loop[0], loop[1], loop[2]});
            return;
        }
        if (length == 4) {
            const Vec3 &p0 = positions[loop[0]], &p1 = positions[loop[1]], &p2 = positions[loop[2]],
                       &p3 = positions[loop[3]];
            if (norm(p2 - p0) <= norm(p3 - p1)) {
                out.add_face({loop[0], loop[1], loop[2]});
                out.add_face({loop[0], loop[2], loop[3]});
            } else {
                out.add_face({loop[0], loop[1], loop[3]});
                out.add_face({loop[1], loop[2], loop[3]});
            }
            return;
        }
        Vec3 centroid;
        for (int q = 0; q < length; ++q) centroid += positions[loop[q]];
        const Index centre = static_cast<Index>(positions.size());
        positions.push_back(centroid * (1.0 / length));
        for (int q = 0; q < length; ++q) out.add_face({centre, loop[q], loop[(q + 1) % length]});
    }

    const PoissonOctree& tree_;
    const IndicatorValues& chi_;
    const OctreeLevel& finest_;
    const std::vector<double>& finest_values_;
    double iso_;
    const Cancel& cancel_;
    int depth_;
    std::int64_t n_;                    //!< finest cells per side
    std::vector<std::uint64_t> cells_;  //!< the cells find_cells found, sorted
    std::size_t collect_bytes_ = 0;     //!< the peak of find_cells' tables
};

}  // namespace

Result<PolygonMesh> extract_surface(const PoissonOctree& tree, const IndicatorValues& chi, double iso,
                                    const Cancel& cancel, ExtractionStats* stats, bool threaded) {
    Extractor extractor(tree, chi, iso, cancel);
    if (Status s = extractor.find_cells(threaded); !s) return s.error();
    return extractor.mesh(stats, threaded);
}

}  // namespace surfaced::reconstruct
