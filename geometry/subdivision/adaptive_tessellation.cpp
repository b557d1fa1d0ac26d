#include "geometry/subdivision/adaptive_tessellation.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <optional>
#include <tuple>
#include <utility>

#include "geometry/core/two_parts.h"
#include "geometry/subdivision/tessellation_bounds.h"
#include "geometry/subdivision/tessellation_decimation.h"
#include "geometry/subdivision/tessellation_grading.h"
#include "geometry/subdivision/tessellation_strips.h"

namespace surfaced {

using namespace tessellation_detail;

namespace {

//! The points along a base edge (or along one half of an edge of an N-gon, whose midpoint is a vertex) or along a
//! spoke: graded by a density over the slot's own parameter, 0 to 1 in its canonical direction (an edge's first face's
//! direction; a spoke from its edge midpoint to the centre). Every domain side on it reads the same points.
struct Slot {
    Density rho{};
    int count = 1;
    std::vector<double> lines;  //!< count + 1 values from 0 to 1; empty: uniform
    double at(int i) const { return lines.empty() ? double(i) / count : lines[std::size_t(i)]; }
};

//! The part [q0, q1] of a domain side (its fraction from corner k to corner k + 1) that a slot covers; reversed: the
//! slot's parameter runs from q1 down to q0.
struct SidePart {
    std::size_t slot = 0;
    double q0 = 0, q1 = 1;
    bool reversed = false;
};

struct EdgeUse {
    std::size_t edge;
    bool forward;  //!< the face runs along the edge's canonical direction
};

//! Everything the plan and the execution share.
struct Context {
    Context(const LimitSurfaceEvaluator& e, const PolygonMesh& b, const LimitTessellationOptions& o)
        : evaluator(e), base(b), options(o) {}
    const LimitSurfaceEvaluator& evaluator;
    const PolygonMesh& base;
    const LimitTessellationOptions& options;
    std::vector<FaceData> faces;
    std::vector<bool> hole;
    std::vector<std::array<Index, 2>> edges;     //!< canonical (v0, v1)
    std::vector<std::size_t> edge_owner;         //!< first non-hole face on the edge
    std::vector<std::uint32_t> edge_owner_side;  //!< its corner index there
    std::vector<std::vector<EdgeUse>> face_edges;
    std::vector<std::size_t> first_domain;  //!< per face, its first domain (domains of a face are contiguous)
    std::vector<std::size_t> first_spoke;   //!< per face, index of its spoke 0 (N-gons)
    std::size_t spokes = 0;
    std::vector<int> edge_faces;  //!< per edge, how many non-hole faces use it (1: an open boundary)
    //! Per edge: its two faces have the same corners (glued back to back), so the surface folds onto itself there and
    //! S near it lies in the plane of the triangles on either side, which the distance to a triangle's plane does not
    //! see: bounded as an open boundary.
    std::vector<bool> fold_edge;
    std::vector<bool> fixed_edge, fixed_vertex;  //!< per edge and base vertex: C0 there, vertices stay on S
    std::vector<bool> halved;            //!< per edge: an N-gon uses it, so its midpoint is a vertex (two slots)
    std::vector<std::size_t> edge_slot;  //!< per edge, its first slot (halves in canonical order)
    std::size_t first_spoke_slot = 0;
    std::vector<Slot> slots;

    std::size_t spoke_slot(std::size_t face, std::size_t j) const { return first_spoke_slot + first_spoke[face] + j; }
    //! Segments of edge e, and the canonical index of its midpoint when it is halved.
    int edge_count(std::size_t e) const {
        return slots[edge_slot[e]].count + (halved[e] ? slots[edge_slot[e] + 1].count : 0);
    }
    //! Canonical fraction of edge e's point i.
    double edge_at(std::size_t e, int i) const {
        const Slot& a = slots[edge_slot[e]];
        if (!halved[e]) return a.at(i);
        return i <= a.count ? 0.5 * a.at(i) : 0.5 + 0.5 * slots[edge_slot[e] + 1].at(i - a.count);
    }
    //! The slots along side k of a domain, in the side's order.
    std::array<SidePart, 2> side_parts(const LimitTessellationPlan::Domain& d, int k, int& parts) const {
        const std::size_t f = d.face, n = faces[f].size;
        parts = 1;
        if (d.subface < 0) {
            const EdgeUse& use = face_edges[f][std::size_t(k)];
            const std::size_t s0 = edge_slot[use.edge];
            if (!halved[use.edge]) return {SidePart{s0, 0.0, 1.0, !use.forward}, SidePart{}};
            parts = 2;
            if (use.forward) return {SidePart{s0, 0.0, 0.5, false}, SidePart{s0 + 1, 0.5, 1.0, false}};
            return {SidePart{s0 + 1, 0.0, 0.5, true}, SidePart{s0, 0.5, 1.0, true}};
        }
        const auto j = std::size_t(d.subface), prev = (j + n - 1) % n;
        if (k == 1) return {SidePart{spoke_slot(f, j), 0.0, 1.0, false}, SidePart{}};
        if (k == 2) return {SidePart{spoke_slot(f, prev), 0.0, 1.0, true}, SidePart{}};
        // side 0: the first half of edge j in the face's direction; side 3: the second half of the previous edge
        const EdgeUse& use = face_edges[f][k == 0 ? j : prev];
        const std::size_t s0 = edge_slot[use.edge];
        const bool first = (k == 0) == use.forward;  // canonical first half
        return {SidePart{first ? s0 : s0 + 1, 0.0, 1.0, !use.forward}, SidePart{}};
    }
};

//! Which sides of domain d lie on an open boundary of the mesh (an edge with one face) or a fold: a triangle with an
//! edge there has no neighbour beyond it (or one in its own plane), so it is bounded on its full distance.
std::array<bool, 4> open_sides(const Context& cx, const LimitTessellationPlan::Domain& d) {
    std::array<bool, 4> open{};
    const std::size_t n = cx.faces[d.face].size;
    for (int k = 0; k < 4; ++k) {
        if (d.subface >= 0 && (k == 1 || k == 2)) continue;  // spokes
        const std::size_t fe = d.subface < 0 ? std::size_t(k)
                               : k == 0      ? std::size_t(d.subface)
                                             : (std::size_t(d.subface) + n - 1) % n;
        const std::size_t e = cx.face_edges[d.face][fe].edge;
        open[std::size_t(k)] = cx.edge_faces[e] == 1 || cx.fold_edge[e];
    }
    return open;
}

//! Builds edges, prepares every face, and plans.
Result<LimitTessellationPlan> plan(Context& cx) {
    const PolygonMesh& base = cx.base;
    const LimitTessellationOptions& options = cx.options;
    if (!std::isfinite(options.tolerance) || options.tolerance <= 0)
        return make_error(ErrorCode::InvalidArgument, "tolerance must be a finite number > 0");
    if (options.max_segments < 1 || options.max_segments > 4096)
        return make_error(ErrorCode::InvalidArgument, "max_segments must be in [1, 4096]");
    if (!(options.straddle >= 0 && options.straddle < 1))
        return make_error(ErrorCode::InvalidArgument, "straddle must be at least 0 and below 1");
    const std::size_t face_count = base.face_count();
    cx.hole.assign(face_count, false);
    for (Index h : base.tags.holes)
        if (h < face_count) cx.hole[h] = true;
    cx.faces.resize(face_count);
    cx.face_edges.resize(face_count);
    cx.first_domain.assign(face_count + 1, 0);
    cx.first_spoke.assign(face_count + 1, 0);

    // edges in order of first use, and each face's domains
    LimitTessellationPlan out;
    std::map<std::pair<Index, Index>, std::size_t> edge_ids;
    for (std::size_t f = 0; f < face_count; ++f) {
        cx.first_domain[f] = out.domains.size();
        cx.first_spoke[f] = cx.spokes;
        if (cx.hole[f]) continue;
        const auto fv = base.face(f);
        const std::size_t n = fv.size();
        for (std::size_t k = 0; k < n; ++k) {
            const Index a = fv[k], b = fv[(k + 1) % n];
            const auto key = std::minmax(a, b);
            auto [it, inserted] = edge_ids.emplace(std::pair{key.first, key.second}, cx.edges.size());
            if (inserted) {
                cx.edges.push_back({a, b});
                cx.edge_owner.push_back(f);
                cx.edge_owner_side.push_back(std::uint32_t(k));
                cx.edge_faces.push_back(0);
                cx.halved.push_back(false);
            }
            cx.face_edges[f].push_back({it->second, cx.edges[it->second][0] == a});
            ++cx.edge_faces[it->second];
            if (n != 4) cx.halved[it->second] = true;
        }
        if (n == 4) {
            out.domains.push_back({std::uint32_t(f), -1, 1, 1, {1, 1, 1, 1}, {}, {}, {}});
        } else {
            for (std::size_t j = 0; j < n; ++j)
                out.domains.push_back({std::uint32_t(f), std::int32_t(j), 1, 1, {1, 1, 1, 1}, {}, {}, {}});
            cx.spokes += n;
        }
    }
    cx.first_domain[face_count] = out.domains.size();
    cx.first_spoke[face_count] = cx.spokes;
    // folds: an edge's two faces with the same corners
    cx.fold_edge.assign(cx.edges.size(), false);
    {
        std::vector<std::size_t> first_face(cx.edges.size(), face_count);
        const auto corners = [&](std::size_t f) {
            const auto fv = base.face(f);
            std::vector<Index> sorted(fv.begin(), fv.end());
            std::sort(sorted.begin(), sorted.end());
            return sorted;
        };
        for (std::size_t f = 0; f < face_count; ++f) {
            if (cx.hole[f]) continue;
            for (const EdgeUse& use : cx.face_edges[f]) {
                if (cx.edge_faces[use.edge] != 2) continue;
                if (first_face[use.edge] == face_count) {
                    first_face[use.edge] = f;
                } else {
                    cx.fold_edge[use.edge] = corners(first_face[use.edge]) == corners(f);
                }
            }
        }
    }
    // where the surface is only C0 (infinitely sharp creases and corners, open boundaries, non-manifold edges, folds):
    // the faces there have different normals, so vertices stay on the surface (straddle_offset is per face)
    cx.fixed_edge.assign(cx.edges.size(), false);
    cx.fixed_vertex.assign(base.vertex_count(), false);
    {
        std::map<std::pair<Index, Index>, double> sharp;
        for (const auto& c : base.tags.creases)
            sharp[std::minmax(c.v0, c.v1)] = std::max(sharp[std::minmax(c.v0, c.v1)], c.sharpness);
        for (std::size_t e = 0; e < cx.edges.size(); ++e) {
            const auto found = sharp.find(std::minmax(cx.edges[e][0], cx.edges[e][1]));
            cx.fixed_edge[e] = cx.edge_faces[e] != 2 || cx.fold_edge[e] ||
                               (found != sharp.end() && found->second >= double(kInfiniteSharpness));
            if (cx.fixed_edge[e]) cx.fixed_vertex[cx.edges[e][0]] = cx.fixed_vertex[cx.edges[e][1]] = true;
        }
        for (const auto& c : base.tags.corners)
            if (c.vertex < base.vertex_count() && c.sharpness >= double(kInfiniteSharpness))
                cx.fixed_vertex[c.vertex] = true;
    }
    // slots: each edge's (two for a halved one), then each spoke's; and a face to name in errors
    std::vector<std::size_t> slot_face;
    cx.edge_slot.resize(cx.edges.size());
    for (std::size_t e = 0; e < cx.edges.size(); ++e) {
        cx.edge_slot[e] = slot_face.size();
        slot_face.insert(slot_face.end(), cx.halved[e] ? 2 : 1, cx.edge_owner[e]);
    }
    cx.first_spoke_slot = slot_face.size();
    for (std::size_t f = 0; f < face_count; ++f)
        slot_face.insert(slot_face.end(), cx.first_spoke[f + 1] - cx.first_spoke[f], f);
    cx.slots.assign(slot_face.size(), Slot{});
    for (Slot& slot : cx.slots) slot.rho.fill(1.0);
    out.edge_rates.assign(cx.edges.size(), 1);

    // raises the slots along side k of domain d, over its fractions [lo, hi], to rho segments per unit of the side
    const auto raise_side = [&](const LimitTessellationPlan::Domain& d, int k, double lo, double hi, double rho) {
        int parts = 0;
        const auto sides = cx.side_parts(d, k, parts);
        for (int p = 0; p < parts; ++p) {
            const SidePart& part = sides[std::size_t(p)];
            const double a = std::max(lo, part.q0), b = std::min(hi, part.q1);
            if (!(b > a)) continue;
            const double w = part.q1 - part.q0;
            double x0 = (a - part.q0) / w, x1 = (b - part.q0) / w;
            if (part.reversed) std::tie(x0, x1) = std::pair{1.0 - x1, 1.0 - x0};
            raise(cx.slots[part.slot].rho, x0, x1, rho * w);
        }
    };
    // the sides follow the domain's inner densities (s along sides 0 and 2, t along 1 and 3; sides 2 and 3 run
    // backwards), so that an edge is fine only where a face on it is
    const auto push_density = [&](const LimitTessellationPlan::Domain& d, const Density& rs, const Density& rt) {
        for (int k = 0; k < 4; ++k)
            for (int b = 0; b < kBins; ++b) {
                const Density& rho = k % 2 == 0 ? rs : rt;
                raise_side(d, k, double(b) / kBins, double(b + 1) / kBins, rho[std::size_t(k < 2 ? b : kBins - 1 - b)]);
            }
    };
    const auto update_slots = [&]() -> Status {
        // measured rates never raise a side, so a halved edge keeps equal halves at the larger rate (the sides
        // stay at least as fine as every inner grid next to them)
        for (std::size_t e = 0; e < cx.edges.size() && !options.guaranteed; ++e)
            if (cx.halved[e]) {
                Density& a = cx.slots[cx.edge_slot[e]].rho;
                Density& b = cx.slots[cx.edge_slot[e] + 1].rho;
                const double top =
                    std::max(*std::max_element(a.begin(), a.end()), *std::max_element(b.begin(), b.end()));
                a.fill(top);
                b.fill(top);
            }
        for (std::size_t i = 0; i < cx.slots.size(); ++i) {
            Slot& slot = cx.slots[i];
            std::tie(slot.count, slot.lines) = grid_lines(slot.rho);
            if (slot.count > options.max_segments) return too_many_segments(slot.count, options, slot_face[i]);
        }
        for (std::size_t e = 0; e < cx.edges.size(); ++e) out.edge_rates[e] = cx.edge_count(e);
        return Ok{};
    };

    // demands: each face's patches and the grids its domains need, on their own (on two threads when allowed:
    // the faces cut in two halves by count, every face computed the same way), then applied in face order
    std::vector<Graded> grades(out.domains.size());
    std::vector<std::optional<GeoError>> failed(face_count);  // per face, the error its work stopped at
    std::vector<char> computed(out.domains.size(), 0);
    const std::size_t half = options.threads == 1 ? face_count : face_count / 2;
    run_two_parts(options.threads != 1 && half > 0, [&](int part) {
        const std::size_t from = part == 0 ? 0 : half, to = part == 0 ? half : face_count;
        std::uint64_t own = 0;  // this part's grids so far: a lower bound on the output
        for (std::size_t f = from; f < to; ++f) {
            if (cx.hole[f]) continue;
            if (options.cancel.requested()) {
                failed[f] = make_error(ErrorCode::Cancelled, "tessellation cancelled");
                return;
            }
            auto surface = cx.evaluator.face_surface(f, kTreeLevels);
            if (!surface) {
                failed[f] = surface.error();
                return;
            }
            FaceData& fd = cx.faces[f];
            fd.surface = std::move(surface.value());
            fd.size = base.face_size(f);
            fd.lift = options.guaranteed ? options.straddle * options.tolerance : 0.0;
            if (fd.lift > 0) {
                const auto fv = base.face(f);
                for (std::size_t k = 0; k < fv.size(); ++k) {
                    fd.fixed_edge.push_back(cx.fixed_edge[cx.face_edges[f][k].edge]);
                    fd.fixed_vertex.push_back(cx.fixed_vertex[fv[k]]);
                }
            }
            fd.patches.resize(fd.surface->patch_count());
            for (std::size_t p = 0; p < fd.patches.size(); ++p) fd.patches[p] = patch_data(fd.surface->patch_points(p));
            for (std::size_t di = cx.first_domain[f]; di < cx.first_domain[f + 1]; ++di) {
                auto& d = out.domains[di];
                if (options.guaranteed) {
                    auto demand = graded_demand(fd, f, d.subface, options);
                    if (!demand) {
                        failed[f] = demand.error();
                        return;
                    }
                    grades[di] = std::move(demand.value());
                    computed[di] = 1;
                    // this part's grids alone over the budget: so is the running total in face order, at this
                    // domain or before it, where the application below stops
                    own += 2 * std::uint64_t(grades[di].nu) * std::uint64_t(grades[di].nv);
                    if (options.max_triangles > 0 && own > options.max_triangles) return;
                } else {
                    auto demand = domain_demand(fd, f, d.subface, options);
                    if (!demand) {
                        failed[f] = demand.error();
                        return;
                    }
                    d.nu = demand->first;
                    d.nv = demand->second;
                    computed[di] = 1;
                }
            }
        }
    });
    // in face order, as one thread would have: the running total over the budget, or the first error
    std::uint64_t demanded = 0;
    for (std::size_t f = 0; f < face_count; ++f) {
        if (cx.hole[f]) continue;
        for (std::size_t di = cx.first_domain[f]; di < cx.first_domain[f + 1] && computed[di]; ++di) {
            auto& d = out.domains[di];
            if (options.guaranteed) {
                const Graded& g = grades[di];
                d.nu = g.nu;
                d.nv = g.nv;
                d.s_lines = g.s_lines;
                d.t_lines = g.t_lines;
                d.staggered = g.staggered;
                push_density(d, g.rs, g.rt);
                // rates only grow from here: the grids so far are a lower bound on the output
                demanded += 2 * std::uint64_t(d.nu) * std::uint64_t(d.nv);
                if (auto status = check_budget(demanded, options); !status) return status.error();
            } else {
                Density rs, rt;
                rs.fill(double(d.nu));
                rt.fill(double(d.nv));
                push_density(d, rs, rt);
            }
        }
        if (failed[f]) return *failed[f];
        for (std::size_t di = cx.first_domain[f]; di < cx.first_domain[f + 1]; ++di)
            if (!computed[di]) return make_error(ErrorCode::BudgetExceeded, "tessellation stopped over the budget");
    }
    if (auto status = update_slots(); !status) return status.error();

    // sides, then the transition check: every triangle of the actual layout bounded (or sampled) within tolerance.
    // A graded domain's failing triangles raise its densities where they lie and, in a transition strip, the density
    // of that side's edge or spoke over the part the triangle spans (then every domain on it is checked again); a
    // uniform domain's raise its inner rates.
    const auto count = [&] {
        std::uint64_t triangles = 0;
        for (auto& d : out.domains) triangles += domain_triangles(d);
        return triangles;
    };
    // each side's points from its slots: a side of a quad on a halved edge runs over both halves
    const auto set_sides = [&](LimitTessellationPlan::Domain& d) {
        for (int k = 0; k < 4; ++k) {
            int parts = 0;
            const auto sides = cx.side_parts(d, k, parts);
            std::vector<double> lines{0.0};
            for (int p = 0; p < parts; ++p) {
                const SidePart& part = sides[std::size_t(p)];
                const Slot& slot = cx.slots[part.slot];
                for (int i = 1; i <= slot.count; ++i) {
                    const double x = part.reversed ? 1.0 - slot.at(slot.count - i) : slot.at(i);
                    lines.push_back(part.q0 + (part.q1 - part.q0) * x);
                }
            }
            const int r = int(lines.size()) - 1;
            d.side[k] = r;
            bool uniform = true;
            for (int i = 0; i <= r && uniform; ++i) uniform = std::abs(lines[std::size_t(i)] - double(i) / r) <= 1e-12;
            if (uniform) lines.clear();
            d.side_lines[std::size_t(k)] = std::move(lines);
        }
        fix_inner(d);
    };
    for (auto& d : out.domains) set_sides(d);
    if (auto status = check_budget(count(), options); !status) return status.error();
    std::vector<bool> dirty(out.domains.size(), true);
    std::vector<double> domain_bound(out.domains.size(), 0.0), domain_sampled(out.domains.size(), 0.0);
    for (int pass = 0;; ++pass) {
        bool any = false;
        for (std::size_t di = 0; di < out.domains.size(); ++di) {
            if (!dirty[di]) continue;
            dirty[di] = false;
            auto& d = out.domains[di];
            if (options.cancel.requested()) return make_error(ErrorCode::Cancelled, "tessellation cancelled");
            const FaceData& fd = cx.faces[d.face];
            Graded& g = grades[di];
            Density next_s = g.rs, next_t = g.rt;
            for (int attempt = 0;; ++attempt) {
                const LocalMesh local = triangulate(d);
                std::vector<OffsetPoint> positions;  // the vertices at the local points, for the triangles' planes
                if (options.guaranteed) {
                    positions.reserve(local.points.size());
                    for (const P2& q : local.points) {
                        auto p = corner_at(fd, d.subface, q);
                        if (!p) return p.error();
                        positions.push_back(*p);
                    }
                }
                const std::uint32_t ring = std::uint32_t(d.side[0] + d.side[1] + d.side[2] + d.side[3]);
                double bound = 0, sampled = 0, worst = 0;  // worst: the largest error ratio
                bool inner_fail = false;
                const std::array<bool, 4> open = open_sides(cx, d);
                for (const auto& tri : local.triangles) {
                    const P2 &a = local.points[tri[0]], &b = local.points[tri[1]], &c = local.points[tri[2]];
                    std::array<OffsetPoint, 3> corners{};
                    if (options.guaranteed) corners = {positions[tri[0]], positions[tri[1]], positions[tri[2]]};
                    auto error = triangle_error(fd, d.subface, open, a, b, c, corners, options.guaranteed);
                    if (!error) return error.error();
                    bound = std::max(bound, error->bound);
                    sampled = std::max(sampled, error->sampled);
                    const double ratio = error->ratio(options.tolerance);
                    worst = std::max(worst, ratio);
                    if (!options.guaranteed || ratio <= 1) continue;
                    // graded: refine where the triangle lies, and its side when it is in a transition strip
                    const double f = std::min(4.0, std::max(1.1, std::sqrt(ratio)));
                    const double lo_s = std::min({a.s, b.s, c.s}), hi_s = std::max({a.s, b.s, c.s});
                    const double lo_t = std::min({a.t, b.t, c.t}), hi_t = std::max({a.t, b.t, c.t});
                    raise(next_s, lo_s, hi_s, f / std::max(hi_s - lo_s, 1e-9));
                    raise(next_t, lo_t, hi_t, f / std::max(hi_t - lo_t, 1e-9));
                    inner_fail = true;
                    // the strip's side: the side every ring vertex of the triangle lies on (a corner is on two)
                    bool on_ring = false;
                    for (std::uint32_t v : tri) on_ring = on_ring || v < ring;
                    int side = -1;
                    for (int k = 0; k < 4 && side < 0 && on_ring; ++k) {
                        bool all = true;
                        for (std::uint32_t v : tri) {
                            if (v >= ring) continue;
                            const P2& q = local.points[v];
                            const bool on = k == 0 ? q.t == 0 : k == 1 ? q.s == 1 : k == 2 ? q.t == 1 : q.s == 0;
                            all = all && on;
                        }
                        if (all) side = k;
                    }
                    if (side >= 0) {
                        // the triangle's span along the side (sides 2 and 3 run backwards)
                        const double lo = side == 0 ? lo_s : side == 1 ? lo_t : side == 2 ? 1.0 - hi_s : 1.0 - hi_t;
                        const double hi = side == 0 ? hi_s : side == 1 ? hi_t : side == 2 ? 1.0 - lo_s : 1.0 - lo_t;
                        raise_side(d, side, lo, hi, f / std::max(hi - lo, 1e-9));
                    }
                }
                const bool ok = worst <= 1;
                if (options.guaranteed) {
                    domain_bound[di] = bound;
                    domain_sampled[di] = sampled;
                    if (ok || pass >= 30) break;
                    any = true;
                    if (inner_fail) {
                        g.rs = next_s;
                        g.rt = next_t;
                        if (auto status = regrade(g, options, d.face); !status) return status.error();
                        apply(g, d);
                        dirty[di] = true;
                    }
                    break;
                }
                if (ok || attempt >= 40 || std::max(d.nu, d.nv) >= options.max_segments) {
                    domain_bound[di] = bound;
                    domain_sampled[di] = sampled;
                    break;
                }
                d.nu = std::min(options.max_segments, d.nu + std::max(1, d.nu / 8));
                d.nv = std::min(options.max_segments, d.nv + std::max(1, d.nv / 8));
                fix_inner(d);
            }
        }
        if (!any) break;
        if (auto status = update_slots(); !status) return status.error();
        for (std::size_t di = 0; di < out.domains.size(); ++di) {
            auto& d = out.domains[di];
            const int before[4] = {d.side[0], d.side[1], d.side[2], d.side[3]};
            const auto lines_before = d.side_lines;
            set_sides(d);
            for (int k = 0; k < 4; ++k)
                if (d.side[k] != before[k] || d.side_lines[std::size_t(k)] != lines_before[std::size_t(k)])
                    dirty[di] = true;
        }
        if (auto status = check_budget(count(), options); !status) return status.error();
    }
    for (std::size_t di = 0; di < out.domains.size(); ++di) {
        out.error_bound = std::max(out.error_bound, domain_bound[di]);
        out.sampled_error = std::max(out.sampled_error, domain_sampled[di]);
    }
    out.triangles = count();
    if (auto status = check_budget(out.triangles, options); !status) return status.error();

    // vertices: base vertices and edge points once, N-gon centres and spoke points once, inner points per domain
    std::vector<bool> used(base.vertex_count(), false);
    std::uint64_t vertices = 0;
    for (std::size_t f = 0; f < face_count; ++f)
        if (!cx.hole[f])
            for (Index v : base.face(f))
                if (!used[v]) {
                    used[v] = true;
                    ++vertices;
                }
    for (int r : out.edge_rates) vertices += std::uint64_t(r - 1);
    for (std::size_t f = 0; f < face_count; ++f)
        if (!cx.hole[f] && cx.faces[f].size != 4) ++vertices;
    for (std::size_t sp = 0; sp < cx.spokes; ++sp)
        vertices += std::uint64_t(cx.slots[cx.first_spoke_slot + sp].count - 1);
    for (const auto& d : out.domains) vertices += inner_points(d).size();
    out.vertices = vertices;
    return out;
}

//! Face (u, v) of the point at fraction a along the face's edge k (corner k to corner k + 1).
std::pair<double, double> edge_uv(std::size_t n, std::size_t k, double a) {
    if (n == 4) {
        static constexpr double kCorners[5][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0}};
        return {kCorners[k][0] + a * (kCorners[k + 1][0] - kCorners[k][0]),
                kCorners[k][1] + a * (kCorners[k + 1][1] - kCorners[k][1])};
    }
    if (a <= 0.5) return face_uv(n, int(k), 2.0 * a, 0.0);
    return face_uv(n, int((k + 1) % n), 0.0, 2.0 * (1.0 - a));
}

}  // namespace

Result<LimitTessellationPlan> plan_limit_tessellation(const LimitSurfaceEvaluator& evaluator, const PolygonMesh& base,
                                                      const LimitTessellationOptions& options) {
    Context cx(evaluator, base, options);
    return plan(cx);
}

Result<LimitTessellation> tessellate_limit(const LimitSurfaceEvaluator& evaluator, const PolygonMesh& base,
                                           const LimitTessellationOptions& options) {
    if (evaluator.face_count() != base.face_count())
        return make_error(ErrorCode::InvalidArgument, "the evaluator was created from another mesh");
    Context cx(evaluator, base, options);
    auto planned = plan(cx);
    if (!planned) return planned.error();
    LimitTessellation out;
    out.plan = std::move(planned.value());
    const LimitTessellationPlan& p = out.plan;
    const std::size_t face_count = base.face_count();

    // 1. vertex ids and where each is evaluated
    std::vector<LimitSite>& sites = out.sites;
    sites.reserve(p.vertices);
    std::vector<Index> vertex_id(base.vertex_count(), kInvalidIndex);
    std::vector<bool> fixed;  // per site: on a C0 feature (Context::fixed_edge), so on the surface
    for (std::size_t f = 0; f < face_count; ++f) {
        if (cx.hole[f]) continue;
        const auto fv = base.face(f);
        for (std::size_t k = 0; k < fv.size(); ++k)
            if (vertex_id[fv[k]] == kInvalidIndex) {
                vertex_id[fv[k]] = Index(sites.size());
                fixed.push_back(cx.fixed_vertex[fv[k]]);
                const auto [u, v] = edge_uv(fv.size(), k, 0.0);
                sites.push_back({std::uint32_t(f), u, v});
            }
    }
    std::vector<std::vector<Index>> edge_points(cx.edges.size());
    for (std::size_t e = 0; e < cx.edges.size(); ++e) {
        const int r = p.edge_rates[e];
        auto& pts = edge_points[e];
        pts.push_back(vertex_id[cx.edges[e][0]]);
        const std::size_t f = cx.edge_owner[e];
        for (int i = 1; i < r; ++i) {
            pts.push_back(Index(sites.size()));
            fixed.push_back(cx.fixed_edge[e]);
            const auto [u, v] = edge_uv(base.face_size(f), cx.edge_owner_side[e], cx.edge_at(e, i));
            sites.push_back({std::uint32_t(f), u, v});
        }
        pts.push_back(vertex_id[cx.edges[e][1]]);
    }
    std::vector<std::vector<Index>> spoke_points(cx.spokes);
    for (std::size_t f = 0; f < face_count; ++f) {
        if (cx.hole[f] || base.face_size(f) == 4) continue;
        const std::size_t n = base.face_size(f);
        const Index centre = Index(sites.size());
        const auto [cu, cv] = face_uv(n, 0, 1.0, 1.0);
        sites.push_back({std::uint32_t(f), cu, cv});
        for (std::size_t j = 0; j < n; ++j) {
            const std::size_t sp = cx.first_spoke[f] + j;
            const Slot& slot = cx.slots[cx.spoke_slot(f, j)];
            const int r = slot.count;
            const auto& use = cx.face_edges[f][j];
            const int half = cx.slots[cx.edge_slot[use.edge]].count;  // the midpoint's canonical index
            auto& pts = spoke_points[sp];
            pts.push_back(edge_points[use.edge][std::size_t(half)]);
            for (int i = 1; i < r; ++i) {
                pts.push_back(Index(sites.size()));
                const auto [u, v] = face_uv(n, int(j), 1.0, slot.at(i));
                sites.push_back({std::uint32_t(f), u, v});
            }
            pts.push_back(centre);
        }
    }
    std::vector<Index> first_inner(p.domains.size());
    for (std::size_t di = 0; di < p.domains.size(); ++di) {
        const auto& d = p.domains[di];
        first_inner[di] = Index(sites.size());
        for (const P2& q : inner_points(d)) {
            const auto [u, v] = face_uv(cx.faces[d.face].size, d.subface, q.s, q.t);
            sites.push_back({d.face, u, v});
        }
    }

    // 2. evaluate every vertex once, face by face
    PolygonMesh& mesh = out.mesh;
    mesh.positions.resize(sites.size());
    mesh.normals.resize(sites.size());
    std::vector<Vec3> offsets(sites.size());  // each vertex's offset from the surface (straddle)
    {
        std::vector<std::vector<Index>> by_face(face_count);
        for (std::size_t i = 0; i < sites.size(); ++i) by_face[sites[i].face].push_back(Index(i));
        for (std::size_t f = 0; f < face_count; ++f) {
            if (by_face[f].empty()) continue;
            if (options.cancel.requested()) return make_error(ErrorCode::Cancelled, "tessellation cancelled");
            for (Index i : by_face[f]) {
                auto sample = cx.faces[f].surface->evaluate(sites[i].u, sites[i].v, cx.faces[f].lift > 0);
                if (!sample) return sample.error();
                if (i >= fixed.size() || !fixed[i]) offsets[i] = straddle_offset(*sample, cx.faces[f].lift);
                mesh.positions[i] = sample->position + offsets[i];
                mesh.normals[i] = sample->normal;
            }
        }
    }

    // 3. triangles per domain, with their corners' (s, t)
    std::vector<DomainTriangle> triangles;
    triangles.reserve(p.triangles);
    for (std::size_t di = 0; di < p.domains.size(); ++di) {
        const auto& d = p.domains[di];
        const std::size_t f = d.face, n = base.face_size(f);
        const LocalMesh local = triangulate(d);
        // side point ids in traversal order
        std::array<std::vector<Index>, 4> side;
        const auto edge_range = [&](std::size_t k, int from, int count) {
            // `count` points from face-direction index `from` of face edge k
            const auto& use = cx.face_edges[f][k];
            const auto& pts = edge_points[use.edge];
            const int r = p.edge_rates[use.edge];
            std::vector<Index> ids;
            for (int i = 0; i < count; ++i) {
                const int fi = from + i;
                ids.push_back(pts[std::size_t(use.forward ? fi : r - fi)]);
            }
            return ids;
        };
        if (d.subface < 0) {
            for (std::size_t k = 0; k < 4; ++k) side[k] = edge_range(k, 0, d.side[k] + 1);
        } else {
            const auto j = std::size_t(d.subface), prev = (j + n - 1) % n;
            side[0] = edge_range(j, 0, d.side[0] + 1);
            // the previous edge's second half in the face's direction: from its midpoint to corner j
            const auto& use = cx.face_edges[f][prev];
            const int mid = cx.slots[cx.edge_slot[use.edge] + (use.forward ? 0 : 1)].count;
            side[3] = edge_range(prev, mid, d.side[3] + 1);
            side[1] = spoke_points[cx.first_spoke[f] + j];
            side[2] = spoke_points[cx.first_spoke[f] + prev];
            std::reverse(side[2].begin(), side[2].end());
        }
        std::vector<Index> ids;
        ids.reserve(local.points.size());
        for (int k = 0; k < 4; ++k)
            for (int i = 0; i < d.side[k]; ++i) ids.push_back(side[std::size_t(k)][std::size_t(i)]);
        const std::size_t ring = ids.size();
        for (std::size_t i = ring; i < local.points.size(); ++i) ids.push_back(first_inner[di] + Index(i - ring));
        for (const auto& tri : local.triangles)
            triangles.push_back({std::uint32_t(di),
                                 {ids[tri[0]], ids[tri[1]], ids[tri[2]]},
                                 {local.points[tri[0]], local.points[tri[1]], local.points[tri[2]]}});
    }

    // 4. vertices the tolerance does not need removed, then the unused ones dropped
    double error_bound = p.error_bound, sampled_error = p.sampled_error;
    if (options.guaranteed && options.decimate) {
        std::vector<DecimationDomain> domains;
        domains.reserve(p.domains.size());
        for (const auto& d : p.domains) domains.push_back({&cx.faces[d.face], d.subface, open_sides(cx, d)});
        auto decimated = decimate(triangles, mesh.positions, offsets, domains, options);
        if (!decimated) return decimated.error();
        out.removed_vertices = decimated->removed_vertices;
        error_bound = decimated->worst.bound;
        sampled_error = decimated->worst.sampled;
        if (out.removed_vertices > 0) {
            std::vector<Index> remap(sites.size(), kInvalidIndex);
            for (const auto& t : triangles)
                for (Index v : t.v) remap[v] = 0;
            Index next = 0;
            for (std::size_t i = 0; i < sites.size(); ++i)
                if (remap[i] != kInvalidIndex) {
                    remap[i] = next;
                    sites[next] = sites[i];
                    mesh.positions[next] = mesh.positions[i];
                    mesh.normals[next] = mesh.normals[i];
                    ++next;
                }
            sites.resize(next);
            mesh.positions.resize(next);
            mesh.normals.resize(next);
            for (auto& t : triangles)
                for (Index& v : t.v) v = remap[v];
        }
    }

    // 5. the output triangles, with UVs bilinear in each domain's (s, t) between its corners' UVs
    const bool uvs = base.has_uvs();
    mesh.face_offsets.reserve(triangles.size() + 1);
    mesh.face_indices.reserve(3 * triangles.size());
    out.face_of_triangle.reserve(triangles.size());
    std::size_t uv_domain = p.domains.size();
    std::array<Vec2, 4> corner_uv{};
    for (const DomainTriangle& tri : triangles) {
        const auto& d = p.domains[tri.domain];
        const std::size_t f = d.face, n = base.face_size(f);
        mesh.add_face(std::span<const Index>(tri.v.data(), 3));
        out.face_of_triangle.push_back(Index(f));
        if (!uvs) continue;
        if (uv_domain != tri.domain) {
            // corner UVs of the domain: the face's, or for a sub-face its corner, edge midpoints and the centre
            uv_domain = tri.domain;
            const auto uv_at = [&](std::size_t k) { return base.uvs[base.uv_indices[base.face_offsets[f] + k]]; };
            if (d.subface < 0) {
                for (std::size_t k = 0; k < 4; ++k) corner_uv[k] = uv_at(k);
            } else {
                const auto j = std::size_t(d.subface);
                const auto mid = [](const Vec2& a, const Vec2& b) {
                    return Vec2{0.5 * (a.x + b.x), 0.5 * (a.y + b.y)};
                };
                Vec2 centre{};
                for (std::size_t k = 0; k < n; ++k) {
                    centre.x += uv_at(k).x / double(n);
                    centre.y += uv_at(k).y / double(n);
                }
                corner_uv = {uv_at(j), mid(uv_at(j), uv_at((j + 1) % n)), centre,
                             mid(uv_at(j), uv_at((j + n - 1) % n))};
            }
        }
        for (const P2& q : tri.p) {
            mesh.uv_indices.push_back(Index(mesh.uvs.size()));
            const double w[4] = {(1 - q.s) * (1 - q.t), q.s * (1 - q.t), q.s * q.t, (1 - q.s) * q.t};
            Vec2 uv{};
            for (int k = 0; k < 4; ++k) {
                uv.x += w[k] * corner_uv[std::size_t(k)].x;
                uv.y += w[k] * corner_uv[std::size_t(k)].y;
            }
            mesh.uvs.push_back(uv);
        }
    }
    out.achieved_error = std::max(error_bound, sampled_error);
    return out;
}

}  // namespace surfaced
