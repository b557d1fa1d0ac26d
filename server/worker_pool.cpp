#include "server/worker_pool.h"

#include <utility>

namespace surfaced::server {

BoundedPool::BoundedPool(std::size_t workers, std::size_t capacity, LoadCounters& counters)
    : capacity_(capacity), counters_(counters) {
    for (std::size_t i = 0; i < workers; ++i) workers_.emplace_back([this] { work(); });
    shedder_ = std::thread([this] { shed(); });
}

BoundedPool::~BoundedPool() { shutdown(); }

void BoundedPool::enqueue(Task task) {
    {
        std::lock_guard lock(mutex_);
        if (jobs_.size() < capacity_) {
            jobs_.push_back(std::move(task));
            counters_.queued.store(static_cast<std::int64_t>(jobs_.size()));
            job_ready_.notify_one();
            return;
        }
        if (shed_jobs_.size() < kShedCapacity) {
            shed_jobs_.push_back(std::move(task));
            shed_ready_.notify_one();
            return;
        }
    }
    task(Admission::Reject);
}

void BoundedPool::shutdown() {
    {
        std::lock_guard lock(mutex_);
        if (stopping_) return;
        stopping_ = true;
    }
    job_ready_.notify_all();
    shed_ready_.notify_all();
    for (std::thread& t : workers_) t.join();
    shedder_.join();
}

void BoundedPool::work() {
    for (;;) {
        Task task;
        {
            std::unique_lock lock(mutex_);
            job_ready_.wait(lock, [&] { return stopping_ || !jobs_.empty(); });
            if (jobs_.empty()) return;  // stopping and nothing left
            task = std::move(jobs_.front());
            jobs_.pop_front();
            counters_.queued.store(static_cast<std::int64_t>(jobs_.size()));
        }
        ++counters_.busy;
        task(Admission::Serve);
        --counters_.busy;
    }
}

void BoundedPool::shed() {
    for (;;) {
        Task task;
        {
            std::unique_lock lock(mutex_);
            shed_ready_.wait(lock, [&] { return stopping_ || !shed_jobs_.empty(); });
            if (shed_jobs_.empty()) return;
            task = std::move(shed_jobs_.front());
            shed_jobs_.pop_front();
        }
        task(Admission::Shed);
    }
}

}  // namespace surfaced::server
