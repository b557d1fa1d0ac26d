// Clocks for the benchmarks: wall time, the process's CPU time (all threads) and the calling thread's CPU time. On a
// machine shared with other work, CPU time leaves out the time slices the scheduler gives other processes.
#pragma once

#include <chrono>
#include <ctime>

namespace surfaced::bench {

enum class Clock {
    Wall,        //!< std::chrono::steady_clock
    ProcessCpu,  //!< CLOCK_PROCESS_CPUTIME_ID: every thread of the process
    ThreadCpu,   //!< CLOCK_THREAD_CPUTIME_ID: the calling thread
};

//! Seconds on `clock` from an arbitrary start: only differences mean something.
inline double now_seconds(Clock clock) {
    if (clock == Clock::Wall)
        return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
    timespec ts{};
    clock_gettime(clock == Clock::ProcessCpu ? CLOCK_PROCESS_CPUTIME_ID : CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

//! Time elapsed on one clock since construction (or restart()).
class Stopwatch {
public:
    explicit Stopwatch(Clock clock = Clock::Wall) : clock_(clock), start_(now_seconds(clock)) {}
    void restart() { start_ = now_seconds(clock_); }
    double seconds() const { return now_seconds(clock_) - start_; }
    double ms() const { return 1e3 * seconds(); }

private:
    Clock clock_;
    double start_;
};

}  // namespace surfaced::bench
