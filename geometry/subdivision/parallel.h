// Two-way work splitting for refinement (internal). Large levels are always cut into the same two parts, decided by
// size alone; whether the parts then run on one thread or two, every sum is formed in the same order, so results
// are bit-identical for any thread count.
#pragma once

#include "geometry/core/two_parts.h"
#include "geometry/core/types.h"

namespace surfaced::subdivision {

//! Levels with fewer elements than this are not split (thread start-up would cost more than it saves).
inline constexpr Index kSplitMinimum = 16384;

//! body(begin, end) over [0, n): independent per element, so split in two when large and threads are allowed.
template <class F>
void for_range(Index n, bool threaded, F&& body) {
    if (!threaded || n < kSplitMinimum) {
        body(Index{0}, n);
        return;
    }
    run_two_parts(true, [&](int part) { part == 0 ? body(Index{0}, n / 2) : body(n / 2, n); });
}

}  // namespace surfaced::subdivision
