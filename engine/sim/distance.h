#pragma once
// Distance constraints (paper eq. 6), projected Gauss-Seidel in array order.
#include <span>

#include "sim/constraints.h"
#include "sim/particles.h"

namespace pbdsplat::sim {

// PBD: each constraint closes `stiffness` (in (0,1]) of its error per call.
void project_distance_pbd(std::span<const DistanceConstraint> constraints, Particles& p, float stiffness);

// XPBD: compliance per constraint, multipliers accumulated in `lambda` (reset each substep).
void project_distance_xpbd(std::span<const DistanceConstraint> constraints, std::span<float> lambda, Particles& p,
                           float inv_dt2);

} // namespace pbdsplat::sim
