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

// Ascending; stable. A pass per digit in which the keys differ: digits where every key has the
// same bits (the high bits of small ids, the gap between the two halves of a packed pair) are
// skipped. 8-bit digits for a few thousand keys (the histogram stays small against them), 11-bit
// ones for more. Other types than uint32_t/uint64_t are not meant to come here.
template <class U>
void radix_sort(std::span<U> items) {
    static_assert(std::is_same_v<U, uint32_t> || std::is_same_v<U, uint64_t>, "radix_sort: unsigned 32- or 64-bit keys");
    // A short list (a tear's few ids) costs less to sort by compares than a pass's histogram
    // costs to clear and add up; the order is the same either way.
    constexpr size_t k_compare_below = 64;
    if (items.size() < k_compare_below) {
        std::sort(items.begin(), items.end());
        return;
    }
    U any = 0, all = ~U(0);
    for (U x : items) any |= x, all &= x;
    const U varying = any ^ all;  // the bits not the same in every key
    const unsigned bits = items.size() < 4096 ? 8 : 11, buckets = 1u << bits;
    thread_local std::vector<U> spare;
    thread_local std::vector<uint32_t> count;
    spare.resize(items.size());
    count.resize(buckets + 1);
    std::span<U> from = items, to = spare;
    for (unsigned shift = 0; shift < 8 * sizeof(U) && (varying >> shift) != 0; shift += bits) {
        if (((varying >> shift) & (buckets - 1)) == 0) continue;
        std::fill(count.begin(), count.end(), 0u);
        for (U x : from) ++count[((x >> shift) & (buckets - 1)) + 1];
        for (unsigned b = 0; b < buckets; ++b) count[b + 1] += count[b];
        for (U x : from) to[count[(x >> shift) & (buckets - 1)]++] = x;
        std::swap(from, to);
    }
    if (from.data() != items.data()) std::copy(from.begin(), from.end(), items.begin());
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
