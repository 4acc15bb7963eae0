#pragma once
// The global volume (overpressure) constraint, paper eqs. 7 and 9.
#include <span>

#include "sim/constraints.h"
#include "sim/particles.h"

namespace pbdsplat::sim {

// Rebuilds the per-vertex rings from the triangles; call after any change to them.
void build_rings(VolumeConstraint& c);

// Volume by the divergence theorem, caps included, in double precision.
double constraint_volume(const VolumeConstraint& c, const Vec4Array& x);

// One projection of V = k*V0. PBD: `stiffness` in (0, 1], alpha_tilde ignored. XPBD (`xpbd`):
// compliance / dt^2 given as alpha_tilde, multiplier accumulated in c.lambda.
// `scratch` holds one gradient per particle (sized to the particle count).
void solve_volume(VolumeConstraint& c, Particles& p, Vec4Array& scratch, bool xpbd, float stiffness, float alpha_tilde);

} // namespace pbdsplat::sim
