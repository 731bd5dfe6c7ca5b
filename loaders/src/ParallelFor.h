#pragma once
// Independent jobs spread over threads, for load-time work on many meshes.
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

namespace sgfx::detail {

/// Runs job(i) for every i in [0, n) on up to `threads` threads (0: the hardware's count), each
/// thread taking the next index, so the caller should order the jobs largest first. The first
/// exception a job throws stops the others from starting new jobs and is rethrown here after every
/// thread has joined. With one thread (or one job) it runs on the caller's thread.
template <class Job> void parallelFor(std::size_t n, unsigned threads, Job&& job) {
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    const std::size_t count = std::min<std::size_t>(threads, n);
    if (count <= 1) {
        for (std::size_t i = 0; i < n; ++i)
            job(i);
        return;
    }
    std::atomic<std::size_t> next{0};
    std::atomic<bool> failed{false};
    std::exception_ptr first;
    std::mutex firstMutex;
    auto worker = [&] {
        for (std::size_t i; !failed.load(std::memory_order_relaxed) && (i = next.fetch_add(1)) < n;) {
            try {
                job(i);
            } catch (...) {
                const std::lock_guard lock(firstMutex);
                if (!first) first = std::current_exception();
                failed = true;
            }
        }
    };
    std::vector<std::thread> pool;
    pool.reserve(count - 1);
    for (std::size_t t = 1; t < count; ++t) {
        try {
            pool.emplace_back(worker);
        } catch (...) { // no more threads to be had (system_error, bad_alloc): fewer do the work
            break;
        }
    }
    worker();
    for (std::thread& t : pool)
        t.join();
    if (first) std::rethrow_exception(first);
}

} // namespace sgfx::detail
