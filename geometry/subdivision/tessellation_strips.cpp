#include "geometry/subdivision/tessellation_strips.h"

#include <algorithm>
#include <utility>

namespace surfaced::tessellation_detail {

bool is_grid(const LimitTessellationPlan::Domain& d) {
    for (const auto& lines : d.side_lines)
        if (!lines.empty()) return false;
    return d.s_lines.empty() && d.t_lines.empty() && d.side[0] == d.nu && d.side[2] == d.nu && d.side[1] == d.nv &&
           d.side[3] == d.nv;
}

std::uint64_t domain_triangles(const LimitTessellationPlan::Domain& d) {
    const bool grid = is_grid(d);
    const auto nu = static_cast<std::uint64_t>(d.nu), nv = static_cast<std::uint64_t>(d.nv);
    if (grid) return 2 * nu * nv;
    std::uint64_t sum = 0;
    for (int k = 0; k < 4; ++k) sum += static_cast<std::uint64_t>(d.side[k]);
    return 2 * (nu - 2) * (nv - 2) + sum + 2 * (nu - 2) + 2 * (nv - 2);
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
    const auto inner = [&](int i, int j) { return ring + std::uint32_t((j - 1) * (nu - 1) + (i - 1)); };
    for (int j = 1; j < nv; ++j)
        for (int i = 1; i < nu; ++i) out.points.push_back({d.s_at(i), d.t_at(j)});
    const bool grid = is_grid(d);
    if (grid) {
        const auto at = [&](int i, int j) -> std::uint32_t {
            if (j == 0) return on_side(0, i);
            if (i == nu) return on_side(1, j);
            if (j == nv) return on_side(2, nu - i);
            if (i == 0) return on_side(3, nv - j);
            return inner(i, j);
        };
        for (int j = 0; j < nv; ++j)
            for (int i = 0; i < nu; ++i) {
                out.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
                out.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
            }
        return out;
    }
    // inner grid
    for (int j = 1; j + 1 < nv; ++j)
        for (int i = 1; i + 1 < nu; ++i) {
            out.triangles.push_back({inner(i, j), inner(i + 1, j), inner(i + 1, j + 1)});
            out.triangles.push_back({inner(i, j), inner(i + 1, j + 1), inner(i, j + 1)});
        }
    // one transition strip per side, between the side's points and the inner grid's outermost row, both running
    // from corner to corner; positions along the side decide which advances (the inner row is on the left)
    for (int k = 0; k < 4; ++k) {
        std::vector<std::pair<std::uint32_t, double>> in;
        if (k == 0)
            for (int i = 1; i < nu; ++i) in.emplace_back(inner(i, 1), d.s_at(i));
        if (k == 1)
            for (int j = 1; j < nv; ++j) in.emplace_back(inner(nu - 1, j), d.t_at(j));
        if (k == 2)
            for (int i = nu - 1; i >= 1; --i) in.emplace_back(inner(i, nv - 1), 1.0 - d.s_at(i));
        if (k == 3)
            for (int j = nv - 1; j >= 1; --j) in.emplace_back(inner(1, j), 1.0 - d.t_at(j));
        const int a = r[k], b = static_cast<int>(in.size()) - 1;
        int io = 0, ii = 0;
        while (io < a || ii < b) {
            const bool outer = ii == b || (io < a && d.side_at(k, io + 1) <= in[std::size_t(ii + 1)].second);
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
