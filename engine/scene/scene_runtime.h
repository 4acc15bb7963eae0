#pragma once
// A scene brought to life: its body, solver, timeline and one frame graph holding every stage
// of a frame, from the timeline to the image. The graph is compiled once, for the scene's
// configuration: a stage the scene does not need is culled, not skipped by an `if`.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/thread_pool.h"
#include "graph/frame_graph.h"
#include "scene/gpu_passes.h"
#include "scene/scene.h"
#include "scene/timeline.h"
#include "sim/solver.h"
#include "splat/fade_in.h"
#include "splat/mapping.h"
#include "splat/sort.h"
#include "surface/boundary_particles.h"
#include "topology/topology_change.h"

namespace pbdsplat::scene {

struct RuntimeOptions {
    gpu::Context* gpu = nullptr;  // null: simulation only (no upload, splat or readback)
    bool readback = true;         // read each frame's image back (offscreen); false when presenting
    bool keep_records = false;    // map to Gaussians even without a renderer (export, metrics)
    unsigned threads = 1;
    std::optional<gpu::UploadPath> upload_path;
    uint32_t frames_in_flight = 2;
    // Check every mesh invariant after each topology change (always on in debug builds).
    bool check_topology = false;
    std::optional<render::SplatPath> splat_path;  // overrides the scene's
    std::optional<render::SplatOrder> sort_on;    // overrides the scene's (and the device's choice)
};

// Per-frame figures, grouped as the paper's Tables 3 and 4.
struct FrameStats {
    uint64_t frame = 0;
    float time = 0.0f;  // simulated seconds at the end of the frame
    size_t particles = 0, boundary_particles = 0, gaussians = 0;
    size_t cuts = 0;   // cut events applied so far
    size_t tears = 0;  // edges torn so far
    double topology_ms = 0.0;  // this frame's cuts and tears, with the boundary particles' refill
    double events_ms = 0.0, apply_forces_ms = 0.0, constraints_ms = 0.0, integrate_normals_ms = 0.0,
           update_particles_ms = 0.0, gpu_record_ms = 0.0, graph_ms = 0.0;
    uint64_t uploaded_bytes = 0;  // of the newest finished GPU frame
    // GPU time of the newest finished frame, per pass, from timestamps (0 where the device has
    // none or the pass did not run): the paper's "GPU Scene" row, broken down.
    double gpu_upload_ms = 0.0, gpu_sort_ms = 0.0, gpu_draw_ms = 0.0;
    double gpu_scene_ms() const { return gpu_upload_ms + gpu_sort_ms + gpu_draw_ms; }
};

class SceneRuntime {
public:
    static core::Result<std::unique_ptr<SceneRuntime>> create(const Scene& scene, const RuntimeOptions& options);
    ~SceneRuntime();

    // Runs one frame through the graph (and submits its GPU work).
    core::Status step();
    // Waits for the GPU; the newest frame's image (offscreen with readback only).
    core::Result<core::ImageRgba8> finish();

    const graph::FrameGraph& graph() const { return graph_; }
    const FrameStats& stats() const { return stats_; }
    const sim::SoftBody& body() const { return body_; }
    const surface::BoundaryParticles& boundary_particles() const { return boundary_; }
    const std::vector<splat::GaussianRecord>& records() const { return records_; }
    float spacing() const { return h_; }
    const Scene& scene() const { return scene_; }
    // What the most recent cut or tear did (empty before any).
    const topology::TopologyChange& last_topology_change() const { return last_change_; }

private:
    SceneRuntime() = default;
    core::Status build(const RuntimeOptions& options);

    Scene scene_;
    sim::SoftBody body_;
    std::unique_ptr<core::ThreadPool> pool_;
    std::unique_ptr<sim::Solver> solver_;
    std::unique_ptr<Timeline> timeline_;
    sim::DragConstraint drag_;
    splat::Appearance appearance_;
    surface::BoundaryParticles boundary_;
    splat::StretchScale stretch_;
    splat::SortScratch sort_scratch_;
    std::vector<splat::GaussianRecord> records_;
    std::vector<splat::GaussianRecord> previous_records_;  // what the GPU holds: for changed ranges
    std::unique_ptr<render::SplatRenderer> renderer_;
    GpuPassResources gpu_resources_;
    GpuFrameInput frame_input_;
    ImageSink sink_;
    graph::FrameGraph graph_;
    std::vector<int> group_of_kept_pass_;  // the Table 3 group of each kept pass, in execution order
    void publish_records();                // hands records_ to the GPU passes with what changed
    FrameStats stats_;
    float time_ = 0.0f;
    float h_ = 0.0f;  // sampling spacing
    // Cut and tear events not yet started, in time order; the tearing now on, if any.
    std::vector<Event> pending_topology_;
    std::optional<TearEvent> tearing_;
    float tearing_until_ = 0.0f;
    core::Status apply_cut(const CutEvent& cut);
    core::Status apply_tears();
    // Everything downstream of the mesh follows a change: samples, fades, stretch, invariants.
    core::Status after_topology_change(const topology::TopologyChange& change);
    core::Status topology_status_;
    splat::FadeIn fade_;
    bool check_topology_ = false;
    size_t cuts_ = 0, tears_ = 0;
    double topology_ms_ = 0.0;
    topology::TopologyChange last_change_;
    uint64_t frame_ = 0;
};

// The byte ranges of `after` that differ from `before` (all of it when the counts differ), so
// only what changed is uploaded; a single empty range when nothing did.
void changed_ranges(std::span<const splat::GaussianRecord> before, std::span<const splat::GaussianRecord> after,
                    std::vector<gpu::ByteRange>& out);

// Loads the mesh of a scene (next to the scene file first), applies the transform, builds the
// body with its pins. Shared by the runtime and the tools that only simulate.
core::Result<sim::SoftBody> make_scene_body(const Scene& scene);

} // namespace pbdsplat::scene
