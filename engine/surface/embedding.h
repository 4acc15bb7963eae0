#pragma once
// The fine surface riding on the coarse one (paper sections 4.2 and 5.2, with a simulation
// mesh decimated from the model): samples of the model's full-resolution surface, each
// embedded in the simulation triangle nearest to it as barycentric coordinates plus a signed
// offset along the interpolated vertex normal. In the rest pose the embedding reproduces each
// sample exactly; under deformation the samples follow the coarse triangles, so the model's
// detail costs no solver time.
#include <span>
#include <vector>

#include "mesh/triangle_mesh.h"
#include "surface/boundary_particles.h"

namespace pbdsplat::surface {

struct EmbeddingStats {
    size_t samples = 0;
    size_t outside = 0;    // samples whose coordinates fall outside their triangle (allowed, exact)
    size_t fallback = 0;   // samples no triangle reproduced exactly: closest point + face-normal offset
    float max_rest_error = 0.0f;  // largest |embedded - sample| at rest
    float max_offset = 0.0f;      // largest |d|
};

// Embeds `points` in the coarse rest mesh (`rest`, `triangles`, unit vertex normals
// `rest_normals`, the ones the solver computes at rest). Appends to `out`; the same with or
// without a pool.
void embed_points(std::span<const SurfacePoint> points, std::span<const Vec3f> rest, std::span<const mesh::Triangle> triangles,
                  std::span<const Vec3f> rest_normals, BoundaryParticles& out, EmbeddingStats* stats = nullptr,
                  core::ThreadPool* pool = nullptr);

// The embedding of a new sample at `bary` on a triangle, from the embedded samples `same` (indices
// into `samples`) of that triangle: offset and rest normal of the nearest ones in barycentric
// space, inverse-distance weighted, so the new sample lies on the fine surface where its
// neighbours do. With no neighbours: offset 0 and the face normal.
void interpolate_embedding(const BoundaryParticles& samples, std::span<const uint32_t> same, const Vec2f& bary, float& offset,
                           Vec3f& local_normal);

// The same from a triangle's embedded samples copied out once (barycentric coordinates,
// offsets, rest normals, in the order of `same`), for many new samples on one triangle: the
// density control's darts read them from a few cache lines instead of gathering them from
// every sample's arrays. The same numbers as the version above.
struct EmbeddedNeighbours {
    std::vector<Vec2f> bary;
    std::vector<float> offset;
    std::vector<Vec3f> local_normal;
    void assign(const BoundaryParticles& samples, std::span<const uint32_t> same);
};
void interpolate_embedding(const EmbeddedNeighbours& same, const Vec2f& bary, float& offset, Vec3f& local_normal);

} // namespace pbdsplat::surface
