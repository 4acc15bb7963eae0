#pragma once
// The stream of textured splats (GaussianTexcoord, beside the records): where a textured
// model's texture lies on each splat this frame, so the fragment stage reads the texture under
// each pixel. A sample's coordinates stay those it was painted with; their gradients, kept at
// rest, turn and stretch with its triangle (a gradient is a covector: it maps by F^-T, where F
// takes the triangle's rest edges and unit normal to its deformed ones).
#include <span>
#include <vector>

#include "mesh/triangle_mesh.h"
#include "splat/gaussian_record.h"
#include "surface/boundary_particles.h"

namespace pbdsplat::splat {

// One entry per record, for records laid out as map_body lays them: `particles` first (textured
// where `particle_texcoords`, one per particle or none, say), then one per boundary particle
// (where its paint says), then up to `records` in all (the cut faces: their own colour).
// A particle's gradients follow one of its triangles.
struct TexcoordScratch {
    std::vector<Mat3f> covector;            // per triangle, F^-T
    std::vector<uint32_t> vertex_triangle;  // per particle, a triangle of its
};
void map_texcoords(std::span<const Vec3f> rest_positions, std::span<const Vec4f> x, std::span<const mesh::Triangle> triangles,
                   size_t particles, std::span<const mesh::SurfaceTexcoord> particle_texcoords,
                   const surface::BoundaryParticles& samples, size_t records, std::vector<GaussianTexcoord>& out,
                   TexcoordScratch& scratch);

// The record's parts, packed (gradients as halves, the tint as bytes).
GaussianTexcoord make_texcoord(const Vec2f& uv, const Vec3f& du, const Vec3f& dv, uint32_t texture, const Vec3f& tint, float reach);

} // namespace pbdsplat::splat
