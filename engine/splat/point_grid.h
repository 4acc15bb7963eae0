#pragma once
// Points hashed into cubic cells, for neighbour queries over splat centres (strays, normals).
// Cells are sorted runs of point indices, not a map of vectors: a trained file holds millions.
#include <cstdint>
#include <span>
#include <vector>

#include "core/math.h"

namespace pbdsplat::splat {

class PointGrid {
public:
    PointGrid(std::span<const Vec3f> points, float cell);

    // The nearest other point within the 27 cells around point i (infinity when none).
    float nearest(uint32_t i) const;
    // Up to k nearest other points, nearest first, searched ring by ring out to `max_rings`
    // cells: a point further than that is not a neighbour for any purpose here.
    void k_nearest(uint32_t i, uint32_t k, int max_rings, std::vector<uint32_t>& out) const;

private:
    Eigen::Vector3i cell_of(const Vec3f& x) const;
    static uint64_t key(const Eigen::Vector3i& c);
    std::span<const uint32_t> cell(const Eigen::Vector3i& c) const;

    std::span<const Vec3f> p_;
    float size_;
    float inv_;
    std::vector<uint64_t> keys_;    // sorted, one per non-empty cell
    std::vector<uint32_t> starts_;  // keys_.size() + 1 offsets into order_
    std::vector<uint32_t> order_;   // point indices grouped by cell
};

} // namespace pbdsplat::splat
