#pragma once
// What follows a topology change downstream of the mesh, as passes that read the frame's
// FrameChanges (written by the topology pass, scene/stages/topology_stage.h) and declare what
// they write:
//   "carry samples": the samples (and the model's embedded vertices) moved onto the children of
//     every split triangle, change by change, and after a cut through an embedded surface dropped
//     where they fell on its far side (their triangles join the refill);
//   "refill": the touched and emptied triangles sampled afresh, once after the frame's changes;
//   "follow mapping": the new particles' fade-in, the deformed shapes, the body's openness, the
//     cut faces told of a cut;
//   "stretch data": the stretch-scaled splats' rest data for the new triangles.
// Each runs only where the scene has its data and cuts or tears can come (an absent resource
// culls it), and does nothing in a frame without a change.
#include <cstdint>
#include <optional>

#include "graph/blackboard.h"
#include "graph/frame_graph.h"
#include "scene/stages/topology_stage.h"
#include "surface/boundary_particles.h"

namespace pbdsplat::scene {

namespace keys {
inline constexpr graph::Key<FrameChanges> changes{"topology changes"};
// The model's vertices embedded in the body (made on the first frame a fine surface is drawn):
// absent without a fine surface.
inline constexpr graph::Key<std::optional<surface::BoundaryParticles>> fine_embedding{"fine surface embedding"};
} // namespace keys

struct ChangePassOptions {
    bool boundary = false;      // the scene has boundary particles
    bool fine = false;          // and a fine surface embedded in the body
    bool stretch = false;       // splats scaled by stretch
    bool cut_faces = false;     // cut faces are drawn
    float h = 0.0f;             // the sampling spacing
    uint32_t seed = 0;          // the surface's seed
    uint32_t fade_frames = 0;   // new samples and particles fade in over this many frames
    bool edge_samples = false;  // samples laid along open edges
    uint32_t tag = 0;           // the passes' group (scene/stages/pass_group.h)
};

// Reads keys::changes, keys::cuts (the marker: absent, the passes are culled), the body, samples,
// density control, fine embedding, mapping, map settings, cut faces and stretch from `board` and
// puts back what the passes wrote.
void add_change_passes(graph::FrameGraph& g, graph::Blackboard& board, const ChangePassOptions& o);

} // namespace pbdsplat::scene
