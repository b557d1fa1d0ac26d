// Trim loops: flattening by bisection of each Bézier piece until its control points lie within the flatness of its
// chord (then the piece, inside their convex hull, does too), the rules of trim_loops.h on the polygons, and the
// orientation. Segment pairs are tested on a uniform grid of buckets over the domain, so the intersection checks cost
// O(segments) for loops of evenly sized segments instead of O(segments^2).
#include "geometry/surfaces/trim_loops.h"

#include <algorithm>
#include <cmath>

#include "geometry/core/format_number.h"
#include "geometry/curves/bezier_curve.h"
#include "geometry/curves/bspline.h"

namespace surfaced {
namespace {

std::string num(double v) { return shortest_text(v); }

std::string point_text(Vec2 p) { return "(" + num(p.x) + ", " + num(p.y) + ")"; }

Vec2 xy(const Vec3& p) { return {p.x, p.y}; }

double cross2(Vec2 a, Vec2 b, Vec2 c) { return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x); }

double distance_to_segment(Vec2 p, Vec2 a, Vec2 b) {
    const double dx = b.x - a.x, dy = b.y - a.y, len2 = dx * dx + dy * dy;
    double t = len2 > 0 ? ((p.x - a.x) * dx + (p.y - a.y) * dy) / len2 : 0.0;
    t = std::clamp(t, 0.0, 1.0);
    const double ex = a.x + t * dx - p.x, ey = a.y + t * dy - p.y;
    return std::sqrt(ex * ex + ey * ey);
}

//! Closed segments a-b and c-d share a point.
bool segments_touch(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
    const double o1 = cross2(a, b, c), o2 = cross2(a, b, d), o3 = cross2(c, d, a), o4 = cross2(c, d, b);
    const auto between = [](Vec2 p, Vec2 q, Vec2 r) {  // r collinear with p-q lies on it
        return std::min(p.x, q.x) <= r.x && r.x <= std::max(p.x, q.x) && std::min(p.y, q.y) <= r.y &&
               r.y <= std::max(p.y, q.y);
    };
    if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0))) return true;
    return (o1 == 0 && between(a, b, c)) || (o2 == 0 && between(a, b, d)) || (o3 == 0 && between(c, d, a)) ||
           (o4 == 0 && between(c, d, b));
}

bool inside_polygon(const std::vector<Vec2>& ring, Vec2 p) {
    bool inside = false;
    for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
        const Vec2 a = ring[i], b = ring[j];
        if ((a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x) inside = !inside;
    }
    return inside;
}

double signed_area(const std::vector<Vec2>& ring) {
    double twice = 0;
    for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++)
        twice += ring[j].x * ring[i].y - ring[i].x * ring[j].y;
    return 0.5 * twice;
}

TrimError error_at(TrimErrorKind kind, TrimLoopKind loop_kind, int loop, int curve, std::string what) {
    TrimError e;
    e.kind = kind;
    e.loop_kind = loop_kind;
    e.loop = loop;
    e.curve = curve;
    e.message = trim_path(loop_kind, loop, curve) + ": " + std::move(what);
    return e;
}

struct Flattener {
    double flatness;
    const std::function<bool(Vec2, Vec2)>& refine;
    std::size_t max_segments;
    std::size_t* segments;
    const std::vector<double>& cut_u;
    const std::vector<double>& cut_v;

    //! Splits `piece` where it crosses a cut line between its ends, if it does: true and the two halves.
    bool cut(const BezierCurve& piece, BezierCurve& left, BezierCurve& right) const {
        const Vec3 a = piece.points.front(), b = piece.points.back();
        for (int axis = 0; axis < 2; ++axis) {
            const double from = axis == 0 ? a.x : a.y, to = axis == 0 ? b.x : b.y;
            for (const double line : axis == 0 ? cut_u : cut_v) {
                if (!((from < line && line < to) || (to < line && line < from))) continue;
                double lo = 0, hi = 1;  // the coordinate minus line changes sign on [lo, hi]
                for (int step = 0; step < 60; ++step) {
                    const double mid = 0.5 * (lo + hi);
                    const double c = axis == 0 ? evaluate(piece, mid).x : evaluate(piece, mid).y;
                    ((c < line) == (from < line) ? lo : hi) = mid;
                }
                auto halves = split(piece, 0.5 * (lo + hi));
                left = std::move(halves.first);
                right = std::move(halves.second);
                (axis == 0 ? left.points.back().x : left.points.back().y) = line;
                right.points.front() = left.points.back();
                return true;
            }
        }
        return false;
    }

    //! Appends the end points of the chords of `piece` (its start is already in `out`).
    bool run(const BezierCurve& piece, std::vector<Vec2>& out, int depth) const {
        if (depth < 48) {
            BezierCurve left, right;
            if (cut(piece, left, right)) return run(left, out, depth + 1) && run(right, out, depth + 1);
        }
        const Vec2 a = xy(piece.points.front()), b = xy(piece.points.back());
        bool flat = true;
        for (const Vec3& p : piece.points)
            if (distance_to_segment(xy(p), a, b) > flatness) {
                flat = false;
                break;
            }
        if (depth >= 48 || (flat && !(refine && refine(a, b)))) {
            if (++*segments > max_segments) return false;
            out.push_back(b);
            return true;
        }
        const auto [left, right] = split(piece, 0.5);
        return run(left, out, depth + 1) && run(right, out, depth + 1);
    }
};

}  // namespace

std::string trim_path(TrimLoopKind kind, int loop, int curve) {
    std::string path = (kind == TrimLoopKind::Outer ? "outer[" : "holes[") + std::to_string(loop) + "]";
    if (curve >= 0) path += "[" + std::to_string(curve) + "]";
    return path;
}

GeoError to_geo_error(const TrimError& error) {
    GeoError out = make_error(
        error.kind == TrimErrorKind::TooManySegments ? ErrorCode::BudgetExceeded : ErrorCode::InvalidArgument,
        error.message);
    out.element = error.loop;
    return out;
}

TrimValidation prepare_trims(const TrimmedSurface& trimmed, double flatness, double closure_tolerance,
                             std::size_t max_segments, const std::function<bool(Vec2, Vec2)>& refine,
                             const std::vector<double>& cut_u, const std::vector<double>& cut_v) {
    TrimValidation result;
    const BSplineSurface& surface = trimmed.surface;
    const auto [u0, u1] = domain_u(surface);
    const auto [v0, v1] = domain_v(surface);
    const double diagonal = std::hypot(u1 - u0, v1 - v0);
    const double gap_limit = closure_tolerance * diagonal;
    result.trims.flatness = flatness;
    std::size_t segments = 0;
    const Flattener flattener{flatness, refine, max_segments, &segments, cut_u, cut_v};

    // 1-3: curves, closure, domain; flattening
    for (const TrimLoopKind kind : {TrimLoopKind::Outer, TrimLoopKind::Hole}) {
        const std::vector<TrimLoop>& loops = kind == TrimLoopKind::Outer ? trimmed.outer : trimmed.holes;
        for (std::size_t l = 0; l < loops.size(); ++l) {
            const int loop = static_cast<int>(l);
            const TrimLoop& input = loops[l];
            if (input.curves.empty()) {
                result.error = error_at(TrimErrorKind::InvalidCurve, kind, loop, -1, "the loop has no curves");
                return result;
            }
            std::vector<BezierChain> chains;
            for (std::size_t c = 0; c < input.curves.size(); ++c) {
                const TrimCurve& curve = input.curves[c];
                BSplineCurve spline;
                spline.degree = curve.degree;
                spline.knots = curve.knots;
                spline.weights = curve.weights;
                for (const Vec2& p : curve.points) spline.points.push_back({p.x, p.y, 0});
                auto chain = to_bezier(spline);
                if (!chain) {
                    result.error =
                        error_at(TrimErrorKind::InvalidCurve, kind, loop, static_cast<int>(c), chain.error().message);
                    return result;
                }
                chains.push_back(std::move(chain.value()));
            }
            const std::size_t n = chains.size();
            for (std::size_t c = 0; c < n; ++c) {
                const Vec2 end = xy(chains[c].pieces.back().points.back());
                const Vec2 next = xy(chains[(c + 1) % n].pieces.front().points.front());
                const double gap = std::hypot(end.x - next.x, end.y - next.y);
                if (!(gap <= gap_limit)) {
                    TrimError e =
                        error_at(TrimErrorKind::OpenLoop, kind, loop, static_cast<int>(c),
                                 "ends at " + point_text(end) + " but " +
                                     trim_path(kind, loop, static_cast<int>((c + 1) % n)) + " starts at " +
                                     point_text(next) + ": the gap " + num(gap) + " exceeds the closure tolerance " +
                                     num(gap_limit) + " (relative to the domain's diagonal)");
                    e.other_kind = kind;
                    e.other_loop = loop;
                    e.other_curve = static_cast<int>((c + 1) % n);
                    result.error = e;
                    return result;
                }
                result.trims.max_gap = std::max(result.trims.max_gap, gap);
            }
            TrimPolygon polygon;
            polygon.kind = kind;
            polygon.loop = loop;
            for (std::size_t c = 0; c < n; ++c) {
                // each curve contributes its start and its chords' ends except the last (the next curve's start)
                const std::size_t first = polygon.points.size();
                polygon.points.push_back(xy(chains[c].pieces.front().points.front()));
                for (const BezierCurve& piece : chains[c].pieces)
                    if (!flattener.run(piece, polygon.points, 0)) {
                        result.error =
                            error_at(TrimErrorKind::TooManySegments, kind, loop, static_cast<int>(c),
                                     "flattening needs more than " + std::to_string(max_segments) + " segments");
                        return result;
                    }
                polygon.points.pop_back();
                polygon.segment_curves.insert(polygon.segment_curves.end(), polygon.points.size() - first,
                                              static_cast<int>(c));
            }
            for (std::size_t k = 0; k < polygon.points.size(); ++k) {
                Vec2& p = polygon.points[k];
                if (!(p.x >= u0 - gap_limit && p.x <= u1 + gap_limit && p.y >= v0 - gap_limit &&
                      p.y <= v1 + gap_limit)) {
                    result.error = error_at(TrimErrorKind::OutsideDomain, kind, loop, polygon.segment_curves[k],
                                            "passes through " + point_text(p) + ", outside the domain [" + num(u0) +
                                                ", " + num(u1) + "] x [" + num(v0) + ", " + num(v1) + "]");
                    return result;
                }
                p.x = std::clamp(p.x, u0, u1);
                p.y = std::clamp(p.y, v0, v1);
            }
            // drop repeated consecutive vertices (a curve of zero length, clamping)
            std::vector<Vec2> points;
            std::vector<int> curves;
            for (std::size_t k = 0; k < polygon.points.size(); ++k) {
                const Vec2 p = polygon.points[k];
                if (!points.empty() && p.x == points.back().x && p.y == points.back().y) continue;
                points.push_back(p);
                curves.push_back(polygon.segment_curves[k]);
            }
            while (points.size() > 1 && points.back().x == points.front().x && points.back().y == points.front().y) {
                points.pop_back();
                curves.pop_back();
            }
            polygon.points = std::move(points);
            polygon.segment_curves = std::move(curves);
            polygon.area = polygon.points.size() >= 3 ? signed_area(polygon.points) : 0.0;
            if (polygon.points.size() < 3) {
                result.error = error_at(TrimErrorKind::DegenerateLoop, kind, loop, -1, "the loop encloses no area");
                return result;
            }
            result.trims.loops.push_back(std::move(polygon));
        }
    }

    // 5-6: intersections, on a grid of buckets over the loops' box
    std::vector<TrimPolygon>& loops = result.trims.loops;
    struct Segment {
        std::size_t loop, index;
    };
    std::vector<Segment> all;
    Vec2 lo{u1, v1}, hi{u0, v0};
    for (std::size_t l = 0; l < loops.size(); ++l)
        for (std::size_t k = 0; k < loops[l].points.size(); ++k) {
            all.push_back({l, k});
            lo = {std::min(lo.x, loops[l].points[k].x), std::min(lo.y, loops[l].points[k].y)};
            hi = {std::max(hi.x, loops[l].points[k].x), std::max(hi.y, loops[l].points[k].y)};
        }
    const auto cells = static_cast<std::size_t>(std::clamp(std::sqrt(static_cast<double>(all.size())), 1.0, 2048.0));
    const double cw = std::max(hi.x - lo.x, 1e-300) / static_cast<double>(cells);
    const double ch = std::max(hi.y - lo.y, 1e-300) / static_cast<double>(cells);
    const auto cell_of = [&](double x, double origin, double size) {
        return std::min(cells - 1, static_cast<std::size_t>(std::max(0.0, (x - origin) / size)));
    };
    std::vector<std::vector<std::size_t>> buckets(cells * cells);
    const auto ends = [&](const Segment& s) {
        const std::vector<Vec2>& ring = loops[s.loop].points;
        return std::pair{ring[s.index], ring[(s.index + 1) % ring.size()]};
    };
    for (std::size_t s = 0; s < all.size(); ++s) {
        const auto [a, b] = ends(all[s]);
        for (std::size_t y = cell_of(std::min(a.y, b.y), lo.y, ch); y <= cell_of(std::max(a.y, b.y), lo.y, ch); ++y)
            for (std::size_t x = cell_of(std::min(a.x, b.x), lo.x, cw); x <= cell_of(std::max(a.x, b.x), lo.x, cw); ++x)
                buckets[y * cells + x].push_back(s);
    }
    for (const std::vector<std::size_t>& bucket : buckets)
        for (std::size_t i = 0; i < bucket.size(); ++i)
            for (std::size_t j = i + 1; j < bucket.size(); ++j) {
                const Segment& s = all[bucket[i]];
                const Segment& t = all[bucket[j]];
                const auto [a, b] = ends(s);
                const auto [c, d] = ends(t);
                const std::size_t n = loops[s.loop].points.size();
                const bool same = s.loop == t.loop;
                if (same && ((s.index + 1) % n == t.index || (t.index + 1) % n == s.index)) {
                    // adjacent: they share a vertex; they must not fold back onto each other
                    const Vec2 shared = (s.index + 1) % n == t.index ? b : a;
                    const Vec2 p = (s.index + 1) % n == t.index ? a : b;
                    const Vec2 q = (s.index + 1) % n == t.index ? d : c;
                    const bool collinear = cross2(shared, p, q) == 0;
                    const bool backwards =
                        (p.x - shared.x) * (q.x - shared.x) + (p.y - shared.y) * (q.y - shared.y) > 0;
                    if (!(collinear && backwards)) continue;
                } else if (!segments_touch(a, b, c, d)) {
                    continue;
                }
                const TrimPolygon& ls = loops[s.loop];
                const TrimPolygon& lt = loops[t.loop];
                const int cs = ls.segment_curves[s.index], ct = lt.segment_curves[t.index];
                TrimError e;
                if (same) {
                    e = error_at(TrimErrorKind::SelfIntersecting, ls.kind, ls.loop, cs,
                                 "the loop intersects itself near " + point_text(a) + " (with " +
                                     trim_path(lt.kind, lt.loop, ct) + ")");
                } else {
                    e = error_at(TrimErrorKind::LoopsCross, ls.kind, ls.loop, cs,
                                 "crosses or touches " + trim_path(lt.kind, lt.loop, ct) + " near " + point_text(a));
                }
                e.other_kind = lt.kind;
                e.other_loop = lt.loop;
                e.other_curve = ct;
                result.error = e;
                return result;
            }

    // 4 (after 5-6, so that a figure eight is reported as self-intersecting): an area
    for (const TrimPolygon& l : loops)
        if (!(std::fabs(l.area) > 1e-14 * diagonal * diagonal)) {
            result.error = error_at(TrimErrorKind::DegenerateLoop, l.kind, l.loop, -1, "the loop encloses no area");
            return result;
        }

    // 7: nesting (the loops are disjoint now, so one vertex decides)
    bool any_outer = false;
    for (const TrimPolygon& l : loops) any_outer = any_outer || l.kind == TrimLoopKind::Outer;
    for (const TrimPolygon& l : loops) {
        int container_outer = -1;
        for (const TrimPolygon& other : loops) {
            if (&other == &l || !inside_polygon(other.points, l.points[0])) continue;
            if (other.kind == TrimLoopKind::Outer && l.kind == TrimLoopKind::Hole) {
                container_outer = other.loop;
                continue;
            }
            TrimError e =
                error_at(TrimErrorKind::NestedLoops, l.kind, l.loop, -1,
                         "lies inside " + trim_path(other.kind, other.loop) +
                             (l.kind == TrimLoopKind::Hole ? ": holes must not nest"
                                                           : ": an outer loop must not lie inside another loop"));
            e.other_kind = other.kind;
            e.other_loop = other.loop;
            result.error = e;
            return result;
        }
        if (l.kind == TrimLoopKind::Hole && any_outer && container_outer < 0) {
            result.error =
                error_at(TrimErrorKind::HoleOutside, l.kind, l.loop, -1, "the hole lies outside every outer loop");
            return result;
        }
    }

    // orientation: the trimmed domain on the left of every loop
    for (TrimPolygon& l : loops) {
        const bool want_positive = l.kind == TrimLoopKind::Outer;
        if ((l.area > 0) == want_positive) continue;
        const std::size_t n = l.points.size();
        std::reverse(l.points.begin(), l.points.end());
        std::vector<int> curves(n);
        for (std::size_t k = 0; k < n; ++k) curves[k] = l.segment_curves[(2 * n - 2 - k) % n];
        l.segment_curves = std::move(curves);
        l.area = -l.area;
        l.reversed = true;
    }
    return result;
}

TrimValidation validate_trims(const TrimmedSurface& trimmed, const TrimValidationOptions& options) {
    const auto [u0, u1] = domain_u(trimmed.surface);
    const auto [v0, v1] = domain_v(trimmed.surface);
    return prepare_trims(trimmed, options.flatness * std::hypot(u1 - u0, v1 - v0), options.closure_tolerance,
                         options.max_segments);
}

bool inside_trimmed_domain(const PreparedTrims& trims, Vec2 p) {
    bool any_outer = false, in_outer = false;
    for (const TrimPolygon& l : trims.loops) {
        if (l.kind == TrimLoopKind::Outer) {
            any_outer = true;
            if (!in_outer && inside_polygon(l.points, p)) in_outer = true;
        } else if (inside_polygon(l.points, p)) {
            return false;
        }
    }
    return !any_outer || in_outer;
}

}  // namespace surfaced
