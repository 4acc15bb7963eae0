#pragma once
// The topology stage of a frame: the scene's cuts at their times, tearing while it is on, and
// the user's strokes, each applied to the body as it comes. It hands on what changed as
// FrameChanges, a resource of the frame graph: what follows a change downstream of the mesh
// (samples carried and refilled, the mapping, the stretch data) is passes that read it
// (scene/stages/change_passes.h), declared like any other.
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

// One frame's topology changes, in the order they happened. A change's split list maps the
// triangles of the mesh before it onto the one after it, so the passes that follow replay the
// list in order (a later tear may split the triangles an earlier one touched); whatever is
// resampled is resampled once, after the last change: three tears in a frame cost one refill.
struct FrameChanges {
    struct Change {
        topology::TopologyChange change;
        std::optional<topology::CutSurface> cut;  // a cut's surface; none for a tear
    };
    std::vector<Change> changes;
    // Triangles to resample after the last change (indices of the mesh as it is now; unsorted,
    // repeats allowed): every change's touched ones, and those the samples' carry emptied.
    std::vector<uint32_t> refill;
    // Added to the surface's seed for the samples laid down: the count of changes before the
    // frame's first, + 1.
    size_t seed_offset = 0;

    bool empty() const { return changes.empty(); }
    void clear() {
        changes.clear();
        refill.clear();
        seed_offset = 0;
    }
};

class TopologyStage {
public:
    explicit TopologyStage(bool check_invariants);

    // The frame [t, t + dt): the cuts and tears `queue` holds for it, in time order (a user's
    // stroke cuts with the camera of that frame), recorded in `changes` (cleared first). A
    // failed scripted change stops the stage (status()); a failed stroke is only noted (note),
    // and the run goes on.
    void run(EventQueue& queue, sim::SoftBody& body, float t, float dt, const render::Camera& camera,
             const topology::CutOptions& options, FrameChanges& changes, std::string& note);

    const core::Status& status() const { return status_; }
    size_t cuts() const { return cuts_; }
    size_t tears() const { return tears_; }
    const topology::TopologyChange& last_change() const { return last_change_; }

private:
    core::Status apply_cut(sim::SoftBody& body, const CutEvent& cut, const render::Camera& camera,
                           const topology::CutOptions& options, FrameChanges& changes);
    core::Status apply_tears(sim::SoftBody& body, const topology::CutOptions& options, FrameChanges& changes);
    core::Status after(sim::SoftBody& body, const topology::TopologyChange& change, const topology::CutSurface* cut,
                       FrameChanges& changes);

    std::optional<TearEvent> tearing_;
    topology::CrackFront front_;  // the rims tears made, where they run on
    float tearing_until_ = 0.0f;
    float gauge_ = 0.0f;  // tears measure stretch over at least this (the body's mean rest edge when tearing began)
    bool check_invariants_ = false;
    core::Status status_;
    size_t cuts_ = 0, tears_ = 0;
    topology::TopologyChange last_change_;
};

} // namespace pbdsplat::scene
