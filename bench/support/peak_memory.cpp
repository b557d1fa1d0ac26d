// The counting global operator new and delete behind peak_memory.h. Each block carries its size in front of the
// pointer handed out: 16 bytes for the plain forms, one alignment unit (at least 16 bytes) for the over-aligned ones,
// which also keep the start of the underlying block there.
#include "bench/support/peak_memory.h"

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdlib>
#include <new>

namespace {
std::atomic<long long> g_live{0}, g_peak{0};

void note_alloc(long long n) {
    const long long live = g_live.fetch_add(n) + n;
    long long peak = g_peak.load();
    while (live > peak && !g_peak.compare_exchange_weak(peak, live)) {}
}
}  // namespace

namespace surfaced::bench {

long long live_heap_bytes() { return g_live.load(); }

HeapPeak::HeapPeak() : before_(g_live.load()) { g_peak.store(before_); }

double HeapPeak::mib() const { return static_cast<double>(g_peak.load() - before_) / (1024.0 * 1024.0); }

}  // namespace surfaced::bench

void* operator new(std::size_t n) {
    void* p = std::malloc(n + 16);
    if (!p) throw std::bad_alloc();
    *static_cast<std::size_t*>(p) = n;
    note_alloc(static_cast<long long>(n));
    return static_cast<char*>(p) + 16;
}
void operator delete(void* p) noexcept {
    if (!p) return;
    char* base = static_cast<char*>(p) - 16;
    g_live.fetch_sub(static_cast<long long>(*reinterpret_cast<std::size_t*>(base)));
    std::free(base);
}
void operator delete(void* p, std::size_t) noexcept { operator delete(p); }
void* operator new[](std::size_t n) { return operator new(n); }
void operator delete[](void* p) noexcept { operator delete(p); }
void operator delete[](void* p, std::size_t) noexcept { operator delete(p); }

// Over-aligned blocks (BlockVector's 2 MiB blocks, 64-byte BVH nodes): the size and the underlying block's start sit
// just below the aligned pointer.
void* operator new(std::size_t n, std::align_val_t align) {
    const std::size_t a = std::max(static_cast<std::size_t>(align), std::size_t{16});
    void* base = std::aligned_alloc(a, (n + a + a - 1) / a * a);
    if (!base) throw std::bad_alloc();
    char* p = static_cast<char*>(base) + a;
    reinterpret_cast<std::size_t*>(p)[-1] = n;
    reinterpret_cast<void**>(p)[-2] = base;
    note_alloc(static_cast<long long>(n));
    return p;
}
void operator delete(void* p, std::align_val_t) noexcept {
    if (!p) return;
    g_live.fetch_sub(static_cast<long long>(reinterpret_cast<std::size_t*>(p)[-1]));
    std::free(reinterpret_cast<void**>(p)[-2]);
}
void operator delete(void* p, std::size_t, std::align_val_t align) noexcept { operator delete(p, align); }
void* operator new[](std::size_t n, std::align_val_t align) { return operator new(n, align); }
void operator delete[](void* p, std::align_val_t align) noexcept { operator delete(p, align); }
void operator delete[](void* p, std::size_t, std::align_val_t align) noexcept { operator delete(p, align); }
