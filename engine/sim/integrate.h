#pragma once
// The non-constraint stages of a PBD step (paper eqs. 5 and 10), and vertex normals.
#include <span>

#include "mesh/triangle_mesh.h"
#include "sim/particles.h"

namespace pbdsplat::sim {

// v += dt * g for free particles, then exponential damping (rate per second).
template <class Real>
void apply_external_forces(ParticlesT<Real>& p, const Vec3f& gravity, float damping, Real dt);
// x_prev = x; x += dt * v (eq. 5).
template <class Real>
void predict_positions(ParticlesT<Real>& p, Real dt);
// v = (x - x_prev) / dt (eq. 10); pinned particles keep no velocity, even when dragged.
template <class Real>
void update_velocities(ParticlesT<Real>& p, Real dt);
// Area-weighted vertex normals of the deformed surface.
void update_normals(std::span<const mesh::Triangle> triangles, const Vec4Array& x, std::vector<Vec3f>& normals);

} // namespace pbdsplat::sim
