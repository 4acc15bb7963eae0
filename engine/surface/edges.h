#pragma once
// Samples along the open boundary of the simulation mesh (a cut line, a tear, an open model's
// rim): the paper generates "additional particles at regular intervals along an edge" so that
// the boundary is tracked after stretching or separation. Here they lie on the boundary edges
// at most `spacing` h apart with smaller splats, so an edge reads as a line, not as a string of
// the surface's round splats. Each rides on the triangle that owns the edge, like any sample.
#include <span>

#include "mesh/triangle_mesh.h"
#include "surface/boundary_particles.h"

namespace pbdsplat::surface {

struct EdgeOptions {
    float spacing = 0.5f;  // along the edge, in units of h
    float size = 0.5f;     // splat size, relative to the surface's
};

// Replaces the edge samples of `samples` with a fresh set along every boundary edge of
// `triangles` (lengths from `rest`). Returns how many it laid.
size_t lay_edge_samples(std::span<const Vec3f> rest, std::span<const mesh::Triangle> triangles, float h,
                        const EdgeOptions& options, BoundaryParticles& samples);

// After a topology change, the same for a region only: the edge samples on the `region`
// triangles (sorted) are replaced by fresh ones along their boundary edges, bit k of
// `boundary_edges[r]` saying whether edge k of triangle region[r] is used by it alone. Where the
// region holds every triangle whose edges changed, the edge samples are, as a set, those
// lay_edge_samples would lay over the whole surface; the others keep their place and fade.
size_t relay_edge_samples(std::span<const Vec3f> rest, std::span<const mesh::Triangle> triangles, std::span<const uint32_t> region,
                          std::span<const uint8_t> boundary_edges, float h, const EdgeOptions& options, BoundaryParticles& samples);

} // namespace pbdsplat::surface
