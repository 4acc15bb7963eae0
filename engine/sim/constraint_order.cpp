#include "sim/constraint_order.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include "core/assert.h"
#include "core/key_table.h"

namespace pbdsplat::sim {

ColourGrouping colour_groups(std::span<const DistanceConstraint> constraints) {
    uint32_t max_particle = 0;
    for (const auto& c : constraints) max_particle = std::max({max_particle, c.i, c.j});
    // Colours taken at each particle: indexed by particle for a whole body, by rank among the
    // few particles involved for a handful of constraints (a body-sized table would cost the
    // body).
    std::vector<uint32_t> ids;
    const bool sparse = constraints.size() * 16 < size_t(max_particle);
    if (sparse) {
        for (const auto& c : constraints) ids.push_back(c.i), ids.push_back(c.j);
        std::sort(ids.begin(), ids.end());
        ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    }
    auto index = [&](uint32_t v) { return sparse ? size_t(std::lower_bound(ids.begin(), ids.end(), v) - ids.begin()) : size_t(v); };
    std::vector<uint64_t> used(sparse ? ids.size() : size_t(max_particle) + 1, 0);
    std::vector<uint8_t> colour(constraints.size());
    uint32_t colours = 0;
    for (size_t k = 0; k < constraints.size(); ++k) {
        const DistanceConstraint& c = constraints[k];
        const size_t a = index(c.i), b = index(c.j);
        const uint64_t taken = used[a] | used[b];
        PBDSPLAT_ASSERT(~taken != 0, "more than 64 edge colours: a vertex has over 32 neighbours; repair the mesh");
        const uint32_t col = uint32_t(std::countr_one(taken));
        used[a] |= 1ull << col;
        used[b] |= 1ull << col;
        colour[k] = uint8_t(col);
        colours = std::max(colours, col + 1);
    }
    ColourGrouping g;
    g.start.assign(colours + 1, 0);
    for (uint8_t c : colour) ++g.start[c + 1u];
    for (uint32_t c = 0; c < colours; ++c) g.start[c + 1] += g.start[c];
    g.order.resize(constraints.size());
    std::vector<uint32_t> fill(g.start.begin(), g.start.end() - 1);
    for (uint32_t k = 0; k < constraints.size(); ++k) g.order[fill[colour[k]]++] = k;
    return g;
}

std::vector<uint32_t> group_by_colour(std::vector<DistanceConstraint>& constraints) {
    ColourGrouping g = colour_groups(constraints);
    std::vector<DistanceConstraint> sorted(constraints.size());
    for (size_t s = 0; s < sorted.size(); ++s) sorted[s] = constraints[g.order[s]];
    constraints = std::move(sorted);
    return std::move(g.start);
}

namespace {
SlackLists<uint32_t> index_by_particle(const std::vector<DistanceConstraint>& constraints, size_t particles) {
    std::vector<uint32_t> start(particles + 1, 0);
    for (const DistanceConstraint& c : constraints)
        if (c.alive()) ++start[c.i + 1], ++start[c.j + 1];
    for (size_t v = 0; v < particles; ++v) start[v + 1] += start[v];
    std::vector<uint32_t> slots(start.back());
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (uint32_t k = 0; k < constraints.size(); ++k) {
        const DistanceConstraint& c = constraints[k];
        if (!c.alive()) continue;
        slots[fill[c.i]++] = k;
        slots[fill[c.j]++] = k;
    }
    SlackLists<uint32_t> lists;
    lists.build(start, slots);
    return lists;
}

std::vector<uint8_t> colour_of_slots(const std::vector<uint32_t>& start) {
    std::vector<uint8_t> colour(start.back());
    for (size_t c = 0; c + 1 < start.size(); ++c) std::fill(colour.begin() + start[c], colour.begin() + start[c + 1], uint8_t(std::min<size_t>(c, 255)));
    return colour;
}

uint64_t colours_at(const DistanceGroups& g, uint32_t v) {
    uint64_t used = 0;
    for (uint32_t slot : g.of_particle.of(v))
        if (const uint32_t c = g.colour[slot]; c < 64) used |= 1ull << c;
    return used;
}


// Where the constraints added by one call went, kept up to date as inserting moves slots.
struct Placement {
    explicit Placement(size_t added) : slot_of_added(added, UINT32_MAX), added_at(added) {}
    std::vector<uint32_t> slot_of_added;
    core::KeyMap<uint32_t> added_at;  // slot -> 1 + added index (0: none; a cut through a large body adds thousands)
    void moved(uint32_t from, uint32_t to) {
        uint32_t* at = added_at.find(from);
        if (!at || *at == 0) return;
        const uint32_t k = *at - 1;
        *at = 0;
        added_at[to] = k + 1, slot_of_added[k] = to;
    }
    void place(uint32_t k, uint32_t slot) {
        slot_of_added[k] = slot;
        added_at[slot] = k + 1;
    }
};

// Opens a slot at the end of colour `col`: the first constraint of each later group moves to
// that group's end, one group after another from the last, and the boundaries shift by one. A
// moved constraint stays in its colour, so the grouping holds; the cost is the number of later
// groups (a dozen or so), not the array's length.
uint32_t open_slot_in_colour(std::vector<DistanceConstraint>& constraints, DistanceGroups& g, std::vector<float>& lambda,
                             uint32_t col, Placement& placement) {
    uint32_t hole = uint32_t(constraints.size());
    constraints.push_back({0, 0, 0.0f, 0.0f});
    lambda.push_back(0.0f);
    const uint32_t groups = uint32_t(g.start.size() - 1);
    g.colour.push_back(uint8_t(std::min<uint32_t>(groups - 1, 255)));
    ++g.start[groups];
    for (uint32_t c = groups - 1; c > col; --c) {
        const uint32_t first = g.start[c];
        const DistanceConstraint moved = constraints[first];
        constraints[hole] = moved;
        lambda[hole] = lambda[first];
        if (moved.alive()) {
            g.of_particle.replace(moved.i, first, hole);
            g.of_particle.replace(moved.j, first, hole);
            placement.moved(first, hole);
        }
        hole = first;
        ++g.start[c];
        g.colour[first] = uint8_t(std::min<uint32_t>(c - 1, 255));  // the slot now ends group c - 1
    }
    return hole;
}

// The added constraints that found no dead slot go into a colour free at both their particles,
// the last such (fewest groups to shift), or into a new group at the end when none is.
void insert_spilled(std::vector<DistanceConstraint>& constraints, DistanceGroups& g, std::vector<float>& lambda,
                    std::span<const DistanceConstraint> add, std::span<const uint32_t> spill, Placement& placement) {
    for (uint32_t k : spill) {
        const DistanceConstraint& c = add[k];
        const uint64_t taken = colours_at(g, c.i) | colours_at(g, c.j);
        const uint32_t groups = uint32_t(g.start.size() - 1);
        uint32_t col = UINT32_MAX;
        for (uint32_t t = std::min<uint32_t>(groups, 64); t-- > 0;)
            if (!(taken >> t & 1u)) {
                col = t;
                break;
            }
        uint32_t slot = 0;
        if (col == UINT32_MAX) {
            slot = uint32_t(constraints.size());
            constraints.push_back(c);
            lambda.push_back(0.0f);
            g.start.push_back(slot + 1);
            g.colour.push_back(uint8_t(std::min<size_t>(g.start.size() - 2, 255)));
            ++g.colours_added;
        } else {
            slot = open_slot_in_colour(constraints, g, lambda, col, placement);
        }
        constraints[slot] = c;
        lambda[slot] = 0.0f;
        g.of_particle.push(c.i, slot);
        g.of_particle.push(c.j, slot);
        placement.place(k, slot);
        ++g.slots_appended;
    }
}

// The live constraints grouped from scratch (dead slots dropped), following where the added
// ones go.
void regroup(std::vector<DistanceConstraint>& constraints, DistanceGroups& g, std::vector<float>& lambda, size_t particles,
             std::vector<uint32_t>& placed) {
    std::vector<uint32_t> new_slot(constraints.size(), UINT32_MAX);
    std::vector<DistanceConstraint> live;
    std::vector<uint32_t> old_slot;
    for (uint32_t s = 0; s < constraints.size(); ++s)
        if (constraints[s].alive()) live.push_back(constraints[s]), old_slot.push_back(s);
    const ColourGrouping grouping = colour_groups(live);
    constraints.resize(live.size());
    for (uint32_t s = 0; s < live.size(); ++s) {
        constraints[s] = live[grouping.order[s]];
        new_slot[old_slot[grouping.order[s]]] = s;
    }
    for (uint32_t& p : placed) p = new_slot[p];
    const size_t reused = g.slots_reused, appended = g.slots_appended, regroupings = g.regroupings + 1, added = g.colours_added;
    g = DistanceGroups{};
    g.colours_added = added;
    g.start = grouping.start;
    g.colour = colour_of_slots(g.start);
    g.of_particle = index_by_particle(constraints, particles);
    g.colours_when_grouped = g.start.size() - 1;
    g.slots_reused = reused, g.slots_appended = appended, g.regroupings = regroupings;
    for (const DistanceConstraint& c : constraints) g.rest_sum += double(c.rest);
    lambda.assign(constraints.size(), 0.0f);
}
} // namespace

DistanceGroups make_distance_groups(std::vector<DistanceConstraint>& constraints, size_t particles) {
    std::erase_if(constraints, [](const DistanceConstraint& c) { return !c.alive(); });
    DistanceGroups g;
    g.start = group_by_colour(constraints);
    g.colour = colour_of_slots(g.start);
    g.of_particle = index_by_particle(constraints, particles);
    g.colours_when_grouped = g.start.size() - 1;
    for (const DistanceConstraint& c : constraints) g.rest_sum += double(c.rest);
    return g;
}

std::vector<uint32_t> replace_distance_constraints(std::vector<DistanceConstraint>& constraints, DistanceGroups& g,
                                                   std::vector<float>& lambda, size_t particles,
                                                   std::span<const uint32_t> remove, std::span<const DistanceConstraint> add) {
    g.of_particle.grow(particles);
    // Dead slots per colour, the new ones first (they sit where the added constraints' old
    // neighbours were: reusing them keeps memory order local).
    std::vector<std::vector<uint32_t>> free_in(g.start.size() - 1);
    for (uint32_t slot : remove) {
        DistanceConstraint& c = constraints[slot];
        PBDSPLAT_ASSERT(c.alive(), "replace_distance_constraints: a slot removed twice");
        g.of_particle.erase(c.i, slot);
        g.of_particle.erase(c.j, slot);
        g.rest_sum -= double(c.rest);
        c = {c.i, c.i, 0.0f, c.compliance};
        lambda[slot] = 0.0f;
        free_in[g.colour[slot]].push_back(slot);
        ++g.dead;
    }
    // The colours (of the first 64) with a dead slot left, as bits: an added constraint takes
    // the lowest one free at both its particles in a few instructions, not a walk over colours.
    uint64_t with_room = 0;
    for (uint32_t col = 0; col < free_in.size() && col < 64; ++col)
        if (!free_in[col].empty()) with_room |= uint64_t(1) << col;
    for (const DistanceConstraint& c : add) g.rest_sum += double(c.rest);
    Placement placement(add.size());
    std::vector<uint32_t> spill;
    for (uint32_t k = 0; k < add.size(); ++k) {
        const DistanceConstraint& c = add[k];
        const uint64_t taken = colours_at(g, c.i) | colours_at(g, c.j);
        uint32_t slot = UINT32_MAX;
        if (const uint64_t open = with_room & ~taken; open != 0) {
            const uint32_t col = uint32_t(std::countr_zero(open));
            slot = free_in[col].back();
            free_in[col].pop_back();
            if (free_in[col].empty()) with_room &= ~(uint64_t(1) << col);
        }
        if (slot == UINT32_MAX) {
            spill.push_back(k);
            continue;
        }
        constraints[slot] = c;
        --g.dead;
        ++g.slots_reused;
        g.of_particle.push(c.i, slot);
        g.of_particle.push(c.j, slot);
        placement.place(k, slot);
    }
    // Dead slots taken first: inserting moves slots (free_in's would go stale).
    insert_spilled(constraints, g, lambda, add, spill, placement);
    std::vector<uint32_t> placed = std::move(placement.slot_of_added);
    // The whole array is grouped again only when dead slots pass an eighth of it (thousands of
    // edits), or when edits added more than a few colours of their own.
    constexpr size_t k_added_colours = 8;
    if (g.dead * 8 > constraints.size() || g.start.size() - 1 > g.colours_when_grouped + k_added_colours)
        regroup(constraints, g, lambda, particles, placed);
    return placed;
}

bool distance_groups_valid(const std::vector<DistanceConstraint>& constraints, const DistanceGroups& g, size_t particles) {
    if (g.start.empty() || g.start.front() != 0 || g.start.back() != constraints.size()) return false;
    if (g.colour != colour_of_slots(g.start)) return false;
    if (g.of_particle.keys() != particles) return false;
    std::vector<uint32_t> last_group(particles, UINT32_MAX);
    size_t dead = 0;
    for (uint32_t c = 0; c + 1 < g.start.size(); ++c)
        for (uint32_t s = g.start[c]; s < g.start[c + 1]; ++s) {
            const DistanceConstraint& k = constraints[s];
            if (!k.alive()) {
                ++dead;
                continue;
            }
            if (k.i >= particles || k.j >= particles) return false;
            if (last_group[k.i] == c || last_group[k.j] == c) return false;
            last_group[k.i] = last_group[k.j] = c;
        }
    if (dead != g.dead) return false;
    for (uint32_t v = 0; v < particles; ++v)
        for (uint32_t s : g.of_particle.of(v))
            if (s >= constraints.size() || !constraints[s].alive() || (constraints[s].i != v && constraints[s].j != v)) return false;
    double rest_sum = 0.0;
    for (const DistanceConstraint& k : constraints) rest_sum += double(k.rest);  // dead slots have rest 0
    if (std::abs(rest_sum - g.rest_sum) > 1e-9 * std::max(1.0, rest_sum)) return false;
    size_t listed = 0;
    for (uint32_t v = 0; v < particles; ++v) listed += g.of_particle.of(v).size();
    return listed == 2 * (constraints.size() - dead);
}

} // namespace pbdsplat::sim
