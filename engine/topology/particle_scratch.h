#pragma once
// Internal to the topology room: per-particle arrays that live from one edit to the next, one
// per thread. An edit takes an array at least the body's size with every entry at its default,
// writes the entries of the particles it looks at, and gives those back at their default: a
// local cut costs what it touches, not a fill (and, past the allocator's threshold, fresh
// zeroed pages) the size of the body.
#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

namespace pbdsplat::topology {

template <class T>
class ParticleScratch {
public:
    explicit ParticleScratch(T fallback) : fallback_(fallback) {}

    // Every entry below n (and past it) at the default.
    std::vector<T>& take(size_t n) {
        if (values_.size() < n) values_.resize(n, fallback_);
        return values_;
    }
    // The entries written since take() back to the default.
    void give_back(std::span<const uint32_t> written) {
        for (uint32_t v : written) values_[v] = fallback_;
    }
    void give_back_all() { std::fill(values_.begin(), values_.end(), fallback_); }

private:
    std::vector<T> values_;
    T fallback_;
};

} // namespace pbdsplat::topology
