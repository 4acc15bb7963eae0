#include "splat/sort.h"

#include <algorithm>

#include "core/assert.h"

namespace pbdsplat::splat {

void sort_far_to_near(std::vector<GaussianRecord>& records, const Mat4f& view, SortScratch& s) {
    const Vec4f row = view.row(2);  // view-space z = row . (x, y, z, 1); farther is more negative
    s.keys.resize(records.size());
    for (uint32_t i = 0; i < records.size(); ++i) {
        const GaussianRecord& r = records[i];
        s.keys[i] = {row.x() * r.position[0] + row.y() * r.position[1] + row.z() * r.position[2] + row.w(), i};
    }
    std::stable_sort(s.keys.begin(), s.keys.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    s.copy = records;
    for (size_t k = 0; k < records.size(); ++k) records[k] = s.copy[s.keys[k].second];
}

void sort_far_to_near(std::vector<GaussianRecord>& records, std::vector<GaussianShape>& shapes, const Mat4f& view,
                      SortScratch& s) {
    sort_far_to_near(records, view, s);
    if (shapes.empty()) return;
    PBDSPLAT_ASSERT(shapes.size() == records.size(), "sort_far_to_near: one shape per record, or none");
    s.shape_copy = shapes;
    for (size_t k = 0; k < shapes.size(); ++k) shapes[k] = s.shape_copy[s.keys[k].second];
}

} // namespace pbdsplat::splat
