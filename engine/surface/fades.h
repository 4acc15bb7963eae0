#pragma once
// Samples appear and leave by fading: a new one fades in, a retired one fades out and then
// leaves the arrays in batches.
#include <cstddef>
#include <cstdint>

#include "surface/boundary_particles.h"

namespace pbdsplat::surface {

// Advances the fades by one frame and removes the samples that finished fading out, in batches:
// once a 64th of them has finished, or when nothing else still fades (until then a finished one
// stays, invisible and retiring). Returns how many were removed; `fading` receives how many
// still fade.
size_t advance_fades(BoundaryParticles& samples, uint32_t* fading = nullptr);

// Starts a fade-in over `frames` frames for samples [first, size()).
void fade_in(BoundaryParticles& samples, size_t first, uint32_t frames);

} // namespace pbdsplat::surface
