#pragma once
// A fixed pool of worker threads for data-parallel loops. parallel_for splits [0, n) into a
// fixed number of contiguous chunks per thread, the same way for the same thread count, and
// the threads take chunks in turn until none is left: a thread that runs slow (a core shared
// with another guest of the machine, a late wake-up) takes fewer, instead of the loop waiting
// for its half. Which thread runs a chunk varies; what each chunk computes does not, so work
// that sums per chunk and then over chunks in order stays deterministic. A solver frame issues
// dozens of short loops, so workers spin briefly before sleeping: a condition-variable wake-up
// per loop would cost more than the loop.
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
    // How many chunks parallel_for cuts a loop into: a few per thread, so a slow thread's share
    // moves to the others, yet few enough that taking one (an atomic add) costs nothing beside it.
    unsigned chunks() const { return workers_.empty() ? 1u : k_chunks_per_thread * size(); }

    // Calls fn(chunk, begin, end) for chunks() contiguous chunks of [0, n), in chunk order per
    // thread, and returns when all are done. The caller takes chunks too. Not reentrant.
    void parallel_for(size_t n, const std::function<void(unsigned chunk, size_t begin, size_t end)>& fn);

private:
    static constexpr unsigned k_chunks_per_thread = 4;
    void worker();
    void take_chunks();

    std::vector<std::thread> workers_;
    std::mutex mutex_;
    std::condition_variable wake_;
    const std::function<void(unsigned, size_t, size_t)>* job_ = nullptr;
    size_t n_ = 0;
    std::atomic<unsigned> generation_{0};
    std::atomic<unsigned> next_chunk_{0};  // the next chunk to take
    std::atomic<unsigned> pending_{0};     // chunks not yet done
    std::atomic<bool> stop_{false};
};

} // namespace pbdsplat::core
