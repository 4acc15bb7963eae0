#include "scene/timeline.h"

#include <algorithm>
#include <limits>

#include "sim/drag.h"

namespace pbdsplat::scene {

Timeline::Timeline(const Scene& scene, const render::Camera& camera)
    : orbit_degrees_per_second_(scene.render.orbit.degrees_per_second), path_(scene.render.path), base_camera_(camera) {}

void Timeline::start(const Event& e) {
    if (auto* p = std::get_if<PressureEvent>(&e.data)) pressure_.push_back({e.time, p->duration, p->value, p->body, {}, false});
    if (auto* o = std::get_if<OpacityEvent>(&e.data)) opacity_.push_back({e.time, o->duration, -1.0f, o->value});
    if (auto* d = std::get_if<DragEvent>(&e.data)) drags_.push_back({e.time, *d, false});
    if (auto* s = std::get_if<SpinEvent>(&e.data)) spins_.push_back({e.time, *s});
}

bool Timeline::has_drag(const EventQueue& queue) const {
    return !drags_.empty() || queue.any([](const EventData& d) { return std::holds_alternative<DragEvent>(d); });
}

void Timeline::advance(EventQueue& queue, float t, float dt, sim::SoftBody& body, sim::DragConstraint& drag, render::Camera& camera,
                       float& opacity) {
    // An event joins its kind's list when it falls due; the lists then behave as if it had
    // been there from the start (each ramp waits for its start time).
    for (const QueuedEvent& q : queue.take_due(t + dt, takes)) start(q.event);
    // What is pushed, pulled or turned must be free to move, and a drag grabs true masses.
    if (acts_on_body(t, dt)) sim::wake_all(body);
    advance_opacity(t, dt, opacity);
    advance_pressure(t, dt, body);
    advance_drags(t, body, drag);
    advance_spins(t, dt, body);
    advance_camera(t, dt, camera);
}

bool Timeline::acts_on_body(float t, float dt) const {
    for (const ModelPressureRamp& r : pressure_)
        if (t >= r.start && t - r.start <= r.duration + dt) return true;
    for (const ActiveDrag& d : drags_)
        if (t >= d.start && t <= d.start + d.event.duration) return true;
    for (const auto& [start, spin] : spins_)
        if (t >= start && t < start + spin.duration) return true;
    return false;
}

void Timeline::advance_opacity(float t, float dt, float& opacity) {
    for (PressureRamp& r : opacity_) {
        if (t < r.start) continue;
        if (r.from < 0.0f) r.from = opacity;
        if (t - r.start > r.duration + dt) {  // over: land on the value once, even if frames skipped it
            if (!r.finished) opacity = r.to;
            r.finished = true;
            continue;
        }
        const float u = r.duration > 0.0f ? std::min(1.0f, (t - r.start) / r.duration) : 1.0f;
        opacity = r.from + (r.to - r.from) * u;
    }
}

void Timeline::advance_pressure(float t, float dt, sim::SoftBody& body) {
    // Each ramp starts each model from whatever its k is when the ramp begins (a sealed piece's,
    // where it has one): a balloon blown up beside another at its own pressure keeps the
    // difference until the ramp ends.
    std::vector<uint32_t> model_of;  // per piece, taken once a frame while a ramp runs
    for (ModelPressureRamp& r : pressure_) {
        if (t < r.start || t - r.start > r.duration + dt || body.volumes.empty()) continue;  // finished: leave k to later events
        if (model_of.empty()) model_of = body.model_of_pieces();
        if (!r.begun) {
            r.from.assign(body.model_count(), -1.0f);
            for (const sim::VolumeConstraint& v : body.volumes) {
                float& from = r.from[std::min<size_t>(model_of[v.piece], r.from.size() - 1)];
                if (from < 0.0f || v.leak == 0.0f) from = v.pressure;
            }
            r.begun = true;
        }
        const float u = r.duration > 0.0f ? std::min(1.0f, (t - r.start) / r.duration) : 1.0f;
        for (sim::VolumeConstraint& v : body.volumes) {
            const size_t m = std::min<size_t>(model_of[v.piece], r.from.size() - 1);
            if (r.body && m != *r.body) continue;
            if (v.leak == 0.0f) v.pressure = r.from[m] + (r.to - r.from[m]) * u;  // an opened piece holds no pressure
        }
    }
}

void Timeline::advance_drags(float t, const sim::SoftBody& body, sim::DragConstraint& drag) {
    // The region about the particle nearest `from` follows a target moving from `from`
    // to `to` (the grab point starts at that particle, wherever `from` is).
    drag.active = false;
    for (ActiveDrag& d : drags_) {
        if (t < d.start || t > d.start + d.event.duration) continue;
        if (!d.picked) {
            float best = std::numeric_limits<float>::max();
            uint32_t nearest = 0;
            for (uint32_t i = 0; i < body.particle_count(); ++i) {
                const float dist = (sim::xyz(body.particles.x[i]) - d.event.from).squaredNorm();
                if (dist < best) best = dist, nearest = i;
            }
            const float radius = d.event.radius > 0.0f ? d.event.radius : sim::default_grab_radius(body);
            d.grab = sim::grab_region(body, nearest, radius, d.event.stiffness);
            d.picked = true;
        }
        const float u = d.event.duration > 0.0f ? (t - d.start) / d.event.duration : 1.0f;
        const Vec3f start = d.grab.target;
        drag = d.grab;
        drag.target = start + (d.event.to - d.event.from) * u;
    }
}

void Timeline::advance_spins(float t, float dt, sim::SoftBody& body) {
    // A rigid turn of what moves about its centre, its velocities turned with it. Pinned
    // particles stay where they are pinned: a static table under the spun models, a pinned rim.
    for (const auto& [start, spin] : spins_) {
        if (t < start || t >= start + spin.duration) continue;
        Vec3f centre = Vec3f::Zero();
        size_t free = 0;
        for (size_t i = 0; i < body.particle_count(); ++i)
            if (body.particles.w[i] > 0.0f) centre += sim::xyz(body.particles.x[i]), ++free;
        if (free == 0) continue;
        centre /= float(free);
        const Mat3f r = Eigen::AngleAxisf(math::radians(spin.degrees_per_second * dt), spin.axis).toRotationMatrix();
        for (size_t i = 0; i < body.particle_count(); ++i) {
            if (!(body.particles.w[i] > 0.0f)) continue;
            body.particles.x[i] = sim::to4(Vec3f(r * (sim::xyz(body.particles.x[i]) - centre) + centre));
            body.particles.v[i] = sim::to4(Vec3f(r * sim::xyz(body.particles.v[i])));
        }
    }
}

void Timeline::advance_camera(float t, float dt, render::Camera& camera) {
    // The path: eye and target between the keys around t + dt, held outside them.
    if (!path_.empty()) {
        const float at = t + dt;
        size_t k = 0;
        while (k + 1 < path_.size() && path_[k + 1].time <= at) ++k;
        const CameraKey& a = path_[k];
        const CameraKey& b = k + 1 < path_.size() ? path_[k + 1] : a;
        const float u = b.time > a.time ? std::clamp((at - a.time) / (b.time - a.time), 0.0f, 1.0f) : 0.0f;
        base_camera_.eye = a.eye + (b.eye - a.eye) * u;
        base_camera_.target = a.target + (b.target - a.target) * u;
        camera.eye = base_camera_.eye;
        camera.target = base_camera_.target;
    }
    // Camera orbit about the target's vertical axis (of the path, when there is one).
    if (orbit_degrees_per_second_ != 0.0f) {
        const Mat3f r = Eigen::AngleAxisf(math::radians(orbit_degrees_per_second_ * (t + dt)), Vec3f::UnitY()).toRotationMatrix();
        camera.eye = base_camera_.target + r * (base_camera_.eye - base_camera_.target);
        camera.target = base_camera_.target;
    }
}

} // namespace pbdsplat::scene
