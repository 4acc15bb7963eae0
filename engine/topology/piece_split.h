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
    std::vector<uint32_t> particles;
    size_t triangles = 0;
    double six_v = 0.0;       // 6 V of its triangles, caps apart
    double area_bound = 0.0;  // >= its area: (|e1|^2 + |e2|^2) / 4 per triangle, no square root
    std::vector<std::vector<uint32_t>> loops;  // filled by the volume policy
};

struct SplitSearch {
    std::vector<std::vector<Part>> parts_of;  // per reached piece, largest first: the first keeps the piece's label
    size_t searched = 0;                      // particles visited
};

// For each piece in `reached` (sorted), grows its parts along the rings from its particles among
// `seeds` (sorted), summing each part's triangles on the way; the parts after the first get new
// labels (`piece_of_particle`, `pieces`). Costs the reached pieces' size: the volumes of the
// parts need every triangle of them, so a search that stopped once its fronts met would still
// leave a whole pass to do.
SplitSearch split_pieces(sim::SoftBody& body, std::span<const uint32_t> reached, std::span<const uint32_t> seeds);

} // namespace pbdsplat::topology
