#pragma once
// One short list per key (a vertex's triangles, its ring, its constraints) in one pool, each with
// a little spare room: a topology edit rewrites the lists of the vertices it touched in place,
// or moves a grown list to the pool's end, instead of rebuilding every list of the body. The
// pool is compacted (key order, fresh slack) once half of it is abandoned space.
#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "core/assert.h"

namespace pbdsplat::sim {

template <class T>
class SlackLists {
public:
    static constexpr uint32_t k_slack = 2;

    size_t keys() const { return first_.size(); }
    std::span<const T> of(uint32_t key) const { return {pool_.data() + first_[key], size_[key]}; }
    size_t pool_size() const { return pool_.size(); }
    // For walks that know which lists they read next (a flood over a large body waits on a
    // cache miss for each list's place, then for its items): the place a few steps ahead, the
    // items a few steps later, once the place is in cache.
    void prefetch_place(uint32_t key) const {
        __builtin_prefetch(first_.data() + key);
        __builtin_prefetch(size_.data() + key);
    }
    void prefetch_items(uint32_t key) const { __builtin_prefetch(pool_.data() + first_[key]); }
    size_t abandoned() const { return abandoned_; }

    // All lists at once, from counts per key and the items in key order (CSR-like).
    void build(std::span<const uint32_t> start, std::span<const T> items) {
        const size_t n = start.empty() ? 0 : start.size() - 1;
        first_.resize(n);
        size_.resize(n);
        capacity_.resize(n);
        pool_.clear();
        pool_.reserve(items.size() + k_slack * n);
        for (size_t k = 0; k < n; ++k) {
            first_[k] = uint32_t(pool_.size());
            size_[k] = start[k + 1] - start[k];
            capacity_[k] = size_[k] + k_slack;
            pool_.insert(pool_.end(), items.begin() + start[k], items.begin() + start[k + 1]);
            pool_.resize(pool_.size() + k_slack);
        }
        abandoned_ = 0;
    }

    // Room for this many keys and pool items without moving (copies do not keep it).
    void reserve(size_t keys, size_t items) {
        first_.reserve(keys), size_.reserve(keys), capacity_.reserve(keys);
        pool_.reserve(items);
    }
    size_t key_capacity() const { return first_.capacity(); }
    size_t pool_capacity() const { return pool_.capacity(); }

    // Keys [keys(), n) appear with empty lists.
    void grow(size_t n) {
        while (first_.size() < n) {
            first_.push_back(uint32_t(pool_.size()));
            size_.push_back(0);
            capacity_.push_back(0);
        }
    }

    void assign(uint32_t key, std::span<const T> items) {
        PBDSPLAT_ASSERT(key < keys(), "SlackLists::assign: grow() the key range first");
        if (items.size() > capacity_[key]) {
            abandoned_ += capacity_[key];
            first_[key] = uint32_t(pool_.size());
            capacity_[key] = uint32_t(items.size()) + k_slack;
            pool_.resize(pool_.size() + capacity_[key]);
        }
        std::copy(items.begin(), items.end(), pool_.begin() + first_[key]);
        size_[key] = uint32_t(items.size());
        if (abandoned_ > pool_.size() / 2) compact();
    }

    // One item at the end of key's list: in place while its room lasts (most edits), else as
    // assign() does.
    void push(uint32_t key, const T& item) {
        PBDSPLAT_ASSERT(key < keys(), "SlackLists::push: grow() the key range first");
        if (size_[key] < capacity_[key]) {
            pool_[first_[key] + size_[key]++] = item;
            return;
        }
        // Moved to the pool's end with fresh slack, as assign() would place it, copied there
        // without a list on the heap between (a new particle's lists start empty and grow by
        // push: two moves each, most of an edit's allocations once).
        const uint32_t n = size_[key], at = uint32_t(pool_.size());
        abandoned_ += capacity_[key];
        capacity_[key] = n + 1 + k_slack;
        pool_.resize(size_t(at) + capacity_[key]);
        std::copy_n(pool_.begin() + first_[key], n, pool_.begin() + at);
        pool_[size_t(at) + n] = item;
        first_[key] = at;
        size_[key] = n + 1;
        if (abandoned_ > pool_.size() / 2) compact();
    }
    // The first `item` in key's list taken out, the items after it moved up (the order kept).
    void erase(uint32_t key, const T& item) {
        const auto first = pool_.begin() + first_[key], last = first + size_[key];
        const auto it = std::find(first, last, item);
        PBDSPLAT_ASSERT(it != last, "SlackLists::erase: the item is not in that key's list");
        std::copy(it + 1, last, it);
        --size_[key];
    }

    // Replaces `from` by `to` in key's list, in place (the item moved elsewhere).
    void replace(uint32_t key, const T& from, const T& to) {
        const auto first = pool_.begin() + first_[key], last = first + size_[key];
        const auto it = std::find(first, last, from);
        PBDSPLAT_ASSERT(it != last, "SlackLists::replace: the item is not in that key's list");
        *it = to;
    }

    // Lays the lists out again in key order with fresh slack (what build() gives).
    void compact() {
        std::vector<uint32_t> start(keys() + 1, 0);
        for (size_t k = 0; k < keys(); ++k) start[k + 1] = start[k] + size_[k];
        std::vector<T> items(start.back());
        for (size_t k = 0; k < keys(); ++k)
            std::copy_n(pool_.begin() + first_[k], size_[k], items.begin() + start[k]);
        build(start, items);
        ++compactions_;
    }
    size_t compactions() const { return compactions_; }

    bool operator==(const SlackLists& o) const {
        if (keys() != o.keys()) return false;
        for (uint32_t k = 0; k < keys(); ++k)
            if (!std::ranges::equal(of(k), o.of(k))) return false;
        return true;
    }

private:
    std::vector<uint32_t> first_, size_, capacity_;
    std::vector<T> pool_;
    size_t abandoned_ = 0, compactions_ = 0;
};

} // namespace pbdsplat::sim
