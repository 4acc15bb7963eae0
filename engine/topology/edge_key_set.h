#pragma once
// Internal to the topology room: a set of edge keys (edge_key in edit.h) for the few thousand
// edges one edit looks at. Open addressing in a power-of-two table sized up front: no
// allocation per entry (a hash set's nodes), no sort and bisection (a sorted vector's), so
// the lookups of an edit cost what it touches.
#include <cstdint>
#include <vector>

namespace pbdsplat::topology {

class EdgeKeySet {
public:
    // Room for `expected` keys at half load or less.
    explicit EdgeKeySet(size_t expected) {
        size_t capacity = 16;
        shift_ = 60;
        while (capacity < 2 * expected) capacity *= 2, --shift_;
        slots_.assign(capacity, k_empty);
        mask_ = capacity - 1;
    }
    // Inserting more keys than `expected` is a bug in the caller (the table does not grow).
    void insert(uint64_t key) {
        size_t at = home(key);
        while (slots_[at] != k_empty && slots_[at] != key) at = (at + 1) & mask_;
        slots_[at] = key;
    }
    bool contains(uint64_t key) const {
        for (size_t at = home(key);; at = (at + 1) & mask_) {
            if (slots_[at] == key) return true;
            if (slots_[at] == k_empty) return false;
        }
    }

private:
    // Both ends of an edge are no larger than 2^32 - 2, so this key is no edge's.
    static constexpr uint64_t k_empty = ~uint64_t(0);
    // Fibonacci hashing: the product's high bits mix both ends of the edge.
    size_t home(uint64_t key) const { return size_t((key * 0x9E3779B97F4A7C15ull) >> shift_); }
    std::vector<uint64_t> slots_;
    size_t mask_ = 0;
    int shift_ = 60;
};

} // namespace pbdsplat::topology
