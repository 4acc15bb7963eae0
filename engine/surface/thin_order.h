#pragma once
// A progressive order over the samples, for drawing fewer, larger splats where they are smaller
// than a few pixels: each sample has a level, and the samples of level >= l form a maximal
// Poisson-disc set at radius h * 2^(l/2) (half as many per area at each level), so any prefix
// of the order covers the surface evenly. A random subset would leave gaps where its neighbours
// happened to go too; this one leaves none wider than its radius.
#include <cstdint>
#include <span>
#include <vector>

#include "core/math.h"

namespace pbdsplat::surface {

// Levels 0 (dropped first) .. k_thin_levels (never dropped).
inline constexpr int k_thin_levels = 4;

// Places the samples past `level`'s end (new ones) in the order. Coarsest level first, in index
// order, a sample rises to a level when no sample of that level or above lies near it (within
// h * 2^(l/2), with the same `tag` and a normal on the same side: the two faces of a thin part,
// or two pieces that touch, do not cover for each other). Around the new samples the order is
// made afresh (the gaps that samples removed near them left are filled: a retired or dropped
// sample's place is refilled where it was), against the levels of the samples around that;
// elsewhere nothing changes. Costs what lies around the new samples; all of them the first time.
// `gaps`: where samples of a level above 0 were removed since: the order is made afresh around
// them too.
void place_in_thin_order(std::span<const Vec3f> position, std::span<const Vec3f> normal, std::span<const uint32_t> tag, float h,
                         std::vector<uint8_t>& level, std::span<const Vec3f> gaps = {});

} // namespace pbdsplat::surface
