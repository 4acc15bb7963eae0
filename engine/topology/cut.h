#pragma once
// Line cutting (paper section 5.7): edges crossing the cut surface are split at the crossing
// (eq. 26), crossed triangles are re-triangulated (eq. 27), and the vertices along the cut are
// duplicated per fan of triangles (eq. 28) so the two sides come apart. Distance constraints
// keep their definitions and change only index references; new edges take rest lengths from
// the rest state at the same parameter t; each component gets a volume constraint by policy.
#include "core/names.h"
#include "core/result.h"
#include "sim/soft_body.h"
#include "topology/cut_surface.h"
#include "topology/topology_change.h"

namespace pbdsplat::topology {

// What happens to the volume (overpressure) constraint when a cut opens a component.
enum class VolumePolicy {
    cap,     // virtual caps over the new boundary loops keep a volume defined; the pieces share
             // the original rest volume in proportion to their volumes at the cut
    burst,   // an opened component leaks: its overpressure escapes over a few frames
             // (CutOptions::burst_leak), then its volume constraint rests
    rebase,  // each changed piece takes the volume it has at the cut as its new target
};
inline constexpr core::EnumName<VolumePolicy> k_volume_policy_names[] = {
    {VolumePolicy::cap, "cap"}, {VolumePolicy::burst, "burst"}, {VolumePolicy::rebase, "rebase"}};
inline const char* volume_policy_name(VolumePolicy p) { return core::name_of<VolumePolicy>(k_volume_policy_names, p); }

struct CutOptions {
    // Crossings closer than snap * edge length to an end snap to that vertex: no slivers.
    float snap = 0.1f;
    // The length `snap` is also taken of (a crossing nearer a vertex than snap * this, in the
    // rest state, snaps too). Give the original mesh's mean edge length, so repeated cuts in
    // one region cannot whittle triangles down; 0 takes the current mean.
    float reference_edge_length = 0.0f;
    // A snap that would cut off fewer triangles than this (a fleck) is undone where the cut's
    // children stay above a sliver; 0 allows any. Whole-body cuts only (tears have their own).
    uint32_t min_fragment_triangles = 8;
    VolumePolicy volume = VolumePolicy::cap;
    float burst_leak = 4.0f;  // 1/s: how fast a burst component's overpressure escapes
};

// Cuts `body` along `surface` (current positions). Particles that move keep their state; new
// particles copy position, previous position and velocity; the total mass is kept. When the
// surface crosses no edge the body is left as it is and the change says so.
core::Result<TopologyChange> cut(sim::SoftBody& body, const CutSurface& surface, const CutOptions& options = {});

} // namespace pbdsplat::topology
