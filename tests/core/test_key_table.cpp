#include <doctest/doctest.h>

#include <map>
#include <random>

#include "core/key_table.h"

using namespace pbdsplat;

TEST_SUITE("core/key_table") {
    TEST_CASE("a key set holds what was inserted and nothing else") {
        core::KeySet set(100);
        for (uint64_t k = 0; k < 100; ++k) set.insert(k * 7919u << 32 | k);
        set.insert(5ull * 7919u << 32 | 5u);  // twice: still one key
        CHECK(set.size() == 100);
        for (uint64_t k = 0; k < 100; ++k) {
            CHECK(set.contains(k * 7919u << 32 | k));
            CHECK_FALSE(set.contains(k * 7919u << 32 | (k + 1)));
        }
    }

    TEST_CASE("a key map agrees with std::map through growth and overwrites") {
        core::KeyMap<uint32_t> map(4);  // far too small: it must grow many times
        std::map<uint64_t, uint32_t> reference;
        std::mt19937_64 rng(3);
        for (uint32_t i = 0; i < 5000; ++i) {
            const uint64_t key = rng() % 3000;  // repeats: overwrites
            map[key] = i + 1;
            reference[key] = i + 1;
        }
        for (uint64_t key = 0; key < 3000; ++key) {
            const uint32_t* v = map.find(key);
            const auto it = reference.find(key);
            REQUIRE((v != nullptr) == (it != reference.end()));
            if (v) CHECK(*v == it->second);
        }
        CHECK(map.find(1ull << 40) == nullptr);
        // A new key reads as a default value before it is set.
        CHECK(map[1ull << 41] == 0u);
    }
}
