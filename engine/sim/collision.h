#pragma once
#include "sim/colliders.h"
#include "sim/particles.h"

namespace pbdsplat::sim {

// Pushes free particles out of every collider and applies friction against the motion since
// the start of the step (x - x_prev).
void solve_collisions(const Colliders& colliders, Particles& p);

} // namespace pbdsplat::sim
