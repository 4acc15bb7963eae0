#pragma once
#include <cstdint>

#include "sim/particles.h"

namespace pbdsplat::sim {

// FNV-1a over the bytes of positions and velocities: equal hashes mean bit-identical state.
uint64_t state_hash(const Particles& p);

} // namespace pbdsplat::sim
