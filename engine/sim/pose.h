#pragma once
// How a body stands, as a user sees it: per model (a scene's [model] and each [[bodies]] entry),
// how far its best-fit rotation from the rest pose tips the vertical, and how tall it is against
// its rest height. Shape error ignores any rigid turn, so a solid that folds its legs and pitches
// onto its nose keeps a small shape error; these two figures see it.
#include <cstddef>

#include "sim/soft_body.h"

namespace pbdsplat::sim {

struct PoseReport {
    double tilt_max_degrees = 0.0;  // the model whose vertical turned most (roll and pitch; a turn about y is not a tilt)
    double height_ratio_min = 1.0;  // the model with the least height (y extent) over its rest height
};

PoseReport pose_report(const SoftBody& body);

// The fewest triangles in any connected piece (0 for a body without triangles): a tear that
// plucks out a fleck of two triangles shows as 2.
size_t smallest_piece_triangles(const SoftBody& body);

} // namespace pbdsplat::sim
