#pragma once
// Internal to the topology room: which pieces an edit split, found by searching the pieces it
// reached from the particles it touched, not by labelling the whole body again.
#include <span>
#include <vector>

#include "sim/soft_body.h"

namespace pbdsplat::topology {

// One part of a piece the edit reached.
struct Part {
    uint32_t label = 0;
    // All its particles and sums, except for the rest of a piece that a local search left
    // unexplored (`complete` false: only the label is known; the caller sums what it needs).
    bool complete = true;
    std::vector<uint32_t> particles;
    size_t triangles = 0;
    double six_v = 0.0;       // 6 V of its triangles, caps apart
    double area_bound = 0.0;  // >= its area: (|e1|^2 + |e2|^2) / 4 per triangle, no square root
    // Filled by the volume policy: its boundary loops, their rest bounds, and 6V of their caps.
    std::vector<std::vector<uint32_t>> loops;
    std::vector<Vec4f> loop_bounds;
    double caps_six_v = 0.0;
};

// The exact area of a complete part (a square root per triangle: the caller tries area_bound first).
double part_area(const sim::SoftBody& body, const Part& part);

struct SplitSearch {
    std::vector<std::vector<Part>> parts_of;  // per reached piece, largest first: the first keeps the piece's label
    size_t searched = 0;                      // particles visited
    size_t searched_whole = 0;                // reached pieces the breadth-first search could not settle within the budget (swept whole)
};

// For each piece in `reached` (sorted), searches from its particles among `seeds` (sorted) all at
// once, breadth first, merging searches that meet. When they have all met, the piece did not
// fall apart; when all but one have closed, the closed ones are parts cut off (complete, summed)
// and the open one is the rest, which keeps the label unexplored. Either way the search costs
// the region around the edit, not the piece. Past `budget` particles (two large parts, as a cut
// through the middle makes) it labels the piece's parts by one pass over its triangles in
// memory order instead; the largest part is the rest, unsummed unless `unmeasured` (per reached
// piece: it has no solver measure to take the rest's volume from). Parts cut off get new labels
// (`piece_of_particle`, `pieces`).
// With `side` (per particle before the edit, the side of a cut through the whole body: -1, +1,
// 0 on the cut), a search still open after the first rings around the edit floods one part at a
// time, the one on the side with fewer of the piece's particles: a cut through the middle
// costs the smaller part, not both parts' first halves or the whole piece. A flood that meets
// a search from the other side (the cut did not go through) falls back to the sweep.
SplitSearch split_pieces(sim::SoftBody& body, std::span<const uint32_t> reached, std::span<const uint8_t> unmeasured,
                         std::span<const uint32_t> seeds, size_t budget, std::span<const int8_t> side = {});

} // namespace pbdsplat::topology
