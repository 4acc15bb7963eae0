#pragma once
// What a frame-graph pass's time counts towards: the rows of the paper's Tables 3 and 4. Each
// stage module tags its passes with one (graph::FrameGraph::add_pass's tag), so the runtime's
// per-frame figures are summed by group, not guessed from pass names.
#include <cstdint>

#include "sim/schedule.h"

namespace pbdsplat::scene {

enum class PassGroup : uint32_t { other, events, topology, forces, constraints, integrate, update, gpu_record };

inline uint32_t tag(PassGroup g) { return uint32_t(g); }

inline PassGroup pass_group(sim::StageGroup g) {
    switch (g) {
    case sim::StageGroup::apply_forces: return PassGroup::forces;
    case sim::StageGroup::constraints: return PassGroup::constraints;
    case sim::StageGroup::integrate_normals: return PassGroup::integrate;
    }
    return PassGroup::other;
}

} // namespace pbdsplat::scene
