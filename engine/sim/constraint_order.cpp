#include "sim/constraint_order.h"

#include <algorithm>
#include <bit>

#include "core/assert.h"

namespace pbdsplat::sim {

std::vector<uint32_t> group_by_colour(std::vector<DistanceConstraint>& constraints) {
    uint32_t max_particle = 0;
    for (const auto& c : constraints) max_particle = std::max({max_particle, c.i, c.j});
    std::vector<uint64_t> used(size_t(max_particle) + 1, 0);  // colours taken at each particle
    std::vector<uint8_t> colour(constraints.size());
    uint32_t colours = 0;
    for (size_t k = 0; k < constraints.size(); ++k) {
        const DistanceConstraint& c = constraints[k];
        const uint64_t taken = used[c.i] | used[c.j];
        PBDSPLAT_ASSERT(~taken != 0, "more than 64 edge colours: a vertex has over 32 neighbours; repair the mesh");
        const uint32_t col = uint32_t(std::countr_one(taken));
        used[c.i] |= 1ull << col;
        used[c.j] |= 1ull << col;
        colour[k] = uint8_t(col);
        colours = std::max(colours, col + 1);
    }
    std::vector<uint32_t> start(colours + 1, 0);
    for (uint8_t c : colour) ++start[c + 1u];
    for (uint32_t c = 0; c < colours; ++c) start[c + 1] += start[c];
    std::vector<DistanceConstraint> sorted(constraints.size());
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (size_t k = 0; k < constraints.size(); ++k) sorted[fill[colour[k]]++] = constraints[k];
    constraints = std::move(sorted);
    return start;
}

} // namespace pbdsplat::sim
