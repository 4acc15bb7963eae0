#include "core/thread_pool.h"

#include "core/assert.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace pbdsplat::core {
namespace {
inline void cpu_relax() {
#if defined(__SSE2__)
    _mm_pause();
#else
    std::this_thread::yield();
#endif
}
constexpr int k_spin = 1 << 14;  // roughly tens of microseconds before sleeping
} // namespace

ThreadPool::ThreadPool(unsigned threads) {
    PBDSPLAT_ASSERT(threads >= 1 && threads <= 256, "ThreadPool: use 1 to 256 threads");
    for (unsigned i = 1; i < threads; ++i) workers_.emplace_back([this] { worker(); });
}

ThreadPool::~ThreadPool() {
    {
        std::lock_guard lock(mutex_);
        stop_.store(true);
        generation_.fetch_add(1);
    }
    wake_.notify_all();
    for (auto& t : workers_) t.join();
}

void ThreadPool::take_chunks() {
    const unsigned chunks = this->chunks();
    // The job and its size are read after each chunk is taken: a thread that was late to see the
    // last chunk go may take the first of the next loop, which its counter's reset published.
    for (unsigned c = next_chunk_.fetch_add(1, std::memory_order_acq_rel); c < chunks; c = next_chunk_.fetch_add(1, std::memory_order_acq_rel)) {
        const size_t n = n_;
        (*job_)(c, n * c / chunks, n * (c + 1) / chunks);
        pending_.fetch_sub(1, std::memory_order_acq_rel);
    }
}

void ThreadPool::worker() {
    unsigned seen = 0;
    while (true) {
        int spins = 0;
        while (generation_.load(std::memory_order_acquire) == seen && spins < k_spin) cpu_relax(), ++spins;
        if (generation_.load(std::memory_order_acquire) == seen) {
            std::unique_lock lock(mutex_);
            wake_.wait(lock, [&] { return generation_.load() != seen; });
        }
        seen = generation_.load(std::memory_order_acquire);
        if (stop_.load()) return;
        take_chunks();
    }
}

void ThreadPool::parallel_for(size_t n, const std::function<void(unsigned, size_t, size_t)>& fn) {
    if (workers_.empty()) {
        fn(0, 0, n);
        return;
    }
    job_ = &fn;
    n_ = n;
    pending_.store(chunks(), std::memory_order_relaxed);
    next_chunk_.store(0, std::memory_order_release);  // publishes the job to whoever takes a chunk
    {
        // Under the mutex, so a worker between its check and its wait cannot miss the change.
        std::lock_guard lock(mutex_);
        generation_.fetch_add(1, std::memory_order_release);
    }
    wake_.notify_all();
    take_chunks();
    while (pending_.load(std::memory_order_acquire) != 0) cpu_relax();
}

} // namespace pbdsplat::core
