#pragma once
// The global volume (overpressure) constraint, paper eqs. 7 and 9.
//
// One projection runs in phases so threads can share it: gather the gradient per vertex (in
// fixed blocks of vertices, each with its partial sums), add the virtual caps, reduce the
// sums block by block in order, then move every vertex. Fixed blocks make the result the same
// for any thread count.
#include <cstddef>
#include <vector>

#include "sim/constraints.h"
#include "sim/particles.h"

namespace pbdsplat::sim {

constexpr size_t k_volume_block = 1024;  // vertices per partial sum

// Rebuilds the per-vertex rings from the triangles; call after any change to them.
void build_rings(VolumeConstraint& c);

// Volume by the divergence theorem, caps included, in double precision.
template <class Real>
double constraint_volume(const VolumeConstraint& c, const Vec4ArrayT<Real>& x);

struct VolumeSums {
    double eighteen_v = 0.0;  // sum of x_i . g_i = 18 V (Euler, V homogeneous of degree 3)
    double denom = 0.0;       // sum of w_i |g_i|^2, g = gradient of 6V
};

size_t volume_blocks(const VolumeConstraint& c);
// Gradient of 6V at the vertices of block `b` into grad; their sums unless the constraint has
// caps (then the sums wait for volume_caps).
template <class Real>
VolumeSums volume_gather(const VolumeConstraint& c, const ParticlesT<Real>& p, Vec4ArrayT<Real>& grad, size_t b);
// Adds the virtual caps' terms (serial: they are few) and returns the block sums to use.
template <class Real>
void volume_caps(const VolumeConstraint& c, const ParticlesT<Real>& p, Vec4ArrayT<Real>& grad,
                 std::vector<VolumeSums>& block_sums);
// The step size along the gradient; updates c.lambda in XPBD mode. 0 when nothing can move.
template <class Real>
Real volume_step(VolumeConstraint& c, const std::vector<VolumeSums>& block_sums, bool xpbd, Real stiffness,
                 Real alpha_tilde);
// x_i += step * w_i * g_i for the vertices of block b.
template <class Real>
void volume_apply(const VolumeConstraint& c, ParticlesT<Real>& p, const Vec4ArrayT<Real>& grad, Real step, size_t b);

// All phases in one thread. `scratch` holds one gradient per particle.
template <class Real>
void solve_volume(VolumeConstraint& c, ParticlesT<Real>& p, Vec4ArrayT<Real>& scratch, bool xpbd, Real stiffness,
                  Real alpha_tilde);

} // namespace pbdsplat::sim
