#pragma once
// A fixed pool of worker threads for data-parallel loops. parallel_for splits [0, n) into one
// contiguous chunk per thread, the same way for the same thread count, so work that sums per
// chunk and then over chunks in order stays deterministic. A solver frame issues dozens of
// short loops, so workers spin briefly before sleeping: a condition-variable wake-up per loop
// would cost more than the loop.
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace pbdsplat::core {

class ThreadPool {
public:
    // `threads` includes the calling thread; 1 runs everything inline.
    explicit ThreadPool(unsigned threads);
    ~ThreadPool();
    ThreadPool(const ThreadPool&) = delete;
    ThreadPool& operator=(const ThreadPool&) = delete;

    unsigned size() const { return unsigned(workers_.size()) + 1; }

    // Calls fn(chunk, begin, end) for size() contiguous chunks of [0, n) and returns when all
    // are done. The caller runs chunk 0. Not reentrant.
    void parallel_for(size_t n, const std::function<void(unsigned chunk, size_t begin, size_t end)>& fn);

private:
    void worker(unsigned index);

    std::vector<std::thread> workers_;
    std::mutex mutex_;
    std::condition_variable wake_;
    const std::function<void(unsigned, size_t, size_t)>* job_ = nullptr;
    size_t n_ = 0;
    std::atomic<unsigned> generation_{0};
    std::atomic<unsigned> pending_{0};
    std::atomic<bool> stop_{false};
};

} // namespace pbdsplat::core
