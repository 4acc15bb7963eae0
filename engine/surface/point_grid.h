#pragma once
// The spatial hash the samplers block candidates with, and that splat-side neighbour queries
// (strays, normals of a trained file) use over a fixed point set.
#include <algorithm>
#include <bit>
#include <cstdlib>
#include <utility>
#include <limits>
#include <cstdint>
#include <vector>

#include "core/math.h"

namespace pbdsplat::surface {

// A hash grid of accepted points with cell size h: any point within h lies in the 27 cells
// around a query. Open addressing over cell keys, with the points of a cell chained through
// an index array: sampling asks it millions of times, so no node allocation and no rehash of
// vectors.
class PointGrid {
public:
    PointGrid(float h, size_t expected_points) : inv_h_(1.0f / h), h2_(h * h) {
        size_t cap = 1024;
        while (cap < expected_points * 2) cap <<= 1;
        keys_.assign(cap, k_empty);
        heads_.assign(cap, k_end);
        mask_ = cap - 1;
        shift_ = 64 - std::countr_zero(cap);
        points_.reserve(expected_points);
        next_.reserve(expected_points);
        tags_.reserve(expected_points);
    }
    // Empties the grid for reuse with a new radius h, keeping its memory.
    void reset(float h) {
        inv_h_ = 1.0f / h;
        h2_ = h * h;
        std::fill(keys_.begin(), keys_.end(), k_empty);
        std::fill(heads_.begin(), heads_.end(), k_end);
        points_.clear();
        next_.clear();
        tags_.clear();
    }
    // Any point within h of p carrying the same tag (k_any matches every tag).
    bool near(const Vec3f& p, uint32_t tag = k_any) const { return blocker(p, tag) != k_none; }
    static constexpr uint32_t k_none = ~0u;
    // A point within h of p carrying the same tag (as near()), or k_none.
    uint32_t blocker(const Vec3f& p, uint32_t tag = k_any) const {
        uint32_t found = k_none;
        each_around(p, [&](uint32_t i) {
            if (blocks(i, p, tag)) found = i;
            return found == k_none;
        });
        return found;
    }
    // Whether point i lies within h of p with a tag matching `tag`.
    bool blocks(uint32_t i, const Vec3f& p, uint32_t tag = k_any) const {
        return (tag == k_any || tags_[i] == k_any || tags_[i] == tag) && (points_[i] - p).squaredNorm() < h2_;
    }
    // Any point within r of p for which accept(i) holds, with cells at least 2r wide: such a
    // point lies in the 2x2x2 block of cells nearest p (on each axis, p's own cell and the one
    // on the side of p's nearer face), so 8 lookups instead of 27 for a test that mostly finds
    // nothing (the density control's crowd test).
    template <class Accept>
    bool near_within_if(const Vec3f& p, float r, const Accept& accept) const {
        return !each_within(p, r, [&](uint32_t i) { return !accept(i); });
    }
    // Visits every point within r of p (cells at least 2r wide) while visit(i) returns true.
    template <class Visit>
    bool each_within(const Vec3f& p, float r, const Visit& visit) const {
        const Vec3f scaled = p * inv_h_;
        const Eigen::Vector3i c = math::floor_to_int(scaled);
        Eigen::Vector3i side;
        for (int k = 0; k < 3; ++k) side[k] = scaled[k] - float(c[k]) < 0.5f ? -1 : 1;
        const float r2 = r * r;
        for (int m = 0; m < 8; ++m) {
            const Eigen::Vector3i cc = c + Eigen::Vector3i(m & 1 ? side.x() : 0, m & 2 ? side.y() : 0, m & 4 ? side.z() : 0);
            const size_t slot = find(key(cc));
            if (slot == k_end) continue;
            for (uint32_t i = heads_[slot]; i != k_end; i = next_[i])
                if ((points_[i] - p).squaredNorm() < r2 && !visit(i)) return false;
        }
        return true;
    }
    // The squared distance from p to the nearest point other than `self` (an index in insertion
    // order) within one cell size; infinity when there is none.
    float nearest_squared(const Vec3f& p, uint32_t self = k_end) const {
        return nearest_squared_if(p, [self](uint32_t i) { return i != self; });
    }
    // The same among the points for which accept(i) holds.
    template <class Accept>
    float nearest_squared_if(const Vec3f& p, const Accept& accept) const {
        float best = std::numeric_limits<float>::infinity();
        each_around(p, [&](uint32_t i) {
            if (accept(i)) best = std::min(best, (points_[i] - p).squaredNorm());
            return true;
        });
        return best;
    }
    // Up to k nearest points other than `self`, nearest first, searched shell of cells by shell
    // out to `max_rings` cells: a point further than that is no neighbour for any purpose here.
    void k_nearest(const Vec3f& p, uint32_t self, uint32_t k, int max_rings, std::vector<uint32_t>& out) const {
        out.clear();
        if (k == 0) return;
        const Eigen::Vector3i c = cell(p);
        std::vector<std::pair<float, uint32_t>> best;  // a max-heap of the k best so far
        best.reserve(k + 1);
        for (int r = 0; r <= max_rings; ++r) {
            for (int dz = -r; dz <= r; ++dz)
                for (int dy = -r; dy <= r; ++dy)
                    for (int dx = -r; dx <= r; ++dx) {
                        if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) != r) continue;  // the shell only
                        const size_t slot = find(key(c + Eigen::Vector3i(dx, dy, dz)));
                        if (slot == k_end) continue;
                        for (uint32_t i = heads_[slot]; i != k_end; i = next_[i]) {
                            if (i == self) continue;
                            const float d2 = (points_[i] - p).squaredNorm();
                            if (best.size() == k && d2 >= best.front().first) continue;
                            best.emplace_back(d2, i);
                            std::push_heap(best.begin(), best.end());
                            if (best.size() > k) std::pop_heap(best.begin(), best.end()), best.pop_back();
                        }
                    }
            // Anything in a further shell is at least r cells away.
            const float reach = float(r) / inv_h_;
            if (best.size() == k && best.front().first <= reach * reach) break;
        }
        std::sort_heap(best.begin(), best.end());
        for (const auto& b : best) out.push_back(b.second);
    }
    static constexpr uint32_t k_any = ~0u;
    void add(const Vec3f& p, uint32_t tag = k_any) {
        if ((points_.size() + 1) * 2 > keys_.size()) grow();
        const uint64_t k = key(cell(p));
        size_t slot = slot_of(k);
        while (keys_[slot] != k_empty && keys_[slot] != k) slot = (slot + 1) & mask_;
        keys_[slot] = k;
        next_.push_back(heads_[slot]);
        heads_[slot] = uint32_t(points_.size());
        points_.push_back(p);
        tags_.push_back(tag);
    }

private:
    // Visits the points in the 27 cells around p while visit(i) returns true; false when a
    // visit stopped it. The point's own cell first, then those sharing a face with it, then the
    // rest: a query that stops at the first point near enough (a rejected candidate) usually
    // stops in the first.
    template <class Visit>
    bool each_around(const Vec3f& p, const Visit& visit) const {
        static constexpr int8_t k_order[27][3] = {
            {0, 0, 0},    {-1, 0, 0},  {1, 0, 0},   {0, -1, 0},  {0, 1, 0},   {0, 0, -1},  {0, 0, 1},
            {-1, -1, 0},  {1, -1, 0},  {-1, 1, 0},  {1, 1, 0},   {-1, 0, -1}, {1, 0, -1},  {-1, 0, 1},
            {1, 0, 1},    {0, -1, -1}, {0, 1, -1},  {0, -1, 1},  {0, 1, 1},   {-1, -1, -1}, {1, -1, -1},
            {-1, 1, -1},  {1, 1, -1},  {-1, -1, 1}, {1, -1, 1},  {-1, 1, 1},  {1, 1, 1}};
        const Eigen::Vector3i c = cell(p);
        for (const auto& d : k_order) {
            const size_t slot = find(key(c + Eigen::Vector3i(d[0], d[1], d[2])));
            if (slot == k_end) continue;
            for (uint32_t i = heads_[slot]; i != k_end; i = next_[i])
                if (!visit(i)) return false;
        }
        return true;
    }
    static constexpr uint64_t k_empty = ~0ull;
    static constexpr uint32_t k_end = ~0u;
    // Fibonacci hashing: the high bits of the product mix all of x, y and z.
    size_t slot_of(uint64_t k) const { return size_t((k * 0x9E3779B97F4A7C15ull) >> shift_); }
    size_t find(uint64_t k) const {
        size_t slot = slot_of(k);
        while (true) {
            if (keys_[slot] == k) return slot;
            if (keys_[slot] == k_empty) return k_end;
            slot = (slot + 1) & mask_;
        }
    }
    void grow() {
        std::vector<Vec3f> old = std::move(points_);
        std::vector<uint32_t> old_tags = std::move(tags_);
        const size_t cap = keys_.size() * 2;
        keys_.assign(cap, k_empty);
        heads_.assign(cap, k_end);
        mask_ = cap - 1;
        shift_ = 64 - std::countr_zero(cap);
        points_.clear();
        next_.clear();
        tags_.clear();
        for (size_t i = 0; i < old.size(); ++i) add(old[i], old_tags[i]);
    }
    Eigen::Vector3i cell(const Vec3f& p) const { return math::floor_to_int(Vec3f(p * inv_h_)); }
    static uint64_t key(const Eigen::Vector3i& c) {
        return (uint64_t(uint32_t(c.x()) & 0x1fffff) << 42) | (uint64_t(uint32_t(c.y()) & 0x1fffff) << 21) |
               uint64_t(uint32_t(c.z()) & 0x1fffff);
    }
    float inv_h_, h2_;
    size_t mask_ = 0;
    int shift_ = 54;
    std::vector<uint64_t> keys_;
    std::vector<uint32_t> heads_;  // per slot: the newest point in that cell
    std::vector<uint32_t> next_;   // per point: the next point in its cell
    std::vector<Vec3f> points_;
    std::vector<uint32_t> tags_;  // per point: the piece it belongs to, or k_any
};

} // namespace pbdsplat::surface
