#pragma once
// Normals for Gaussians that came without one (trained files rarely carry them): the paper's
// shading needs a normal per splat. A flat Gaussian is its own answer, its shortest axis; a
// round one takes the plane through its nearest neighbours (the smallest principal axis of
// their scatter). Signs travel along the neighbour graph from the file's own normals, or from
// each piece's outermost point (Hoppe et al.'s spanning-tree orientation), so surfaces that
// fold back (ears, feet, the inside of a handle) keep one side out.
#include <cstddef>
#include <cstdint>
#include <span>

#include "splat/gaussian_record.h"

namespace pbdsplat::splat {

struct NormalEstimate {
    size_t from_shape = 0;       // flat Gaussians: the shortest axis
    size_t from_neighbours = 0;  // round ones: the plane of their neighbours
    size_t unresolved = 0;       // too few neighbours, or no plane among them: left as they were
};

// Sets the normal of every record whose `missing[i]` is not zero. `shapes` is one per record or empty.
NormalEstimate estimate_normals(std::span<GaussianRecord> records, std::span<const GaussianShape> shapes,
                                std::span<const uint8_t> missing);

} // namespace pbdsplat::splat
