#include "splat/strays.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "splat/point_grid.h"

namespace pbdsplat::splat {

StrayReport count_strays(std::span<const Vec3f> centres, float hint) {
    StrayReport out;
    if (centres.size() < 2 || !(hint > 0.0f)) return out;
    // First pass: nearest-neighbour spacing, for the median.
    const PointGrid fine(centres, hint);
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
    const PointGrid coarse(centres, reach);
    for (uint32_t i = 0; i < centres.size(); ++i) {
        if (nn[i] <= reach) continue;
        if (coarse.nearest(i) > reach) ++out.strays;
    }
    return out;
}

} // namespace pbdsplat::splat
