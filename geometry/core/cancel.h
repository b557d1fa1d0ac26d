// Cooperative cancellation for long geometry work (STYLE: the library never owns threads or clocks it was not
// given). A caller that wants a deadline or an abort button passes a Cancel in the algorithm's options; the
// algorithm polls `requested()` between units of work (a refinement level, a batch of collapses, a slab of grid
// cells) and returns ErrorCode::Cancelled. A default-constructed Cancel never fires and costs one branch.
#pragma once

#include <atomic>
#include <chrono>

namespace surfaced {

struct Cancel {
    using Clock = std::chrono::steady_clock;

    //! Work past this instant is abandoned. Default: never.
    Clock::time_point deadline = Clock::time_point::max();
    //! Set to true by another thread (shutdown, client gone) to abandon the work. Not owned; may be null.
    const std::atomic<bool>* flag = nullptr;

    //! True once the deadline has passed or the flag is set. Cheap enough to call every few thousand elements.
    bool requested() const {
        if (flag && flag->load(std::memory_order_relaxed)) return true;
        return deadline != Clock::time_point::max() && Clock::now() >= deadline;
    }
};

}  // namespace surfaced
