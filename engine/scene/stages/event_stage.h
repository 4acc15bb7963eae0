#pragma once
// The first passes of a frame: "events" (the scene's timeline at this time: pressure, drags,
// spins, opacity, the camera's orbit and path; the user's drag over the script's) and
// "topology" (the scene's cuts and tears, the user's strokes, and what follows each change).
// Both reach their data through the graph's handles.
#include <string>
#include <vector>

#include "graph/frame_graph.h"
#include "passes/gpu_passes.h"
#include "scene/stages/change_follow.h"
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

struct EventHandles {
    graph::Handle<FrameControl> control;
    graph::Handle<Timeline> timeline;              // absent when the scene has no timed events
    graph::Handle<EventQueue> queue;               // the run's one queue: each pass takes its kinds
    graph::Handle<EventQueue> cuts;                // the queue as a marker: absent when no cut or tear can come
    graph::Handle<TopologyStage> topology;
    graph::Handle<ChangeFollowers> followers;
    graph::Handle<sim::SoftBody> body;
    graph::Handle<sim::DragConstraint> drag;       // absent when nothing drags
    graph::Handle<splat::Appearance> appearance;   // the timeline fades the opacity
    graph::Handle<passes::GpuFrameInput> input;    // the camera
    graph::Handle<surface::BoundaryParticles> samples;
    graph::Handle<surface::DensityControl> density;
    graph::Handle<splat::StretchScale> stretch;
    graph::Handle<std::string> note;               // what the user's last stroke did
};

struct EventPassOptions {
    float dt = 0.0f;
    bool interactive = false;  // strokes and drags may come at any time: the passes always run
    bool timeline = false;  // the scene has timed events (else the handle is absent)
    bool drags = false, boundary = false, stretch = false;
    topology::CutOptions cut;
    uint32_t tag = 0, topology_tag = 0;  // what the timeline's and the topology pass's times count towards
};

void add_event_passes(graph::FrameGraph& g, EventHandles& h, const EventPassOptions& o);

} // namespace pbdsplat::scene
