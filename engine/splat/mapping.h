#pragma once
// The particle-to-Gaussian mapping (paper eqs. 11-13 and 21): one isotropic Gaussian per
// simulation particle and per boundary particle, centre = position, R = I, the scale s0 from
// the sampling spacing h, opacity = sigmoid(o), colour from the material (or vertex colours).
#include <span>
#include <vector>

#include "core/thread_pool.h"
#include "mesh/triangle_mesh.h"
#include "splat/gaussian_record.h"
#include "splat/normal_field.h"
#include "surface/boundary_particles.h"

namespace pbdsplat::splat {

// Grows a splat with the stretch of its triangle (the largest singular value of the
// triangle's deformation gradient, at least 1), so stretching does not open holes (the
// paper's limitation 7.5.2).
class StretchScale {
public:
    StretchScale() = default;
    StretchScale(std::span<const Vec3f> rest_positions, std::span<const mesh::Triangle> triangles);
    // Per-triangle and per-vertex factors for the current positions: the largest singular value
    // of each triangle's deformation gradient, clamped to [1, 3]; slivers keep 1.
    void update(std::span<const Vec4f> x, std::span<const mesh::Triangle> triangles);
    float triangle(uint32_t t) const { return triangle_[t]; }
    float vertex(uint32_t v) const { return vertex_[v]; }
    bool empty() const { return inverse_rest_.empty(); }

private:
    std::vector<Eigen::Matrix2f> inverse_rest_;  // D_m^-1 in each triangle's own rest frame
    std::vector<uint32_t> ring_start_, ring_;     // vertex -> incident triangles
    std::vector<float> triangle_, vertex_;
};

// Records for the particles (x, normals), then for the boundary particles (may be null).
// `colors`, when not empty, gives a colour per particle (boundary particles interpolate it,
// unless the samples carry a painted colour of their own: BoundaryParticles::color).
// `stretch`, when not null, scales each splat by its stretch factor. `field`, when not null and
// current, gives each splat how the normal turns across it (the particles' only when it has
// vertices); else every splat is lit with one normal. `kept` (one entry per sample, or empty):
// the records of the samples marked 1 are those `out` holds from the last call, which made them
// from the same sample at the same place, and are left as they are (the caller knows: their
// piece has not moved, nothing was added or removed, they do not fade).
void map_body(std::span<const Vec4f> x, std::span<const Vec3f> normals, std::span<const Vec3f> colors,
              std::span<const mesh::Triangle> triangles, const surface::BoundaryParticles* samples, const Appearance& look,
              const StretchScale* stretch, const NormalField* field, std::vector<GaussianRecord>& out,
              core::ThreadPool* pool = nullptr, std::span<const uint8_t> kept = {});

} // namespace pbdsplat::splat
