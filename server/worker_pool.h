// BoundedPool: the worker threads that serve accepted connections, with a bounded queue in front of them. What does
// not fit goes to a shedding thread (which answers 503), or, when even its queue is full, is refused at once.
// LoadCounters: the load gauges the pool, the connection loop and /metrics share.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace surfaced::server {

struct LoadCounters {
    std::atomic<std::int64_t> queued{0};     //!< accepted connections waiting for a worker
    std::atomic<std::int64_t> busy{0};       //!< workers holding a connection
    std::atomic<std::int64_t> in_flight{0};  //!< requests being read, computed or written (the connection loop)
};

//! How a task is to treat the connection it owns.
enum class Admission {
    Serve,   //!< on a worker: serve it
    Shed,    //!< on the shedding thread: answer 503 + Retry-After and close
    Reject,  //!< on the thread that enqueued it, when even the shedding queue is full: close without an answer
};

//! Each task is "serve this accepted socket" and owns the socket, so every task runs exactly once: on a worker when
//! the queue has room, else on the shedding thread, else at once on the caller's thread.
class BoundedPool {
public:
    using Task = std::function<void(Admission)>;
    static constexpr std::size_t kShedCapacity = 256;

    BoundedPool(std::size_t workers, std::size_t capacity, LoadCounters& counters);
    ~BoundedPool();
    BoundedPool(const BoundedPool&) = delete;
    BoundedPool& operator=(const BoundedPool&) = delete;

    void enqueue(Task task);
    //! Runs what is queued, then joins every thread. Idempotent.
    void shutdown();

private:
    void work();
    void shed();

    const std::size_t capacity_;
    LoadCounters& counters_;
    std::mutex mutex_;
    std::condition_variable job_ready_;
    std::condition_variable shed_ready_;
    std::deque<Task> jobs_;
    std::deque<Task> shed_jobs_;
    bool stopping_ = false;
    std::vector<std::thread> workers_;
    std::thread shedder_;
};

}  // namespace surfaced::server
