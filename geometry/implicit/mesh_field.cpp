#include "geometry/implicit/mesh_field.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <unordered_map>
#include <vector>

#include "geometry/implicit/cell_faces.h"
#include "geometry/implicit/qef.h"
#include "geometry/simplify/qem.h"

namespace surfaced::implicit {
namespace {

constexpr int kMaxResolution = 65536;
constexpr double kPiOver180 = 3.14159265358979323846 / 180.0;
//! QEF re-solves at a sharp feature (each re-samples the Hermite data at the vertex; see refine_feature).
constexpr int kFeatureRefinements = 4;

// ---- the field as meshed: g = max(f, signed distance to the bounds box) ------------------------------------------

double box_distance(const Box3& box, const Vec3& p, Vec3* gradient) {
    Vec3 q, s;
    for (int a = 0; a < 3; ++a) {
        const double c = 0.5 * (box.min[a] + box.max[a]);
        const double h = 0.5 * (box.max[a] - box.min[a]);
        s[a] = p[a] >= c ? 1.0 : -1.0;
        q[a] = std::fabs(p[a] - c) - h;
    }
    const Vec3 outside{std::max(q.x, 0.0), std::max(q.y, 0.0), std::max(q.z, 0.0)};
    const double out_len = norm(outside);
    if (out_len > 0) {
        if (gradient) *gradient = Vec3{outside.x * s.x, outside.y * s.y, outside.z * s.z} * (1.0 / out_len);
        return out_len;
    }
    int axis = 0;
    if (q.y > q[axis]) axis = 1;
    if (q.z > q[axis]) axis = 2;
    if (gradient) {
        *gradient = Vec3{};
        (*gradient)[axis] = s[axis];
    }
    return q[axis];
}

class BoundedField {
public:
    BoundedField(const Field& field, const Box3& bounds) : field_(field), bounds_(bounds) {}

    double value(const Vec3& p) const {
        ++evaluations;
        double f = field_.value(p);
        if (std::isnan(f)) f = std::numeric_limits<double>::max();  // undefined counts as outside
        return std::max(f, box_distance(bounds_, p, nullptr));
    }

    Vec3 gradient(const Vec3& p) const {
        ++evaluations;
        Vec3 box_gradient;
        const double b = box_distance(bounds_, p, &box_gradient);
        const double f = field_.value(p);
        if (std::isnan(f) || f < b) return box_gradient;
        return field_.gradient(p);
    }

    mutable std::uint64_t evaluations = 0;

private:
    const Field& field_;
    Box3 bounds_;
};

// ---- cell-local numbering (cell_faces.h) ----------------------------------------------------------------------------
using cell_faces::bit;
using cell_faces::edge_start_corner;
using cell_faces::face_segments;
using cell_faces::local_edge;
using cell_faces::Segment;

// Position of a cell around an edge, counter-clockwise seen from +axis: cell offsets (-o_b, -o_c) = (0,0), (1,0),
// (1,1), (0,1) are slots 0..3.
constexpr int kSlotOfOffsets[4] = {0, 1, 3, 2};  // index o_b + 2 o_c

// ---- the mesher ----------------------------------------------------------------------------------------------------

struct EdgeRecord {
    Vec3 point;
    Index vertex[4] = {kInvalidIndex, kInvalidIndex, kInvalidIndex, kInvalidIndex};
};

class Mesher {
public:
    Mesher(const Field& field, const Box3& bounds, const MeshFieldGrid& grid, const MeshFieldOptions& options)
        : g_(field, bounds), bounds_(bounds), options_(options) {
        n_[0] = grid.nx;
        n_[1] = grid.ny;
        n_[2] = grid.nz;
        d_ = grid.spacing;
        stride_[0] = 1;
        stride_[1] = static_cast<std::uint64_t>(n_[0]) + 1;
        stride_[2] = stride_[1] * (static_cast<std::uint64_t>(n_[1]) + 1);
        values_.assign(stride_[2] * (static_cast<std::uint64_t>(n_[2]) + 1), std::numeric_limits<float>::quiet_NaN());
        h_min_ = std::min({d_.x, d_.y, d_.z});
    }

    Status run_uniform() {
        for (int k = 0; k <= n_[2]; ++k) {
            if (options_.cancel.requested()) return cancelled();
            for (int j = 0; j <= n_[1]; ++j)
                for (int i = 0; i <= n_[0]; ++i) node_value(i, j, k);
        }
        for (int k = 0; k < n_[2]; ++k) {
            if (options_.cancel.requested()) return cancelled();
            for (int j = 0; j < n_[1]; ++j)
                for (int i = 0; i < n_[0]; ++i) process_cell(i, j, k);
        }
        return Ok{};
    }

    Status run_adaptive(const Field& field) {
        const double lipschitz = std::max(1.0, field.lipschitz());
        const bool can_cull = field.kind() != FieldKind::General && std::isfinite(lipschitz);
        if (!can_cull) return run_uniform();
        lipschitz_ = lipschitz;
        return block({0, 0, 0}, {n_[0], n_[1], n_[2]});
    }

    PolygonMesh finish(MeshFieldStats* stats) {
        build_polygons();
        PolygonMesh mesh;
        triangulate(mesh);
        repair_degenerate(mesh);
        if (stats) {
            stats->field_evaluations = g_.evaluations;
            stats->surface_cells = surface_cells_;
            stats->vertices_before_simplify = mesh.vertex_count();
            stats->triangles_before_simplify = mesh.face_count();
            stats->non_manifold_fixes = non_manifold_fixes_;
            stats->degenerate_fixes = degenerate_fixes_;
        }
        return mesh;
    }

private:
    static GeoError cancelled() { return make_error(ErrorCode::Cancelled, "meshing cancelled (deadline passed)"); }

    std::uint64_t node_id(int i, int j, int k) const { return i + stride_[1] * j + stride_[2] * k; }
    bool on_bounds(int i, int j, int k) const {
        return i == 0 || j == 0 || k == 0 || i == n_[0] || j == n_[1] || k == n_[2];
    }
    double coordinate(int axis, int i) const {
        return i == n_[axis] ? bounds_.max[axis] : bounds_.min[axis] + i * d_[axis];
    }
    Vec3 node_position(int i, int j, int k) const { return {coordinate(0, i), coordinate(1, j), coordinate(2, k)}; }

    float node_value(int i, int j, int k) {
        float& slot = values_[node_id(i, j, k)];
        if (!std::isnan(slot)) return slot;
        double g = g_.value(node_position(i, j, k));
        if (on_bounds(i, j, k)) g = std::max(g, 0.0);  // on the bounds is outside
        constexpr double kCap = 1e30;
        g = std::clamp(g, -kCap, kCap);
        float v = static_cast<float>(g);
        if (g < 0 && !(v < 0)) v = -std::numeric_limits<float>::min();  // keep the sign through the rounding
        slot = v;
        return v;
    }

    // Octree over cell ranges [lo, hi): blocks that provably hold no zero of g are skipped.
    Status block(std::array<int, 3> lo, std::array<int, 3> hi) {
        Vec3 a = node_position(lo[0], lo[1], lo[2]), b = node_position(hi[0], hi[1], hi[2]);
        const Vec3 centre = (a + b) * 0.5;
        const double radius = 0.5 * norm(b - a);
        const double value = g_.value(centre);
        if (std::fabs(value) > lipschitz_ * radius * (1 + 1e-6) + 1e-12 * bounds_.diagonal()) return Ok{};
        const int largest = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
        if (largest <= 2) {
            if ((++leaves_ & 63) == 0 && options_.cancel.requested()) return cancelled();
            for (int k = lo[2]; k <= hi[2]; ++k)
                for (int j = lo[1]; j <= hi[1]; ++j)
                    for (int i = lo[0]; i <= hi[0]; ++i) node_value(i, j, k);
            for (int k = lo[2]; k < hi[2]; ++k)
                for (int j = lo[1]; j < hi[1]; ++j)
                    for (int i = lo[0]; i < hi[0]; ++i) process_cell(i, j, k);
            return Ok{};
        }
        std::array<int, 3> mid;
        for (int axis = 0; axis < 3; ++axis) mid[axis] = hi[axis] - lo[axis] > 1 ? (lo[axis] + hi[axis]) / 2 : hi[axis];
        for (int child = 0; child < 8; ++child) {
            std::array<int, 3> clo, chi;
            bool empty = false;
            for (int axis = 0; axis < 3; ++axis) {
                const bool upper = (child >> axis) & 1;
                clo[axis] = upper ? mid[axis] : lo[axis];
                chi[axis] = upper ? hi[axis] : mid[axis];
                if (clo[axis] >= chi[axis]) empty = true;
            }
            if (empty) continue;
            if (auto status = block(clo, chi); !status) return status;
        }
        return Ok{};
    }

    std::uint64_t edge_id(int axis, int i, int j, int k) const { return node_id(i, j, k) * 3 + axis; }

    EdgeRecord& crossing(int axis, int i, int j, int k) {
        const std::uint64_t id = edge_id(axis, i, j, k);
        auto [it, inserted] = edges_.try_emplace(id);
        if (!inserted) return it->second;
        int hi[3] = {i, j, k};
        ++hi[axis];
        const Vec3 p0 = node_position(i, j, k), p1 = node_position(hi[0], hi[1], hi[2]);
        double t0 = 0, t1 = 1;
        double v0 = node_value(i, j, k), v1 = node_value(hi[0], hi[1], hi[2]);
        const bool inside0 = v0 < 0;
        // Illinois regula falsi on g along the edge, bracketing the inside/outside change.
        int side = 0;
        double t = 0.5;
        for (int iter = 0; iter < 24; ++iter) {
            t = (v1 - v0) != 0 ? (t0 * v1 - t1 * v0) / (v1 - v0) : 0.5 * (t0 + t1);
            if (!(t > t0 && t < t1)) t = 0.5 * (t0 + t1);
            if (t1 - t0 < 1e-9) break;
            const double v = g_.value(p0 + (p1 - p0) * t);
            if ((v < 0) == inside0) {
                t0 = t;
                v0 = v;
                if (side == -1) v1 *= 0.5;
                side = -1;
            } else {
                t1 = t;
                v1 = v;
                if (side == 1) v0 *= 0.5;
                side = 1;
            }
            if (std::fabs(v) < 1e-14 * h_min_) break;
        }
        it->second.point = p0 + (p1 - p0) * t;
        return it->second;
    }

    void process_cell(int i, int j, int k) {
        float v[8];
        int inside = 0;
        for (int c = 0; c < 8; ++c) {
            v[c] = node_value(i + bit(c, 0), j + bit(c, 1), k + bit(c, 2));
            if (v[c] < 0) inside |= 1 << c;
        }
        if (inside == 0 || inside == 255) return;
        ++surface_cells_;
        // segments on the six faces -> two partners per crossed edge
        int partner[12][2];
        int partners[12] = {};
        for (int a = 0; a < 3; ++a)
            for (int s = 0; s < 2; ++s) {
                Segment seg[2];
                const int count = face_segments(v, a, s, seg);
                for (int q = 0; q < count; ++q) {
                    partner[seg[q].e0][partners[seg[q].e0]++] = seg[q].e1;
                    partner[seg[q].e1][partners[seg[q].e1]++] = seg[q].e0;
                }
            }
        // loops -> one vertex each
        bool visited[12] = {};
        const Vec3 lo = node_position(i, j, k), hi = node_position(i + 1, j + 1, k + 1);
        for (int start = 0; start < 12; ++start) {
            if (partners[start] != 2 || visited[start]) continue;
            int loop[12], length = 0;
            int previous = -1, current = start;
            while (!visited[current]) {
                visited[current] = true;
                loop[length++] = current;
                const int next = partner[current][0] != previous ? partner[current][0] : partner[current][1];
                previous = current;
                current = next;
            }
            Qef qef;
            EdgeRecord* records[12];
            Vec3 points[12], normals[12];
            for (int q = 0; q < length; ++q) {
                const int e = loop[q], axis = e / 4, c0 = edge_start_corner(e);
                records[q] = &crossing(axis, i + bit(c0, 0), j + bit(c0, 1), k + bit(c0, 2));
                points[q] = records[q]->point;
                normals[q] = g_.gradient(points[q]);
                qef.add(points[q], normals[q]);
            }
            // The QEF minimiser within the cell (box-constrained, so that a feature whose planes meet just
            // outside the cell still gets the point of the cell nearest to them).
            Vec3 x = qef.solve_in_box(options_.qef_threshold, lo, hi);
            int rank = 0;
            (void)qef.solve(options_.qef_threshold, &rank);
            if (rank >= 2) x = refine_feature(x, points, normals, length, qef.mass_point(), lo, hi);
            // What is still off the surface (a smooth patch: the QEF point lies on the mean tangent plane, off a
            // curved surface by the sag of the patch across the cell; a feature whose planes meet outside the cell:
            // the box-constrained point) moves onto the surface along the gradient, when that stays in the cell and
            // on a sheet the crossings saw (normal within ~25 degrees of one of theirs).
            if (rank <= 1 || std::fabs(g_.value(x)) > 1e-9 * h_min_) {
                Vec3 on_surface = x, normal;
                if (project_to_surface(on_surface, normal, 3) && in_box(on_surface, lo, hi)) {
                    const double l = norm(normal);
                    bool same_sheet = false;
                    for (int q = 0; q < length && l > 0; ++q)
                        same_sheet = same_sheet || dot(normal, normals[q]) > 0.9 * l * norm(normals[q]);
                    if (same_sheet) x = on_surface;
                }
            }
            // Clamp into the cell, a little inside its faces so that vertices of neighbouring cells never
            // coincide; on the bounds there is no neighbour, so caps stay exactly on the bounds faces.
            const int cell[3] = {i, j, k};
            for (int axis = 0; axis < 3; ++axis) {
                const double margin = 1e-3 * d_[axis];
                const double low = cell[axis] == 0 ? lo[axis] : lo[axis] + margin;
                const double high = cell[axis] + 1 == n_[axis] ? hi[axis] : hi[axis] - margin;
                x[axis] = std::clamp(x[axis], low, high);
            }
            const Index vertex = static_cast<Index>(positions_.size());
            positions_.push_back(x);
            mass_points_.push_back(qef.mass_point());
            for (int q = 0; q < length; ++q) {
                const int e = loop[q], axis = e / 4;
                const int ob = e & 1, oc = (e >> 1) & 1;
                (void)axis;
                records[q]->vertex[kSlotOfOffsets[ob + 2 * oc]] = vertex;
            }
        }
    }

    static bool in_box(const Vec3& p, const Vec3& lo, const Vec3& hi) {
        return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y && p.z >= lo.z && p.z <= hi.z;
    }

    // Newton steps along the gradient from p towards g = 0 (at most `steps`); false when g has no usable gradient.
    bool project_to_surface(Vec3& p, Vec3& normal, int steps) const {
        for (int s = 0;; ++s) {
            const double v = g_.value(p);
            if (!std::isfinite(v)) return false;
            const bool done = std::fabs(v) < 1e-9 * h_min_;
            if (!done && s == steps) return false;
            normal = g_.gradient(p);
            const double n2 = dot(normal, normal);
            if (!(n2 > 0) || !std::isfinite(n2)) return false;
            if (done) return true;
            p -= normal * (v / n2);
        }
    }

    // A sharp feature (QEF rank 2 or 3) on a curved surface: the tangent planes at the edge crossings, up to a cell
    // away, meet off the surface (tangents of a circle meet outside it; the crossings' mass point lies inside the arc),
    // which makes a curved crease saw-toothed. Re-sample the Hermite data where the vertex is: each crossing's plane
    // is replaced by the tangent plane at the surface point nearest to the vertex's foot on that plane, when that
    // point is on the same sheet (normal within ~25 degrees of the crossing's), then the QEF is solved again. Straight
    // features are fixed points (their planes do not change), so sharp cube edges stay as they were.
    Vec3 refine_feature(Vec3 x, const Vec3* points, const Vec3* normals, int count, const Vec3& mass_point,
                        const Vec3& lo, const Vec3& hi) const {
        // One plane per sheet: the crossings are grouped by normal (within ~25 degrees of a group's first), each
        // group represented by its crossing nearest to x. sheet: that crossing's normal, which re-samples keep near.
        Vec3 p[12], n[12], sheet[12];
        int sheets = 0;
        for (int q = 0; q < count; ++q) {
            const double l = norm(normals[q]);
            if (!(l > 0)) continue;
            const Vec3 unit = normals[q] * (1.0 / l);
            int group = 0;
            while (group < sheets && dot(unit, sheet[group]) <= 0.9) ++group;
            if (group == sheets) {
                sheet[sheets++] = unit;
            } else if (norm(points[q] - x) >= norm(p[group] - x)) {
                continue;
            }
            p[group] = points[q];
            n[group] = unit;
        }
        count = sheets;
        const double reach = 1.5 * norm(hi - lo);
        for (int iteration = 0; iteration < kFeatureRefinements; ++iteration) {
            Qef qef;
            for (int q = 0; q < count; ++q) {
                const double offset = norm(n[q]) > 0 ? dot(n[q], x - p[q]) : 0.0;
                const Vec3 foot = x - n[q] * offset;
                // A flat sheet keeps its plane: the gradient halfway from the sample to the foot is the sample's own
                // normal (straight edges and corners cost one gradient per sample and settle at once).
                bool flat = norm(foot - p[q]) < 1e-9 * h_min_;
                if (!flat && norm(n[q]) > 0) {
                    const Vec3 halfway = g_.gradient((p[q] + foot) * 0.5);
                    flat = dot(halfway, n[q]) > (1 - 1e-12) * norm(halfway);
                }
                if (!flat) {
                    // the farthest point towards the foot whose surface projection is still on this sheet
                    if (norm(foot - p[q]) < reach) {
                        Vec3 best_p = p[q], best_n = n[q];
                        auto accept = [&](double t) {
                            Vec3 candidate = p[q] + (foot - p[q]) * t, normal;
                            if (!project_to_surface(candidate, normal, 3)) return false;
                            const double l = norm(normal);
                            if (!(l > 0) || dot(normal, sheet[q]) <= 0.9 * l || norm(candidate - x) >= reach)
                                return false;
                            best_p = candidate;
                            best_n = normal * (1.0 / l);
                            return true;
                        };
                        if (!accept(1.0)) {
                            double good = 0, bad = 1;  // bisection for the end of this sheet
                            for (int step = 0; step < 6; ++step) {
                                const double mid = 0.5 * (good + bad);
                                (accept(mid) ? good : bad) = mid;
                            }
                        }
                        p[q] = best_p;
                        n[q] = best_n;
                    }
                }
                qef.add(p[q], n[q]);
            }
            // the original mass point, so that truncated directions (along the crease) keep the vertex where the
            // crossings are
            qef.set_mass_point(mass_point);
            const Vec3 next = qef.solve_in_box(options_.qef_threshold, lo, hi);
            const bool settled = norm(next - x) < 1e-6 * h_min_;
            x = next;
            if (settled) break;
        }
        return x;
    }

    // Cell origin of the cell in `slot` around edge (axis, node).
    std::array<int, 3> slot_cell(int axis, const std::array<int, 3>& node, int slot) const {
        static constexpr int kOffsets[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
        std::array<int, 3> cell = node;
        cell[(axis + 1) % 3] -= kOffsets[slot][0];
        cell[(axis + 2) % 3] -= kOffsets[slot][1];
        return cell;
    }

    // The vertex inserted on the face between the cells in slots s and s+1 around edge (axis, node), for the segment
    // through that edge's crossing.
    Index segment_vertex(int axis, const std::array<int, 3>& node, int slot) {
        const std::array<int, 3> cell = slot_cell(axis, node, slot);
        const int next = (slot + 1) % 4;
        const std::array<int, 3> other = slot_cell(axis, node, next);
        int face_axis = 0;
        for (int a = 0; a < 3; ++a)
            if (cell[a] != other[a]) face_axis = a;
        const int side = other[face_axis] > cell[face_axis] ? 1 : 0;
        float v[8];
        for (int c = 0; c < 8; ++c)
            v[c] = values_[node_id(cell[0] + bit(c, 0), cell[1] + bit(c, 1), cell[2] + bit(c, 2))];
        int corner = 0;
        for (int a = 0; a < 3; ++a) corner |= (node[a] - cell[a]) << a;
        const int e = local_edge(axis, corner);
        Segment seg[2];
        const int count = face_segments(v, face_axis, side, seg);
        int partner_edge = -1;
        for (int q = 0; q < count; ++q) {
            if (seg[q].e0 == e) partner_edge = seg[q].e1;
            if (seg[q].e1 == e) partner_edge = seg[q].e0;
        }
        if (partner_edge < 0) return kInvalidIndex;  // cannot happen: both cells saw this segment
        const int pc = edge_start_corner(partner_edge), paxis = partner_edge / 4;
        const std::uint64_t id0 = edge_id(axis, node[0], node[1], node[2]);
        const std::uint64_t id1 = edge_id(paxis, cell[0] + bit(pc, 0), cell[1] + bit(pc, 1), cell[2] + bit(pc, 2));
        const std::pair<std::uint64_t, std::uint64_t> key{std::min(id0, id1), std::max(id0, id1)};
        auto [it, inserted] = segment_vertices_.try_emplace(key, kInvalidIndex);
        if (inserted) {
            const Vec3 p = (edges_.at(id0).point + edges_.at(id1).point) * 0.5;
            it->second = static_cast<Index>(positions_.size());
            positions_.push_back(p);
            mass_points_.push_back(p);
            ++non_manifold_fixes_;
        }
        return it->second;
    }

    static std::uint64_t undirected(Index a, Index b) {
        return (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
    }

    void build_polygons() {
        // quads, oriented so that the normal points from inside to outside along the edge
        std::vector<std::pair<std::uint64_t, std::array<Index, 4>>> quads;
        quads.reserve(edges_.size());
        for (const auto& [id, record] : edges_) {
            const int axis = static_cast<int>(id % 3);
            const std::uint64_t node = id / 3;
            const bool lower_inside = values_[node] < 0;
            std::array<Index, 4> q{record.vertex[0], record.vertex[1], record.vertex[2], record.vertex[3]};
            (void)axis;
            if (std::find(q.begin(), q.end(), kInvalidIndex) != q.end()) {
                incomplete_ = true;  // a cell around a crossed edge was not processed: a bug
                continue;
            }
            if (!lower_inside) std::swap(q[1], q[3]);
            quads.push_back({id, q});
        }
        std::sort(quads.begin(), quads.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
        std::unordered_map<std::uint64_t, int> edge_use;
        edge_use.reserve(quads.size() * 2);
        for (const auto& [id, q] : quads)
            for (int s = 0; s < 4; ++s) ++edge_use[undirected(q[s], q[(s + 1) % 4])];
        polygons_.reserve(quads.size());
        for (const auto& [id, q] : quads) {
            Polygon polygon;
            const int axis = static_cast<int>(id % 3);
            const std::uint64_t node_index = id / 3;
            const std::array<int, 3> node{static_cast<int>(node_index % stride_[1]),
                                          static_cast<int>((node_index / stride_[1]) % (n_[1] + 1)),
                                          static_cast<int>(node_index / stride_[2])};
            const bool lower_inside = values_[node_index] < 0;
            for (int s = 0; s < 4; ++s) {
                polygon.vertices[polygon.size++] = q[s];
                if (edge_use[undirected(q[s], q[(s + 1) % 4])] > 2) {
                    // slot of q[s] in counter-clockwise order (q was reversed when the lower end is outside)
                    const int slot = lower_inside ? s : (4 - s) % 4;
                    const int next_slot = lower_inside ? (s + 1) % 4 : (4 - s + 3) % 4;
                    const int first = (next_slot == (slot + 1) % 4) ? slot : next_slot;
                    const Index inserted = segment_vertex(axis, node, first);
                    if (inserted == kInvalidIndex) continue;
                    if (polygon.inserted < 0) polygon.inserted = polygon.size;
                    polygon.vertices[polygon.size++] = inserted;
                }
            }
            polygons_.push_back(polygon);
        }
    }

    static double twice_area(const Vec3& a, const Vec3& b, const Vec3& c) { return norm(cross(b - a, c - a)); }
    static double quality(const Vec3& a, const Vec3& b, const Vec3& c) {
        const double l = std::max({dot(b - a, b - a), dot(c - b, c - b), dot(a - c, a - c)});
        return l > 0 ? twice_area(a, b, c) / l : 0.0;
    }

    void triangulate(PolygonMesh& mesh) {
        mesh.face_indices.reserve(polygons_.size() * 6);
        mesh.face_offsets.reserve(polygons_.size() * 2 + 1);
        for (const Polygon& polygon : polygons_) {
            const Index* v = polygon.vertices.data();
            if (polygon.inserted >= 0) {  // fan from the inserted vertex
                const int n = polygon.size, m = polygon.inserted;
                for (int s = 1; s + 1 < n; ++s) mesh.add_face({v[m], v[(m + s) % n], v[(m + s + 1) % n]});
                continue;
            }
            const Vec3 &p0 = positions_[v[0]], &p1 = positions_[v[1]], &p2 = positions_[v[2]], &p3 = positions_[v[3]];
            // diagonal 0-2: (0,1,2) (0,2,3); diagonal 1-3: (0,1,3) (1,2,3). Prefer the one without a fold, then the
            // better worst triangle.
            const bool fold02 = dot(cross(p1 - p0, p2 - p0), cross(p2 - p0, p3 - p0)) < 0;
            const bool fold13 = dot(cross(p1 - p0, p3 - p0), cross(p2 - p1, p3 - p1)) < 0;
            const double q02 = std::min(quality(p0, p1, p2), quality(p0, p2, p3));
            const double q13 = std::min(quality(p0, p1, p3), quality(p1, p2, p3));
            const bool use02 = fold02 != fold13 ? !fold02 : q02 >= q13;
            if (use02) {
                mesh.add_face({v[0], v[1], v[2]});
                mesh.add_face({v[0], v[2], v[3]});
            } else {
                mesh.add_face({v[0], v[1], v[3]});
                mesh.add_face({v[1], v[2], v[3]});
            }
        }
        mesh.positions = positions_;
    }

    // Zero-area triangles (vertices clamped onto the same point or line): move their vertices towards the mass
    // point of their patch, which lies strictly inside the vertex's cell.
    void repair_degenerate(PolygonMesh& mesh) {
        const double tiny = 1e-10 * h_min_ * h_min_;
        for (int round = 0; round < 16; ++round) {
            bool any = false;
            for (std::size_t f = 0; f < mesh.face_count(); ++f) {
                const auto face = mesh.face(f);
                if (twice_area(mesh.positions[face[0]], mesh.positions[face[1]], mesh.positions[face[2]]) > tiny)
                    continue;
                any = true;
                ++degenerate_fixes_;
                for (Index vertex : face) {
                    Vec3& p = mesh.positions[vertex];
                    p = p + (mass_points_[vertex] - p) * 0.25;
                }
            }
            if (!any) break;
        }
    }

    struct Polygon {
        std::array<Index, 8> vertices{};
        int size = 0;
        int inserted = -1;  //!< position of the first inserted vertex, or -1
    };

    BoundedField g_;
    Box3 bounds_;
    const MeshFieldOptions& options_;
    int n_[3] = {};
    Vec3 d_;
    double h_min_ = 0;
    double lipschitz_ = 1;
    std::uint64_t stride_[3] = {};
    std::vector<float> values_;
    std::unordered_map<std::uint64_t, EdgeRecord> edges_;
    std::map<std::pair<std::uint64_t, std::uint64_t>, Index> segment_vertices_;
    std::vector<Vec3> positions_;
    std::vector<Vec3> mass_points_;
    std::vector<Polygon> polygons_;
    std::uint64_t surface_cells_ = 0;
    std::uint64_t non_manifold_fixes_ = 0;
    std::uint64_t degenerate_fixes_ = 0;
    std::uint64_t leaves_ = 0;

public:
    bool incomplete_ = false;
};

}  // namespace

Result<MeshFieldGrid> mesh_field_grid(const Box3& bounds, const MeshFieldOptions& options) {
    for (int a = 0; a < 3; ++a)
        if (!std::isfinite(bounds.min[a]) || !std::isfinite(bounds.max[a]) || !(bounds.min[a] < bounds.max[a]))
            return make_error(ErrorCode::InvalidArgument, "bounds must be finite with min < max on every axis");
    const Vec3 extent = bounds.max - bounds.min;
    const double longest = std::max({extent.x, extent.y, extent.z});
    double h = 0;
    if (options.cell_size != 0) {
        if (!std::isfinite(options.cell_size) || options.cell_size < 0)
            return make_error(ErrorCode::InvalidArgument, "cell_size must be a positive number");
        h = options.cell_size;
        if (longest / h < 2)
            return make_error(ErrorCode::InvalidArgument, "cell_size gives fewer than 2 cells along the longest side");
    } else {
        if (options.resolution < 2 || options.resolution > kMaxResolution)
            return make_error(ErrorCode::InvalidArgument,
                              "resolution must be between 2 and " + std::to_string(kMaxResolution));
        h = longest / options.resolution;
    }
    double counts[3];
    double total = 1;
    for (int a = 0; a < 3; ++a) {
        counts[a] = std::max(1.0, std::ceil(extent[a] / h - 1e-9));
        total *= counts[a];
    }
    if (!(total <= static_cast<double>(options.max_cells)) || counts[0] > kMaxResolution ||
        counts[1] > kMaxResolution || counts[2] > kMaxResolution)
        return make_error(ErrorCode::BudgetExceeded, "the grid would have " +
                                                         std::to_string(static_cast<unsigned long long>(total)) +
                                                         " cells; the limit is " + std::to_string(options.max_cells));
    MeshFieldGrid grid;
    grid.nx = static_cast<int>(counts[0]);
    grid.ny = static_cast<int>(counts[1]);
    grid.nz = static_cast<int>(counts[2]);
    grid.spacing = {extent.x / grid.nx, extent.y / grid.ny, extent.z / grid.nz};
    grid.cells = static_cast<std::uint64_t>(grid.nx) * grid.ny * grid.nz;
    return grid;
}

Result<PolygonMesh> mesh_field(const Field& field, const Box3& bounds, const MeshFieldOptions& options,
                               MeshFieldStats* stats) {
    auto grid = mesh_field_grid(bounds, options);
    if (!grid) return grid.error();
    if (!(options.qef_threshold >= 0 && options.qef_threshold <= 1))
        return make_error(ErrorCode::InvalidArgument, "qef_threshold must be in [0, 1]");
    if (!(std::isfinite(options.simplify_tolerance) && options.simplify_tolerance >= 0))
        return make_error(ErrorCode::InvalidArgument, "simplify_tolerance must be a finite distance >= 0");
    if (stats) *stats = MeshFieldStats{};
    if (stats) stats->grid = *grid;

    Mesher mesher(field, bounds, *grid, options);
    Status status = options.mode == MeshFieldMode::Adaptive ? mesher.run_adaptive(field) : mesher.run_uniform();
    if (!status) return status.error();
    PolygonMesh mesh = mesher.finish(stats);
    if (mesher.incomplete_) return make_error(ErrorCode::Internal, "meshing left a crossed grid edge without a face");
    if (options.cancel.requested()) return make_error(ErrorCode::Cancelled, "meshing cancelled (deadline passed)");

    if (options.mode == MeshFieldMode::Adaptive && mesh.face_count() > 0) {
        const double tolerance = options.simplify_tolerance;
        if (tolerance > 0) {
            SimplifyOptions simplify;
            simplify.max_error = tolerance;
            // caps on the bounds stay put, so that no vertex leaves the bounds
            for (Index v = 0; v < mesh.vertex_count(); ++v)
                for (int a = 0; a < 3; ++a)
                    if (mesh.positions[v][a] <= bounds.min[a] || mesh.positions[v][a] >= bounds.max[a]) {
                        simplify.locked_vertices.push_back(v);
                        break;
                    }
            auto simplified = simplify_qem(mesh, simplify);
            if (!simplified) return simplified.error();
            mesh = std::move(simplified->mesh);
            for (Vec3& p : mesh.positions)  // a collapse next to a cap may land a hair outside
                for (int a = 0; a < 3; ++a) p[a] = std::clamp(p[a], bounds.min[a], bounds.max[a]);
            if (options.cancel.requested())
                return make_error(ErrorCode::Cancelled, "meshing cancelled (deadline passed)");
        }
    }
    return mesh;
}

PolygonMesh split_normals_at_creases(const PolygonMesh& mesh, double crease_angle_degrees) {
    const std::size_t faces = mesh.face_count();
    // corners of triangle f are 3f..3f+2; union-find over corners: one output vertex per class
    std::vector<std::uint32_t> parent(3 * faces);
    for (std::size_t c = 0; c < parent.size(); ++c) parent[c] = static_cast<std::uint32_t>(c);
    auto find = [&](std::uint32_t c) {
        while (parent[c] != c) c = parent[c] = parent[parent[c]];
        return c;
    };
    auto unite = [&](std::uint32_t a, std::uint32_t b) {
        a = find(a);
        b = find(b);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
    };
    std::vector<Vec3> face_normal(faces);
    std::vector<char> triangle(faces, 0);
    for (std::size_t f = 0; f < faces; ++f) {
        const auto face = mesh.face(f);
        if (face.size() != 3) continue;
        triangle[f] = 1;
        const Vec3 n =
            cross(mesh.positions[face[1]] - mesh.positions[face[0]], mesh.positions[face[2]] - mesh.positions[face[0]]);
        const double l = norm(n);
        face_normal[f] = l > 0 ? n * (1.0 / l) : Vec3{};
    }
    const double cos_limit = crease_angle_degrees >= 180 ? -2.0 : std::cos(crease_angle_degrees * kPiOver180);
    auto edge_key = [](Index a, Index b) {
        return (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
    };
    std::unordered_map<std::uint64_t, int> uses;  // faces per undirected edge; only edges used twice are joined
    uses.reserve(3 * faces);
    for (std::size_t f = 0; f < faces; ++f) {
        if (!triangle[f]) continue;
        const auto face = mesh.face(f);
        for (int k = 0; k < 3; ++k) ++uses[edge_key(face[k], face[(k + 1) % 3])];
    }
    struct Use {
        std::uint32_t low_corner, high_corner;  // the face's corners at the edge's smaller and larger vertex
        std::size_t face;
    };
    // second pass: join the two faces of each edge used exactly twice, when their normals are close enough
    std::unordered_map<std::uint64_t, Use> first;
    first.reserve(uses.size());
    for (std::size_t f = 0; f < faces; ++f) {
        if (!triangle[f]) continue;
        const auto face = mesh.face(f);
        for (int k = 0; k < 3; ++k) {
            const Index a = face[k], b = face[(k + 1) % 3];
            const std::uint64_t key = edge_key(a, b);
            if (uses.at(key) != 2) continue;
            const std::uint32_t ca = static_cast<std::uint32_t>(3 * f + k),
                                cb = static_cast<std::uint32_t>(3 * f + (k + 1) % 3);
            const Use use{a < b ? ca : cb, a < b ? cb : ca, f};
            auto [it, inserted] = first.try_emplace(key, use);
            if (inserted) continue;
            const Use& other = it->second;
            if (dot(face_normal[other.face], face_normal[f]) < cos_limit) continue;  // a sharp edge
            unite(other.low_corner, use.low_corner);
            unite(other.high_corner, use.high_corner);
        }
    }
    // one output vertex per class, angle-weighted normals of its faces
    PolygonMesh out;
    std::vector<Index> vertex_of(parent.size(), kInvalidIndex);
    std::vector<Vec3> normal_sum;
    for (std::size_t f = 0; f < faces; ++f) {
        const auto face = mesh.face(f);
        std::vector<Index> corners;
        for (std::size_t k = 0; k < face.size(); ++k) {
            Index id = kInvalidIndex;
            if (triangle[f]) id = vertex_of[find(static_cast<std::uint32_t>(3 * f + k))];
            if (id == kInvalidIndex) {
                id = static_cast<Index>(out.positions.size());
                out.positions.push_back(mesh.positions[face[k]]);
                normal_sum.push_back(Vec3{});
                if (triangle[f]) vertex_of[find(static_cast<std::uint32_t>(3 * f + k))] = id;
            }
            if (triangle[f]) {
                const Vec3 &p = mesh.positions[face[k]], &p1 = mesh.positions[face[(k + 1) % 3]],
                           &p2 = mesh.positions[face[(k + 2) % 3]];
                const Vec3 e1 = p1 - p, e2 = p2 - p;
                const double angle = std::atan2(norm(cross(e1, e2)), dot(e1, e2));
                normal_sum[id] += face_normal[f] * angle;
            }
            corners.push_back(id);
        }
        out.add_face(corners);
    }
    out.normals.resize(out.positions.size());
    for (std::size_t v = 0; v < out.positions.size(); ++v) {
        const double l = norm(normal_sum[v]);
        out.normals[v] = l > 0 ? normal_sum[v] * (1.0 / l) : Vec3{0, 0, 1};
    }
    return out;
}

}  // namespace surfaced::implicit
