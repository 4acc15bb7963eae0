#pragma once
// The topology stage of a frame: the scene's cuts at their times, tearing while it is on, and
// the user's strokes, each applied to the body as it comes. What follows a change downstream
// of the mesh runs through `Follow` in two parts: `each` right after every change, in the order
// the changes happen (samples carried across the splits: a later tear may split the triangles
// an earlier one touched), and `settle` once after the frame's last change, over every triangle
// the frame's changes touched (the refill, fades, stretch data): three tears in a frame cost
// one refill, not three.
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "render/frame_inputs.h"
#include "scene/event_queue.h"
#include "scene/scene.h"
#include "sim/soft_body.h"
#include "topology/cut.h"
#include "topology/tear.h"
#include "topology/topology_change.h"

namespace pbdsplat::scene {

class TopologyStage {
public:
    struct Follow {
        // Returns triangles to refill beyond the change's touched ones (samples dropped there).
        std::function<core::Result<std::vector<uint32_t>>(const topology::TopologyChange&, const topology::CutSurface*)> each;
        // `touched`: sorted, valid for the mesh as it is now; `seed_offset`: added to the
        // surface's seed for the samples laid down (the count of changes before the frame's first, + 1).
        std::function<core::Status(std::span<const uint32_t> touched, size_t seed_offset)> settle;
    };

    explicit TopologyStage(bool check_invariants);

    // The frame [t, t + dt): the cuts and tears `queue` holds for it, in time order (a user's
    // stroke cuts with the camera of that frame). A failed scripted change stops the stage
    // (status()); a failed stroke is only noted (note), and the run goes on.
    void run(EventQueue& queue, sim::SoftBody& body, float t, float dt, const render::Camera& camera,
             const topology::CutOptions& options, const Follow& follow, std::string& note);

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
    core::Status settle(const Follow& follow);

    std::optional<TearEvent> tearing_;
    topology::CrackFront front_;  // the rims tears made, where they run on
    float tearing_until_ = 0.0f;
    bool check_invariants_ = false;
    core::Status status_;
    size_t cuts_ = 0, tears_ = 0;
    double ms_ = 0.0;
    topology::TopologyChange last_change_;
    std::vector<uint32_t> frame_touched_;  // triangles this frame's changes touched
    size_t frame_seed_offset_ = 0;         // 0: no change yet this frame
};

} // namespace pbdsplat::scene
