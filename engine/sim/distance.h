#pragma once
// Distance constraints (paper eq. 6), projected Gauss-Seidel in array order.
#include <span>

#include "sim/constraints.h"
#include "sim/particles.h"

namespace pbdsplat::sim {

// PBD: each constraint closes `stiffness` (in (0,1]) of its error per call. The constraints of
// one call share no particle (a colour of DistanceGroups, or a part of one; dead slots aside):
// on SSE they are projected four at a time, to the same bits as one at a time.
template <class Real>
void project_distance_pbd(std::span<const DistanceConstraint> constraints, ParticlesT<Real>& p, Real stiffness);

// PBD with a stiffness per constraint (`stiffness[k]` for constraints[k]): the models of a scene
// that name their own stretch stiffness. The same arithmetic, lane by lane.
template <class Real>
void project_distance_pbd(std::span<const DistanceConstraint> constraints, std::span<const Real> stiffness, ParticlesT<Real>& p);

// XPBD: compliance per constraint, multipliers accumulated in `lambda` (reset each substep).
template <class Real>
void project_distance_xpbd(std::span<const DistanceConstraint> constraints, std::span<Real> lambda, ParticlesT<Real>& p,
                           Real inv_dt2);

} // namespace pbdsplat::sim
