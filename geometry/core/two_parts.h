// Two-way work splitting (internal to geometry/): the library starts a second thread only where its options allow
// one (SubdivisionOptions::threads, SimplifyOptions::threads), for work cut into two parts that never write the same
// memory. Callers cut by size or by data alone, so that results do not depend on whether the parts ran concurrently.
#pragma once

#include <exception>
#include <thread>

namespace surfaced {

//! Runs part(0) and part(1): concurrently when `threaded` and a second thread can be started, else one after the
//! other. An exception from a part is rethrown once both have ended (part(0)'s first).
template <class F>
void run_two_parts(bool threaded, F&& part) {
    if (!threaded) {
        part(0);
        part(1);
        return;
    }
    std::exception_ptr failure;
    std::thread other;
    try {
        other = std::thread([&] {
            try {
                part(1);
            } catch (...) {
                failure = std::current_exception();
            }
        });
    } catch (...) {  // no thread to be had: both parts here
        part(0);
        part(1);
        return;
    }
    try {
        part(0);
    } catch (...) {
        other.join();
        throw;
    }
    other.join();
    if (failure) std::rethrow_exception(failure);
}

}  // namespace surfaced
