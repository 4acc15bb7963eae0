#include "splat/sort.h"

#include <cstdint>
#include <cstring>

#include "core/assert.h"
#include "core/radix_sort.h"

namespace pbdsplat::splat {

namespace {
// A float's bits turned so that unsigned order is numeric order (negatives reversed below the
// positives).
uint32_t depth_order_bits(float v) {
    uint32_t b;
    std::memcpy(&b, &v, sizeof b);
    return (b & 0x80000000u) ? ~b : (b | 0x80000000u);
}
} // namespace

void sort_far_to_near(std::vector<GaussianRecord>& records, const Mat4f& view, SortScratch& s) {
    PBDSPLAT_ASSERT(records.size() <= UINT32_MAX, "sort_far_to_near: at most 2^32 records");
    const Vec4f row = view.row(2);  // view-space z = row . (x, y, z, 1); farther is more negative
    s.keys.resize(records.size());
    for (uint32_t i = 0; i < records.size(); ++i) {
        const GaussianRecord& r = records[i];
        const float z = row.x() * r.position[0] + row.y() * r.position[1] + row.z() * r.position[2] + row.w();
        s.keys[i] = uint64_t(depth_order_bits(z)) << 32 | i;
    }
    core::radix_sort(std::span<uint64_t>(s.keys));
    s.copy = records;
    for (size_t k = 0; k < records.size(); ++k) records[k] = s.copy[uint32_t(s.keys[k])];
}

void sort_far_to_near(std::vector<GaussianRecord>& records, std::vector<GaussianShape>& shapes, const Mat4f& view,
                      SortScratch& s) {
    sort_far_to_near(records, view, s);
    if (shapes.empty()) return;
    PBDSPLAT_ASSERT(shapes.size() == records.size(), "sort_far_to_near: one shape per record, or none");
    s.shape_copy = shapes;
    for (size_t k = 0; k < shapes.size(); ++k) shapes[k] = s.shape_copy[uint32_t(s.keys[k])];
}

} // namespace pbdsplat::splat
