// An open-addressing hash table of element indices (vertices, faces, grid cells), for the repair steps that look
// elements up by content: equal positions, equal vertex sets, occupied grid cells. The caller hashes and compares;
// the table stores only the index and a tag of the hash. Several times faster than std::unordered_map at millions of
// entries, which is what keeps a soup of a million triangles well under a second.
#pragma once

#include <cassert>
#include <cstdint>
#include <cstring>
#include <vector>

#include "geometry/core/types.h"

namespace surfaced::repair_detail {

//! A 64-bit finaliser (splitmix64): spreads nearby inputs over the whole range.
inline std::uint64_t mix64(std::uint64_t x) {
    x ^= x >> 30;
    x *= 0xbf58476d1ce4e5b9ULL;
    x ^= x >> 27;
    x *= 0x94d049bb133111ebULL;
    x ^= x >> 31;
    return x;
}

inline std::uint64_t hash_double(double d) {
    d += 0.0;  // -0.0 and 0.0 compare equal: hash them alike
    std::uint64_t bits = 0;
    std::memcpy(&bits, &d, sizeof bits);
    return mix64(bits);
}

class IndexTable {
public:
    //! Room for `expected` entries at a load factor of at most 1/2.
    explicit IndexTable(std::size_t expected) {
        std::size_t capacity = 16;
        while (capacity < 2 * expected) capacity *= 2;
        slots_.assign(capacity, Slot{});
        mask_ = capacity - 1;
    }

    //! The stored index for which equal(stored) holds, or kInvalidIndex.
    template <class Equal>
    Index find(std::uint64_t hash, Equal&& equal) const {
        const auto tag = static_cast<std::uint32_t>(hash >> 32);
        for (std::size_t i = hash & mask_;; i = (i + 1) & mask_) {
            const Slot& s = slots_[i];
            if (s.index == kInvalidIndex) return kInvalidIndex;
            if (s.tag == tag && equal(s.index)) return s.index;
        }
    }

    //! The stored index for which equal(stored) holds; when there is none, stores `index` and returns it. At most
    //! `expected` (the constructor's) indices may be stored.
    template <class Equal>
    Index find_or_insert(std::uint64_t hash, Index index, Equal&& equal) {
        const auto tag = static_cast<std::uint32_t>(hash >> 32);
        for (std::size_t i = hash & mask_;; i = (i + 1) & mask_) {
            Slot& s = slots_[i];
            if (s.index == kInvalidIndex) {
                assert(2 * (size_ + 1) <= slots_.size());
                s = Slot{index, tag};
                ++size_;
                return index;
            }
            if (s.tag == tag && equal(s.index)) return s.index;
        }
    }

private:
    struct Slot {
        Index index = kInvalidIndex;
        std::uint32_t tag = 0;
    };

    std::vector<Slot> slots_;
    std::size_t mask_ = 0;
    std::size_t size_ = 0;
};

}  // namespace surfaced::repair_detail
