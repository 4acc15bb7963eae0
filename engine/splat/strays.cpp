#include "splat/strays.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <vector>

namespace pbdsplat::splat {
namespace {

// Points hashed into cubic cells; nearest neighbour within the 27 cells around a point.
class CellHash {
public:
    CellHash(std::span<const Vec3f> p, float cell) : p_(p), inv_(1.0f / cell) {
        cells_.reserve(p.size());
        for (uint32_t i = 0; i < p.size(); ++i) cells_[key(cell_of(p[i]))].push_back(i);
    }
    // Nearest other point within the 27 cells (infinity when none).
    float nearest(uint32_t i) const {
        const Eigen::Vector3i c = cell_of(p_[i]);
        float best = std::numeric_limits<float>::infinity();
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const auto it = cells_.find(key(c + Eigen::Vector3i(dx, dy, dz)));
                    if (it == cells_.end()) continue;
                    for (uint32_t j : it->second)
                        if (j != i) best = std::min(best, (p_[j] - p_[i]).squaredNorm());
                }
        return std::sqrt(best);
    }

private:
    Eigen::Vector3i cell_of(const Vec3f& x) const { return (x * inv_).array().floor().cast<int>(); }
    static uint64_t key(const Eigen::Vector3i& c) {
        return (uint64_t(uint32_t(c.x()) & 0x1fffff) << 42) | (uint64_t(uint32_t(c.y()) & 0x1fffff) << 21) | uint64_t(uint32_t(c.z()) & 0x1fffff);
    }
    std::span<const Vec3f> p_;
    float inv_;
    std::unordered_map<uint64_t, std::vector<uint32_t>> cells_;
};

} // namespace

StrayReport count_strays(std::span<const Vec3f> centres, float hint) {
    StrayReport out;
    if (centres.size() < 2 || !(hint > 0.0f)) return out;
    // First pass: nearest-neighbour spacing, for the median.
    const CellHash fine(centres, hint);
    std::vector<float> nn(centres.size());
    for (uint32_t i = 0; i < centres.size(); ++i) nn[i] = fine.nearest(i);
    std::vector<float> finite;
    for (float d : nn)
        if (std::isfinite(d)) finite.push_back(d);
    if (finite.empty()) return out;
    std::nth_element(finite.begin(), finite.begin() + finite.size() / 2, finite.end());
    out.median_spacing = finite[finite.size() / 2];
    // Second pass: anyone within 3x the median? Cells that large see that far.
    const float reach = 3.0f * out.median_spacing;
    const CellHash coarse(centres, reach);
    for (uint32_t i = 0; i < centres.size(); ++i) {
        if (nn[i] <= reach) continue;
        if (coarse.nearest(i) > reach) ++out.strays;
    }
    return out;
}

} // namespace pbdsplat::splat
