#pragma once
// The topology stage of a frame: the scene's cuts at their times, tearing while it is on, and
// the user's strokes, each applied to the body as it comes. What follows a change downstream
// of the mesh (samples, fades, stretch data) runs through `Follow` right after that change, in
// the order the changes happen: a later tear may split the triangles an earlier one refilled.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "render/frame_inputs.h"
#include "scene/scene.h"
#include "sim/soft_body.h"
#include "topology/cut.h"
#include "topology/topology_change.h"

namespace pbdsplat::scene {

class TopologyStage {
public:
    // `seed_offset`: added to the surface's seed for the samples this change lays down.
    using Follow = std::function<core::Status(const topology::TopologyChange&, const topology::CutSurface*, size_t seed_offset)>;

    TopologyStage(const Scene& scene, bool check_invariants);

    // A stroke from the window, applied at the next frame (camera of that frame).
    void queue_user_cut(const CutEvent& c) { user_cuts_.push_back(c); }
    // Scripted cuts or tears still to come (or an interactive run's strokes): the pass is kept.
    bool has_scripted_events() const { return !pending_.empty(); }
    std::vector<Event>& pending() { return pending_; }

    // The frame [t, t + dt). A failed scripted change stops the stage (status()); a failed
    // stroke is only noted (note), and the run goes on.
    void run(sim::SoftBody& body, float t, float dt, const render::Camera& camera, const topology::CutOptions& options,
             const Follow& follow, std::string& note);

    const core::Status& status() const { return status_; }
    size_t cuts() const { return cuts_; }
    size_t tears() const { return tears_; }
    double ms() const { return ms_; }  // the last frame's, follow-ups included
    const topology::TopologyChange& last_change() const { return last_change_; }

private:
    core::Status apply_cut(sim::SoftBody& body, const CutEvent& cut, const render::Camera& camera,
                           const topology::CutOptions& options, const Follow& follow);
    core::Status apply_tears(sim::SoftBody& body, const topology::CutOptions& options, const Follow& follow);
    core::Status after(sim::SoftBody& body, const topology::TopologyChange& change, const topology::CutSurface* cut,
                       const Follow& follow);

    std::vector<Event> pending_;  // cuts and tears not yet started, in time order
    std::vector<CutEvent> user_cuts_;
    std::optional<TearEvent> tearing_;
    float tearing_until_ = 0.0f;
    bool check_invariants_ = false;
    core::Status status_;
    size_t cuts_ = 0, tears_ = 0;
    double ms_ = 0.0;
    topology::TopologyChange last_change_;
};

} // namespace pbdsplat::scene
