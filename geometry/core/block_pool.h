// Large aligned memory blocks for arrays that are read at random: BlockAllocator (64-byte alignment; arrays of 1 MiB
// or more as whole 2 MiB pages on 2 MiB boundaries, with transparent huge pages requested) and BlockPool, which a
// caller owns and passes in to keep freed large blocks for reuse by later allocations of the same size.
#pragma once

#include <cstddef>
#include <limits>
#include <mutex>
#include <new>
#include <type_traits>
#include <vector>

namespace surfaced {

//! Large blocks are whole multiples of this, on boundaries of it: the size of an x86-64 huge page.
inline constexpr std::size_t kLargeBlockAlign = std::size_t{2} << 20;

//! A fresh block of `bytes` (a multiple of kLargeBlockAlign) on a kLargeBlockAlign boundary, with transparent huge
//! pages requested where the kernel leaves that to the program (Linux THP "madvise"). Throws std::bad_alloc.
void* allocate_large_block(std::size_t bytes);
//! Frees a block from allocate_large_block().
void free_large_block(void* block) noexcept;

//! Freed large blocks (from allocate_large_block()), kept for later allocations of exactly the same size: every first
//! touch of fresh memory faults and has the kernel clear the page, and the C library returns blocks this large to the
//! system when they are freed, so work that allocates the same large arrays again and again (sizes are whole pages
//! and vectors grow by doubling, so sizes repeat) pays that every time without a pool. Keeps at most max_bytes in all
//! (the oldest freed is dropped first beyond that); one mutex guards it, so threads may share a pool. Under
//! AddressSanitizer it keeps nothing: every block must be seen freed for a use after free to be caught.
class BlockPool {
public:
    explicit BlockPool(std::size_t max_bytes);
    ~BlockPool();  //!< frees the blocks kept
    BlockPool(const BlockPool&) = delete;
    BlockPool& operator=(const BlockPool&) = delete;

    //! A kept block of exactly `bytes`, the last freed of that size, or nullptr.
    void* take(std::size_t bytes) noexcept;
    //! Keeps a block from allocate_large_block() of `bytes`, freeing the oldest kept ones to stay within max_bytes()
    //! (or this one, when it is larger than that).
    void give(void* block, std::size_t bytes) noexcept;

    //! The most this pool keeps: the limit given, or 0 under AddressSanitizer.
    std::size_t max_bytes() const { return max_bytes_; }
    std::size_t kept_bytes() const;
    std::size_t kept_blocks() const;
    //! How many blocks take() has handed out again so far.
    std::size_t reused_blocks() const;

private:
    struct Block {
        void* p = nullptr;
        std::size_t bytes = 0;
    };
    const std::size_t max_bytes_;
    //! More blocks than max_bytes_ holds whole large blocks are never kept (reserved up front: give() never allocates).
    const std::size_t max_blocks_;
    mutable std::mutex mutex_;
    std::vector<Block> blocks_;  //!< oldest first
    std::size_t total_ = 0;      //!< bytes in blocks_
    std::size_t reused_ = 0;
};

//! Allocates on 64-byte boundaries (so that a 64-byte-aligned record fills whole cache lines), and arrays of 1 MiB or
//! more as large blocks: whole 2 MiB pages on 2 MiB boundaries, with transparent huge pages requested. Code that reads
//! arrays of up to hundreds of MB at random would otherwise miss the TLB on nearly every access, and pay a fault
//! for every 4 KiB page first touched. Large blocks come from and go back to `pool` when one is given; without one
//! they are allocated and freed on every call. Every instance can free what any other allocated (equal: true).
template <class T>
class BlockAllocator {
public:
    using value_type = T;
    using propagate_on_container_move_assignment = std::true_type;
    using propagate_on_container_swap = std::true_type;

    BlockAllocator() = default;
    explicit BlockAllocator(BlockPool* pool) noexcept : pool_(pool) {}
    template <class U>
    BlockAllocator(const BlockAllocator<U>& other) noexcept : pool_(other.pool()) {}

    T* allocate(std::size_t n) {
        if (n > (std::numeric_limits<std::size_t>::max() >> 2) / sizeof(T)) throw std::bad_array_new_length();
        if (!large(n)) return static_cast<T*>(::operator new (n * sizeof(T), std::align_val_t{64}));
        const std::size_t bytes = large_bytes(n);
        if (pool_)
            if (void* kept = pool_->take(bytes)) return static_cast<T*>(kept);
        return static_cast<T*>(allocate_large_block(bytes));
    }
    void deallocate(T* p, std::size_t n) noexcept {
        if (!large(n))
            ::operator delete (p, std::align_val_t{64});
        else if (pool_)
            pool_->give(p, large_bytes(n));
        else
            free_large_block(p);
    }

    BlockPool* pool() const noexcept { return pool_; }
    template <class U>
    bool operator==(const BlockAllocator<U>&) const noexcept {
        return true;
    }

private:
    static bool large(std::size_t n) { return n * sizeof(T) >= kLargeBlockAlign / 2; }
    //! A large block's size: whole 2 MiB pages
    static std::size_t large_bytes(std::size_t n) {
        return (n * sizeof(T) + kLargeBlockAlign - 1) / kLargeBlockAlign * kLargeBlockAlign;
    }
    BlockPool* pool_ = nullptr;
};

template <class T>
using BlockVector = std::vector<T, BlockAllocator<T>>;

}  // namespace surfaced
