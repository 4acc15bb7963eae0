#pragma once
// Internal to the topology room: the volume constraints after a topology change, one per
// connected component, by the scene's policy (see VolumePolicy in cut.h).
#include <span>
#include <vector>

#include "sim/soft_body.h"
#include "topology/cut.h"
#include "topology/edit.h"

namespace pbdsplat::topology {

// `old_volume_of_triangle[t]`: the constraint (in `old_volumes`) triangle t's material belonged
// to before the change, -1 for none.
// Components whose triangles and boundary loops did not change keep their constraint as it was.
// Under `cap` a piece keeps its parent's ratio of volume to target, so no piece jumps: with a
// planar cut through a closed body the pieces' targets sum to the parent's.
// `leak`: the rate at which a component opened under `burst` loses its overpressure (1/s).
// Only the constraints in `touched` (by old index) are looked at: the others are kept as they
// are (their pieces did not change). Their boundary loops are traced locally from
// `touched_triangles` (the edit's) and from their old loops that the edit reached.
struct VolumeOutcome {
    size_t pieces = 0;              // connected components after
    std::vector<uint32_t> rebuilt;  // constraints (new indices) whose derived rings must be made again
    bool loops_fell_back = false;   // a local trace did not close: loops counted over the pieces
};
VolumeOutcome apply_volume_policy(sim::SoftBody& body, VolumePolicy policy, float leak, std::span<const int32_t> old_volume_of_triangle,
                                  std::span<OldVolume> old_volumes, std::span<const uint8_t> touched,
                                  std::span<const uint32_t> touched_triangles);

} // namespace pbdsplat::topology
