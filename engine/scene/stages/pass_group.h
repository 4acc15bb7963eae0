#pragma once
// What a frame-graph pass's time counts towards: the rows of the paper's Tables 3 and 4. Each
// stage module tags its passes with one (graph::FrameGraph::add_pass's tag), so the runtime's
// per-frame figures are summed by group, not guessed from pass names. The table below is the
// one place the groups are named: FrameStats, the bench tables and JSON, the render CSV and the
// demo's overlay are all made from it.
#include <array>
#include <cstddef>
#include <cstdint>

#include "sim/schedule.h"

namespace pbdsplat::scene {

// `other` (0) is what a pass gets when its module gives no tag: its time counts nowhere.
enum class PassGroup : uint32_t { other, events, topology, forces, constraints, integrate, update, gpu_record };
inline constexpr size_t k_timed_groups = size_t(PassGroup::gpu_record);  // every group but `other`

inline uint32_t tag(PassGroup g) { return uint32_t(g); }

struct PassGroupNames {
    PassGroup group;
    const char* key;    // JSON (bench scene's stages_median_ms; with "_ms" its before/after split)
    const char* csv;    // the render CSV's column
    const char* label;  // tables
    const char* brief;  // the demo's overlay
    bool stage_a;       // one of the simulation's own stages (the paper's Table 3 rows)
};

inline constexpr std::array<PassGroupNames, k_timed_groups> k_pass_groups = {{
    {PassGroup::events, "events", "events_ms", "events", "events", false},
    {PassGroup::topology, "topology", "topology_ms", "topology (cuts, tears)", "topology", false},
    {PassGroup::forces, "apply_forces", "apply_forces_ms", "apply forces", "forces", true},
    {PassGroup::constraints, "constraint_projection", "constraints_ms", "constraint projection", "constraints", true},
    {PassGroup::integrate, "integrate_normals", "integrate_normals_ms", "integrate + normals", "integrate", true},
    {PassGroup::update, "update_particles", "update_particles_ms", "update particles", "update", false},
    {PassGroup::gpu_record, "gpu_record", "gpu_record_ms", "GPU recording", "record", false},
}};
// In the enum's order, so GroupTimes::ms can be walked beside the table.
static_assert([] {
    for (size_t i = 0; i < k_pass_groups.size(); ++i)
        if (k_pass_groups[i].group != PassGroup(i + 1)) return false;
    return true;
}());

// Milliseconds of one frame per timed group (indexed by any group but `other`).
struct GroupTimes {
    std::array<double, k_timed_groups> ms{};
    double& operator[](PassGroup g) { return ms[slot(g)]; }
    double operator[](PassGroup g) const { return ms[slot(g)]; }
    static size_t slot(PassGroup g) { return size_t(g) - 1; }
    double cpu_total() const {
        double t = 0.0;
        for (double v : ms) t += v;
        return t;
    }
    // Stage A: the simulation's own stages, without events, topology and the splats' update.
    double stage_a() const {
        double t = 0.0;
        for (const auto& n : k_pass_groups) t += n.stage_a ? (*this)[n.group] : 0.0;
        return t;
    }
};

// The key of a pass's tag ("other" for an untagged pass or a tag that is no group).
inline const char* group_key(uint32_t tag) {
    for (const auto& n : k_pass_groups)
        if (tag == uint32_t(n.group)) return n.key;
    return "other";
}

inline PassGroup pass_group(sim::StageGroup g) {
    switch (g) {
    case sim::StageGroup::apply_forces: return PassGroup::forces;
    case sim::StageGroup::constraints: return PassGroup::constraints;
    case sim::StageGroup::integrate_normals: return PassGroup::integrate;
    }
    return PassGroup::other;
}

} // namespace pbdsplat::scene
