// The simplifier's priority queue of collapse candidates (internal to geometry/simplify): Candidate, an edge with its
// cost and the version stamp that tells whether it is still current, and CandidateHeap, a radix heap of them.
//
// Reference: R. Ahuja, K. Mehlhorn, J. Orlin, R. Tarjan, "Faster Algorithms for the Shortest Path Problem", 1990.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>

#include "geometry/core/block_pool.h"
#include "geometry/core/types.h"

namespace surfaced::simplify_detail {

// 16 bytes: the heap holds a few million of these for a 1M-triangle mesh, and popping is cache-bound.
struct Candidate {
    float cost;  //!< ordering only; the collapse itself is re-evaluated in double when popped
    Index a, b;
    //! version_[a] + version_[b] when pushed. Versions only grow (a vertex's also when it dies), so the entry is
    //! current exactly while the sum is unchanged.
    std::uint32_t stamp;
};
static_assert(sizeof(Candidate) == 16);

//! A radix heap on the cost's float bits, which order like the costs for costs >= 0. Keys popped never decrease, and
//! an edge's cost only grows when quadrics are merged, so a pushed key is nearly always >= the last one popped; one
//! that is not is clamped to it and comes out next, which is where a comparison heap would put it too. Bucket i > 0
//! holds the keys whose highest bit differing from the last key popped is bit i - 1; popping refills bucket 0 from the
//! lowest non-empty bucket. Every entry moves to a lower bucket a few times in all, by sequential copies: on meshes of
//! millions of triangles that is cheaper than a comparison heap's root-to-leaf walk of cache misses per pop.
class CandidateHeap {
public:
    //! `pool`: where the buckets' large arrays come from (BlockAllocator); nullptr: allocated per use.
    explicit CandidateHeap(BlockPool* pool = nullptr) {
        for (auto& bucket : buckets_) bucket = BlockVector<Candidate>(BlockAllocator<Candidate>(pool));
    }
    bool empty() const { return size_ == 0; }
    std::size_t size() const { return size_; }
    void clear() {
        for (auto& bucket : buckets_) bucket.clear();
        size_ = 0;
        last_ = 0;
    }
    void push(Candidate c) {
        std::uint32_t key = bits(c.cost);
        if (key < last_) {
            key = last_;
            std::memcpy(&c.cost, &key, sizeof key);
        }
        buckets_[bucket_of(key)].push_back(c);
        ++size_;
    }
    //! The entry with the lowest key, or nullptr when none is left. Entries for which current(entry) is false are
    //! dropped on the way (stale ones: checked while they are copied anyway).
    template <class Current>
    const Candidate* top(Current current) {
        settle(current);
        return buckets_[0].empty() ? nullptr : &buckets_[0].back();
    }
    //! \pre top() returned an entry
    Candidate pop() {
        const Candidate c = buckets_[0].back();
        buckets_[0].pop_back();
        --size_;
        return c;
    }
    //! Moves the entries of `other` for which current(entry) holds into this heap (other is left empty).
    template <class Current>
    void absorb(CandidateHeap& other, Current current) {
        for (auto& bucket : other.buckets_) {
            for (const Candidate& c : bucket)
                if (current(c)) push(c);
            bucket.clear();
        }
        other.size_ = 0;
    }
    template <class Pred>
    void erase_if(Pred pred) {
        size_ = 0;
        for (auto& bucket : buckets_) {
            bucket.erase(std::remove_if(bucket.begin(), bucket.end(), pred), bucket.end());
            size_ += bucket.size();
        }
    }

private:
    //! Costs are >= 0 (Quadric::error clamps); a negative or NaN bit pattern would only sort last.
    static std::uint32_t bits(float cost) {
        std::uint32_t key;
        std::memcpy(&key, &cost, sizeof key);
        return key;
    }
    std::size_t bucket_of(std::uint32_t key) const {
        return key == last_ ? 0 : 32 - static_cast<std::size_t>(__builtin_clz(key ^ last_));
    }
    template <class Current>
    void settle(Current current) {
        std::size_t i = 0;
        while (buckets_[0].empty()) {
            do {
                if (++i == buckets_.size()) return;  // empty
            } while (buckets_[i].empty());
            auto& from = buckets_[i];
            // drop stale entries, then move the rest below the lowest
            std::size_t kept = 0;
            std::uint32_t lowest = std::numeric_limits<std::uint32_t>::max();
            for (const Candidate& c : from)
                if (current(c)) {
                    from[kept++] = c;
                    lowest = std::min(lowest, bits(c.cost));
                }
            size_ -= from.size() - kept;
            from.resize(kept);
            if (kept == 0) continue;
            last_ = lowest;
            for (const Candidate& c : from) buckets_[bucket_of(bits(c.cost))].push_back(c);
            from.clear();
        }
    }
    std::array<BlockVector<Candidate>, 33> buckets_;
    std::size_t size_ = 0;
    std::uint32_t last_ = 0;
};

}  // namespace surfaced::simplify_detail
