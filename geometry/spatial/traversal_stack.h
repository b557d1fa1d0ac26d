// The stack of a hierarchy descent (internal to geometry/spatial). A descent pushes at most one node per level, so a
// fixed array covers 64 levels without touching the heap; deeper hierarchies (many coincident centroids) spill to a
// vector.
#pragma once

#include <cstddef>
#include <vector>

namespace surfaced::spatial_detail {

template <class T>
class TraversalStack {
public:
    bool empty() const { return size_ == 0; }
    void push(const T& value) {
        if (size_ < kFixed)
            fixed_[size_] = value;
        else
            overflow_.push_back(value);
        ++size_;
    }
    T pop() {
        --size_;
        if (size_ < kFixed) return fixed_[size_];
        T value = overflow_.back();
        overflow_.pop_back();
        return value;
    }

private:
    static constexpr std::size_t kFixed = 64;
    T fixed_[kFixed];
    std::vector<T> overflow_;
    std::size_t size_ = 0;
};

}  // namespace surfaced::spatial_detail
