#pragma once
// Order of Gauss-Seidel sweeps. Sorted by particle, consecutive constraints share a particle and
// each waits for the previous one's store (a serial chain of sqrt and divide). Grouping the
// constraints by colour (no two in a colour share a particle) lets the CPU overlap neighbours
// and lets threads split a colour, and since a colour's constraints are independent, the
// result is the same whatever the thread count.
#include <span>
#include <vector>

#include "sim/constraints.h"
#include "sim/slack_lists.h"

namespace pbdsplat::sim {

// Greedy colouring in array order: the groups' offsets, and for each slot of the grouped order
// the index of the constraint it holds.
struct ColourGrouping {
    std::vector<uint32_t> start, order;
};
ColourGrouping colour_groups(std::span<const DistanceConstraint> constraints);

// Greedy colouring in array order; reorders the constraints colour by colour (keeping their
// relative order, and so the memory locality, inside a colour) and returns the offsets:
// colour c holds [start[c], start[c + 1]).
std::vector<uint32_t> group_by_colour(std::vector<DistanceConstraint>& constraints);

// The colour groups kept up to date through topology edits at the cost of what an edit touches:
// removed constraints leave dead slots; an added one takes a dead slot of a colour free at both
// its particles, else a slot opened at the end of such a colour (the first constraint of each
// later group moves to its group's end: a dozen moves, whatever the body's size), else a new
// group at the end. Everything is regrouped from scratch (dead slots dropped) only when dead
// slots pass an eighth of the array or edits have added more than a few colours.
struct DistanceGroups {
    std::vector<uint32_t> start;          // colour c holds [start[c], start[c + 1])
    std::vector<uint8_t> colour;          // per slot, its group (an edit reads it for every slot around the particles it touches)
    SlackLists<uint32_t> of_particle;     // each particle's constraint slots
    size_t dead = 0;                      // dead slots in the array
    size_t colours_when_grouped = 0;      // groups after the last full grouping
    size_t regroupings = 0;               // full groupings after the first (counted, they cost the body)
    size_t colours_added = 0;             // groups edits made for constraints no colour could take
    size_t slots_reused = 0;              // added constraints that took a dead slot
    size_t slots_appended = 0;            // added constraints that took an opened slot or a new group
    double rest_sum = 0.0;                // of the live constraints' rest lengths, kept through edits
    double mean_rest() const {
        const size_t live = start.empty() ? 0 : start.back() - dead;
        return live ? rest_sum / double(live) : 0.0;
    }
};

// Groups `constraints` (reordering them) and indexes them per particle.
DistanceGroups make_distance_groups(std::vector<DistanceConstraint>& constraints, size_t particles);

// Kills the constraints at `remove` and places `add`; `lambda` (XPBD) follows the array (new
// slots 0). Particles may have grown since the last call. Returns the slots of `add`, in order.
std::vector<uint32_t> replace_distance_constraints(std::vector<DistanceConstraint>& constraints, DistanceGroups& groups,
                                                   std::vector<float>& lambda, size_t particles,
                                                   std::span<const uint32_t> remove, std::span<const DistanceConstraint> add);

// Whether the grouping holds: no two live constraints of a group share a particle, the index
// lists exactly the live constraints, the dead count is right. For tests.
bool distance_groups_valid(const std::vector<DistanceConstraint>& constraints, const DistanceGroups& groups, size_t particles);

} // namespace pbdsplat::sim
