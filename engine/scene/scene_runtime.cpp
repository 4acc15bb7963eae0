#include "scene/scene_runtime.h"

#include <algorithm>

#include "core/timer.h"
#include "mesh/topology.h"
#include "scene/stages/body_view.h"
#include "scene/stages/fine_surface.h"
#include "scene/stages/mapping_stage.h"
#include "scene/stages/pass_group.h"
#include "scene/stages/render_setup.h"
#include "scene/stages/simulation_stage.h"
#include "scene/stages/surface_stage.h"
#include "topology/cut.h"
#include "topology/invariants.h"

namespace pbdsplat::scene {

core::Result<std::unique_ptr<SceneRuntime>> SceneRuntime::create(const Scene& scene, const RuntimeOptions& options) {
    if (auto v = sim::validate(scene.simulation.solver); !v.ok()) return v.error();
    const uint32_t projections = scene.simulation.solver.iterations * scene.simulation.solver.substeps;
    if (projections > 256)
        return core::make_error("iterations x substeps = " + std::to_string(projections) +
                                " constraint sweeps a frame; a scene may ask for at most 256");
    auto rt = std::unique_ptr<SceneRuntime>(new SceneRuntime());
    rt->scene_ = scene;
    auto model = load_scene_model(scene);
    if (!model.ok()) return model.error();
    rt->body_ = std::move(model.value().body);
    rt->fine_ = std::move(model.value().fine);
    rt->decimation_ = model.value().decimation;
    PBDSPLAT_TRY(rt->build(options));
    return rt;
}

SceneRuntime::~SceneRuntime() = default;

core::Status SceneRuntime::build(const RuntimeOptions& options) {
    options_ = options;
    readback_ = options.readback;
    pool_ = std::make_unique<core::ThreadPool>(std::max(1u, options.threads));
    solver_ = std::make_unique<sim::Solver>(pool_.get());
    frame_input_.frame = scene_.render.frame;
    timeline_ = std::make_unique<Timeline>(scene_, scene_.render.frame.camera);

    const MaterialDesc& mat = scene_.material;
    appearance_.albedo = mat.color;
    appearance_.opacity_logit = math::logit(mat.opacity);
    const SurfaceDesc& sd_surface = scene_.surface;
    auto surface = setup_surface(sd_surface, scene_.simulation.fade_frames, body_, fine_, boundary_, embedding_, density_);
    if (!surface.ok()) return surface.error();
    h_ = surface->h;
    splat_particles_ = surface->particles_are_splats;
    if (sd_surface.stretch_scale) stretch_ = splat::StretchScale(body_.rest_positions, body_.triangles);
    mapping_ = std::make_unique<MappingStage>(body_, scene_.simulation.fade_frames, scene_.render.deformed_shapes());
    appearance_.scale = mat.splat_scale * h_;
    update_closed();
    frame_input_.frame.lighting.intensity *= mat.diffuse;
    frame_input_.frame.lighting.specular = mat.specular;
    frame_input_.frame.lighting.shininess = mat.shininess;

    const SortChoice sort = choose_sort(scene_, options.sort_on, options.gpu ? &options.gpu->caps() : nullptr);
    const render::SplatOrder order = sort.order;
    frame_input_.frame.style.order = order;
    sorted_order_ = sort.when_sorted;
    base_scale_multiplier_ = frame_input_.frame.style.scale_multiplier;

    if (options.gpu) {
        RendererNeeds needs{body_.particle_count() + boundary_.size(), options.interactive, !density_.empty()};
        size_t max_samples = 0;
        render::RendererOptions ro = renderer_options(scene_, sort, needs, &max_samples);
        // What the density control may fill: the renderer's capacity less the cuts' room.
        if (!density_.empty()) density_.set_max_samples(max_samples - (splat_particles_ ? body_.particle_count() : 0));
        ro.frames_in_flight = options.frames_in_flight;
        ro.upload_path = options.upload_path;
        if (options.splat_path) ro.path = options.splat_path;
        auto r = render::SplatRenderer::create(*options.gpu, ro);
        if (!r.ok()) return r.error();
        renderer_ = std::move(r).value();
    }

    bool check_topology = options.check_topology;
#ifndef NDEBUG
    check_topology = true;
#endif
    topology_ = std::make_unique<TopologyStage>(scene_, check_topology);
    order_ = order;
    return build_graph();
}

core::Status SceneRuntime::build_graph() {
    const RuntimeOptions& options = options_;
    const render::SplatOrder order = order_;
    const SurfaceDesc& sd_surface = scene_.surface;
    const bool boundary = sd_surface.mode == SurfaceMode::boundary;
    graph_ = graph::FrameGraph();
    // The resources: what exists depends on the scene, and decides which passes survive.
    const SimulationDesc& sd = scene_.simulation;
    const bool has_volume = sd.solver.volume && !body_.volumes.empty();
    const bool has_events = !scene_.events.empty() || scene_.render.orbit.degrees_per_second != 0.0f ||
                            !scene_.render.path.empty();
    graph::FrameGraph& g = graph_;
    auto body = g.import("body", &body_, true);
    auto timeline = g.import("timeline", has_events ? timeline_.get() : static_cast<Timeline*>(nullptr));
    auto volumes = g.import("volume constraints", has_volume ? &body_.volumes : static_cast<std::vector<sim::VolumeConstraint>*>(nullptr));
    const bool has_shape = sd.solver.shape_stiffness > 0.0f && body_.shape_matching;
    auto shapes = g.import("shape clusters", has_shape ? &body_.shapes : static_cast<std::vector<sim::ShapeCluster>*>(nullptr));
    auto colliders = g.import("colliders", sd.colliders.empty() ? nullptr : &scene_.simulation.colliders);
    const bool drags = timeline_->has_drag() || options.interactive;
    auto drag = g.import("drag", drags ? &drag_ : static_cast<sim::DragConstraint*>(nullptr));
    auto input = g.import("frame input", &frame_input_);

    const float dt = sd.dt;
    const sim::SolverSettings& settings = scene_.simulation.solver;
    sim::Solver& solver = *solver_;
    auto cpu_pass = [&](const std::string& name, PassGroup group, auto setup) { g.add_pass(name, graph::PassKind::cpu, setup, tag(group)); };

    auto samples = g.import("boundary particles", boundary ? &boundary_ : static_cast<surface::BoundaryParticles*>(nullptr));
    auto density = g.import("density control", boundary ? &density_ : static_cast<surface::DensityControl*>(nullptr));
    // Sorting only matters when splats are composited with "over" and the scene asks for it.
    const bool sorted = order == render::SplatOrder::cpu;  // the GPU sort is a GPU pass
    auto sort = g.import("sort", sorted ? &mapping_->sort_scratch() : static_cast<splat::SortScratch*>(nullptr));
    auto stretch = g.import("stretch", sd_surface.stretch_scale ? &stretch_ : static_cast<splat::StretchScale*>(nullptr));
    auto sink = g.import("image", readback_ ? &sink_ : static_cast<passes::ImageSink*>(nullptr));
    const bool topology_events = topology_->has_scripted_events() || options.interactive;
    auto cuts = g.import("topology events", topology_events ? &topology_->pending() : static_cast<std::vector<Event>*>(nullptr));
    // Paused: nothing moves, so no simulation stage runs; the frame is drawn again as it was.
    if (!paused_) {
    cpu_pass("events", PassGroup::events, [&](graph::PassBuilder& b) {
        if (!options.interactive) b.read(timeline);
        body = b.write(body);
        if (drags) drag = b.write(drag);
        input = b.write(input);
        return [this, dt](const graph::PassResources&, graph::ExecuteContext&) {
            render::Camera scripted = frame_input_.frame.camera;
            float opacity = math::sigmoid(appearance_.opacity_logit);
            const float before = opacity;
            timeline_->advance(time_, dt, body_, drag_, camera_override_ ? scripted : frame_input_.frame.camera, opacity);
            if (opacity != before) appearance_.opacity_logit = math::logit(opacity);
            if (user_drag_.active) drag_ = user_drag_;  // the hand wins over the script
        };
    });
    cpu_pass("topology", PassGroup::events, [&](graph::PassBuilder& b) {
        b.read(cuts);
        body = b.write(body);
        // What a change re-samples, only where the scene has it: an absent resource culls a
        // pass that declares it (vertices-only scenes lost their cuts so).
        if (boundary) samples = b.write(samples), density = b.write(density);
        if (sd_surface.stretch_scale) stretch = b.write(stretch);
        return [this, dt](const graph::PassResources&, graph::ExecuteContext&) {
            TopologyStage::Follow follow;
            follow.each = [this](const topology::TopologyChange& c, const topology::CutSurface* cut) { return after_each_change(c, cut); };
            follow.settle = [this](std::span<const uint32_t> touched, size_t seed_offset) { return settle_changes(touched, seed_offset); };
            topology_->run(body_, time_, dt, frame_input_.frame.camera, scene_.simulation.cut, follow, note_);
        };
    });
    SimulationHandles sim_handles{body, volumes, shapes, drag, colliders};
    add_simulation_passes(g, sim_handles, solver, settings, dt);
    body = sim_handles.body;
    }  // !paused_
    auto density_stats = g.import("density stats", &density_stats_);
    SurfaceHandles surface{body, samples, density, density_stats, stretch};
    add_surface_passes(g, surface, {splat_particles_, h_, scene_.surface.seed, tag(PassGroup::update)});
    samples = surface.samples;
    stretch = surface.stretch;
    const bool keep = options.keep_records;
    cpu_pass("map", PassGroup::update, [&](graph::PassBuilder& b) {
        b.read(body);
        if (boundary) b.read(samples);
        if (sd_surface.stretch_scale) b.read(stretch);
        input = b.write(input);
        if (keep) b.side_effect();
        return [this, boundary, sorted](const graph::PassResources&, graph::ExecuteContext&) {
            MappingStage::Sources sources;
            sources.body = &body_;
            sources.particles = splat_particles_;
            sources.samples = boundary && show_boundary_ ? &boundary_ : nullptr;
            sources.stretch = stretch_.empty() ? nullptr : &stretch_;
            mapping_->map(sources, appearance_);
            BodyViewOptions view;
            view.cull_back = scene_.render.cull_back;
            view.closed = body_closed_;
            view.opaque = frame_input_.frame.style.blend == render::Blend::over && appearance_.opacity_logit > math::logit(0.9f);
            view.draw_ground = scene_.render.ground;
            follow_body(body_.particles.x, scene_.simulation.colliders.ground, view, frame_input_.frame);
            if (!sorted) mapping_->publish(frame_input_);  // else the sort stage reorders them first
        };
    });
    cpu_pass("sort", PassGroup::update, [&](graph::PassBuilder& b) {
        b.read(sort);
        input = b.write(input);
        if (keep) b.side_effect();
        return [this](const graph::PassResources&, graph::ExecuteContext&) {
            mapping_->sort(frame_input_.frame.camera);
            mapping_->publish(frame_input_);
        };
    });
    if (renderer_) {
        const auto drawn = passes::add_gpu_passes(g, *renderer_, gpu_resources_, input, sink, order == render::SplatOrder::gpu,
                                                  tag(PassGroup::gpu_record));
        passes::PresentSources sources{drawn, {}, renderer_->width(), renderer_->height(), [this] { return renderer_->slot(); }};
        if (mesh_raster_ && (view_ == DisplayView::mesh || view_ == DisplayView::side_by_side)) {
            auto mesh_color = g.import("mesh colour", &mesh_color_);
            auto mesh_depth = g.import("mesh depth", &mesh_depth_);
            g.add_pass("mesh", graph::PassKind::gpu, [&](graph::PassBuilder& b) {
                b.read(body);
                b.read(input);
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
        if (options.presenter) options.presenter->add_passes(g, sources);
    }
    PBDSPLAT_TRY(g.compile());
    group_of_kept_pass_.clear();
    for (const graph::PassInfo& p : g.describe())
        if (!p.culled) group_of_kept_pass_.push_back(PassGroup(p.tag));
    return core::Status::success();
}

size_t SceneRuntime::pieces() const { return topology::count_components_and_loops(body_).components; }

void SceneRuntime::update_closed() {
    body_closed_ = !body_.triangles.empty() && mesh::boundary_loops(body_.triangles, body_.particle_count()).empty();
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
    if (body_closed_) body_closed_ = !opens_boundary(body_, change.touched_triangles);
    mapping_->topology_changed(body_, change, splat_particles_);
    if (scene_.surface.mode != SurfaceMode::boundary) return std::vector<uint32_t>{};
    return carry_samples_across(surface_follow(), body_, change, cut);
}

core::Status SceneRuntime::settle_changes(std::span<const uint32_t> touched, size_t seed_offset) {
    if (scene_.surface.mode == SurfaceMode::boundary) refill_touched(surface_follow(), body_, touched, seed_offset);
    if (!stretch_.empty()) stretch_ = splat::StretchScale(body_.rest_positions, body_.triangles);
    return core::Status::success();
}

void SceneRuntime::deformed_surface(std::vector<Vec4f>& x, std::vector<mesh::Triangle>& triangles) {
    if (!fine_) {
        x = body_.particles.x;
        triangles = body_.triangles;
        return;
    }
    deformed_fine_surface(body_, *fine_, fine_vertices_, x, triangles);
}

core::Status SceneRuntime::step() {
    const core::Stopwatch frame_clock;
    graph::ExecuteContext ctx{VK_NULL_HANDLE, frame_};
    if (renderer_) {
        auto cmd = renderer_->begin_frame();
        if (!cmd.ok()) return cmd.error();
        ctx.cmd = cmd.value();
        gpu_resources_.refresh(*renderer_);
    }
    const auto& ms = graph_.execute(ctx);
    last_pass_ms_ = ms;
    if (renderer_) {
        passes::Presenter* p = options_.presenter;
        PBDSPLAT_TRY(renderer_->end_frame(p ? p->wait_semaphore() : nullptr, p ? p->signal_semaphore() : nullptr));
    }
    if (!topology_->status().ok()) return topology_->status();
    if (renderer_) PBDSPLAT_TRY(frame_input_.upload_status);
    if (!paused_) time_ += scene_.simulation.dt;
    ++frame_;

    FrameStats s;
    s.cuts = topology_->cuts();
    s.tears = topology_->tears();
    s.topology_ms = topology_->ms();
    s.frame = frame_;
    s.time = time_;
    s.particles = body_.particle_count();
    s.boundary_particles = boundary_.size();
    s.density = density_stats_;
    s.gaussians = mapping_->records().size();
    for (size_t k = 0; k < ms.size(); ++k) {
        const double t = ms[k];
        switch (group_of_kept_pass_[k]) {
            case PassGroup::events: s.events_ms += t; break;
            case PassGroup::forces: s.apply_forces_ms += t; break;
            case PassGroup::constraints: s.constraints_ms += t; break;
            case PassGroup::integrate: s.integrate_normals_ms += t; break;
            case PassGroup::update: s.update_particles_ms += t; break;
            case PassGroup::gpu_record: s.gpu_record_ms += t; break;
            case PassGroup::other: break;
        }
    }
    if (renderer_) {
        const render::GpuTimings g = renderer_->timings();
        s.uploaded_bytes = g.uploaded_bytes;
        s.gpu_upload_ms = g.upload_ms;
        s.gpu_sort_ms = g.sort_ms;
        s.gpu_draw_ms = g.draw_ms;
    }
    s.graph_ms = frame_clock.elapsed_ms();
    stats_ = s;
    for (const auto& x : body_.particles.x)
        if (!x.allFinite())
            return core::make_error("the simulation produced NaN or Inf at frame " + std::to_string(frame_) +
                                    "; lower dt or raise the iterations or substeps");
    return core::Status::success();
}

core::Result<core::ImageRgba8> SceneRuntime::finish() {
    if (!renderer_) return core::make_error("this scene runtime has no renderer (created without a GPU context)");
    return renderer_->finish();
}

} // namespace pbdsplat::scene
