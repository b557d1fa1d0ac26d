// BlockPool: freed large blocks are handed out again for the same size only, the last freed first; the pool keeps no
// more than its byte limit, dropping the oldest first; BlockAllocator draws from it when given one.
#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>

#include "geometry/core/block_pool.h"

namespace surfaced {
namespace {

constexpr std::size_t kMiB = std::size_t{1} << 20;

//! Under AddressSanitizer a pool keeps nothing (every block must be seen freed): checked here, and then the tests of
//! what it keeps skip.
bool keeps_nothing(BlockPool& pool) {
    if (pool.max_bytes() > 0) return false;
    pool.give(allocate_large_block(2 * kMiB), 2 * kMiB);
    EXPECT_EQ(pool.kept_blocks(), 0u);
    EXPECT_EQ(pool.take(2 * kMiB), nullptr);
    return true;
}

TEST(BlockPool, ReusesBlocksOfExactlyTheSameSize) {
    BlockPool pool(8 * kMiB);
    if (keeps_nothing(pool)) GTEST_SKIP() << "AddressSanitizer: the pool keeps nothing";
    void* small = allocate_large_block(2 * kMiB);
    void* large = allocate_large_block(4 * kMiB);
    pool.give(small, 2 * kMiB);
    pool.give(large, 4 * kMiB);
    EXPECT_EQ(pool.kept_blocks(), 2u);
    EXPECT_EQ(pool.kept_bytes(), 6 * kMiB);
    EXPECT_EQ(pool.take(6 * kMiB), nullptr);
    EXPECT_EQ(pool.take(2 * kMiB), small);
    EXPECT_EQ(pool.take(2 * kMiB), nullptr);
    EXPECT_EQ(pool.take(4 * kMiB), large);
    EXPECT_EQ(pool.kept_blocks(), 0u);
    EXPECT_EQ(pool.kept_bytes(), 0u);
    EXPECT_EQ(pool.reused_blocks(), 2u);
    free_large_block(small);
    free_large_block(large);
}

TEST(BlockPool, KeepsWithinItsLimitDroppingTheOldestFirst) {
    BlockPool pool(4 * kMiB);
    if (keeps_nothing(pool)) GTEST_SKIP() << "AddressSanitizer: the pool keeps nothing";
    void* a = allocate_large_block(2 * kMiB);
    void* b = allocate_large_block(2 * kMiB);
    void* c = allocate_large_block(2 * kMiB);
    pool.give(a, 2 * kMiB);
    pool.give(b, 2 * kMiB);
    pool.give(c, 2 * kMiB);  // a, the oldest, is freed
    EXPECT_EQ(pool.kept_blocks(), 2u);
    EXPECT_EQ(pool.kept_bytes(), 4 * kMiB);
    pool.give(allocate_large_block(6 * kMiB), 6 * kMiB);  // over the limit by itself: freed, nothing else dropped
    EXPECT_EQ(pool.kept_bytes(), 4 * kMiB);
    EXPECT_EQ(pool.take(2 * kMiB), c);  // the last freed first
    EXPECT_EQ(pool.take(2 * kMiB), b);
    EXPECT_EQ(pool.take(2 * kMiB), nullptr);  // a is gone
    pool.give(b, 2 * kMiB);
    pool.give(c, 2 * kMiB);
    void* d = allocate_large_block(4 * kMiB);
    pool.give(d, 4 * kMiB);  // both b and c must go
    EXPECT_EQ(pool.kept_blocks(), 1u);
    EXPECT_EQ(pool.take(2 * kMiB), nullptr);
    EXPECT_EQ(pool.take(4 * kMiB), d);
    free_large_block(d);
}

TEST(BlockPool, ABlockGivenBackAgainIsTheNewest) {
    BlockPool pool(4 * kMiB);
    if (keeps_nothing(pool)) GTEST_SKIP() << "AddressSanitizer: the pool keeps nothing";
    void* x = allocate_large_block(2 * kMiB);
    void* y = allocate_large_block(2 * kMiB);
    void* z = allocate_large_block(2 * kMiB);
    pool.give(x, 2 * kMiB);
    pool.give(y, 2 * kMiB);
    EXPECT_EQ(pool.take(2 * kMiB), y);
    pool.give(y, 2 * kMiB);  // y again: newer than x
    pool.give(z, 2 * kMiB);  // x is freed, not y
    EXPECT_EQ(pool.kept_blocks(), 2u);
    EXPECT_EQ(pool.take(2 * kMiB), z);
    EXPECT_EQ(pool.take(2 * kMiB), y);
    free_large_block(y);
    free_large_block(z);
}

TEST(BlockPool, AllocatorDrawsFromThePool) {
    BlockPool pool(64 * kMiB);
    const std::size_t n = 3 * kMiB / sizeof(std::uint32_t);  // 3 MiB: a large block of two 2 MiB pages
    const std::uint32_t* data = nullptr;
    {
        BlockVector<std::uint32_t> v{BlockAllocator<std::uint32_t>(&pool)};
        v.resize(n, 7);
        data = v.data();
        EXPECT_EQ(reinterpret_cast<std::uintptr_t>(data) % kLargeBlockAlign, 0u);
    }
    if (keeps_nothing(pool)) GTEST_SKIP() << "AddressSanitizer: the pool keeps nothing";
    EXPECT_EQ(pool.kept_blocks(), 1u);
    EXPECT_EQ(pool.kept_bytes(), 4 * kMiB);
    {
        BlockVector<std::uint32_t> v{BlockAllocator<std::uint32_t>(&pool)};
        v.resize(n);
        EXPECT_EQ(v.data(), data);  // the same block again
        EXPECT_EQ(pool.kept_blocks(), 0u);
        BlockVector<std::uint32_t> small{BlockAllocator<std::uint32_t>(&pool)};
        small.resize(1000);  // small arrays never touch the pool
        EXPECT_EQ(reinterpret_cast<std::uintptr_t>(small.data()) % 64, 0u);
    }
    EXPECT_EQ(pool.kept_blocks(), 1u);
    EXPECT_EQ(pool.reused_blocks(), 1u);
    // without a pool: allocated and freed per use
    BlockVector<std::uint32_t> plain(n, 1);
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(plain.data()) % kLargeBlockAlign, 0u);
    EXPECT_EQ(plain.get_allocator().pool(), nullptr);
}

}  // namespace
}  // namespace surfaced
