#include <doctest/doctest.h>

#include <atomic>
#include <vector>

#include "core/thread_pool.h"

using namespace pbdsplat;

TEST_SUITE("core/thread_pool") {
    TEST_CASE("every index is visited once, in chunks whose bounds depend on the loop alone") {
        for (unsigned threads : {1u, 2u, 3u}) {
            core::ThreadPool pool(threads);
            const unsigned chunks = pool.chunks();
            CHECK(chunks >= threads);
            // Many short loops back to back, as the solver issues them, of sizes below and above
            // the chunk count.
            for (size_t n : {size_t(0), size_t(1), size_t(5), size_t(37), size_t(1000), size_t(4096)}) {
                for (int round = 0; round < 200; ++round) {
                    std::vector<std::atomic<int>> visits(n);
                    std::vector<std::atomic<int>> chunk_runs(chunks);
                    std::atomic<bool> bounds_ok{true};
                    pool.parallel_for(n, [&](unsigned chunk, size_t begin, size_t end) {
                        if (chunk >= chunks || begin != n * chunk / chunks || end != n * (chunk + 1) / chunks) bounds_ok = false;
                        else chunk_runs[chunk].fetch_add(1);
                        for (size_t i = begin; i < end; ++i) visits[i].fetch_add(1);
                    });
                    CHECK(bounds_ok.load());
                    for (size_t i = 0; i < n; ++i) REQUIRE(visits[i].load() == 1);
                    for (unsigned c = 0; c < chunks; ++c) REQUIRE(chunk_runs[c].load() == 1);
                }
            }
        }
    }
}
