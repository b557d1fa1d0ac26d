// Morton numbering of the simplifier's vertices (spatial_order.h).
#include "geometry/simplify/spatial_order.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>

namespace surfaced::simplify_detail {
namespace {

//! Spreads the low 10 bits of x to every third bit (bits 0, 3, ..., 27).
std::uint32_t spread_bits(std::uint32_t x) {
    x &= 0x3ffu;
    x = (x | (x << 16)) & 0x030000ffu;
    x = (x | (x << 8)) & 0x0300f00fu;
    x = (x | (x << 4)) & 0x030c30c3u;
    x = (x | (x << 2)) & 0x09249249u;
    return x;
}

}  // namespace

std::vector<Index> spatial_order(const std::vector<Vec3>& positions, bool halves) {
    const std::size_t n = positions.size();
    Box3 box;
    for (const Vec3& p : positions) box.add(p);
    const Vec3 size = box.max - box.min;
    const double extent = std::max({size.x, size.y, size.z});
    const double scale = extent > 0 ? 1023.0 / extent : 0.0;
    std::vector<std::uint64_t> keys(n), sorted(n);
    const int axis = size.x >= size.y && size.x >= size.z ? 0 : (size.y >= size.z ? 1 : 2);
    std::vector<std::uint16_t> slab(halves ? n : 0);  //!< the cell along the longest side
    for (std::size_t v = 0; v < n; ++v) {
        const Vec3 q = (positions[v] - box.min) * scale;
        const auto cell = [](double c) { return static_cast<std::uint32_t>(std::clamp(c, 0.0, 1023.0)); };
        const std::uint64_t code = spread_bits(cell(q.x)) | spread_bits(cell(q.y)) << 1 | spread_bits(cell(q.z)) << 2;
        keys[v] = code << 32 | v;
        if (halves) slab[v] = static_cast<std::uint16_t>(cell(axis == 0 ? q.x : (axis == 1 ? q.y : q.z)));
    }
    for (int shift = 32; shift < 62; shift += 10) {  // three 10-bit digits of the 30-bit code, least significant first
        std::array<std::size_t, 1025> start{};
        for (std::uint64_t k : keys) ++start[(k >> shift & 1023) + 1];
        for (std::size_t d = 1; d < start.size(); ++d) start[d] += start[d - 1];
        for (std::uint64_t k : keys) sorted[start[k >> shift & 1023]++] = k;
        keys.swap(sorted);
    }
    if (halves) {
        // the slab holding the median, and how many of its vertices (the lowest numbered) join the lower half
        std::array<std::size_t, 1024> count{};
        for (std::uint16_t c : slab) ++count[c];
        std::size_t below = 0, median = 0;
        while (below + count[median] < n / 2) below += count[median++];
        std::size_t take = n / 2 - below;
        std::vector<std::uint8_t> lower(n, 0);
        for (std::size_t v = 0; v < n; ++v)
            if (slab[v] < median || (slab[v] == median && take > 0 && take--)) lower[v] = 1;
        // stable partition of the Morton order: the lower half first
        std::size_t front = 0;
        for (std::uint64_t k : keys)
            if (lower[k & 0xffffffffu]) sorted[front++] = k;
        for (std::uint64_t k : keys)
            if (!lower[k & 0xffffffffu]) sorted[front++] = k;
        keys.swap(sorted);
    }
    std::vector<Index> rank(n);
    for (std::size_t i = 0; i < n; ++i) rank[keys[i] & 0xffffffffu] = static_cast<Index>(i);
    return rank;
}

}  // namespace surfaced::simplify_detail
