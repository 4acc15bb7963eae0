// SceneRuntime's frame graph: the resources a scene has (an absent one culls the passes that
// need it) and each stage's passes in frame order, and what follows a topology change.
#include "scene/scene_runtime.h"

#include "scene/stages/body_view.h"
#include "scene/stages/mapping_stage.h"
#include "scene/stages/pass_group.h"
#include "scene/stages/simulation_stage.h"
#include "scene/stages/surface_stage.h"

namespace pbdsplat::scene {

// The frame's resources as the passes declared so far left them (each write gives the next
// version), passed from one stage's passes to the next.
struct SceneRuntime::GraphHandles {
    graph::Handle<sim::SoftBody> body;
    graph::Handle<Timeline> timeline;
    graph::Handle<std::vector<sim::VolumeConstraint>> volumes;
    graph::Handle<std::vector<sim::ShapeCluster>> shapes;
    graph::Handle<sim::Colliders> colliders;
    graph::Handle<sim::DragConstraint> drag;
    graph::Handle<passes::GpuFrameInput> input;
    graph::Handle<surface::BoundaryParticles> samples;
    graph::Handle<surface::DensityControl> density;
    graph::Handle<splat::SortScratch> sort;
    graph::Handle<splat::StretchScale> stretch;
    graph::Handle<passes::ImageSink> sink;
    graph::Handle<std::vector<Event>> cuts;
    bool boundary = false, drags = false, sorted = false;
};

core::Status SceneRuntime::build_graph() {
    const SurfaceDesc& sd_surface = scene_.surface;
    const SimulationDesc& sd = scene_.simulation;
    graph_ = graph::FrameGraph();
    graph::FrameGraph& g = graph_;
    GraphHandles h;
    h.boundary = sd_surface.mode == SurfaceMode::boundary;
    h.drags = timeline_->has_drag() || options_.interactive;
    // Sorting only matters when splats are composited with "over" and the scene asks for it.
    h.sorted = order_ == render::SplatOrder::cpu;  // the GPU sort is a GPU pass
    const bool has_volume = sd.solver.volume && !body_.volumes.empty();
    const bool has_events = !scene_.events.empty() || scene_.render.orbit.degrees_per_second != 0.0f || !scene_.render.path.empty();
    const bool has_shape = sd.solver.shape_stiffness > 0.0f && body_.shape_matching;
    const bool topology_events = topology_->has_scripted_events() || options_.interactive;
    h.body = g.import("body", &body_, true);
    h.timeline = g.import("timeline", has_events ? timeline_.get() : static_cast<Timeline*>(nullptr));
    h.volumes = g.import("volume constraints", has_volume ? &body_.volumes : static_cast<std::vector<sim::VolumeConstraint>*>(nullptr));
    h.shapes = g.import("shape clusters", has_shape ? &body_.shapes : static_cast<std::vector<sim::ShapeCluster>*>(nullptr));
    h.colliders = g.import("colliders", sd.colliders.empty() ? nullptr : &scene_.simulation.colliders);
    h.drag = g.import("drag", h.drags ? &drag_ : static_cast<sim::DragConstraint*>(nullptr));
    h.input = g.import("frame input", &frame_input_);
    h.samples = g.import("boundary particles", h.boundary ? &boundary_ : static_cast<surface::BoundaryParticles*>(nullptr));
    h.density = g.import("density control", h.boundary ? &density_ : static_cast<surface::DensityControl*>(nullptr));
    h.sort = g.import("sort", h.sorted ? &mapping_->sort_scratch() : static_cast<splat::SortScratch*>(nullptr));
    h.stretch = g.import("stretch", sd_surface.stretch_scale ? &stretch_ : static_cast<splat::StretchScale*>(nullptr));
    h.sink = g.import("image", readback_ ? &sink_ : static_cast<passes::ImageSink*>(nullptr));
    h.cuts = g.import("topology events", topology_events ? &topology_->pending() : static_cast<std::vector<Event>*>(nullptr));
    // Paused: nothing moves, so no simulation stage runs; the frame is drawn again as it was.
    if (!paused_) {
        add_event_passes(h);
        SimulationHandles sim_handles{h.body, h.volumes, h.shapes, h.drag, h.colliders};
        add_simulation_passes(g, sim_handles, *solver_, sd.solver, sd.dt);
        h.body = sim_handles.body;
    }
    auto density_stats = g.import("density stats", &density_stats_);
    SurfaceHandles surface{h.body, h.samples, h.density, density_stats, h.stretch};
    add_surface_passes(g, surface, {splat_particles_, h_, scene_.surface.seed, tag(PassGroup::update)});
    h.samples = surface.samples;
    h.stretch = surface.stretch;
    map_settings_.particles = splat_particles_;
    map_settings_.cull_back = scene_.render.cull_back;
    map_settings_.draw_ground = scene_.render.ground;
    map_settings_.ground = scene_.simulation.colliders.ground;
    MapHandles map{h.body, h.samples, h.stretch, h.sort, g.import("appearance", &appearance_), g.import("map settings", &map_settings_),
                   g.import("mapping", mapping_.get()), h.input};
    add_mapping_passes(g, map, {h.boundary, sd_surface.stretch_scale, h.sorted, options_.keep_records, tag(PassGroup::update)});
    h.input = map.input;
    if (renderer_) add_view_passes(h);
    PBDSPLAT_TRY(g.compile());
    group_of_kept_pass_.clear();
    for (const graph::PassInfo& p : g.describe())
        if (!p.culled) group_of_kept_pass_.push_back(PassGroup(p.tag));
    return core::Status::success();
}

void SceneRuntime::add_event_passes(GraphHandles& h) {
    const float dt = scene_.simulation.dt;
    graph_.add_pass("events", graph::PassKind::cpu, [&](graph::PassBuilder& b) {
        if (!options_.interactive) b.read(h.timeline);
        h.body = b.write(h.body);
        if (h.drags) h.drag = b.write(h.drag);
        h.input = b.write(h.input);
        return [this, dt](const graph::PassResources&, graph::ExecuteContext&) {
            render::Camera scripted = frame_input_.frame.camera;
            float opacity = math::sigmoid(appearance_.opacity_logit);
            const float before = opacity;
            timeline_->advance(time_, dt, body_, drag_, camera_override_ ? scripted : frame_input_.frame.camera, opacity);
            if (opacity != before) appearance_.opacity_logit = math::logit(opacity);
            if (user_drag_.active) drag_ = user_drag_;  // the hand wins over the script
        };
    }, tag(PassGroup::events));
    graph_.add_pass("topology", graph::PassKind::cpu, [&](graph::PassBuilder& b) {
        b.read(h.cuts);
        h.body = b.write(h.body);
        // What a change re-samples, only where the scene has it: an absent resource culls a
        // pass that declares it (vertices-only scenes lost their cuts so).
        if (h.boundary) h.samples = b.write(h.samples), h.density = b.write(h.density);
        if (scene_.surface.stretch_scale) h.stretch = b.write(h.stretch);
        return [this, dt](const graph::PassResources&, graph::ExecuteContext&) {
            TopologyStage::Follow follow;
            follow.each = [this](const topology::TopologyChange& c, const topology::CutSurface* cut) { return after_each_change(c, cut); };
            follow.settle = [this](std::span<const uint32_t> touched, size_t seed_offset) { return settle_changes(touched, seed_offset); };
            topology_->run(body_, time_, dt, frame_input_.frame.camera, scene_.simulation.cut, follow, note_);
        };
    }, tag(PassGroup::events));
}

void SceneRuntime::add_view_passes(GraphHandles& h) {
    graph::FrameGraph& g = graph_;
    const auto drawn = passes::add_gpu_passes(g, *renderer_, gpu_resources_, h.input, h.sink, order_ == render::SplatOrder::gpu,
                                              tag(PassGroup::gpu_record));
    passes::PresentSources sources{drawn, {}, renderer_->width(), renderer_->height(), [this] { return renderer_->slot(); }};
    if (mesh_raster_ && (view_ == DisplayView::mesh || view_ == DisplayView::side_by_side)) {
        auto mesh_color = g.import("mesh colour", &mesh_color_);
        auto mesh_depth = g.import("mesh depth", &mesh_depth_);
        g.add_pass("mesh", graph::PassKind::gpu, [&](graph::PassBuilder& b) {
            b.read(h.body);
            b.read(h.input);
            mesh_color = b.write(mesh_color, passes::to_graph(render::uses::color_attachment));
            b.write(mesh_depth, passes::to_graph(render::uses::depth_attachment));
            return [this](const graph::PassResources&, graph::ExecuteContext& c) {
                const uint32_t slot = renderer_->slot();
                if (const core::Status s = mesh_raster_->set_mesh(body_.particles.x, body_.triangles, body_.normals, slot); !s.ok())
                    note_ = "mesh view: " + s.error().to_string();  // drawn with the last mesh that fitted
                mesh_raster_->draw(c.cmd, frame_input_.frame, render::MeshView::shaded, appearance_.albedo, slot);
            };
        });
        sources.mesh = mesh_color;
    }
    if (options_.presenter) options_.presenter->add_passes(g, sources);
}

SurfaceFollow SceneRuntime::surface_follow() {
    SurfaceFollow f;
    f.samples = &boundary_;
    f.fine_vertices = fine_vertices_ ? &*fine_vertices_ : nullptr;
    f.density = &density_;
    f.h = h_;
    f.seed = scene_.surface.seed;
    f.fade_frames = scene_.simulation.fade_frames;
    f.edge_samples = scene_.surface.edge_samples;
    f.particles_are_splats = splat_particles_;
    return f;
}

core::Result<std::vector<uint32_t>> SceneRuntime::after_each_change(const topology::TopologyChange& change, const topology::CutSurface* cut) {
    // Only a cut or tear can open the boundary, and only where it touched.
    if (map_settings_.closed) map_settings_.closed = !opens_boundary(body_, change.touched_triangles);
    mapping_->topology_changed(body_, change, splat_particles_);
    if (scene_.surface.mode != SurfaceMode::boundary) return std::vector<uint32_t>{};
    return carry_samples_across(surface_follow(), body_, change, cut);
}

core::Status SceneRuntime::settle_changes(std::span<const uint32_t> touched, size_t seed_offset) {
    if (scene_.surface.mode == SurfaceMode::boundary) refill_touched(surface_follow(), body_, touched, seed_offset);
    if (!stretch_.empty()) stretch_ = splat::StretchScale(body_.rest_positions, body_.triangles);
    return core::Status::success();
}

} // namespace pbdsplat::scene
