#pragma once
// A set of 64-bit keys, and a map from them to a small value, for the few thousand keys one
// topology edit looks at (edge keys, constraint slots). Open addressing in a power-of-two table
// sized up front: no allocation per entry (a hash map's nodes), no sort and bisection (a sorted
// vector's), so the lookups of an edit cost what it touches. Any key but 2^64 - 1.
#include <cstdint>
#include <utility>
#include <vector>

namespace pbdsplat::core {

class KeySet {
public:
    // Room for `expected` keys at half load or less.
    explicit KeySet(size_t expected) {
        size_t capacity = 16;
        shift_ = 60;
        while (capacity < 2 * expected) capacity *= 2, --shift_;
        slots_.assign(capacity, k_empty);
        mask_ = capacity - 1;
    }
    // Inserting more keys than `expected` is a bug in the caller (the set does not grow; a
    // KeyMap does). Returns the key's place in the table.
    size_t insert(uint64_t key) {
        size_t at = home(key);
        while (slots_[at] != k_empty && slots_[at] != key) at = (at + 1) & mask_;
        count_ += slots_[at] == k_empty;
        slots_[at] = key;
        return at;
    }
    bool contains(uint64_t key) const { return find(key) != k_absent; }
    // The key's place in the table, or k_absent.
    size_t find(uint64_t key) const {
        for (size_t at = home(key);; at = (at + 1) & mask_) {
            if (slots_[at] == key) return at;
            if (slots_[at] == k_empty) return k_absent;
        }
    }
    size_t capacity() const { return slots_.size(); }
    size_t size() const { return count_; }
    // The key at a place in the table, or k_empty.
    uint64_t key_at(size_t at) const { return slots_[at]; }
    static constexpr size_t k_absent = SIZE_MAX;

    // No edge key (both ends at most 2^32 - 2) and no slot.
    static constexpr uint64_t k_empty = ~uint64_t(0);

private:
    // Fibonacci hashing: the product's high bits mix all of the key (both ends of an edge).
    size_t home(uint64_t key) const { return size_t((key * 0x9E3779B97F4A7C15ull) >> shift_); }
    std::vector<uint64_t> slots_;
    size_t mask_ = 0;
    size_t count_ = 0;
    int shift_ = 60;
};

// The same table with a value per key; it doubles when half full.
template <class Value>
class KeyMap {
public:
    explicit KeyMap(size_t expected) : keys_(expected), values_(keys_.capacity()) {}
    // The value of `key`, default-constructed when the key is new.
    Value& operator[](uint64_t key) {
        if (2 * (keys_.size() + 1) > keys_.capacity()) grow();
        return values_[keys_.insert(key)];
    }
    // Null when the key is absent.
    const Value* find(uint64_t key) const {
        const size_t at = keys_.find(key);
        return at == KeySet::k_absent ? nullptr : &values_[at];
    }
    Value* find(uint64_t key) {
        const size_t at = keys_.find(key);
        return at == KeySet::k_absent ? nullptr : &values_[at];
    }

private:
    void grow() {
        KeyMap bigger(keys_.capacity());
        for (size_t at = 0; at < keys_.capacity(); ++at)
            if (keys_.key_at(at) != KeySet::k_empty) bigger.values_[bigger.keys_.insert(keys_.key_at(at))] = std::move(values_[at]);
        *this = std::move(bigger);
    }
    KeySet keys_;
    std::vector<Value> values_;
};

} // namespace pbdsplat::core
