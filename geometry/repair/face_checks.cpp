// Degenerate and duplicate face tests.
#include "geometry/repair/face_checks.h"

#include <algorithm>
#include <vector>

namespace surfaced::repair_detail {

bool has_repeated_index(std::span<const Index> face) {
    const std::size_t n = face.size();
    if (n == 3) return face[0] == face[1] || face[0] == face[2] || face[1] == face[2];
    if (n <= 8) {
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = i + 1; j < n; ++j)
                if (face[i] == face[j]) return true;
        return false;
    }
    std::vector<Index> sorted(face.begin(), face.end());
    std::sort(sorted.begin(), sorted.end());
    return std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end();
}

bool has_zero_area(std::span<const Vec3> positions, std::span<const Index> face) {
    const Vec3& origin = positions[face[0]];
    Vec3 area;
    for (std::size_t i = 1; i + 1 < face.size(); ++i)
        area += cross(positions[face[i]] - origin, positions[face[i + 1]] - origin);
    return area.x == 0 && area.y == 0 && area.z == 0;
}

bool FaceSets::insert(std::span<const Index> face) {
    scratch_.assign(face.begin(), face.end());
    if (scratch_.size() <= 8) {  // insertion sort: triangles and quads, nearly every face there is
        for (std::size_t i = 1; i < scratch_.size(); ++i)
            for (std::size_t j = i; j > 0 && scratch_[j] < scratch_[j - 1]; --j)
                std::swap(scratch_[j], scratch_[j - 1]);
    } else {
        std::sort(scratch_.begin(), scratch_.end());
    }
    std::uint64_t hash = scratch_.size();
    for (Index v : scratch_) hash = (hash ^ v) * 0x9E3779B97F4A7C15ULL;
    hash = mix64(hash);
    const auto slot = static_cast<Index>(start_.size());
    const Index found = table_.find_or_insert(hash, slot, [&](Index other) {
        const std::size_t b = start_[other];
        const std::size_t e = other + 1 < start_.size() ? start_[other + 1] : sorted_.size();
        return e - b == scratch_.size() && std::equal(scratch_.begin(), scratch_.end(), sorted_.begin() + b);
    });
    if (found != slot) return false;
    start_.push_back(sorted_.size());
    sorted_.insert(sorted_.end(), scratch_.begin(), scratch_.end());
    return true;
}

}  // namespace surfaced::repair_detail
