#pragma once
// Boundary particles across a topology change: samples on a re-triangulated triangle move to
// the child holding them by a change of barycentric basis, so nothing jumps on screen.
#include <functional>
#include <span>

#include "mesh/triangle_split.h"
#include "surface/boundary_particles.h"

namespace pbdsplat::surface {

// Returns how many samples changed triangle.
size_t remap_samples(std::span<const mesh::TriangleSplit> splits, BoundaryParticles& samples);

} // namespace pbdsplat::surface

namespace pbdsplat::surface {

// After a cut: embedded samples that lie on a side of the cut where none of their triangle's
// corners lies are dropped. An embedded sample is carried by its offset, not only by its
// coordinates, so near the cut it can hang over the cut surface; the local refill then fills
// its place from the right side. `side(p)` is the signed distance to the cut surface (0 where
// the cut does not reach p). Returns how many were dropped; `emptied`, when given, receives
// the triangles that lost samples (sorted, once each), for the refill.
size_t drop_across_cut(const std::function<float(const Vec3f&)>& side, std::span<const mesh::Triangle> triangles,
                       std::span<const Vec4f> x, BoundaryParticles& samples, std::vector<uint32_t>* emptied = nullptr);

} // namespace pbdsplat::surface
