#pragma once
// Order of Gauss-Seidel sweeps. Sorted by particle, consecutive constraints share a particle and
// each waits for the previous one's store (a serial chain of sqrt and divide). Grouping the
// constraints by colour (no two in a colour share a particle) lets the CPU overlap neighbours
// and lets threads split a colour, and since a colour's constraints are independent, the
// result is the same whatever the thread count.
#include <span>
#include <vector>

#include "sim/constraints.h"

namespace pbdsplat::sim {

// Greedy colouring in array order; reorders the constraints colour by colour (keeping their
// relative order, and so the memory locality, inside a colour) and returns the offsets:
// colour c holds [start[c], start[c + 1]).
std::vector<uint32_t> group_by_colour(std::vector<DistanceConstraint>& constraints);

} // namespace pbdsplat::sim
