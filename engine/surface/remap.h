#pragma once
// Boundary particles across a topology change: samples on a re-triangulated triangle move to
// the child holding them by a change of barycentric basis, so nothing jumps on screen.
#include <span>

#include "mesh/triangle_split.h"
#include "surface/boundary_particles.h"

namespace pbdsplat::surface {

// Returns how many samples changed triangle.
size_t remap_samples(std::span<const mesh::TriangleSplit> splits, BoundaryParticles& samples);

} // namespace pbdsplat::surface
