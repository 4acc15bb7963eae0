#include <doctest/doctest.h>

#include <algorithm>
#include <random>
#include <utility>
#include <vector>

#include "core/small_sort.h"

using namespace pbdsplat;

TEST_SUITE("core/small_sort") {
    TEST_CASE("insertion_sort orders as std::stable_sort does, ties in their order") {
        std::mt19937 rng(7);
        for (int n = 0; n < 40; ++n) {
            // Keys with many ties; the second member records the original position.
            std::vector<std::pair<int, int>> items;
            for (int k = 0; k < n; ++k) items.push_back({int(rng() % 5), k});
            auto expected = items;
            std::stable_sort(expected.begin(), expected.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
            struct ByKey {
                std::pair<int, int> p;
                bool operator<(const ByKey& o) const { return p.first < o.p.first; }
            };
            std::vector<ByKey> sorted;
            for (const auto& p : items) sorted.push_back({p});
            core::insertion_sort(sorted.begin(), sorted.end());
            REQUIRE(sorted.size() == expected.size());
            for (size_t k = 0; k < sorted.size(); ++k) CHECK(sorted[k].p == expected[k]);
        }
    }

    TEST_CASE("insertion_sort leaves an empty or one-item range alone") {
        std::vector<unsigned> none, one{3};
        core::insertion_sort(none.begin(), none.end());
        core::insertion_sort(one.begin(), one.end());
        CHECK(none.empty());
        CHECK(one == std::vector<unsigned>{3});
    }
}
