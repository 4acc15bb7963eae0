#include "scene/stages/simulation_stage.h"

#include <string>

#include "scene/stages/body_parts.h"
#include "scene/stages/frame_keys.h"
#include "scene/stages/pass_group.h"

namespace pbdsplat::scene {

namespace {
struct SimulationHandles {
    BodyParts body;  // the state written by every pass, the caches by the normals
    graph::Handle<std::vector<sim::VolumeConstraint>> volumes;
    graph::Handle<std::vector<sim::ShapeCluster>> shapes;
    graph::Handle<sim::DragConstraint> drag;
    graph::Handle<sim::Colliders> colliders;
};
} // namespace

void add_simulation_passes(graph::FrameGraph& g, graph::Blackboard& board, sim::Solver& solver, const sim::SolverSettings& settings,
                           float dt) {
    SimulationHandles h{BodyParts::from(board), board.get(keys::volumes), board.get(keys::shapes), board.get(keys::drag),
                        board.get(keys::colliders)};
    const float substep = dt / float(settings.substeps);
    for (const sim::ScheduledStage& entry : sim::frame_schedule(settings)) {
        const sim::Stage stage = entry.stage;
        // Names as the graph has always printed them: distance[1].3 is substep 1's fourth
        // iteration (the substep index only when there are several).
        std::string name = sim::stage_name(stage);
        if (settings.substeps > 1 && stage != sim::Stage::normals) name += "[" + std::to_string(entry.substep) + "]";
        if (sim::stage_group(stage) == sim::StageGroup::constraints) name += "." + std::to_string(entry.iteration);
        g.add_pass(
            name, graph::PassKind::cpu,
            [&](graph::PassBuilder& b) {
                // Only what the stage reads is declared: an absent one culls the pass.
                if (stage == sim::Stage::volume) b.read(h.volumes);
                if (stage == sim::Stage::shape) b.read(h.shapes);
                if (stage == sim::Stage::drag) b.read(h.drag);
                if (stage == sim::Stage::collide) b.read(h.colliders);
                // Every stage moves the state; the first of a substep also lets the gas out of
                // the volume constraints that leak (their pressure, part of the structure), and
                // the last of a frame makes the normals (the caches).
                const BodyWrites writes{stage == sim::Stage::forces && settings.volume, true, stage == sim::Stage::normals};
                h.body.declare(b, writes);
                return [&solver, &settings, stage, substep, writes, handles = h](const graph::PassResources& r, graph::ExecuteContext&) {
                    static const sim::Colliders k_no_colliders;
                    static const sim::DragConstraint k_no_drag;
                    const sim::Colliders& colliders = stage == sim::Stage::collide ? r.read(handles.colliders) : k_no_colliders;
                    const sim::DragConstraint& drag = stage == sim::Stage::drag ? r.read(handles.drag) : k_no_drag;
                    solver.run(stage, handles.body.body(r, writes), settings, substep, colliders, drag);
                };
            },
            tag(pass_group(sim::stage_group(stage))));
    }
    h.body.put(board);
}

} // namespace pbdsplat::scene
