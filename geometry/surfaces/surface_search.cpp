// Branch and bound over Bézier pieces (see surface_search.h). A piece is a sub-patch of one of the surface's Bézier
// patches with its parameter rectangle inside that patch; its bound comes from its control points. For the closest
// point the bound is the larger of the distances from the query to two boxes holding the control points: the
// axis-aligned one and two aligned with the piece's own frame (its normal and its net's u or v direction), whose
// thickness along the normal shrinks quadratically with the piece, so the proof needs few levels of splitting.
#include "geometry/surfaces/surface_search.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <queue>
#include <string>
#include <vector>

#include "geometry/core/format_number.h"

namespace surfaced {
namespace {

Vec3 normalized(const Vec3& v) { return v * (1.0 / norm(v)); }

std::string num(double v) { return shortest_text(v); }

//! A piece of patch `patch` over [s0, s1] x [t0, t1] of that patch's [0, 1]^2, its control net in `net`.
struct Piece {
    std::size_t patch = 0;
    double s0 = 0, s1 = 1, t0 = 0, t1 = 1;
    BezierPatch net;
    double bound = 0;  //!< lower bound on the objective over the piece (closest point: distance)
};

struct ByBound {
    bool operator()(const Piece& a, const Piece& b) const { return a.bound > b.bound; }  // min-heap
};

//! Splits `in` at the parameter midpoint along u (along_u) or v into `low` and `high`, in homogeneous coordinates.
void split(const BezierPatch& in, bool along_u, BezierPatch& low, BezierPatch& high) {
    const int p = in.degree_u, q = in.degree_v;
    low = in;
    high = in;
    const int lines = along_u ? q + 1 : p + 1, length = along_u ? p + 1 : q + 1;
    const auto index = [&](int line, int k) {
        return static_cast<std::size_t>(along_u ? line * (p + 1) + k : k * (p + 1) + line);
    };
    std::array<Vec3, kMaxPatchDegree + 1> hp;
    std::array<double, kMaxPatchDegree + 1> w;
    std::array<Vec3, kMaxPatchDegree + 1> e;
    for (int line = 0; line < lines; ++line) {
        bool same = true;
        for (int k = 0; k < length; ++k) {
            w[static_cast<std::size_t>(k)] = in.rational() ? in.weights[index(line, k)] : 1.0;
            e[static_cast<std::size_t>(k)] = in.points[index(line, k)];
            hp[static_cast<std::size_t>(k)] = w[static_cast<std::size_t>(k)] * e[static_cast<std::size_t>(k)];
            same = same && e[static_cast<std::size_t>(k)] == e[0];
        }
        const auto store = [&](BezierPatch& out, int k, std::size_t from) {
            out.points[index(line, k)] = same ? e[0] : hp[from] * (1.0 / w[from]);
            if (in.rational()) out.weights[index(line, k)] = w[from];
        };
        // de Casteljau at 1/2: after level r, entry 0 is low's point r and entry length-1-r is high's
        store(low, 0, 0);
        store(high, length - 1, static_cast<std::size_t>(length - 1));
        for (int r = 1; r < length; ++r) {
            for (int k = 0; k + r < length; ++k) {
                const auto a = static_cast<std::size_t>(k);
                hp[a] = 0.5 * (hp[a] + hp[a + 1]);
                w[a] = 0.5 * (w[a] + w[a + 1]);
            }
            store(low, r, 0);
            store(high, length - 1 - r, static_cast<std::size_t>(length - 1 - r));
        }
    }
}

//! Distance from q to the box [lo, hi] per axis, coordinates given in some orthonormal frame.
double box_distance(const Vec3& q, const Vec3& lo, const Vec3& hi) {
    double sum = 0;
    for (int c = 0; c < 3; ++c) {
        const double d = q[c] < lo[c] ? lo[c] - q[c] : q[c] > hi[c] ? q[c] - hi[c] : 0.0;
        sum += d * d;
    }
    return std::sqrt(sum);
}

//! Lower bound on the distance from `query` to the patch: the larger of the distances to its axis-aligned box and to
//! its box in the frame of its net, less a rounding allowance.
double distance_bound(const BezierPatch& net, const Vec3& query) {
    Box3 box;
    for (const Vec3& p : net.points) box.add(p);
    double bound = box_distance(query, box.min, box.max);
    const int p = net.degree_u, q = net.degree_v;
    Vec3 tu = (net.at(p, 0) - net.at(0, 0)) + (net.at(p, q) - net.at(0, q));
    Vec3 tv = (net.at(0, q) - net.at(0, 0)) + (net.at(p, q) - net.at(p, 0));
    Vec3 n = cross(tu, tv);
    const double scale = norm(box.max) + norm(box.min) + norm(query);
    if (norm(tu) > 0 && norm(tv) > 0 && norm(n) > 1e-6 * norm(tu) * norm(tv)) {
        n = normalized(n);
        // two frames, one with an axis along the net's u direction and one along its v direction: where the minimum
        // lies on an edge of the piece along a skewed parametrisation, one of them has that edge at a constant
        // coordinate, so the bound approaches the distance quadratically as the piece shrinks
        for (const Vec3& axis : {normalized(tu), normalized(tv)}) {
            const Vec3 other = cross(n, axis);
            const auto frame = [&](const Vec3& x) { return Vec3{dot(x, axis), dot(x, other), dot(x, n)}; };
            Box3 local;
            for (const Vec3& x : net.points) local.add(frame(x));
            bound = std::max(bound, box_distance(frame(query), local.min, local.max));
        }
    }
    return std::max(0.0, bound - 1e-15 * scale);
}

double automatic_tolerance(const SurfaceBezierPatches& patches, const Vec3& query) {
    Box3 box;
    for (const BezierPatch& patch : patches.patches)
        for (const Vec3& p : patch.points) box.add(p);
    return 1e-9 * (box.diagonal() + box_distance(query, box.min, box.max));
}

struct Candidate {
    std::size_t patch = 0;
    double s = 0, t = 0;
    Vec3 point;
    double distance = std::numeric_limits<double>::infinity();
    bool converged = false;
};

//! Projected Newton on f = |S(s, t) - query|^2 / 2 over the patch's [0, 1]^2 from (s, t), with backtracking (a step
//! is taken when f does not grow beyond rounding, since near the minimum f cannot resolve the last digits of the
//! parameters while the gradient still can). Returns the last iterate; converged when S is at the query, S - query
//! is orthogonal to the free tangents to 1e-10 in the cosine, or the full Newton step is below 1e-14.
Candidate newton(const BezierPatch& patch, std::size_t index, double s, double t, const Vec3& query, int iterations,
                 double size) {
    Candidate out{index, s, t, {}, 0, false};
    PatchDerivatives D = evaluate_derivatives(patch, s, t);
    for (int it = 0; it < iterations; ++it) {
        const Vec3 r = D.position - query;
        const double rn = norm(r);
        if (rn <= 1e-12 * size) {
            out.converged = true;
            break;
        }
        double gs = dot(D.du, r), gt = dot(D.dv, r);
        // components held on the boundary: at a bound with the gradient pointing out of the square
        const bool hold_s = (s <= 0 && gs > 0) || (s >= 1 && gs < 0);
        const bool hold_t = (t <= 0 && gt > 0) || (t >= 1 && gt < 0);
        const double cs = hold_s ? 0.0 : std::abs(gs) / (norm(D.du) * rn + 1e-300);
        const double ct = hold_t ? 0.0 : std::abs(gt) / (norm(D.dv) * rn + 1e-300);
        if (cs <= 1e-10 && ct <= 1e-10) {
            out.converged = true;
            break;
        }
        double h00 = dot(D.du, D.du) + dot(D.duu, r), h01 = dot(D.du, D.dv) + dot(D.duv, r);
        double h11 = dot(D.dv, D.dv) + dot(D.dvv, r);
        if (hold_s) {
            gs = 0;
            h01 = 0;
            h00 = 1;
        }
        if (hold_t) {
            gt = 0;
            h01 = 0;
            h11 = 1;
        }
        double det = h00 * h11 - h01 * h01;
        if (!(h00 > 0 && det > 1e-14 * (h00 * h00 + h11 * h11))) {  // not convex here: Gauss-Newton
            h00 = hold_s ? 1 : dot(D.du, D.du);
            h11 = hold_t ? 1 : dot(D.dv, D.dv);
            h01 = (hold_s || hold_t) ? 0 : dot(D.du, D.dv);
            const double damp = 1e-9 * (h00 + h11) + 1e-300;
            h00 += damp;
            h11 += damp;
            det = h00 * h11 - h01 * h01;
        }
        double ds = -(h11 * gs - h01 * gt) / det, dt = -(h00 * gt - h01 * gs) / det;
        if (!std::isfinite(ds) || !std::isfinite(dt)) break;
        if (std::abs(ds) + std::abs(dt) <= 1e-14) {
            out.converged = true;
            break;
        }
        const double f = 0.5 * rn * rn;
        bool moved = false;
        for (int halving = 0; halving < 40; ++halving) {
            const double ns = std::clamp(s + ds, 0.0, 1.0), nt = std::clamp(t + dt, 0.0, 1.0);
            const PatchDerivatives E = evaluate_derivatives(patch, ns, nt);
            const Vec3 nr = E.position - query;
            if (0.5 * dot(nr, nr) <= f * (1 + 1e-13)) {
                s = ns;
                t = nt;
                D = E;
                moved = true;
                break;
            }
            ds *= 0.5;
            dt *= 0.5;
        }
        if (!moved) break;
    }
    out.s = s;
    out.t = t;
    out.point = D.position;
    out.distance = norm(D.position - query);
    return out;
}

//! The decomposition's patch (a, b) parameters -> the surface's.
void to_surface(const SurfaceBezierPatches& patches, std::size_t index, double s, double t, double& u, double& v) {
    const std::size_t nu = patches.breaks_u.size() - 1;
    const std::size_t a = index % nu, b = index / nu;
    const double u0 = patches.breaks_u[a], u1 = patches.breaks_u[a + 1];
    const double v0 = patches.breaks_v[b], v1 = patches.breaks_v[b + 1];
    u = s >= 1 ? u1 : u0 + s * (u1 - u0);
    v = t >= 1 ? v1 : v0 + t * (v1 - v0);
}

}  // namespace

Box3 control_hull_box(const BSplineSurface& surface) {
    Box3 box;
    for (const Vec3& p : surface.points) box.add(p);
    return box;
}

Result<SurfaceClosestPoint> closest_point(const BSplineSurface& surface, const Vec3& query,
                                          const SurfaceSearchOptions& options) {
    auto patches = to_bezier(surface, options.cancel);
    if (!patches) return patches.error();
    return closest_point(patches.value(), query, options);
}

Result<SurfaceClosestPoint> closest_point(const SurfaceBezierPatches& patches, const Vec3& query,
                                          const SurfaceSearchOptions& options) {
    if (!is_finite(query)) return make_error(ErrorCode::InvalidArgument, "the query point is not finite");
    if (!(std::isfinite(options.tolerance) && options.tolerance >= 0))
        return make_error(ErrorCode::InvalidArgument, "tolerance must be a finite number >= 0");
    if (patches.patches.empty()) return make_error(ErrorCode::InvalidArgument, "the surface has no Bézier patches");
    const double tolerance = options.tolerance > 0 ? options.tolerance : automatic_tolerance(patches, query);
    Box3 all;
    for (const BezierPatch& patch : patches.patches)
        for (const Vec3& p : patch.points) all.add(p);
    const double size = std::max(all.diagonal(), std::numeric_limits<double>::min());

    Candidate best;
    const auto consider = [&](const Candidate& c) {
        if (c.distance < best.distance || (c.distance == best.distance && c.converged && !best.converged)) best = c;
    };
    const auto corners = [&](const Piece& piece) {
        const BezierPatch& n = piece.net;
        const int p = n.degree_u, q = n.degree_v;
        const std::array<std::array<double, 2>, 4> st = {
            {{piece.s0, piece.t0}, {piece.s1, piece.t0}, {piece.s0, piece.t1}, {piece.s1, piece.t1}}};
        const std::array<Vec3, 4> xs = {n.at(0, 0), n.at(p, 0), n.at(0, q), n.at(p, q)};
        for (std::size_t k = 0; k < 4; ++k)
            consider({piece.patch, st[k][0], st[k][1], xs[k], norm(xs[k] - query), false});
    };

    std::priority_queue<Piece, std::vector<Piece>, ByBound> heap;
    for (std::size_t k = 0; k < patches.patches.size(); ++k) {
        Piece piece;
        piece.patch = k;
        piece.net = patches.patches[k];
        piece.bound = distance_bound(piece.net, query);
        corners(piece);
        heap.push(std::move(piece));
    }
    std::size_t splits = 0;
    double dropped = std::numeric_limits<double>::infinity();  // the smallest bound of a dropped piece
    while (!heap.empty()) {
        if (heap.top().bound >= best.distance - tolerance) break;  // nothing left can beat best by the tolerance
        if (splits >= options.max_subdivisions)
            return make_error(ErrorCode::BudgetExceeded,
                              "the closest point search needed more than " + std::to_string(options.max_subdivisions) +
                                  " patch splits to prove the global minimum within " + num(tolerance) +
                                  " (best distance found " + num(best.distance) + ", lower bound " +
                                  num(heap.top().bound) + "); the point may be equidistant from a large part of the " +
                                  "surface, or the tolerance too small");
        if (splits % 64 == 0 && options.cancel.requested())
            return make_error(ErrorCode::Cancelled, "cancelled while searching for the closest point");
        Piece piece = heap.top();
        heap.pop();
        ++splits;
        // refine: the piece's centre, and Newton from it when the centre improves on the best distance
        const double sc = 0.5 * (piece.s0 + piece.s1), tc = 0.5 * (piece.t0 + piece.t1);
        const Vec3 centre = evaluate(piece.net, 0.5, 0.5);
        const double dc = norm(centre - query);
        if (dc < best.distance) {
            consider({piece.patch, sc, tc, centre, dc, false});
            consider(
                newton(patches.patches[piece.patch], piece.patch, sc, tc, query, options.max_newton_iterations, size));
        }
        // split into four and keep the pieces that may still hold a better point
        BezierPatch low, high, parts[4];
        split(piece.net, true, low, high);
        split(low, false, parts[0], parts[2]);
        split(high, false, parts[1], parts[3]);
        const double s_bounds[3] = {piece.s0, sc, piece.s1}, t_bounds[3] = {piece.t0, tc, piece.t1};
        for (int k = 0; k < 4; ++k) {
            Piece child;
            child.patch = piece.patch;
            child.s0 = s_bounds[k % 2];
            child.s1 = s_bounds[k % 2 + 1];
            child.t0 = t_bounds[k / 2];
            child.t1 = t_bounds[k / 2 + 1];
            child.net = std::move(parts[k]);
            child.bound = distance_bound(child.net, query);
            corners(child);
            if (child.bound < best.distance - tolerance)
                heap.push(std::move(child));
            else
                dropped = std::min(dropped, child.bound);
        }
    }
    // a final polish of the best point (it may be a corner or a centre that no Newton run started from)
    // (taken when it converged and is no further than rounding away: the proof holds for it too)
    if (!best.converged) {
        const Candidate polished =
            newton(patches.patches[best.patch], best.patch, best.s, best.t, query, options.max_newton_iterations, size);
        if (polished.distance < best.distance ||
            (polished.converged && polished.distance <= best.distance + 1e-12 * (size + best.distance)))
            best = polished;
    }
    SurfaceClosestPoint out;
    to_surface(patches, best.patch, best.s, best.t, out.u, out.v);
    out.point = best.point;
    out.distance = best.distance;
    out.converged = best.converged;
    double lower = std::min(best.distance, dropped);
    if (!heap.empty()) lower = std::min(lower, heap.top().bound);
    out.gap = std::max(0.0, best.distance - lower);
    out.subdivisions = splits;
    return out;
}

Result<Box3> tight_bounding_box(const SurfaceBezierPatches& patches, const SurfaceSearchOptions& options) {
    if (!(std::isfinite(options.tolerance) && options.tolerance >= 0))
        return make_error(ErrorCode::InvalidArgument, "tolerance must be a finite number >= 0");
    if (patches.patches.empty()) return make_error(ErrorCode::InvalidArgument, "the surface has no Bézier patches");
    Box3 hull;
    for (const BezierPatch& patch : patches.patches)
        for (const Vec3& p : patch.points) hull.add(p);
    const double tolerance = options.tolerance > 0 ? options.tolerance : 1e-9 * hull.diagonal();
    Box3 out;
    // per axis c and side (sign +1: the maximum of x_c, -1: the minimum as the maximum of -x_c)
    for (int c = 0; c < 3; ++c)
        for (double sign : {1.0, -1.0}) {
            // bound = -(the largest sign * x_c of the net): the heap pops the piece that may reach furthest first
            const auto bound = [&](const BezierPatch& net) {
                double m = -std::numeric_limits<double>::infinity();
                for (const Vec3& p : net.points) m = std::max(m, sign * p[c]);
                return -m;
            };
            double best = -std::numeric_limits<double>::infinity();  // the largest sign * x_c on the surface so far
            const auto corners = [&](const BezierPatch& n) {
                for (const Vec3& p :
                     {n.at(0, 0), n.at(n.degree_u, 0), n.at(0, n.degree_v), n.at(n.degree_u, n.degree_v)})
                    best = std::max(best, sign * p[c]);
            };
            std::priority_queue<Piece, std::vector<Piece>, ByBound> heap;
            for (std::size_t k = 0; k < patches.patches.size(); ++k) {
                Piece piece;
                piece.net = patches.patches[k];
                piece.bound = bound(piece.net);
                corners(piece.net);
                heap.push(std::move(piece));
            }
            std::size_t side_splits = 0;
            double dropped = -std::numeric_limits<double>::infinity();  // the furthest reach of a dropped piece
            while (!heap.empty() && -heap.top().bound > best + tolerance) {
                if (side_splits >= options.max_subdivisions)
                    return make_error(ErrorCode::BudgetExceeded,
                                      "the tight bounding box needed more than " +
                                          std::to_string(options.max_subdivisions) +
                                          " patch splits on one side to reach the tolerance " + num(tolerance));
                if (side_splits % 64 == 0 && options.cancel.requested())
                    return make_error(ErrorCode::Cancelled, "cancelled while computing the tight bounding box");
                Piece piece = heap.top();
                heap.pop();
                ++side_splits;
                best = std::max(best, sign * evaluate(piece.net, 0.5, 0.5)[c]);
                BezierPatch low, high, parts[4];
                split(piece.net, true, low, high);
                split(low, false, parts[0], parts[2]);
                split(high, false, parts[1], parts[3]);
                for (BezierPatch& part : parts) {
                    Piece child;
                    child.bound = bound(part);
                    corners(part);
                    child.net = std::move(part);
                    if (-child.bound > best + tolerance)
                        heap.push(std::move(child));
                    else
                        dropped = std::max(dropped, -child.bound);
                }
            }
            // every piece's hull reaches at most this far, and the surface reaches `best`: report the hull's side
            // (it holds the surface, within the tolerance of best)
            double extreme = std::max(best, dropped);
            if (!heap.empty()) extreme = std::max(extreme, -heap.top().bound);
            if (sign > 0)
                out.max[c] = extreme;
            else
                out.min[c] = -extreme;
        }
    return out;
}

}  // namespace surfaced
