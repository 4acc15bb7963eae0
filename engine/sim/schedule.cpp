#include "sim/schedule.h"

#include "sim/solver.h"

namespace pbdsplat::sim {

const char* stage_name(Stage s) {
    switch (s) {
    case Stage::forces: return "forces";
    case Stage::distance: return "distance";
    case Stage::volume: return "volume";
    case Stage::shape: return "shape";
    case Stage::drag: return "drag";
    case Stage::collide: return "collide";
    case Stage::find_contacts: return "contacts";
    case Stage::contact: return "contact";
    case Stage::velocities: return "velocities";
    case Stage::normals: return "normals";
    case Stage::sleep: return "sleep";
    }
    return "?";
}

StageGroup stage_group(Stage s) {
    switch (s) {
    case Stage::forces: return StageGroup::apply_forces;
    case Stage::find_contacts: return StageGroup::constraints;
    case Stage::velocities:
    case Stage::normals:
    case Stage::sleep: return StageGroup::integrate_normals;
    default: return StageGroup::constraints;
    }
}

std::vector<ScheduledStage> frame_schedule(const SolverSettings& s) {
    constexpr Stage k_constraints[] = {Stage::distance, Stage::volume, Stage::shape, Stage::drag, Stage::collide, Stage::contact};
    const bool contact = s.contact.enabled;
    std::vector<ScheduledStage> out;
    out.reserve(size_t(s.substeps) * (3 + s.iterations * std::size(k_constraints)) + 2);
    for (uint32_t sub = 0; sub < s.substeps; ++sub) {
        out.push_back({Stage::forces, sub, 0});
        if (contact) out.push_back({Stage::find_contacts, sub, 0});
        for (uint32_t it = 0; it < s.iterations; ++it)
            for (Stage c : k_constraints)
                if (c != Stage::contact || contact) out.push_back({c, sub, it});
        out.push_back({Stage::velocities, sub, 0});
    }
    out.push_back({Stage::normals, 0, 0});
    if (s.sleep.enabled) out.push_back({Stage::sleep, 0, 0});
    return out;
}

} // namespace pbdsplat::sim
