// BlockPool and the large blocks it keeps (block_pool.h).
#include "geometry/core/block_pool.h"

#if defined(__linux__)
#include <sys/mman.h>
#endif

#if defined(__SANITIZE_ADDRESS__)
#define SURFACED_BLOCK_POOL_KEEPS 0  // AddressSanitizer must see every block freed, to catch a use after free
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SURFACED_BLOCK_POOL_KEEPS 0
#endif
#endif
#ifndef SURFACED_BLOCK_POOL_KEEPS
#define SURFACED_BLOCK_POOL_KEEPS 1
#endif

namespace surfaced {

void* allocate_large_block(std::size_t bytes) {
    void* p = ::operator new (bytes, std::align_val_t{kLargeBlockAlign});
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    ::madvise(p, bytes, MADV_HUGEPAGE);  // advice only: failure changes nothing
#endif
    return p;
}

void free_large_block(void* block) noexcept { ::operator delete (block, std::align_val_t{kLargeBlockAlign}); }

BlockPool::BlockPool(std::size_t max_bytes)
    : max_bytes_(SURFACED_BLOCK_POOL_KEEPS ? max_bytes : 0), max_blocks_(max_bytes_ / kLargeBlockAlign + 1) {
    blocks_.reserve(max_blocks_);
}

BlockPool::~BlockPool() {
    for (const Block& block : blocks_) free_large_block(block.p);
}

void* BlockPool::take(std::size_t bytes) noexcept {
    const std::lock_guard lock(mutex_);
    for (std::size_t i = blocks_.size(); i-- > 0;)
        if (blocks_[i].bytes == bytes) {
            void* p = blocks_[i].p;
            blocks_.erase(blocks_.begin() + static_cast<std::ptrdiff_t>(i));
            total_ -= bytes;
            ++reused_;
            return p;
        }
    return nullptr;
}

void BlockPool::give(void* block, std::size_t bytes) noexcept {
    if (bytes > max_bytes_) {
        free_large_block(block);
        return;
    }
    for (;;) {  // drop the oldest, freed outside the lock, until this one fits
        Block oldest;
        {
            const std::lock_guard lock(mutex_);
            if (total_ + bytes <= max_bytes_ && blocks_.size() < max_blocks_) {
                blocks_.push_back({block, bytes});  // within the capacity reserved: no allocation
                total_ += bytes;
                return;
            }
            oldest = blocks_.front();
            blocks_.erase(blocks_.begin());
            total_ -= oldest.bytes;
        }
        free_large_block(oldest.p);
    }
}

std::size_t BlockPool::kept_bytes() const {
    const std::lock_guard lock(mutex_);
    return total_;
}

std::size_t BlockPool::kept_blocks() const {
    const std::lock_guard lock(mutex_);
    return blocks_.size();
}

std::size_t BlockPool::reused_blocks() const {
    const std::lock_guard lock(mutex_);
    return reused_;
}

}  // namespace surfaced
