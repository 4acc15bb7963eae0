#include "sim/constraint_order.h"

#include <algorithm>
#include <vector>

namespace pbdsplat::sim {

uint32_t interleave_independent(std::span<DistanceConstraint> constraints, size_t block) {
    uint32_t most = 0;
    std::vector<std::pair<uint32_t, uint32_t>> colour_mask;  // particle -> bitmask of colours used
    std::vector<uint32_t> colour(block);
    std::vector<DistanceConstraint> sorted(block);
    for (size_t start = 0; start < constraints.size(); start += block) {
        const size_t n = std::min(block, constraints.size() - start);
        colour_mask.clear();
        colour_mask.reserve(2 * block);  // never reallocates below: references stay valid
        auto mask_of = [&](uint32_t particle) -> uint32_t& {
            for (auto& [p, m] : colour_mask)
                if (p == particle) return m;
            colour_mask.push_back({particle, 0u});
            return colour_mask.back().second;
        };
        uint32_t colours = 0;
        for (size_t k = 0; k < n; ++k) {
            const DistanceConstraint& c = constraints[start + k];
            uint32_t& mi = mask_of(c.i);
            uint32_t& mj = mask_of(c.j);
            const uint32_t used = mi | mj;
            uint32_t col = 0;
            while (col < 31 && (used >> col) & 1u) ++col;
            mi |= 1u << col;
            mj |= 1u << col;
            colour[k] = col;
            colours = std::max(colours, col + 1);
        }
        // Counting sort by colour, stable.
        std::vector<uint32_t> offset(colours + 1, 0);
        for (size_t k = 0; k < n; ++k) ++offset[colour[k] + 1];
        for (uint32_t c = 0; c < colours; ++c) offset[c + 1] += offset[c];
        for (size_t k = 0; k < n; ++k) sorted[offset[colour[k]]++] = constraints[start + k];
        std::copy(sorted.begin(), sorted.begin() + long(n), constraints.begin() + long(start));
        most = std::max(most, colours);
    }
    return most;
}

} // namespace pbdsplat::sim
