#pragma once
// The non-constraint stages of a PBD step (paper eqs. 5 and 10), and vertex normals.
#include <span>

#include "mesh/triangle_mesh.h"
#include "sim/particles.h"
#include "sim/slack_lists.h"

namespace pbdsplat::sim {

// Each stage works on the particle range [begin, end), so threads can split it.

// v += dt * g for free particles, then exponential damping (rate per second); then
// x_prev = x; x += dt * v (eq. 5).
template <class Real>
void apply_forces_and_predict(ParticlesT<Real>& p, const Vec3f& gravity, float damping, Real dt, size_t begin, size_t end);
// The same with each model's own decay: particle i's velocity is scaled by keep[model[i]]
// (e^(-rate dt), taken once a substep per model, not once per particle).
template <class Real>
void apply_forces_and_predict(ParticlesT<Real>& p, const Vec3f& gravity, std::span<const Real> keep, std::span<const uint32_t> model, Real dt,
                              size_t begin, size_t end);
// v = (x - x_prev) / dt (eq. 10); pinned particles keep no velocity, even when dragged.
template <class Real>
void update_velocities(ParticlesT<Real>& p, Real dt, size_t begin, size_t end);

// Per-vertex triangle rings: for vertex i, the (j, k) of each triangle (i, j, k), and beside
// it the triangle's index, both in increasing triangle order (the order a pass over the whole
// triangle list meets them, so sums over a ring do not depend on how the ring was made).
struct VertexRings {
    SlackLists<std::array<uint32_t, 2>> ring;
    SlackLists<uint32_t> triangles;
    // Per vertex, twice its fan's vector area at rest (the length of the volume gradient there
    // when the body is at rest), at least a quarter of its longest edge squared: the volume pass
    // holds each particle's push to a few times it. open_fan: 1 where the fan does not close (a
    // vertex on a boundary), whose gradient depends on where the origin is. Both empty until
    // set_rest_ring_areas is called.
    std::vector<float> rest_area;
    std::vector<uint8_t> open_fan;
    size_t size() const { return ring.keys(); }
};
VertexRings build_vertex_rings(std::span<const mesh::Triangle> triangles, size_t vertex_count);
// After an edit: the rings of `vertices` made again from their current triangles, found among
// each one's old ring triangles and `extra` (triangles that are new or whose corners changed).
// `vertices` ascending. Rings grow to `triangles`' vertex count. Equal to build_vertex_rings afterwards.
void update_vertex_rings(VertexRings& rings, std::span<const mesh::Triangle> triangles, size_t vertex_count,
                         std::span<const uint32_t> vertices, std::span<const uint32_t> extra);

// rings.rest_area and rings.open_fan of every vertex, from the rest positions; after an edit,
// of the edited `vertices` only.
void set_rest_ring_areas(VertexRings& rings, std::span<const Vec3f> rest);
void update_rest_ring_areas(VertexRings& rings, std::span<const Vec3f> rest, std::span<const uint32_t> vertices);

// Whether edge (a, b) of triangle t lies on the boundary: no other triangle has both ends.
// Costs a's ring.
bool edge_on_boundary(const VertexRings& rings, std::span<const mesh::Triangle> triangles, uint32_t t, uint32_t a, uint32_t b);

// Area-weighted vertex normals of the deformed surface, gathered per vertex over [begin, end).
void update_normals(const VertexRings& rings, const Vec4Array& x, std::vector<Vec3f>& normals, size_t begin, size_t end);

} // namespace pbdsplat::sim
