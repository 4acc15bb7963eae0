#include "scene/scene.h"

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

} // namespace pbdsplat::scene
