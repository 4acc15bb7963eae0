#pragma once
// The order of a simulation frame, as data: the one place that says it. A substep is forces,
// the search for contacts, I x [distance, volume, shape, drag, collide, contact], velocities; a
// frame is S substeps, then normals, then the pieces at rest put to sleep (the paper's section 5.2, with contact between moving
// surfaces added; without it, the contact stages are not scheduled). Solver::step runs it and the scene's frame graph makes one pass per
// entry, so the two cannot drift apart.
#include <cstdint>
#include <vector>

namespace pbdsplat::sim {

struct SolverSettings;

enum class Stage : uint8_t { forces, find_contacts, distance, volume, shape, drag, collide, contact, velocities, normals, sleep };
const char* stage_name(Stage s);

// The rows of the paper's Tables 3 and 4 that a stage's time counts towards.
enum class StageGroup : uint8_t { apply_forces, constraints, integrate_normals };
StageGroup stage_group(Stage s);

struct ScheduledStage {
    Stage stage;
    uint32_t substep = 0;
    uint32_t iteration = 0;  // the constraint stages' iteration within their substep
};

std::vector<ScheduledStage> frame_schedule(const SolverSettings& s);

} // namespace pbdsplat::sim
