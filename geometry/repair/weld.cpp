// Vertex welding: exact (vertices sorted by a hash of their coordinates) or within a distance (a hash of grid cells
// as wide as the distance, searching the 27 cells around each vertex).
#include "geometry/repair/weld.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <utility>

#include "geometry/repair/index_table.h"
#include "geometry/repair/radix_sort.h"

namespace surfaced::repair_detail {

namespace {

//! The position's coordinates as bits, -0.0 taken as 0.0 (positions are finite: equal bits <=> equal positions).
std::array<std::uint64_t, 3> position_bits(const Vec3& p) {
    std::array<std::uint64_t, 3> bits{};
    for (int i = 0; i < 3; ++i) {
        const double d = p[i] + 0.0;
        std::memcpy(&bits[static_cast<std::size_t>(i)], &d, sizeof d);
    }
    return bits;
}

//! One multiply-add chain over the coordinates' bits, then one finaliser: a position hash for millions of vertices.
std::uint64_t hash_position(const Vec3& p) {
    const auto [x, y, z] = position_bits(p);
    return mix64(x + 0x9E3779B97F4A7C15ULL * (y + 0xC2B2AE3D27D4EB4FULL * z));
}

//! The vertices of one hash, keyed[b..e) in increasing index, split by exact position: each merges into the first
//! (lowest) vertex of its position.
void split_by_position(std::span<const Vec3> positions, const std::uint64_t* keyed, std::size_t b, std::size_t e,
                       std::vector<Index>& target) {
    if (e - b <= 32) {
        std::vector<Index> leaders;  // the distinct positions, by their first vertex
        for (std::size_t i = b; i < e; ++i) {
            const auto v = static_cast<Index>(keyed[i]);
            Index found = kInvalidIndex;
            for (Index leader : leaders)
                if (positions[leader] == positions[v]) {
                    found = leader;
                    break;
                }
            if (found == kInvalidIndex) leaders.push_back(found = v);
            target[v] = found;
        }
        return;
    }
    // many vertices of one hash (one position used very often, or collisions): sort them by position, then index
    std::vector<std::pair<std::array<std::uint64_t, 3>, Index>> run;
    run.reserve(e - b);
    for (std::size_t i = b; i < e; ++i) {
        const auto v = static_cast<Index>(keyed[i]);
        run.emplace_back(position_bits(positions[v]), v);
    }
    std::sort(run.begin(), run.end());
    for (std::size_t i = 0; i < run.size(); ++i)
        target[run[i].second] = i > 0 && run[i].first == run[i - 1].first ? target[run[i - 1].second] : run[i].second;
}

//! Vertices sorted by a 32-bit hash of their position (radix sort, stable: increasing index within a hash). Every
//! vertex first takes the first vertex of its hash, which is right unless two positions share the hash; that is
//! checked in vertex order (the compared positions are mostly near each other in memory), and only the hashes where
//! it failed are split by exact position.
std::vector<Index> weld_exact(std::span<const Vec3> positions) {
    const std::size_t n = positions.size();
    std::vector<Index> target(n);
    std::vector<std::uint64_t> keyed(n), scratch;
    constexpr std::uint64_t kHigh = ~std::uint64_t{0xFFFFFFFF};
    for (std::size_t v = 0; v < n; ++v) keyed[v] = (hash_position(positions[v]) & kHigh) | v;
    radix_sort_by_high_half(keyed, scratch);
    for (std::size_t b = 0, e = 0; b < n; b = e) {
        const auto first = static_cast<Index>(keyed[b]);
        for (e = b; e < n && (keyed[e] & kHigh) == (keyed[b] & kHigh); ++e)
            target[static_cast<Index>(keyed[e])] = first;
    }
    std::vector<std::uint8_t> collided;
    for (std::size_t v = 0; v < n; ++v) {
        if (target[v] == v || positions[target[v]] == positions[v]) continue;
        if (collided.empty()) collided.assign(n, 0);
        collided[v] = 1;
    }
    if (collided.empty()) return target;
    for (std::size_t b = 0, e = 0; b < n; b = e) {
        bool redo = false;
        for (e = b; e < n && (keyed[e] & kHigh) == (keyed[b] & kHigh); ++e)
            redo |= collided[static_cast<Index>(keyed[e])] != 0;
        if (redo) split_by_position(positions, keyed.data(), b, e, target);
    }
    return target;
}

using Cell = std::array<std::int64_t, 3>;

// Cell coordinates are clamped (and a NaN from 0 * inf taken as 0) so that a tolerance tiny against the coordinates
// cannot overflow; clamped cells only share more vertices (slower), the distance test stays exact.
Cell cell_of(const Vec3& p, double inverse_width) {
    Cell c{};
    for (int i = 0; i < 3; ++i) {
        const double x = std::floor(p[i] * inverse_width);
        constexpr double kLimit = 4.0e18;
        c[i] = std::isnan(x) ? 0 : static_cast<std::int64_t>(x < -kLimit ? -kLimit : (x > kLimit ? kLimit : x));
    }
    return c;
}

std::uint64_t hash_cell(const Cell& c) {
    return mix64(static_cast<std::uint64_t>(c[0]) * 0x9E3779B97F4A7C15ULL ^
                 static_cast<std::uint64_t>(c[1]) * 0xC2B2AE3D27D4EB4FULL ^
                 static_cast<std::uint64_t>(c[2]) * 0x165667B19E3779F9ULL);
}

// Cells are twice the tolerance wide, so that the vertices within the tolerance of a point lie in the 2 x 2 x 2
// cells nearest to it (the half of each neighbouring cell the point is closer to).
std::vector<Index> weld_within(std::span<const Vec3> positions, double tolerance) {
    const std::size_t n = positions.size();
    const double inverse_width = 0.5 / tolerance;
    const double tolerance2 = tolerance * tolerance;
    // identical positions merge alike (into the target of the first of them): only first occurrences search
    std::vector<Index> target = weld_exact(positions);
    // cell -> its first kept vertex; the rest of the cell's kept vertices follow through next_in_cell
    IndexTable cells(n);
    std::vector<Index> next_in_cell(n, kInvalidIndex);
    auto in_cell = [&](const Cell& c) {
        return [&, c](Index kept) { return cell_of(positions[kept], inverse_width) == c; };
    };
    for (std::size_t v = 0; v < n; ++v) {
        if (target[v] != v) {
            target[v] = target[target[v]];
            continue;
        }
        const Vec3& p = positions[v];
        const Cell home = cell_of(p, inverse_width);
        Cell first{};  // the lower of the two cells to search along each axis
        for (int i = 0; i < 3; ++i) {
            const double x = p[i] * inverse_width;
            first[i] = home[i] - (x - std::floor(x) < 0.5 ? 1 : 0);
        }
        Index best = kInvalidIndex;
        for (int corner = 0; corner < 8; ++corner) {
            const Cell c{first[0] + (corner & 1), first[1] + ((corner >> 1) & 1), first[2] + ((corner >> 2) & 1)};
            for (Index k = cells.find(hash_cell(c), in_cell(c)); k != kInvalidIndex; k = next_in_cell[k]) {
                const Vec3 d = positions[k] - p;
                if (k < best && dot(d, d) <= tolerance2) best = k;
            }
        }
        if (best != kInvalidIndex) {
            target[v] = best;
            continue;
        }
        const Index head = cells.find_or_insert(hash_cell(home), static_cast<Index>(v), in_cell(home));
        if (head != v) {  // the cell has kept vertices already: v goes second in its list
            next_in_cell[v] = next_in_cell[head];
            next_in_cell[head] = static_cast<Index>(v);
        }
    }
    return target;
}

}  // namespace

std::vector<Index> weld_targets(std::span<const Vec3> positions, double tolerance) {
    return tolerance > 0 ? weld_within(positions, tolerance) : weld_exact(positions);
}

}  // namespace surfaced::repair_detail
