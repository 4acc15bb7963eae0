#include "scene/stages/event_stage.h"

#include "scene/stages/body_parts.h"
#include "scene/stages/change_passes.h"
#include "scene/stages/frame_keys.h"

namespace pbdsplat::scene {

namespace {

struct EventHandles {
    graph::Handle<FrameControl> control;
    graph::Handle<Timeline> timeline;              // absent when the scene has no timed events
    graph::Handle<EventQueue> queue;               // the run's one queue: each pass takes its kinds
    graph::Handle<EventQueue> cuts;                // the queue as a marker: absent when no cut or tear can come
    graph::Handle<TopologyStage> topology;
    graph::Handle<FrameChanges> changes;           // what the topology pass changed, for the passes after it
    BodyParts body;
    graph::Handle<sim::DragConstraint> drag;       // absent when nothing drags
    graph::Handle<splat::Appearance> appearance;   // the timeline fades the opacity
    graph::Handle<render::FrameInputs> view;       // the camera
    graph::Handle<std::string> note;               // what the user's last stroke did
};

// The timeline ramps pressures (the structure's volumes) and spins the body (its state); a cut
// or tear changes every part.
constexpr BodyWrites k_timeline_writes{true, true, false};
constexpr BodyWrites k_topology_writes{true, true, true};

void add_timeline_pass(graph::FrameGraph& g, EventHandles& h, const EventPassOptions& o) {
    g.add_pass("events", graph::PassKind::cpu, [&](graph::PassBuilder& b) {
        // An interactive run keeps the pass for the user's drag, with or without a timeline; a
        // script without one has nothing to do (the absent timeline culls it).
        if (!o.interactive || o.timeline) h.timeline = b.write(h.timeline);
        b.read(h.control);
        h.queue = b.write(h.queue);
        h.body.declare(b, k_timeline_writes);
        if (o.drags) h.drag = b.write(h.drag);
        h.appearance = b.write(h.appearance);
        h.view = b.write(h.view);
        const bool has_timeline = o.timeline;
        return [o, has_timeline, hh = h](const graph::PassResources& r, graph::ExecuteContext&) {
            const FrameControl& control = r.read(hh.control);
            render::FrameInputs& view = r.write(hh.view);
            splat::Appearance& look = r.write(hh.appearance);
            sim::DragConstraint no_drag;
            sim::DragConstraint& drag = o.drags ? r.write(hh.drag) : no_drag;
            // A camera the user took over is not the script's to move: it moves a copy.
            render::Camera scripted = view.camera;
            float opacity = math::sigmoid(look.opacity_logit);
            const float before = opacity;
            if (has_timeline)
                r.write(hh.timeline).advance(r.write(hh.queue), control.time, o.dt, hh.body.body(r, k_timeline_writes), drag,
                                             control.camera_override ? scripted : view.camera, opacity);
            if (opacity != before) look.opacity_logit = math::logit(opacity);
            if (control.user_drag.active) {
                drag = control.user_drag;  // the hand wins over the script
                sim::wake_all(hh.body.body(r, k_timeline_writes));
            }
        };
    }, o.tag);
}

void add_topology_pass(graph::FrameGraph& g, EventHandles& h, const EventPassOptions& o) {
    g.add_pass("topology", graph::PassKind::cpu, [&](graph::PassBuilder& b) {
        b.read(h.cuts);
        h.queue = b.write(h.queue);
        b.read(h.control);
        b.read(h.view);
        h.topology = b.write(h.topology);
        h.changes = b.write(h.changes);
        h.body.declare(b, k_topology_writes);
        h.note = b.write(h.note);
        return [o, hh = h](const graph::PassResources& r, graph::ExecuteContext&) {
            r.write(hh.topology).run(r.write(hh.queue), hh.body.body(r, k_topology_writes), r.read(hh.control).time, o.dt, r.read(hh.view).camera, o.cut,
                                     r.write(hh.changes), r.write(hh.note));
        };
    }, o.topology_tag);
}

} // namespace

void add_event_passes(graph::FrameGraph& g, graph::Blackboard& board, const EventPassOptions& o) {
    EventHandles h{board.get(keys::control),    board.get(keys::timeline), board.get(keys::queue), board.get(keys::cuts),
                   board.get(keys::topology),   board.get(keys::changes),  BodyParts::from(board),  board.get(keys::drag),
                   board.get(keys::appearance), board.get(keys::view),     board.get(keys::note)};
    add_timeline_pass(g, h, o);
    add_topology_pass(g, h, o);
    board.put(keys::queue, h.queue);
    board.put(keys::timeline, h.timeline);
    h.body.put(board);
    board.put(keys::drag, h.drag);
    board.put(keys::appearance, h.appearance);
    board.put(keys::view, h.view);
    board.put(keys::changes, h.changes);
    board.put(keys::note, h.note);
}

} // namespace pbdsplat::scene
