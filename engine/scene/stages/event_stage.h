#pragma once
// The first passes of a frame: "events" (the scene's timeline at this time: pressure, drags,
// spins, opacity, the camera's orbit and path; the user's drag over the script's) and
// "topology" (the scene's cuts and tears, the user's strokes, recorded for the passes that
// follow a change: scene/stages/change_passes.h).
// Both reach their data through the graph's handles.
#include <string>
#include <vector>

#include "graph/blackboard.h"
#include "graph/frame_graph.h"
#include "passes/gpu_passes.h"
#include "scene/stages/topology_stage.h"
#include "scene/event_queue.h"
#include "scene/timeline.h"
#include "sim/drag.h"
#include "splat/mapping.h"

namespace pbdsplat::scene {

// The frame's clock and what the user holds: read by the events pass.
struct FrameControl {
    float time = 0.0f;             // the frame starts here (s)
    bool camera_override = false;  // the user moves the camera: the script does not
    sim::DragConstraint user_drag;
};

namespace keys {
inline constexpr graph::Key<FrameControl> control{"frame control"};
inline constexpr graph::Key<TopologyStage> topology{"topology stage"};
} // namespace keys

struct EventPassOptions {
    float dt = 0.0f;
    bool interactive = false;  // strokes and drags may come at any time: the passes always run
    bool timeline = false;  // the scene has timed events (else the handle is absent)
    bool drags = false;
    topology::CutOptions cut;
    uint32_t tag = 0, topology_tag = 0;  // what the timeline's and the topology pass's times count towards
};

// Reads keys::control, keys::topology, keys::changes and the frame's shared resources from
// `board` (the timeline, the drag and the cut marker may be absent) and puts back what the two
// passes wrote: the queue, timeline, body, drag, appearance, frame view, changes and note.
void add_event_passes(graph::FrameGraph& g, graph::Blackboard& board, const EventPassOptions& o);

} // namespace pbdsplat::scene
