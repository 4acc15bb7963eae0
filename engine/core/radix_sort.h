#pragma once
// Sorting the id lists of a topology edit (a region's particles, its triangles' corners, edge
// keys: a few thousand unsigned integers): std::sort's compares branch unpredictably on such
// data, and a cut spent more time mispredicting in its sorts than in any of its own steps. A
// least-significant-digit radix sort reads each item a few times with no compare at all.
#include <algorithm>
#include <cstdint>
#include <span>
#include <type_traits>
#include <vector>

namespace pbdsplat::core {

// Ascending; stable. 11-bit digits, only as many passes as the largest key needs (two for ids
// under four million). Other types than uint32_t/uint64_t are not meant to come here.
template <class U>
void radix_sort(std::span<U> items) {
    static_assert(std::is_same_v<U, uint32_t> || std::is_same_v<U, uint64_t>, "radix_sort: unsigned 32- or 64-bit keys");
    if (items.size() < 2) return;
    U largest = 0;
    for (U x : items) largest |= x;
    constexpr unsigned k_bits = 11, k_buckets = 1u << k_bits;
    thread_local std::vector<U> spare;
    spare.resize(items.size());
    std::span<U> from = items, to = spare;
    unsigned passes = 0;
    for (unsigned shift = 0; shift < 8 * sizeof(U) && (largest >> shift) != 0; shift += k_bits, ++passes) {
        uint32_t count[k_buckets + 1] = {};
        for (U x : from) ++count[((x >> shift) & (k_buckets - 1)) + 1];
        for (unsigned b = 0; b < k_buckets; ++b) count[b + 1] += count[b];
        for (U x : from) to[count[(x >> shift) & (k_buckets - 1)]++] = x;
        std::swap(from, to);
    }
    if (passes % 2 == 1) std::copy(from.begin(), from.end(), items.begin());
}

// Sorted ascending with duplicates dropped.
template <class U>
void radix_sort_unique(std::vector<U>& items) {
    radix_sort(std::span<U>(items));
    size_t kept = 0;
    for (size_t k = 0; k < items.size(); ++k)
        if (kept == 0 || items[k] != items[kept - 1]) items[kept++] = items[k];
    items.resize(kept);
}

} // namespace pbdsplat::core
