#pragma once
// Plays a scene's timed events onto the body, the drag constraint and the camera, frame by
// frame: pressure ramps, drags, spins, the camera orbit.
#include <vector>

#include "scene/scene.h"
#include "sim/soft_body.h"

namespace pbdsplat::scene {

class Timeline {
public:
    Timeline(const Scene& scene, const render::Camera& initial_camera);

    // Applies what happens during [t, t + dt): called once per frame before the solver.
    // `opacity`: the splats' sigmoid(o), changed by opacity ramps.
    void advance(float t, float dt, sim::SoftBody& body, sim::DragConstraint& drag, render::Camera& camera, float& opacity);
    bool has_drag() const;

private:
    struct PressureRamp {
        float start, duration, from = -1.0f, to;
        bool finished = false;
    };
    struct ActiveDrag {
        float start;
        DragEvent event;
        bool picked = false;
    };
    std::vector<PressureRamp> pressure_;
    std::vector<PressureRamp> opacity_;  // the same shape: from what it is when the ramp starts
    std::vector<ActiveDrag> drags_;
    std::vector<std::pair<float, SpinEvent>> spins_;
    float orbit_degrees_per_second_ = 0.0f;
    std::vector<CameraKey> path_;
    render::Camera base_camera_;
};

} // namespace pbdsplat::scene
