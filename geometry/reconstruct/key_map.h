// Maps from packed integer grid coordinates to dense indices, for the sparse levels of the Poisson octree: a row
// index over a sorted key list (RowIndex: the octree's key sets), and open addressing with linear probing over a
// power-of-two table (KeyCollector, KeyMap, GrowingKeyMap: sets collected in any order). No per-process hash seed,
// and key lists always come out sorted, so everything built on them is deterministic.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace surfaced::reconstruct {

//! Packs grid coordinates (each < 2^21) into one key.
inline std::uint64_t pack_key(std::uint32_t i, std::uint32_t j, std::uint32_t k) {
    return std::uint64_t{i} | (std::uint64_t{j} << 21) | (std::uint64_t{k} << 42);
}
inline std::uint32_t key_i(std::uint64_t key) { return static_cast<std::uint32_t>(key & 0x1fffff); }
inline std::uint32_t key_j(std::uint64_t key) { return static_cast<std::uint32_t>((key >> 21) & 0x1fffff); }
inline std::uint32_t key_k(std::uint64_t key) { return static_cast<std::uint32_t>((key >> 42) & 0x1fffff); }

//! splitmix64's finaliser: spreads packed coordinates over the table.
inline std::uint64_t hash_key(std::uint64_t x) {
    x ^= x >> 30;
    x *= 0xbf58476d1ce4e5b9ull;
    x ^= x >> 27;
    x *= 0x94d049bb133111ebull;
    x ^= x >> 31;
    return x;
}

//! Collects distinct keys (a growing open-addressing set); take() returns them sorted.
class KeyCollector {
public:
    void insert(std::uint64_t key) {
        if (2 * (size_ + 1) > table_.size()) grow();
        std::size_t slot = hash_key(key) & (table_.size() - 1);
        while (table_[slot] != kEmpty) {
            if (table_[slot] == key) return;
            slot = (slot + 1) & (table_.size() - 1);
        }
        table_[slot] = key;
        ++size_;
    }
    std::vector<std::uint64_t> take() {
        std::vector<std::uint64_t> keys;
        keys.reserve(size_);
        for (const std::uint64_t k : table_)
            if (k != kEmpty) keys.push_back(k);
        std::sort(keys.begin(), keys.end());
        table_.clear();
        size_ = 0;
        return keys;
    }
    std::size_t size() const { return size_; }
    std::size_t memory_bytes() const { return table_.capacity() * 8; }

private:
    static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};
    void grow() {
        std::vector<std::uint64_t> old = std::move(table_);
        table_.assign(old.empty() ? 64 : 2 * old.size(), kEmpty);
        size_ = 0;
        for (const std::uint64_t k : old)
            if (k != kEmpty) insert(k);
    }
    std::vector<std::uint64_t> table_;
    std::size_t size_ = 0;
};

class KeyMap {
public:
    static constexpr std::uint32_t kNone = 0xffffffffu;

    //! Builds the map key -> position for a list of distinct keys.
    void assign(const std::vector<std::uint64_t>& keys) {
        std::size_t capacity = 16;
        while (capacity < 2 * keys.size()) capacity *= 2;
        keys_.assign(capacity, kEmpty);
        values_.assign(capacity, kNone);
        mask_ = capacity - 1;
        for (std::size_t n = 0; n < keys.size(); ++n) {
            std::size_t slot = hash(keys[n]) & mask_;
            while (keys_[slot] != kEmpty) slot = (slot + 1) & mask_;
            keys_[slot] = keys[n];
            values_[slot] = static_cast<std::uint32_t>(n);
        }
    }

    //! Position of `key` in the list given to assign(), or kNone.
    std::uint32_t find(std::uint64_t key) const {
        if (keys_.empty()) return kNone;
        std::size_t slot = hash(key) & mask_;
        while (true) {
            const std::uint64_t stored = keys_[slot];
            if (stored == key) return values_[slot];
            if (stored == kEmpty) return kNone;
            slot = (slot + 1) & mask_;
        }
    }

    std::size_t memory_bytes() const { return keys_.capacity() * 8 + values_.capacity() * 4; }

private:
    static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};
    static std::uint64_t hash(std::uint64_t x) { return hash_key(x); }

    std::vector<std::uint64_t> keys_;
    std::vector<std::uint32_t> values_;
    std::size_t mask_ = 0;
};

//! Positions of a sorted list of distinct keys, found through their grid rows: keys sorted by (k, j, i) come in rows
//! of equal (j, k), so a dense table of where each row starts (one entry per (j, k), a few MB on the finest octree
//! level against several hundred for a hash table of its keys) narrows a lookup to one row, searched by bisection.
//! Built in one linear pass over the keys, with no random writes.
class RowIndex {
public:
    static constexpr std::uint32_t kNone = 0xffffffffu;

    //! Indexes `keys` (sorted, distinct); they must outlive the index and stay unchanged.
    void assign(const std::vector<std::uint64_t>& keys) {
        keys_ = &keys;
        std::uint32_t side = 1;
        for (const std::uint64_t key : keys) side = std::max({side, key_j(key) + 1, key_k(key) + 1});
        side_ = side;
        starts_.assign(std::size_t{side} * side + 1, 0);
        for (const std::uint64_t key : keys) ++starts_[row(key) + 1];
        for (std::size_t r = 1; r < starts_.size(); ++r) starts_[r] += starts_[r - 1];
    }

    //! Position of `key` in the indexed list, or kNone.
    std::uint32_t find(std::uint64_t key) const {
        if (starts_.empty() || key_j(key) >= side_ || key_k(key) >= side_) return kNone;
        const std::size_t r = row(key);
        const std::uint64_t* first = keys_->data() + starts_[r];
        const std::uint64_t* last = keys_->data() + starts_[r + 1];
        const std::uint64_t* at = std::lower_bound(first, last, key);
        return at != last && *at == key ? static_cast<std::uint32_t>(at - keys_->data()) : kNone;
    }

    std::size_t memory_bytes() const { return starts_.capacity() * 4; }
    //! Points the index at another copy of the same keys (KeySet's copies and moves).
    void rebind(const std::vector<std::uint64_t>& keys) { keys_ = &keys; }

private:
    std::size_t row(std::uint64_t key) const { return std::size_t{key_k(key)} * side_ + key_j(key); }

    const std::vector<std::uint64_t>* keys_ = nullptr;
    std::uint32_t side_ = 0;
    std::vector<std::uint32_t> starts_;  //!< per row (j, k), the position of its first key; then the list's size
};

//! A growing map from keys to dense indices (open addressing, linear probing): insert() hands out 0, 1, 2, ... in
//! order of first insertion, so with a deterministic insertion order the indices are deterministic too.
class GrowingKeyMap {
public:
    static constexpr std::uint32_t kNone = 0xffffffffu;

    //! The index of `key`, or kNone.
    std::uint32_t find(std::uint64_t key) const {
        if (keys_.empty()) return kNone;
        std::size_t slot = hash_key(key) & (keys_.size() - 1);
        while (true) {
            const std::uint64_t stored = keys_[slot];
            if (stored == key) return values_[slot];
            if (stored == kEmpty) return kNone;
            slot = (slot + 1) & (keys_.size() - 1);
        }
    }

    //! The index of `key`, inserting it with the next index when absent; `inserted` says which.
    std::uint32_t insert(std::uint64_t key, bool& inserted) {
        if (2 * (size_ + 1) > keys_.size()) grow();
        std::size_t slot = hash_key(key) & (keys_.size() - 1);
        while (keys_[slot] != kEmpty) {
            if (keys_[slot] == key) {
                inserted = false;
                return values_[slot];
            }
            slot = (slot + 1) & (keys_.size() - 1);
        }
        keys_[slot] = key;
        values_[slot] = static_cast<std::uint32_t>(size_++);
        inserted = true;
        return values_[slot];
    }

    std::size_t size() const { return size_; }
    std::size_t memory_bytes() const { return keys_.capacity() * 8 + values_.capacity() * 4; }

private:
    static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};
    void grow() {
        std::vector<std::uint64_t> old_keys = std::move(keys_);
        std::vector<std::uint32_t> old_values = std::move(values_);
        const std::size_t capacity = old_keys.empty() ? 64 : 2 * old_keys.size();
        keys_.assign(capacity, kEmpty);
        values_.assign(capacity, kNone);
        for (std::size_t s = 0; s < old_keys.size(); ++s) {
            if (old_keys[s] == kEmpty) continue;
            std::size_t slot = hash_key(old_keys[s]) & (capacity - 1);
            while (keys_[slot] != kEmpty) slot = (slot + 1) & (capacity - 1);
            keys_[slot] = old_keys[s];
            values_[slot] = old_values[s];
        }
    }

    std::vector<std::uint64_t> keys_;
    std::vector<std::uint32_t> values_;
    std::size_t size_ = 0;
};

//! The packed form of a signed offset (di, dj, dk): key + offset_delta(...) is the key of the offset coordinates when
//! they stay in range (the fields do not carry into each other then).
inline std::uint64_t offset_delta(int di, int dj, int dk) {
    return static_cast<std::uint64_t>(static_cast<std::int64_t>(di) + static_cast<std::int64_t>(dj) * (1ll << 21) +
                                      static_cast<std::int64_t>(dk) * (1ll << 42));
}

//! Looks keys up in a sorted list for non-decreasing targets (a sorted key list plus a fixed offset), with a pointer
//! that only moves forward: linear in the list's length for a whole pass, sequential in memory, no hashing. The
//! first seek finds its place by bisection, so that a pass may start anywhere in the list (half of it, say).
class SortedCursor {
public:
    static constexpr std::uint32_t kNone = 0xffffffffu;
    explicit SortedCursor(const std::vector<std::uint64_t>& keys) : keys_(&keys) {}
    std::uint32_t seek(std::uint64_t target) {
        const std::vector<std::uint64_t>& keys = *keys_;
        if (!started_) {
            pos_ = static_cast<std::size_t>(std::lower_bound(keys.begin(), keys.end(), target) - keys.begin());
            started_ = true;
        }
        while (pos_ < keys.size() && keys[pos_] < target) ++pos_;
        return pos_ < keys.size() && keys[pos_] == target ? static_cast<std::uint32_t>(pos_) : kNone;
    }

private:
    const std::vector<std::uint64_t>* keys_;
    std::size_t pos_ = 0;
    bool started_ = false;
};

}  // namespace surfaced::reconstruct
