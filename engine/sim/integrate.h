#pragma once
// The non-constraint stages of a PBD step (paper eqs. 5 and 10), and vertex normals.
#include <span>

#include "mesh/triangle_mesh.h"
#include "sim/particles.h"

namespace pbdsplat::sim {

// v += dt * g for free particles, then exponential damping (rate per second).
void apply_external_forces(Particles& p, const Vec3f& gravity, float damping, float dt);
// x_prev = x; x += dt * v (eq. 5).
void predict_positions(Particles& p, float dt);
// v = (x - x_prev) / dt (eq. 10).
void update_velocities(Particles& p, float dt);
// Area-weighted vertex normals of the deformed surface.
void update_normals(std::span<const mesh::Triangle> triangles, const Vec4Array& x, std::vector<Vec3f>& normals);

} // namespace pbdsplat::sim
