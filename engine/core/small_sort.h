#pragma once
// Sorting a handful of items (a vertex's triangles, its fan): std::sort's set-up costs more
// than the sort itself below a dozen or so, and topology edits sort thousands of such lists.
#include <iterator>
#include <utility>

namespace pbdsplat::core {

// Ascending by operator<; stable. Quadratic: for short ranges only.
template <class It>
void insertion_sort(It first, It last) {
    if (first == last) return;
    for (It a = std::next(first); a != last; ++a)
        for (It c = a; c != first && *c < *std::prev(c); --c) std::iter_swap(c, std::prev(c));
}

} // namespace pbdsplat::core
