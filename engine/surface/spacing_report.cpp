#include "surface/spacing_report.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/assert.h"
#include "surface/point_grid.h"

namespace pbdsplat::surface {

SpacingReport spacing_report(std::span<const Vec3f> points, float h, const SpacingQuery& query) {
    PBDSPLAT_ASSERT(query.normals.empty() || query.normals.size() == points.size(),
                    "spacing_report: give one normal per point, or none");
    SpacingReport r;
    r.points = std::min(query.measured, points.size());
    if (points.size() < 2 || r.points == 0) return r;
    // Cells of 2h: a nearest neighbour farther than that counts as "too far" anyway.
    PointGrid grid(2.0f * h, points.size());
    for (const Vec3f& p : points) grid.add(p);
    constexpr float same_side = 0.5f;  // cos 60 degrees
    std::vector<float> d(r.points);
    size_t in = 0;
    for (size_t i = 0; i < r.points; ++i) {
        const float d2 = query.normals.empty()
                             ? grid.nearest_squared(points[i], uint32_t(i))
                             : grid.nearest_squared_if(points[i], [&](uint32_t j) {
                                   return j != i && query.normals[j].dot(query.normals[i]) >= same_side;
                               });
        d[i] = std::isfinite(d2) ? std::sqrt(d2) / h : 2.0f;
        in += d[i] >= query.low && d[i] <= query.high;
    }
    r.within = float(in) / float(r.points);
    auto q = [&](float f) {
        const size_t k = std::min(d.size() - 1, size_t(f * float(d.size())));
        std::nth_element(d.begin(), d.begin() + k, d.end());
        return d[k];
    };
    r.p05 = q(0.05f);
    r.median = q(0.5f);
    r.p95 = q(0.95f);
    return r;
}

} // namespace pbdsplat::surface
