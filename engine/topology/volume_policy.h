#pragma once
// Internal to the topology room: the volume constraints after a topology change, one per
// connected component, by the scene's policy (see VolumePolicy in cut.h).
#include <span>
#include <vector>

#include "sim/soft_body.h"
#include "topology/cut.h"
#include "topology/edit.h"

namespace pbdsplat::topology {

// Every piece the edit reached (through `touched_triangles`) is searched along the body's rings
// from the touched particles (topology/piece_split.h); where it fell apart, the largest part
// keeps its label and the others get new ones (`SoftBody::piece_of_particle`). The pieces the
// edit did not reach keep their labels and their volume constraints as they were.
// A reached piece's volume constraint is remade for each part by the policy: under `cap` a part
// keeps its parent's ratio of volume to target, so no piece jumps (with a planar cut through a
// closed body the parts' targets sum to the parent's); a part that did not change keeps its
// target. `leak`: the rate at which a part opened under `burst` loses its overpressure (1/s).
// The rest of a piece (the part that keeps its label) keeps its constraint, updated in place:
// its loops away from the edit stay where they are (settled by their rest bounds, unread), the
// loops the edit reached are traced again locally from `touched_triangles`, and its caps' volume
// follows the solver's last measure. The parts cut off get new constraints.
struct VolumeOutcome {
    size_t pieces = 0;              // connected components after
    size_t particles_searched = 0;  // by the search for the parts of the reached pieces
    size_t searched_whole = 0;      // reached pieces the local search could not settle
    size_t summed_whole = 0;        // unexplored rests whose volume took a pass over the body's triangles (no measure)
    bool loops_fell_back = false;   // a local trace did not close: loops counted over the parts
};
// `first_new_triangle`: the triangle count before the edit (triangles from there on are new).
// `side`: optional, per particle before the edit, the side of a cut through the whole body it
// was on (-1, +1, 0 on the cut): see split_pieces.
VolumeOutcome apply_volume_policy(sim::SoftBody& body, VolumePolicy policy, float leak, std::span<const uint32_t> touched_triangles,
                                  size_t first_new_triangle, std::span<const int8_t> side = {});

} // namespace pbdsplat::topology
