#include "geometry/subdivision/tessellation_strips.h"

#include <algorithm>
#include <utility>

namespace surfaced::tessellation_detail {
namespace {

//! Inner points of row j (1..nv - 1): the row without its two side points.
int inner_in_row(bool stagger, int nu, int j) { return stagger && j % 2 == 1 ? nu : nu - 1; }

bool staggers(const LimitTessellationPlan::Domain& d) { return staggered(d.staggered, d.nu, d.nv); }

}  // namespace

std::vector<double> row_s(const std::vector<double>& s_lines, int nu, int nv, int j, bool stagger) {
    std::vector<double> out;
    if (stagger && j % 2 == 1 && j < nv) {
        out.reserve(std::size_t(nu) + 2);
        out.push_back(0.0);
        for (int i = 0; i < nu; ++i) out.push_back(0.5 * (line_at(s_lines, nu, i) + line_at(s_lines, nu, i + 1)));
        out.push_back(1.0);
        return out;
    }
    out.reserve(std::size_t(nu) + 1);
    for (int i = 0; i <= nu; ++i) out.push_back(line_at(s_lines, nu, i));
    return out;
}

void zigzag(std::span<const std::uint32_t> bottom, std::span<const double> bottom_s, std::span<const std::uint32_t> top,
            std::span<const double> top_s, std::vector<std::array<std::uint32_t, 3>>& out) {
    const std::size_t b = bottom.size() - 1, t = top.size() - 1;
    std::size_t ib = 0, it = 0;
    while (ib < b || it < t) {
        if (it == t || (ib < b && bottom_s[ib + 1] <= top_s[it + 1])) {
            out.push_back({bottom[ib], bottom[ib + 1], top[it]});
            ++ib;
        } else {
            out.push_back({bottom[ib], top[it + 1], top[it]});
            ++it;
        }
    }
}

void cells(std::span<const std::uint32_t> bottom, std::span<const std::uint32_t> top,
           std::vector<std::array<std::uint32_t, 3>>& out) {
    for (std::size_t i = 0; i + 1 < bottom.size(); ++i) {
        out.push_back({bottom[i], bottom[i + 1], top[i + 1]});
        out.push_back({bottom[i], top[i + 1], top[i]});
    }
}

bool is_grid(const LimitTessellationPlan::Domain& d) {
    for (const auto& lines : d.side_lines)
        if (!lines.empty()) return false;
    return d.s_lines.empty() && d.t_lines.empty() && d.side[0] == d.nu && d.side[2] == d.nu && d.side[1] == d.nv &&
           d.side[3] == d.nv;
}

std::uint64_t domain_triangles(const LimitTessellationPlan::Domain& d) {
    const int nu = d.nu, nv = d.nv;
    // a band between rows of a and b points has a + b - 2 triangles
    const bool stagger = staggers(d);
    const auto row = [&](int j) { return std::uint64_t(inner_in_row(stagger, nu, j)); };
    std::uint64_t sum = 0;
    if (is_grid(d)) {
        const auto whole = [&](int j) { return j == 0 || j == nv ? std::uint64_t(nu) + 1 : row(j) + 2; };
        for (int j = 0; j < nv; ++j) sum += whole(j) + whole(j + 1) - 2;
        return sum;
    }
    for (int j = 1; j + 1 < nv; ++j) sum += row(j) + row(j + 1) - 2;
    for (int k = 0; k < 4; ++k) sum += static_cast<std::uint64_t>(d.side[k]);
    // each strip joins a side to the inner grid's outermost row or column
    return sum + (row(1) - 1) + (row(nv - 1) - 1) + 2 * std::uint64_t(nv - 2);
}

std::vector<P2> inner_points(const LimitTessellationPlan::Domain& d) {
    std::vector<P2> out;
    for (int j = 1; j < d.nv; ++j) {
        const std::vector<double> s = row_s(d.s_lines, d.nu, d.nv, j, staggers(d));
        for (std::size_t i = 1; i + 1 < s.size(); ++i) out.push_back({s[i], d.t_at(j)});
    }
    return out;
}

void fix_inner(LimitTessellationPlan::Domain& d) {
    const bool grid = is_grid(d);
    if (!grid) {
        d.nu = std::max(d.nu, 2);
        d.nv = std::max(d.nv, 2);
    }
}

LocalMesh triangulate(const LimitTessellationPlan::Domain& d) {
    LocalMesh out;
    const int r[4] = {d.side[0], d.side[1], d.side[2], d.side[3]};
    const std::uint32_t offset[4] = {0, std::uint32_t(r[0]), std::uint32_t(r[0] + r[1]),
                                     std::uint32_t(r[0] + r[1] + r[2])};
    const std::uint32_t ring = std::uint32_t(r[0] + r[1] + r[2] + r[3]);
    for (int i = 0; i < r[0]; ++i) out.points.push_back({d.side_at(0, i), 0.0});
    for (int i = 0; i < r[1]; ++i) out.points.push_back({1.0, d.side_at(1, i)});
    for (int i = 0; i < r[2]; ++i) out.points.push_back({1.0 - d.side_at(2, i), 1.0});
    for (int i = 0; i < r[3]; ++i) out.points.push_back({0.0, 1.0 - d.side_at(3, i)});
    const auto on_side = [&](int k, int i) { return (offset[k] + std::uint32_t(i)) % ring; };
    const int nu = d.nu, nv = d.nv;
    // inner rows: their first point's index and their points' s
    std::vector<std::uint32_t> row_start(std::size_t(nv) + 1, ring);
    std::vector<std::vector<double>> row_points(std::size_t(nv) + 1);
    for (int j = 1; j < nv; ++j) {
        row_points[std::size_t(j)] = row_s(d.s_lines, nu, nv, j, staggers(d));
        const std::vector<double>& s = row_points[std::size_t(j)];
        row_start[std::size_t(j)] = std::uint32_t(out.points.size());
        for (std::size_t i = 1; i + 1 < s.size(); ++i) out.points.push_back({s[i], d.t_at(j)});
    }
    // inner row j's ids and s, without the sides' points
    const auto inner_row = [&](int j, std::vector<std::uint32_t>& ids, std::vector<double>& s) {
        const std::vector<double>& all = row_points[std::size_t(j)];
        ids.clear();
        s.assign(all.begin() + 1, all.end() - 1);
        for (std::size_t i = 0; i < s.size(); ++i) ids.push_back(row_start[std::size_t(j)] + std::uint32_t(i));
    };
    std::vector<std::uint32_t> lower, upper;
    std::vector<double> lower_s, upper_s;
    if (is_grid(d)) {
        // whole rows, the sides' points included: row 0 is side 0, row nv side 2 backwards
        const auto whole_row = [&](int j, std::vector<std::uint32_t>& ids, std::vector<double>& s) {
            if (j == 0 || j == nv) {
                ids.clear();
                s.clear();
                for (int i = 0; i <= nu; ++i) {
                    ids.push_back(j == 0 ? on_side(0, i) : on_side(2, nu - i));
                    s.push_back(double(i) / nu);
                }
                return;
            }
            inner_row(j, ids, s);
            ids.insert(ids.begin(), on_side(3, nv - j));
            s.insert(s.begin(), 0.0);
            ids.push_back(on_side(1, j));
            s.push_back(1.0);
        };
        if (!staggers(d)) {  // the cells' two right triangles
            for (int j = 0; j < nv; ++j) {
                whole_row(j, lower, lower_s);
                whole_row(j + 1, upper, upper_s);
                cells(lower, upper, out.triangles);
            }
            return out;
        }
        for (int j = 0; j < nv; ++j) {
            whole_row(j, lower, lower_s);
            whole_row(j + 1, upper, upper_s);
            zigzag(lower, lower_s, upper, upper_s, out.triangles);
        }
        return out;
    }
    // inner bands
    for (int j = 1; j + 1 < nv; ++j) {
        inner_row(j, lower, lower_s);
        inner_row(j + 1, upper, upper_s);
        if (staggers(d)) {
            zigzag(lower, lower_s, upper, upper_s, out.triangles);
            continue;
        }
        cells(lower, upper, out.triangles);
    }
    // one transition strip per side, between the side's points and the inner grid's outermost row or column, both
    // running from corner to corner; positions along the side decide which advances (the inner row is on the left)
    for (int k = 0; k < 4; ++k) {
        std::vector<std::pair<std::uint32_t, double>> in;
        if (k == 0 || k == 2) {
            inner_row(k == 0 ? 1 : nv - 1, lower, lower_s);
            for (std::size_t i = 0; i < lower.size(); ++i) in.emplace_back(lower[i], lower_s[i]);
            if (k == 2) {
                std::reverse(in.begin(), in.end());
                for (auto& e : in) e.second = 1.0 - e.second;
            }
        } else {
            for (int j = 1; j < nv; ++j) {
                inner_row(j, lower, lower_s);
                const std::size_t i = k == 1 ? lower.size() - 1 : 0;
                in.emplace_back(lower[i], d.t_at(j));
            }
            if (k == 3) {
                std::reverse(in.begin(), in.end());
                for (auto& e : in) e.second = 1.0 - e.second;
            }
        }
        const int a = r[k], b = static_cast<int>(in.size()) - 1;
        const auto point = [&](std::uint32_t id) { return out.points[id]; };
        // the inner row's distance from the side, which scales the strip's width to its points' spacing along it
        const auto across = [&](std::uint32_t id) {
            const P2 q = point(id);
            return k == 0 ? q.t : k == 1 ? 1.0 - q.s : k == 2 ? 1.0 - q.t : q.s;
        };
        int io = 0, ii = 0;
        while (io < a || ii < b) {
            // of the two triangles that can come next, the one on the shorter diagonal of the quad they split
            // (lengths with the strip's width and the step along it as units) when both are counter-clockwise, the
            // counter-clockwise one when only one is (a staggered column can put a corner in line with two of its
            // points), else the one whose next point comes first along the side
            bool outer = ii == b || (io < a && d.side_at(k, io + 1) <= in[std::size_t(ii + 1)].second);
            if (io < a && ii < b) {
                const P2 o0 = point(on_side(k, io)), o1 = point(on_side(k, io + 1));
                const P2 i0 = point(in[std::size_t(ii)].first), i1 = point(in[std::size_t(ii + 1)].first);
                const auto ccw = [](const P2& p, const P2& q, const P2& w) {
                    return (q.s - p.s) * (w.t - p.t) - (q.t - p.t) * (w.s - p.s) > 0;
                };
                const bool outer_ok = ccw(o0, o1, i0), inner_ok = ccw(o0, i1, i0);
                if (outer_ok != inner_ok) outer = outer_ok;
                if (outer_ok && inner_ok) {
                    const double width =
                        0.5 * (across(in[std::size_t(ii)].first) + across(in[std::size_t(ii + 1)].first));
                    const double step = std::max(d.side_at(k, io + 1) - d.side_at(k, io),
                                                 in[std::size_t(ii + 1)].second - in[std::size_t(ii)].second);
                    const auto length = [&](double along, double wide) {
                        return (along / step) * (along / step) + (wide / width) * (wide / width);
                    };
                    const double to_outer =
                        length(d.side_at(k, io + 1) - in[std::size_t(ii)].second, across(in[std::size_t(ii)].first));
                    const double to_inner = length(in[std::size_t(ii + 1)].second - d.side_at(k, io),
                                                   across(in[std::size_t(ii + 1)].first));
                    if (width > 0 && step > 0 && to_outer != to_inner) outer = to_outer < to_inner;
                }
            }
            if (outer) {
                out.triangles.push_back({on_side(k, io), on_side(k, io + 1), in[std::size_t(ii)].first});
                ++io;
            } else {
                out.triangles.push_back({on_side(k, io), in[std::size_t(ii + 1)].first, in[std::size_t(ii)].first});
                ++ii;
            }
        }
    }
    return out;
}

}  // namespace surfaced::tessellation_detail
