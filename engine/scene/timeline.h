#pragma once
// Plays the timed events onto the body, the drag constraint and the camera, frame by frame:
// pressure ramps, drags, spins, opacity, the camera orbit and path. The events come from the
// run's one queue (event_queue.h) as they fall due.
#include <vector>

#include "scene/event_queue.h"
#include "scene/scene.h"
#include "sim/soft_body.h"

namespace pbdsplat::scene {

class Timeline {
public:
    Timeline(const Scene& scene, const render::Camera& initial_camera);

    // Applies what happens during [t, t + dt): called once per frame before the solver. Takes
    // from `queue` the events of its kinds due in the frame. `opacity`: the splats' sigmoid(o),
    // changed by opacity ramps.
    void advance(EventQueue& queue, float t, float dt, sim::SoftBody& body, sim::DragConstraint& drag, render::Camera& camera,
                 float& opacity);
    // A drag is running or will come.
    bool has_drag(const EventQueue& queue) const;
    // The timeline's kinds: everything but cuts and tears.
    static bool takes(const EventData& d) { return !is_topology_event(d); }

private:
    void start(const Event& e);
    // Whether a pressure ramp, a drag or a spin acts on the body during [t, t + dt).
    bool acts_on_body(float t, float dt) const;
    // One kind of event each, for the frame from t to t + dt.
    void advance_opacity(float t, float dt, float& opacity);
    void advance_pressure(float t, float dt, sim::SoftBody& body);
    void advance_drags(float t, const sim::SoftBody& body, sim::DragConstraint& drag);
    void advance_spins(float t, float dt, sim::SoftBody& body);
    void advance_camera(float t, float dt, render::Camera& camera);
    struct PressureRamp {
        float start, duration, from = -1.0f, to;
        bool finished = false;
    };
    struct ActiveDrag {
        float start;
        DragEvent event;
        bool picked = false;
        sim::DragConstraint grab;  // the region, once picked
    };
    // A pressure ramp: each model's pieces from the pressure that model had when it began.
    struct ModelPressureRamp {
        float start, duration, to;
        std::optional<uint32_t> body;  // the one model it ramps; none: every model
        std::vector<float> from;       // per model, once begun
        bool begun = false;
    };
    std::vector<ModelPressureRamp> pressure_;
    std::vector<PressureRamp> opacity_;  // the same shape: from what it is when the ramp starts
    std::vector<ActiveDrag> drags_;
    std::vector<std::pair<float, SpinEvent>> spins_;
    float orbit_degrees_per_second_ = 0.0f;
    std::vector<CameraKey> path_;
    render::Camera base_camera_;
};

} // namespace pbdsplat::scene
