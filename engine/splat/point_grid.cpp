#include "splat/point_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <utility>

namespace pbdsplat::splat {

PointGrid::PointGrid(std::span<const Vec3f> points, float cell) : p_(points), size_(cell), inv_(1.0f / cell) {
    std::vector<std::pair<uint64_t, uint32_t>> keyed(points.size());
    for (uint32_t i = 0; i < points.size(); ++i) keyed[i] = {key(cell_of(points[i])), i};
    std::sort(keyed.begin(), keyed.end());
    order_.resize(points.size());
    for (uint32_t i = 0; i < keyed.size(); ++i) {
        order_[i] = keyed[i].second;
        if (i == 0 || keyed[i].first != keyed[i - 1].first) keys_.push_back(keyed[i].first), starts_.push_back(i);
    }
    starts_.push_back(uint32_t(keyed.size()));
}

Eigen::Vector3i PointGrid::cell_of(const Vec3f& x) const { return (x * inv_).array().floor().cast<int>(); }

uint64_t PointGrid::key(const Eigen::Vector3i& c) {
    return (uint64_t(uint32_t(c.x()) & 0x1fffff) << 42) | (uint64_t(uint32_t(c.y()) & 0x1fffff) << 21) | uint64_t(uint32_t(c.z()) & 0x1fffff);
}

std::span<const uint32_t> PointGrid::cell(const Eigen::Vector3i& c) const {
    const auto it = std::lower_bound(keys_.begin(), keys_.end(), key(c));
    if (it == keys_.end() || *it != key(c)) return {};
    const size_t k = size_t(it - keys_.begin());
    return std::span<const uint32_t>(order_).subspan(starts_[k], starts_[k + 1] - starts_[k]);
}

float PointGrid::nearest(uint32_t i) const {
    const Eigen::Vector3i c = cell_of(p_[i]);
    float best = std::numeric_limits<float>::infinity();
    for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx)
                for (uint32_t j : cell(c + Eigen::Vector3i(dx, dy, dz)))
                    if (j != i) best = std::min(best, (p_[j] - p_[i]).squaredNorm());
    return std::sqrt(best);
}

void PointGrid::k_nearest(uint32_t i, uint32_t k, int max_rings, std::vector<uint32_t>& out) const {
    out.clear();
    if (k == 0) return;
    const Eigen::Vector3i c = cell_of(p_[i]);
    // (squared distance, index), a max-heap of the k best so far.
    std::vector<std::pair<float, uint32_t>> best;
    best.reserve(k + 1);
    for (int r = 0; r <= max_rings; ++r) {
        // The shell of cells at Chebyshev distance r.
        for (int dz = -r; dz <= r; ++dz)
            for (int dy = -r; dy <= r; ++dy)
                for (int dx = -r; dx <= r; ++dx) {
                    if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) != r) continue;
                    for (uint32_t j : cell(c + Eigen::Vector3i(dx, dy, dz))) {
                        if (j == i) continue;
                        const float d2 = (p_[j] - p_[i]).squaredNorm();
                        if (best.size() == k && d2 >= best.front().first) continue;
                        best.emplace_back(d2, j);
                        std::push_heap(best.begin(), best.end());
                        if (best.size() > k) std::pop_heap(best.begin(), best.end()), best.pop_back();
                    }
                }
        // Anything in a further shell is at least r cells away.
        const float reach = float(r) * size_;
        if (best.size() == k && best.front().first <= reach * reach) break;
    }
    std::sort_heap(best.begin(), best.end());
    for (const auto& b : best) out.push_back(b.second);
}

} // namespace pbdsplat::splat
