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
#include "passes/gpu_passes.h"
#include "scene/scene.h"
#include "scene/stages/event_stage.h"
#include "scene/stages/fine_surface.h"
#include "scene/stages/pass_group.h"
#include "scene/stages/mapping_stage.h"
#include "scene/stages/surface_stage.h"
#include "scene/stages/topology_stage.h"
#include "scene/scene_model.h"
#include "scene/event_queue.h"
#include "scene/timeline.h"
#include "sim/solver.h"
#include "splat/fade_in.h"
#include "splat/deformed_shape.h"
#include "splat/mapping.h"
#include "render/mesh_raster.h"
#include "splat/sort.h"
#include "scene/stages/paint.h"
#include "scene/stages/solid_pieces.h"
#include "scene/stages/stillness.h"
#include "surface/boundary_particles.h"
#include "surface/density.h"
#include "surface/embedding.h"
#include "topology/topology_change.h"

namespace pbdsplat::scene {

using sim::k_max_sweeps;
// Splats beyond which loading says where they are (a few per pixel of a 1280x720 frame).
inline constexpr size_t k_many_samples = 250000;

struct RuntimeOptions {
    gpu::Context* gpu = nullptr;  // null: simulation only (no upload, splat or readback)
    bool readback = true;         // read each frame's image back (offscreen); false when presenting
    bool keep_records = false;    // map to Gaussians even without a renderer (export, metrics)
    unsigned threads = 1;
    std::optional<gpu::UploadPath> upload_path;
    uint32_t frames_in_flight = 2;
    // Check every mesh invariant after each topology change (always on in debug builds), where
    // the body as loaded keeps them (invariants_at_load()).
    bool check_topology = false;
    std::optional<render::SplatPath> splat_path;  // overrides the scene's
    std::optional<render::SplatOrder> sort_on;    // overrides the scene's (and the device's choice)
    // Interaction between steps (drags, cuts): keeps the drag and topology stages in the graph
    // even when the scene scripts none.
    bool interactive = false;
    // Fingerprint the shared CPU resources around every pass and note each change a pass did not
    // declare (graph().write_violations()); for tests: it hashes the records every pass.
    bool check_writes = false;
    // Windowed frames: the passes that take the image to the screen (not owned).
    passes::Presenter* presenter = nullptr;
};

// What a windowed frame shows.
enum class DisplayView { splats, mesh, points, side_by_side };
const char* display_view_name(DisplayView v);

// Per-frame figures, grouped as the paper's Tables 3 and 4.
struct FrameStats {
    uint64_t frame = 0;
    float time = 0.0f;  // simulated seconds at the end of the frame
    size_t particles = 0, boundary_particles = 0, gaussians = 0;
    size_t cuts = 0;   // cut events applied so far
    size_t tears = 0;  // edges torn so far
    // CPU ms per group (stages/pass_group.h). Events: the timeline (pressure, drags, spins,
    // opacity); topology: this frame's cuts and tears, with the boundary particles' refill.
    GroupTimes groups;
    double graph_ms = 0.0;  // the whole frame, wall clock
    uint64_t uploaded_bytes = 0;  // of the newest finished GPU frame
    // GPU time of the newest finished frame, per pass, from timestamps (0 where the device has
    // none or the pass did not run): the paper's "GPU Scene" row, broken down.
    render::GpuTimings gpu;
    double gpu_scene_ms() const { return gpu.upload_ms + gpu.sort_ms + gpu.draw_ms; }
    surface::DensityStats density;  // this frame's density control
};

struct SortChoice;  // scene/stages/render_setup.h

class SceneRuntime {
public:
    static core::Result<std::unique_ptr<SceneRuntime>> create(const Scene& scene, const RuntimeOptions& options);
    ~SceneRuntime();

    // Runs one frame through the graph (and submits its GPU work).
    core::Status step();
    // Waits for the GPU; the newest frame's image (offscreen with readback only).
    core::Result<core::ImageRgba8> finish();
    // The lit mesh of the body as it is now, drawn from this frame's inputs (camera, lights,
    // environment about the body) by the runtime's own mesh raster, the one the windowed mesh
    // view draws with: the splats' counterpart for image comparisons. Waits for the GPU.
    core::Result<core::ImageRgba8> mesh_image();

    const graph::FrameGraph& graph() const { return graph_; }
    const FrameStats& stats() const { return stats_; }
    // CPU milliseconds of each pass the last step ran, in the order of graph().describe()'s kept passes.
    const std::vector<double>& pass_ms() const { return last_pass_ms_; }
    const sim::SoftBody& body() const { return body_; }
    // The frame's drag (inactive when nothing pulls).
    const sim::DragConstraint& drag() const { return drag_; }
    // The model's full-resolution surface (rest pose, scene space) when the body simulates a
    // decimated copy of it; empty otherwise.
    const std::optional<mesh::TriangleMesh>& fine_surface() const { return fine_; }
    // Per vertex of the surface deformed_surface() gives, the model's own colour at rest
    // (linear): its look painted on it. Empty for plain materials.
    std::span<const Vec3f> surface_colors();
    // Where a model has a texture: its look on `triangles` (of the surface deformed_surface()
    // gives) apart, for a reference that samples the texture per pixel. Empty otherwise.
    TriangleLooks triangle_looks(std::span<const mesh::Triangle> triangles);
    const mesh::DecimateReport& decimation() const { return decimation_; }
    const surface::EmbeddingStats& embedding() const { return embedding_; }
    // The surface the splats stand for, as it is now: the model's full-resolution mesh carried
    // by the simulation mesh (its vertices embedded like the samples), or the simulation mesh
    // itself. Triangles that a cut or tear tore across (corners on different pieces, or an
    // edge stretched past 3x) are left out. For coverage against a mesh raster.
    // With `one_sided`, the triangles are ordered as the mesh occluders draw them, and it gets
    // the leading triangles they draw front faces only once the cut faces are appended
    // (scene/stages/solid_pieces.h), so a check's splat image is the runtime's.
    void deformed_surface(std::vector<Vec4f>& x, std::vector<mesh::Triangle>& triangles, SolidOrder* one_sided = nullptr);
    // The same surface as the mesh occluders of a device that simplifies it within
    // `simplify_error` draw it (render::occluder_simplify_share; at once, where the frames wait
    // for a cut's topology to hold): what a check's splat image is occluded by.
    void occluder_surface(std::vector<Vec4f>& x, std::vector<mesh::Triangle>& triangles, SolidOrder& one_sided, float simplify_error);
    // How far from the fine surface the mesh occluders on a device with these capabilities draw
    // it (world units; 0: every triangle).
    float occluder_simplify_error(const gpu::DeviceCaps& caps) const;
    // The faces cuts made, as drawn (splat/cut_faces.h): their triangles appended to `triangles`
    // on corners of their own appended to `x`, and with `colors`, each corner's colour. Nothing
    // before a cut.
    const splat::CutFaces& cut_faces() const { return cut_faces_; }
    void append_cut_faces(std::vector<Vec4f>& x, std::vector<mesh::Triangle>& triangles, std::vector<Vec3f>* colors = nullptr) const {
        cut_faces_.append_surface(particles_with_models(body_), x, triangles, body_.colors, colors);
    }
    const surface::BoundaryParticles& boundary_particles() const { return boundary_; }
    bool particles_are_splats() const { return splat_particles_; }
    // The splats of the last frame: the particles' first, then the boundary particles'; with an
    // embedded model surface, the boundary particles' only.
    const std::vector<splat::GaussianRecord>& records() const { return mapping_->records(); }
    const MappingStage& mapping() const { return *mapping_; }
    // The last frame found the body where it was on the frame before (asleep or paused): its
    // samples, records and occluder mesh were kept, not made again (stages/stillness.h).
    bool body_still() const { return stillness_.still(); }
    // With render.splat_shape = "deformed": each record's axes; else empty.
    const std::vector<splat::GaussianShape>& shapes() const { return mapping_->shapes(); }
    // Where a textured model's texture lies on each record (empty unless textured splats).
    const std::vector<splat::GaussianTexcoord>& texcoords() const { return mapping_->texcoords(); }
    float spacing() const { return h_; }
    const Scene& scene() const { return scene_; }
    // What the body as loaded breaks of the topology invariants, where they were to be checked
    // (RuntimeOptions::check_topology): a model the repair could not make fully manifold runs
    // unchecked, and this says why. Empty: nothing, or not checked.
    const std::string& invariants_at_load() const { return invariants_at_load_; }
    // What the most recent cut or tear did (empty before any).
    const topology::TopologyChange& last_topology_change() const { return topology_->last_change(); }
    float time() const { return control_.time; }
    // Connected pieces of the body now (a cut or tear may have split it).
    size_t pieces() const;

    // ---- Interaction (the windowed demo, scripted input); call between steps. -------------
    // Pixels are window coordinates (y down) of a view `view_size` large.
    // From now on the camera is the caller's: the scene's orbit and camera path stop moving it.
    void set_camera(const render::Camera& camera);
    const render::Camera& camera() const { return frame_input_.frame.camera; }
    // What the renderer is given this frame (camera, lights, style, ground).
    const render::FrameInputs& frame_inputs() const { return frame_input_.frame; }
    // Grabs the particle nearest the view ray through `pixel`; false when the ray misses the body.
    bool begin_drag(const Vec2f& pixel, const Vec2f& view_size);
    // Moves the grabbed particle's target under `pixel`, at the depth it was grabbed at.
    void move_drag(const Vec2f& pixel, const Vec2f& view_size);
    void end_drag();
    bool dragging() const { return control_.user_drag.active; }
    // A cut along the stroke a -> b, applied at the next step. A stroke that cuts nothing, or
    // fails, is reported by interaction_note() and the run goes on.
    void queue_cut(const Vec2f& a, const Vec2f& b, const Vec2f& view_size);
    const std::string& interaction_note() const { return note_; }
    // Multiplies every volume constraint's pressure factor k.
    void scale_pressure(float factor);
    float pressure() const;
    void set_environment_sampling(render::EnvSampling s) { frame_input_.frame.lighting.environment.sampling = s; }
    render::EnvSampling environment_sampling() const { return frame_input_.frame.lighting.environment.sampling; }
    // Hides or shows the boundary particles' splats (the particles' own stay).
    void set_boundary_visible(bool visible) { map_settings_.show_boundary = visible; }
    bool boundary_visible() const { return map_settings_.show_boundary; }
    // These change which passes run, so the graph is rebuilt.
    core::Status set_paused(bool paused);
    bool paused() const { return paused_; }
    core::Status set_sorted(bool sorted);  // far to near on the device's preferred side, or not
    render::SplatOrder order() const { return order_; }
    core::Status set_view(DisplayView view);
    // Reads frames back (for finish()) from the next step on; windowed runs turn it on only for
    // a screenshot.
    core::Status set_readback(bool readback);
    DisplayView view() const { return view_; }

private:
    SceneRuntime() = default;
    core::Status build(const RuntimeOptions& options);
    // A scene that does not place its camera gets one framing its models where the default view
    // misses them (scene/framing.h); before build, which hands the camera to the timeline.
    void frame_unplaced_camera();
    void report_sampling(float edge_h, float eta_h) const;  // once at load, where h is not eta's or the splats are many
    std::string largest_body_share(size_t total) const;
    void set_up_look();  // the splats' size, the occluders' tolerances, the lights from the material
    core::Status create_renderer(const SortChoice& sort);
    core::Status ensure_mesh_raster();  // made on first need (a mesh view, mesh_image())
    // The frame graph for the current settings; run again when one that changes it does.
    core::Status build_graph();  // runtime_graph.cpp, with the stages' passes below
    // Substeps this frame: the scene's, raised to its contact substeps while pieces are stacked
    // (sim/contact.h), within the 256 sweeps a frame may take.
    uint32_t frame_substeps() const;
    sim::SolverSettings step_settings_;  // what the graph's simulation passes run with
    struct GraphAssembly;
    bool has_timed_events() const;
    void import_resources(GraphAssembly& h);  // absent where the scene does not need them
    void add_frame_event_passes(GraphAssembly& h, bool has_events);
    void add_surface_and_map_passes(GraphAssembly& h);
    void add_view_passes(GraphAssembly& h);
    void add_occluder_mesh_pass(GraphAssembly& h);
    graph::Handle<graph::GpuImageRef> add_mesh_view_pass(GraphAssembly& h);
    void fingerprint_resources(const GraphAssembly& h);
    RuntimeOptions options_;
    std::string invariants_at_load_;
    render::SplatOrder order_ = render::SplatOrder::unsorted;
    render::SplatOrder sorted_order_ = render::SplatOrder::cpu;  // what set_sorted(true) picks
    float drag_depth_ = 0.0f;
    std::string note_;
    bool paused_ = false;
    bool readback_ = true;
    DisplayView view_ = DisplayView::splats;
    float base_scale_multiplier_ = 1.0f;
    std::unique_ptr<render::MeshRaster> mesh_raster_;  // made when a view first shows the mesh
    graph::GpuImageRef mesh_color_{VK_NULL_HANDLE, VK_IMAGE_ASPECT_COLOR_BIT};
    graph::GpuImageRef mesh_depth_{VK_NULL_HANDLE, VK_IMAGE_ASPECT_DEPTH_BIT};

    Scene scene_;
    sim::SoftBody body_;
    std::optional<mesh::TriangleMesh> fine_;  // the model's surface when the body is decimated
    FineCopies fine_copies_;  // the models fine_ holds only a copy of
    mesh::DecimateReport decimation_;
    SurfacePaint paint_;  // the models' looks; empty for plain materials (no paint pass then)
    std::vector<Vec3f> surface_colors_;  // with FineCopies: fine_colors_, then the particles'
    std::vector<Vec3f> fine_colors_;  // the look on the fine surface's vertices, made when first asked
    surface::EmbeddingStats embedding_;
    std::optional<surface::BoundaryParticles> fine_vertices_;  // made on the first deformed_surface()
    FineTriangles check_occluders_;  // occluder_surface()'s simplified fine triangles
    // The surface as deformed_surface() gives it, the fine triangles judged (and simplified) in
    // `keep` where given.
    void surface_as(std::vector<Vec4f>& x, std::vector<mesh::Triangle>& triangles, SolidOrder* one_sided, FineTriangles* keep);
    // The surface mesh as the mesh occluders draw it (render.visibility = "mesh"): the fine
    // surface where the body carries one, else the body's own triangles (not copied unless cut
    // faces are added to them).
    struct OccluderMesh {
        std::vector<Vec4f> x;
        std::vector<mesh::Triangle> triangles;
        FineTriangles whole;  // which fine triangles are drawn, judged again after each edit
    } occluder_mesh_;
    core::Status upload_status_;  // what the frame's upload and occluder passes left
    std::unique_ptr<core::ThreadPool> pool_;
    std::unique_ptr<sim::Solver> solver_;
    std::unique_ptr<EventQueue> queue_;  // the scene's timed events and the user's strokes, in time order
    std::unique_ptr<Timeline> timeline_;
    sim::DragConstraint drag_;
    splat::Appearance appearance_;
    surface::BoundaryParticles boundary_;
    splat::CutFaces cut_faces_;  // followed and drawn where cuts can come
    splat::StretchScale stretch_;
    surface::DensityControl density_;  // empty when the scene turns it off
    surface::DensityStats density_stats_;
    Stillness stillness_;  // whether the body moved since the surface passes last ran (stages/stillness.h)
    std::unique_ptr<render::SplatRenderer> renderer_;
    passes::GpuPassResources gpu_resources_;
    passes::GpuFrameInput frame_input_;
    passes::ImageSink sink_;
    graph::FrameGraph graph_;
    std::vector<PassGroup> group_of_kept_pass_;  // the Table 3 group of each kept pass, in execution order
    FrameStats stats_;
    std::vector<double> last_pass_ms_;
    FrameControl control_;  // the frame's time, the user's camera and drag (stages/event_stage.h)
    float h_ = 0.0f;  // sampling spacing
    bool splat_particles_ = true;  // the particles are splats too (not with an embedded surface)
    std::unique_ptr<TopologyStage> topology_;  // scripted cuts and tears, the user's strokes
    std::unique_ptr<MappingStage> mapping_;    // body -> Gaussians -> the GPU passes
    // The frame's topology changes, which the passes after the topology pass follow
    // (stages/change_passes.h): samples, fades, mapping, stretch.
    FrameChanges changes_;
    // No open boundary: back-facing splats cannot show (kept from build and each topology change).
    MapSettings map_settings_;  // what the map pass reads of the runtime (stages/mapping_stage.h)
    void update_closed();
    uint64_t frame_ = 0;
};



} // namespace pbdsplat::scene
