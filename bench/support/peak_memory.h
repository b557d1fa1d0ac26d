// Peak heap of a call: peak_memory.cpp replaces the global operator new and delete (the over-aligned forms too) with
// ones that count the live bytes and their peak. A replacement must exist once per executable: link the
// bench_peak_memory library into a bench that measures memory, and never into the service. Memory a library takes
// from its own allocator (TBB's, Embree's, malloc) is not counted.
#pragma once

#include <utility>

#include "bench/support/timing.h"

namespace surfaced::bench {

//! Bytes allocated through the global operator new and not yet deleted.
long long live_heap_bytes();

//! The live-heap peak above the live bytes at construction, which resets the peak (one measurement at a time).
class HeapPeak {
public:
    HeapPeak();
    double mib() const;

private:
    long long before_;
};

//! One run: its time on one clock and the live-heap peak above its start, in MiB.
struct Measurement {
    double seconds = 1e300;
    double peak_mib = 0;
};

//! Runs `step` once: its time on `clock` and its heap peak.
template <class Step>
Measurement measure(Step&& step, Clock clock) {
    const HeapPeak peak;
    const Stopwatch watch(clock);
    std::forward<Step>(step)();
    Measurement m;
    m.seconds = watch.seconds();
    m.peak_mib = peak.mib();
    return m;
}

//! Folds one run into `best`: the fastest time, the peak of the latest run.
inline void keep_fastest(Measurement& best, const Measurement& run) {
    if (run.seconds < best.seconds) best.seconds = run.seconds;
    best.peak_mib = run.peak_mib;
}

}  // namespace surfaced::bench
