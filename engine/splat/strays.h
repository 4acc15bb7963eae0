#pragma once
// Stray Gaussians: splats that left the surface they belong to. A splat is a stray when no
// other splat lies within 3x the median nearest-neighbour spacing of all splats, or 3x the
// sampling spacing where that is longer: on a sampled surface every splat has neighbours about
// one spacing away, so a lone dot floating above the pieces, or a flake of a few dots, stands
// out.
#include <cstddef>
#include <span>

#include "core/math.h"

namespace pbdsplat::splat {

struct StrayReport {
    size_t strays = 0;
    float median_spacing = 0.0f;  // of the nearest-neighbour distances
};

// `hint`: the sampling spacing h (it also sizes the search grid).
StrayReport count_strays(std::span<const Vec3f> centres, float hint);

} // namespace pbdsplat::splat
