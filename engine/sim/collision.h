#pragma once
#include "sim/colliders.h"
#include "sim/particles.h"

namespace pbdsplat::sim {

// Pushes free particles of [begin, end) out of every collider and applies friction against
// the motion since the start of the step (x - x_prev).
template <class Real>
void solve_collisions(const Colliders& colliders, ParticlesT<Real>& p, size_t begin, size_t end);

} // namespace pbdsplat::sim
