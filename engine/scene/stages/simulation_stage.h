#pragma once
// Stage A in the frame graph: one pass per entry of sim::frame_schedule (the order the solver
// itself runs), each declaring what it reads and reaching the body and its inputs through the
// graph's handles alone. A stage whose input is absent (no volume constraint, no collider, no
// drag) is culled by the graph.
#include <vector>

#include "graph/frame_graph.h"
#include "sim/solver.h"

namespace pbdsplat::scene {

struct SimulationHandles {
    graph::Handle<sim::SoftBody> body;  // written by every pass: the newest version on return
    graph::Handle<std::vector<sim::VolumeConstraint>> volumes;
    graph::Handle<std::vector<sim::ShapeCluster>> shapes;
    graph::Handle<sim::DragConstraint> drag;
    graph::Handle<sim::Colliders> colliders;
};

// `solver` and `settings` must outlive the graph; `dt` is the frame's length.
void add_simulation_passes(graph::FrameGraph& g, SimulationHandles& h, sim::Solver& solver, const sim::SolverSettings& settings,
                           float dt);

} // namespace pbdsplat::scene
