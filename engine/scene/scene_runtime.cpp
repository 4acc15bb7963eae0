#include "scene/scene_runtime.h"

#include <algorithm>
#include <cstdio>
#include <thread>

#include "core/timer.h"
#include "gpu/context.h"
#include "mesh/topology.h"
#include "render/occluder_pass.h"
#include "scene/framing.h"
#include "scene/scene_model.h"
#include "sim/rigid_response.h"
#include "scene/stages/body_view.h"
#include "scene/stages/fine_surface.h"
#include "scene/stages/mapping_stage.h"
#include "scene/stages/pass_group.h"
#include "scene/stages/render_setup.h"
#include "scene/stages/simulation_stage.h"
#include "scene/stages/surface_stage.h"
#include "surface/thin_parts.h"
#include "topology/cut.h"
#include "topology/invariants.h"

namespace pbdsplat::scene {

core::Result<std::unique_ptr<SceneRuntime>> SceneRuntime::create(const Scene& scene, const RuntimeOptions& options) {
    if (auto v = sim::validate(scene.simulation.solver); !v.ok()) return v.error();
    const uint32_t projections = scene.simulation.solver.iterations * scene.simulation.solver.substeps;
    if (projections > k_max_sweeps)
        return core::make_error("iterations x substeps = " + std::to_string(projections) + " constraint sweeps a frame; a scene may ask for at most " +
                                std::to_string(k_max_sweeps));
    auto rt = std::unique_ptr<SceneRuntime>(new SceneRuntime());
    rt->scene_ = scene;
    auto model = load_scene_model(scene);
    if (!model.ok()) return model.error();
    rt->scene_.simulation.solver.substeps = model.value().substeps;
    rt->body_ = std::move(model.value().body);
    rt->fine_ = std::move(model.value().fine);
    rt->fine_copies_ = std::move(model.value().fine_copies);
    rt->decimation_ = model.value().decimation;
    rt->paint_ = std::move(model.value().paint);
    rt->frame_unplaced_camera();
    PBDSPLAT_TRY(rt->build(options));
    return rt;
}

SceneRuntime::~SceneRuntime() = default;

void SceneRuntime::frame_unplaced_camera() {
    RenderDesc& rd = scene_.render;
    if (rd.camera_given || body_.particle_count() == 0) return;
    const size_t n = body_.particle_count();
    std::vector<Vec3f> points;
    points.reserve(2 * n);
    for (size_t i = 0; i < n; ++i) points.push_back(sim::xyz(body_.particles.x[i]));
    // What is dropped comes to rest on the ground: where it lands is framed too.
    if (const auto& ground = scene_.simulation.colliders.ground)
        for (size_t i = 0; i < n; ++i)
            if (const float h = ground->normal.dot(points[i]) - ground->offset; h > 0.0f) points.push_back(points[i] - h * ground->normal);
    const float aspect = float(rd.width) / float(std::max(rd.height, 1u));
    // Framed too where the models would show as a speck: spanning under a tenth of the view.
    if (!camera_sees(rd.frame.camera, points, aspect, 0.95f, 0.1f)) rd.frame.camera = framing_camera(mesh::bounds(points), rd.frame.camera, aspect);
}

core::Status SceneRuntime::build(const RuntimeOptions& options) {
    options_ = options;
    readback_ = options.readback;
    pool_ = std::make_unique<core::ThreadPool>(std::max(1u, options.threads));
    // Loading takes every core whatever the simulation's thread count: its result does not depend
    // on the threads, and the user is waiting for the first frame.
    const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
    auto load_pool = options.threads >= cores ? nullptr : std::make_unique<core::ThreadPool>(cores);
    core::ThreadPool* loader = load_pool ? load_pool.get() : pool_.get();
    solver_ = std::make_unique<sim::Solver>(pool_.get());
    frame_input_.frame = scene_.render.frame;
    queue_ = std::make_unique<EventQueue>(scene_.events);
    timeline_ = std::make_unique<Timeline>(scene_, scene_.render.frame.camera);

    const MaterialDesc& mat = scene_.material;
    appearance_.albedo = mat.color;
    appearance_.opacity_logit = math::logit(mat.opacity);
    const SurfaceDesc& sd_surface = scene_.surface;
    auto surface = setup_surface(sd_surface, scene_.simulation.fade_frames, body_, fine_, boundary_, embedding_, density_,
                                 loader);
    if (!surface.ok()) return surface.error();
    h_ = surface->h;
    splat_particles_ = surface->particles_are_splats;
    report_sampling(surface->edge_h, surface->eta_h);
    // A textured model's splats read its texture per pixel, as far as they reach (a Gaussian cut
    // at two standard deviations, and a margin) or to the nearest seam.
    if (paint_.textured() && boundary_.size() > 0) paint_.texture_reach = 2.5f * mat.splat_scale * h_;
    if (const size_t n = paint_.textures().size(); paint_.texture_reach > 0.0f && n > SPLAT_MAX_TEXTURES)
        std::fprintf(stderr, "warning: the models have %zu textures; splats read the first %u under each pixel, the others' one colour a splat\n",
                     n, unsigned(SPLAT_MAX_TEXTURES));
    if (!paint_.empty()) paint_samples(paint_, body_, boundary_, loader);
    if (splat_particles_) paint_particle_texcoords(paint_, body_);
    if (sd_surface.stretch_scale) stretch_ = splat::StretchScale(body_.rest_positions, body_.triangles);
    cut_faces_ = splat::CutFaces(h_, mat.interior_color, mat.color, scene_.simulation.fade_frames, sd_surface.seed);
    mapping_ = std::make_unique<MappingStage>(body_, scene_.simulation.fade_frames, scene_.render.deformed_shapes(),
                                               scene_.render.varying_normals, pool_.get());
    set_up_look();
    update_closed();

    const SortChoice sort = choose_sort(scene_, options.sort_on, options.gpu ? &options.gpu->caps() : nullptr);
    const render::SplatOrder order = sort.order;
    frame_input_.frame.style.order = order;
    sorted_order_ = sort.when_sorted;
    base_scale_multiplier_ = frame_input_.frame.style.scale_multiplier;
    if (options.gpu) PBDSPLAT_TRY(create_renderer(sort));

    bool check_topology = options.check_topology;
#ifndef NDEBUG
    check_topology = true;
#endif
    if (check_topology)
        if (auto s = topology::check_invariants(body_); !s.ok()) invariants_at_load_ = s.error().to_string(), check_topology = false;
    topology_ = std::make_unique<TopologyStage>(check_topology);
    order_ = order;
    return build_graph();
}

// Every body is sampled at the scene's one spacing (h from the mean edge of them all), so a large
// body beside small ones (a table under a few models) holds most of the splats, and a detailed
// scan as many as it has triangles. The sample budget caps both by raising h; loading says so
// once, naming the body that holds most, so a coarser look or a slow scene has its reason.
void SceneRuntime::report_sampling(float edge_h, float eta_h) const {
    const bool thin = eta_h < edge_h * 0.9999f;
    const size_t total = boundary_.size() + (splat_particles_ ? body_.particle_count() : 0);
    const bool budgeted = h_ > eta_h * 1.0001f;
    if (thin && !budgeted)
        std::fprintf(stderr,
                     "note: sampled at h = %.4g m, %.2f of eta's spacing by the edge: a closed part about %.3g m thick (4 x volume / "
                     "area) would otherwise get samples on one face only and show gaps from the side\n",
                     double(h_), double(h_ / edge_h), double(eta_h / surface::k_spacing_over_thickness));
    if ((!budgeted && total < k_many_samples) || total == 0) return;
    const std::string where = largest_body_share(total);
    if (budgeted) {
        char asked[160];
        if (thin)
            std::snprintf(asked, sizeof asked, "%.4g m, held within a closed part %.3g m thick", double(eta_h),
                          double(eta_h / surface::k_spacing_over_thickness));
        else
            std::snprintf(asked, sizeof asked, "%.4g m, eta %.2f of the edge", double(eta_h), double(scene_.surface.eta));
        const double wanted = double(total) * double(h_ / eta_h) * double(h_ / eta_h);
        std::fprintf(stderr,
                     "note: sampled at h = %.4g m, %.2f times the spacing asked for (%s): at that spacing the surface would take "
                     "about %.0f splats%s, past surface.sample_budget = %u. Raise the budget for the finer look\n",
                     double(h_), double(h_ / eta_h), asked, wanted, where.c_str(), scene_.surface.sample_budget);
        return;
    }
    std::fprintf(stderr, "warning: %zu splats at the scene's spacing h = %.4g m%s: set a surface.sample_budget or raise surface.eta\n", total,
                 double(h_), where.c_str());
}

// Where a scene has several bodies: " (N % of them on BODY: ...)" for the one holding most samples.
std::string SceneRuntime::largest_body_share(size_t total) const {
    if (body_.model_of_particle.size() != body_.particle_count() || scene_.bodies.empty()) return {};
    std::vector<size_t> per_model;
    for (uint32_t t : boundary_.triangle) {
        const uint32_t m = body_.model_of_particle[body_.triangles[t][0]];
        if (m >= per_model.size()) per_model.resize(m + 1, 0);
        ++per_model[m];
    }
    const auto largest = std::ranges::max_element(per_model);
    if (largest == per_model.end()) return {};
    const std::string name = model_name(scene_, size_t(largest - per_model.begin()));
    char share[512];
    std::snprintf(share, sizeof share, " (%.0f %% of them on %s: every body is sampled at one spacing, so a large one beside "
                  "small ones costs in proportion to its area)", 100.0 * double(*largest) / double(total), name.c_str());
    return share;
}

void SceneRuntime::set_up_look() {
    const MaterialDesc& mat = scene_.material;
    appearance_.scale = mat.splat_scale * h_;
    if (scene_.render.frame.style.mesh_occluders) {
        render::SplatStyle& style = frame_input_.frame.style;
        style.occluder_tolerance = scene_.render.occluder_tolerance * appearance_.scale;
        // Behind the mesh, the surface's own carriers lie at their centres' depth, which on a
        // surface turned from the eye is up to about their reach farther than the mesh there.
        // (Pushed back only as far as the tolerance, a splat of the squashed base showed as a
        // bright dot against the ground, and the frame was no faster.)
        style.occluder_push = std::max(4.0f * appearance_.scale, 2.0f * style.occluder_tolerance);
        if (options_.gpu) occluder_mesh_.whole.simplify_error = occluder_simplify_error(options_.gpu->caps());
    }
    frame_input_.frame.lighting.intensity *= mat.diffuse;
    frame_input_.frame.lighting.specular = mat.specular;
    frame_input_.frame.lighting.shininess = mat.shininess;
    if (mat.interior_color) frame_input_.frame.style.interior = Vec4f(mat.interior_color->x(), mat.interior_color->y(), mat.interior_color->z(), 1.0f);
}

core::Status SceneRuntime::create_renderer(const SortChoice& sort) {
    std::vector<const asset::Texture*> textures = paint_.texture_reach > 0.0f ? paint_.textures() : std::vector<const asset::Texture*>{};
    textures.resize(std::min<size_t>(textures.size(), SPLAT_MAX_TEXTURES));
    RendererNeeds needs{body_.particle_count() + boundary_.size(), options_.interactive, !density_.empty(), uint32_t(textures.size())};
    size_t max_samples = 0;
    render::RendererOptions ro = renderer_options(scene_, sort, needs, &max_samples);
    // What the density control may fill: the renderer's capacity less the cuts' room.
    if (!density_.empty()) density_.set_max_samples(max_samples - (splat_particles_ ? body_.particle_count() : 0));
    ro.frames_in_flight = options_.frames_in_flight;
    ro.upload_path = options_.upload_path;
    if (options_.splat_path) ro.path = options_.splat_path;
    auto r = render::SplatRenderer::create(*options_.gpu, ro);
    if (!r.ok()) return r.error();
    renderer_ = std::move(r).value();
    if (!textures.empty()) PBDSPLAT_TRY(renderer_->set_textures(gpu_textures(textures)));
    return core::Status::success();
}

size_t SceneRuntime::pieces() const { return body_.pieces; }

void SceneRuntime::update_closed() {
    map_settings_.closed = !body_.triangles.empty() && mesh::boundary_loops(body_.triangles, body_.particle_count()).empty();
}



std::span<const Vec3f> SceneRuntime::surface_colors() {
    if (paint_.empty()) return {};
    if (!fine_) return body_.colors;
    if (fine_colors_.size() != fine_->vertex_count()) {
        if (!fine_vertices_) {  // the fine surface's embedding, made with its first deformed copy
            std::vector<Vec4f> x;
            std::vector<mesh::Triangle> triangles;
            deformed_surface(x, triangles);
        }
        fine_colors_ = paint_vertices(paint_, body_, *fine_, *fine_vertices_);
    }
    if (!fine_copies_.any()) return fine_colors_;
    // The body's particles follow the fine vertices (FineCopies).
    surface_colors_.assign(fine_colors_.begin(), fine_colors_.end());
    surface_colors_.insert(surface_colors_.end(), body_.colors.begin(), body_.colors.end());
    return surface_colors_;
}

TriangleLooks SceneRuntime::triangle_looks(std::span<const mesh::Triangle> triangles) {
    if (paint_.empty()) return {};
    if (!fine_) return paint_triangles(paint_, body_.rest_positions, body_.model_of_particle, triangles);
    if (!fine_vertices_) {
        std::vector<Vec4f> x;
        std::vector<mesh::Triangle> t;
        deformed_surface(x, t);
    }
    // A fine vertex's model is that of the body triangle it is embedded in.
    std::vector<uint32_t> model(fine_->vertex_count(), 0u);
    for (size_t v = 0; v < model.size() && v < fine_vertices_->size(); ++v) {
        const uint32_t particle = body_.triangles[fine_vertices_->triangle[v]][0];
        if (particle < body_.model_of_particle.size()) model[v] = body_.model_of_particle[particle];
    }
    if (!fine_copies_.any()) return paint_triangles(paint_, fine_->positions, model, triangles);
    // The body's particles follow the fine vertices, at their rest places (FineCopies).
    std::vector<Vec3f> rest(fine_->positions);
    rest.insert(rest.end(), body_.rest_positions.begin(), body_.rest_positions.end());
    model.insert(model.end(), body_.model_of_particle.begin(), body_.model_of_particle.end());
    model.resize(rest.size(), 0u);
    return paint_triangles(paint_, rest, model, triangles);
}

void SceneRuntime::deformed_surface(std::vector<Vec4f>& x, std::vector<mesh::Triangle>& triangles, SolidOrder* one_sided) {
    surface_as(x, triangles, one_sided, nullptr);
}

float SceneRuntime::occluder_simplify_error(const gpu::DeviceCaps& caps) const {
    // Where the device pays per triangle, the fine surface drawn simplified within a share of the
    // tolerance. Only on stiff bodies: a soft one bends inside a simplified triangle, away from
    // the surface it stood for (bunny_tear, a balloon: holes 0 -> 0.1 %, specks up 0.1 points in
    // `check`).
    if (!fine_ || !scene_.render.frame.style.mesh_occluders || stiffest_shape(scene_) < sim::k_rigid_response_stiffness) return 0.0f;
    return render::occluder_simplify_share(caps) * frame_input_.frame.style.occluder_tolerance;
}

void SceneRuntime::occluder_surface(std::vector<Vec4f>& x, std::vector<mesh::Triangle>& triangles, SolidOrder& one_sided,
                                    float simplify_error) {
    check_occluders_.simplify_error = simplify_error;
    check_occluders_.settle_frames = 0;
    surface_as(x, triangles, &one_sided, &check_occluders_);
}

void SceneRuntime::surface_as(std::vector<Vec4f>& x, std::vector<mesh::Triangle>& triangles, SolidOrder* one_sided, FineTriangles* keep) {
    if (!fine_) {
        x = body_.particles.x;
        triangles = body_.triangles;
    } else {
        deformed_fine_surface(body_, *fine_, fine_copies_, fine_vertices_, x, triangles, keep);
    }
    mark_vertex_models(body_, fine_ ? &*fine_vertices_ : nullptr, x);
    if (one_sided) *one_sided = order_solids_first(body_, solid_pieces(body_, &cut_faces_), triangles, fine_ ? &*fine_vertices_ : nullptr);
}

core::Status SceneRuntime::step() {
    const core::Stopwatch frame_clock;
    // Pieces came to rest on each other or parted at the last frame's contact search: this
    // frame steps in the substeps that suit it.
    if (!paused_ && frame_substeps() != step_settings_.substeps) PBDSPLAT_TRY(build_graph());
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
    if (renderer_) PBDSPLAT_TRY(upload_status_);
    if (!paused_) control_.time += scene_.simulation.dt;
    ++frame_;

    FrameStats s;
    s.cuts = topology_->cuts();
    s.tears = topology_->tears();
    s.frame = frame_;
    s.time = control_.time;
    s.particles = body_.particle_count();
    s.boundary_particles = boundary_.size();
    s.density = density_stats_;
    s.gaussians = mapping_->records().size();
    for (size_t k = 0; k < ms.size(); ++k) {
        const PassGroup g = group_of_kept_pass_[k];
        if (g != PassGroup::other) s.groups[g] += ms[k];
    }
    if (renderer_) {
        const render::GpuTimings g = renderer_->timings();
        s.uploaded_bytes = g.uploaded_bytes;
        s.gpu = g;
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
