#include "scene/scene.h"

#include <algorithm>

namespace pbdsplat::scene {

bool Scene::has_topology_events() const {
    for (const Event& e : events)
        if (std::holds_alternative<CutEvent>(e.data) || std::holds_alternative<TearEvent>(e.data)) return true;
    return false;
}

const char* splat_shape_name(SplatShape s) {
    switch (s) {
    case SplatShape::round: return "round";
    case SplatShape::surfel: return "surfel";
    case SplatShape::deformed: return "deformed";
    }
    return "?";
}

const char* event_type_name(const EventData& e) {
    struct Visitor {
        const char* operator()(const PressureEvent&) const { return "pressure"; }
        const char* operator()(const DragEvent&) const { return "drag"; }
        const char* operator()(const SpinEvent&) const { return "spin"; }
        const char* operator()(const CutEvent&) const { return "cut"; }
        const char* operator()(const TearEvent&) const { return "tear"; }
        const char* operator()(const OpacityEvent&) const { return "opacity"; }
    };
    return std::visit(Visitor{}, e);
}

const OwnSettings& own_settings(const Scene& scene, size_t m) { return m == 0 ? scene.model_own : scene.bodies[m - 1].own; }

float shape_stiffness_of(const Scene& scene, size_t m) {
    return own_settings(scene, m).shape_stiffness.value_or(scene.simulation.solver.shape_stiffness);
}

float pressure_of(const Scene& scene, size_t m) { return own_settings(scene, m).pressure.value_or(scene.simulation.pressure); }

float stiffest_shape(const Scene& scene) {
    float most = 0.0f;
    for (size_t m = 0; m <= scene.bodies.size(); ++m) most = std::max(most, shape_stiffness_of(scene, m));
    return most;
}

} // namespace pbdsplat::scene
