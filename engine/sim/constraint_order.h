#pragma once
// Order of Gauss-Seidel sweeps. Sorted by particle, consecutive constraints share a particle and
// each waits for the previous one's store (a serial chain of sqrt and divide). Reordering each
// small block so that neighbours in the array share no particle keeps the memory locality of
// the sorted order and lets the CPU overlap them.
#include <span>

#include "sim/constraints.h"

namespace pbdsplat::sim {

// Greedy colouring inside consecutive blocks of `block` constraints, then by colour within
// each block. Deterministic; returns the largest colour count of any block.
uint32_t interleave_independent(std::span<DistanceConstraint> constraints, size_t block = 128);

} // namespace pbdsplat::sim
