#pragma once
// Far-to-near order for "over" blending (paper section 5.4), on the CPU: records sorted by the
// view-space depth of their centres, ties kept in their original order.
#include <span>
#include <vector>

#include "splat/gaussian_record.h"

namespace pbdsplat::splat {

// Reorders `records` in place, farthest first, for the camera `view` (world to view, looking
// down -z). `scratch` keeps its allocations between frames.
struct SortScratch {
    // Per record, its depth made an ordered unsigned integer (high half) and its index (low
    // half): sorted by a radix sort, which on a million captured Gaussians takes a fraction of a
    // comparison sort's time; the index breaks ties in the original order.
    std::vector<uint64_t> keys;
    std::vector<GaussianRecord> copy;
    std::vector<GaussianShape> shape_copy;
};
void sort_far_to_near(std::vector<GaussianRecord>& records, const Mat4f& view, SortScratch& scratch);
// The same, carrying each record's shape along (`shapes` parallel to `records`, or empty).
void sort_far_to_near(std::vector<GaussianRecord>& records, std::vector<GaussianShape>& shapes, const Mat4f& view,
                      SortScratch& scratch);

// Puts a stream parallel to the records in the order the last sort with `scratch` gave them.
template <class T>
void reorder_like_last_sort(const SortScratch& scratch, std::vector<T>& stream) {
    if (stream.empty()) return;
    const std::vector<T> copy = stream;
    for (size_t k = 0; k < stream.size(); ++k) stream[k] = copy[uint32_t(scratch.keys[k])];
}

} // namespace pbdsplat::splat
