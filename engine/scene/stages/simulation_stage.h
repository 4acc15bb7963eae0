#pragma once
// Stage A in the frame graph: one pass per entry of sim::frame_schedule (the order the solver
// itself runs), each declaring what it reads and reaching the body and its inputs through the
// graph's handles alone. A stage whose input is absent (no volume constraint, no collider, no
// drag) is culled by the graph.
#include <vector>

#include "graph/blackboard.h"
#include "graph/frame_graph.h"
#include "sim/solver.h"

namespace pbdsplat::scene {

// Reads the body, volume constraints, shape clusters, drag and colliders from `board`
// (scene/stages/frame_keys.h) and puts back the body's newest version. `solver` and `settings`
// must outlive the graph; `dt` is the frame's length.
void add_simulation_passes(graph::FrameGraph& g, graph::Blackboard& board, sim::Solver& solver, const sim::SolverSettings& settings,
                           float dt);

} // namespace pbdsplat::scene
