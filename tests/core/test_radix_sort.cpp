#include <doctest/doctest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "core/radix_sort.h"

using namespace pbdsplat;

TEST_SUITE("core/radix_sort") {
    TEST_CASE("radix_sort orders 32- and 64-bit keys as std::sort does, at every digit count") {
        std::mt19937_64 rng(11);
        for (uint64_t range : {uint64_t(1), uint64_t(7), uint64_t(2048), uint64_t(1) << 22, uint64_t(1) << 32}) {
            for (size_t n : {size_t(0), size_t(1), size_t(2), size_t(100), size_t(5000)}) {
                std::vector<uint32_t> a;
                for (size_t k = 0; k < n; ++k) a.push_back(uint32_t(rng() % range));
                std::vector<uint32_t> expected = a;
                std::sort(expected.begin(), expected.end());
                core::radix_sort(std::span<uint32_t>(a));
                CHECK(a == expected);
                std::vector<uint64_t> b;
                for (size_t k = 0; k < n; ++k) b.push_back((rng() % range) << 32 | (rng() % range));
                std::vector<uint64_t> expected_b = b;
                std::sort(expected_b.begin(), expected_b.end());
                core::radix_sort(std::span<uint64_t>(b));
                CHECK(b == expected_b);
            }
        }
    }

    TEST_CASE("radix_sort skips digits every key shares and still orders packed pairs") {
        // (vertex << 32 | triangle) with a shared high vertex bit and both halves small: the
        // digits between the halves are the same in every key.
        std::mt19937 rng(3);
        for (size_t n : {size_t(3), size_t(500), size_t(6000)}) {
            std::vector<uint64_t> keys;
            for (size_t k = 0; k < n; ++k) keys.push_back(uint64_t((1u << 20) | (rng() % 4000)) << 32 | (rng() % 9000));
            std::vector<uint64_t> expected = keys;
            std::sort(expected.begin(), expected.end());
            core::radix_sort(std::span<uint64_t>(keys));
            CHECK(keys == expected);
        }
        std::vector<uint32_t> same(100, 77u);
        core::radix_sort(std::span<uint32_t>(same));
        CHECK(same == std::vector<uint32_t>(100, 77u));
    }

    TEST_CASE("radix_sort_unique drops duplicates") {
        std::vector<uint32_t> a{5, 3, 5, 0, 3, 4000000, 0, 9};
        core::radix_sort_unique(a);
        CHECK(a == std::vector<uint32_t>{0, 3, 5, 9, 4000000});
        std::vector<uint64_t> none;
        core::radix_sort_unique(none);
        CHECK(none.empty());
    }
}
