#pragma once
// The global volume (overpressure) constraint, paper eqs. 7 and 9.
#include "sim/constraints.h"
#include "sim/particles.h"

namespace pbdsplat::sim {

// Rebuilds the per-vertex rings from the triangles; call after any change to them.
void build_rings(VolumeConstraint& c);

// Volume by the divergence theorem, caps included, in double precision.
template <class Real>
double constraint_volume(const VolumeConstraint& c, const Vec4ArrayT<Real>& x);

// One projection of V = k*V0. PBD: `stiffness` in (0, 1]. XPBD (`xpbd`): compliance / dt^2
// given as alpha_tilde, multiplier accumulated in c.lambda. `scratch` holds one gradient per
// particle (sized to the particle count).
template <class Real>
void solve_volume(VolumeConstraint& c, ParticlesT<Real>& p, Vec4ArrayT<Real>& scratch, bool xpbd, Real stiffness,
                  Real alpha_tilde);

} // namespace pbdsplat::sim
