// SceneRuntime's frame graph: the resources a scene has (an absent one culls the passes that
// need it) and each stage's passes in frame order, and what follows a topology change.
#include <algorithm>

#include "scene/scene_runtime.h"

#include "scene/stages/body_parts.h"
#include "scene/stages/body_view.h"
#include "scene/stages/change_passes.h"
#include "scene/stages/event_stage.h"
#include "scene/stages/frame_keys.h"
#include "scene/stages/fine_surface.h"
#include "scene/stages/mapping_stage.h"
#include "scene/stages/paint.h"
#include "scene/stages/pass_group.h"
#include "scene/stages/simulation_stage.h"
#include "scene/stages/solid_pieces.h"
#include "scene/stages/stillness.h"
#include "scene/stages/surface_stage.h"
#include "scene/stages/write_check.h"
#include "sim/approach.h"

namespace pbdsplat::scene {

// The frame's resources as the passes added so far left them (each write gives the next
// version) on the blackboard, and what the scene has.
struct SceneRuntime::GraphAssembly {
    graph::Blackboard board;
    bool boundary = false, drags = false, sorted = false, cut_faces_on = false;
};

bool SceneRuntime::has_timed_events() const {
    return !scene_.events.empty() || scene_.render.orbit.degrees_per_second != 0.0f || !scene_.render.path.empty();
}

void SceneRuntime::import_resources(GraphAssembly& h) {
    const SurfaceDesc& sd_surface = scene_.surface;
    const SimulationDesc& sd = scene_.simulation;
    graph::FrameGraph& g = graph_;
    h.boundary = sd_surface.mode == SurfaceMode::boundary;
    h.drags = timeline_->has_drag(*queue_) || options_.interactive;
    // Sorting only matters when splats are composited with "over" and the scene asks for it.
    h.sorted = order_ == render::SplatOrder::cpu;  // the GPU sort is a GPU pass
    const bool has_volume = sd.solver.volume && !body_.volumes.empty();
    const bool has_shape = stiffest_shape(scene_) > 0.0f && body_.shape_matching;
    const bool topology_events = queue_->any(is_topology_event) || options_.interactive;
    graph::Blackboard& board = h.board;
    // The body in its three parts (scene/stages/body_parts.h), each a base of the one body.
    graph::import_into(g, board, keys::body_structure, static_cast<sim::BodyStructure*>(&body_), true);
    graph::import_into(g, board, keys::body_state, static_cast<sim::BodyState*>(&body_), true);
    graph::import_into(g, board, keys::body_caches, static_cast<sim::BodyCaches*>(&body_), true);
    graph::import_into(g, board, keys::timeline, has_timed_events() ? timeline_.get() : static_cast<Timeline*>(nullptr));
    graph::import_into(g, board, keys::volumes, has_volume ? &body_.volumes : static_cast<std::vector<sim::VolumeConstraint>*>(nullptr));
    graph::import_into(g, board, keys::shapes, has_shape ? &body_.shapes : static_cast<std::vector<sim::ShapeCluster>*>(nullptr));
    graph::import_into(g, board, keys::colliders, sd.colliders.empty() ? nullptr : &scene_.simulation.colliders);
    graph::import_into(g, board, keys::drag, h.drags ? &drag_ : static_cast<sim::DragConstraint*>(nullptr));
    const passes::GpuInputHandles gpu_input = passes::import_gpu_input(g, frame_input_);
    board.put(keys::view, gpu_input.frame);
    board.put(keys::splats, gpu_input.splats);
    board.put(keys::occluder_input, gpu_input.occluders);
    graph::import_into(g, board, keys::samples, h.boundary ? &boundary_ : static_cast<surface::BoundaryParticles*>(nullptr));
    graph::import_into(g, board, keys::density, h.boundary ? &density_ : static_cast<surface::DensityControl*>(nullptr));
    graph::import_into(g, board, keys::sort, h.sorted ? &mapping_->sort_scratch() : static_cast<splat::SortScratch*>(nullptr));
    graph::import_into(g, board, keys::stretch, sd_surface.stretch_scale ? &stretch_ : static_cast<splat::StretchScale*>(nullptr));
    graph::import_into(g, board, keys::sink, readback_ ? &sink_ : static_cast<passes::ImageSink*>(nullptr));
    graph::import_into(g, board, keys::appearance, &appearance_);
    graph::import_into(g, board, keys::note, &note_);
    graph::import_into(g, board, keys::queue, queue_.get());
    // The queue again, as a marker read by the topology pass: absent when no cut or tear can come,
    // so that the pass is culled (it is never written through this handle).
    graph::import_into(g, board, keys::cuts, topology_events ? queue_.get() : static_cast<EventQueue*>(nullptr));
    // The faces a cut makes, drawn where surfaces are sampled: once cuts can come, and for as long
    // as the body has openings (the graph is rebuilt after the last cut).
    const bool opened = std::any_of(body_.volumes.begin(), body_.volumes.end(), [](const sim::VolumeConstraint& v) { return v.opened(); });
    h.cut_faces_on = (topology_events || opened) && h_ > 0.0f;
    graph::import_into(g, board, keys::cut_faces, h.cut_faces_on ? &cut_faces_ : static_cast<splat::CutFaces*>(nullptr));
    graph::import_into(g, board, keys::changes, &changes_);
    graph::import_into(g, board, keys::fine_embedding, fine_ ? &fine_vertices_ : static_cast<std::optional<surface::BoundaryParticles>*>(nullptr));
    graph::import_into(g, board, keys::map_settings, &map_settings_);
    graph::import_into(g, board, keys::mapping, mapping_.get());
}

void SceneRuntime::add_surface_and_map_passes(GraphAssembly& h) {
    graph::FrameGraph& g = graph_;
    graph::Blackboard& board = h.board;
    graph::import_into(g, board, keys::density_stats, &density_stats_);
    graph::import_into(g, board, keys::stillness, &stillness_);
    add_stillness_pass(g, board, tag(PassGroup::update));
    SurfacePassConfig surface{splat_particles_, h_, scene_.surface.seed, tag(PassGroup::update)};
    const render::SplatStyle& style = scene_.render.frame.style;
    surface.thin = style.thin_below > 0.0f && style.blend == render::Blend::normalised;
    surface.pool = pool_.get();
    add_surface_passes(g, board, surface);
    if (h.boundary && !paint_.empty()) {
        graph::import_into(g, board, keys::paint, &paint_);
        add_paint_pass(g, board, tag(PassGroup::update));
    }
    map_settings_.particles = splat_particles_;
    map_settings_.cull_back = scene_.render.cull_back;
    map_settings_.draw_ground = scene_.render.ground;
    map_settings_.ground = scene_.simulation.colliders.ground;
    MapPassOptions mo{h.boundary, scene_.surface.stretch_scale, h.sorted, options_.keep_records, !paused_, tag(PassGroup::update)};
    mo.cut_faces = h.cut_faces_on;
    mo.stillness = true;
    add_mapping_passes(g, board, mo);
}

void SceneRuntime::fingerprint_resources(const GraphAssembly& h) {
    graph::FrameGraph& g = graph_;
    const auto print = [](const auto& resource) { return fingerprint(resource); };
    const graph::Blackboard& board = h.board;
    g.set_fingerprint<sim::BodyStructure>(board.get(keys::body_structure), print);
    g.set_fingerprint<sim::BodyState>(board.get(keys::body_state), print);
    g.set_fingerprint<sim::BodyCaches>(board.get(keys::body_caches), print);
    g.set_fingerprint<splat::Appearance>(board.get(keys::appearance), print);
    g.set_fingerprint<render::FrameInputs>(board.get(keys::view), print);
    g.set_fingerprint<passes::SplatStream>(board.get(keys::splats), print);
    g.set_fingerprint<std::string>(board.get(keys::note), print);
    g.set_fingerprint<MapSettings>(board.get(keys::map_settings), print);
    g.set_fingerprint<FrameChanges>(board.get(keys::changes), print);
    if (h.drags) g.set_fingerprint<sim::DragConstraint>(board.get(keys::drag), print);
    if (h.boundary) g.set_fingerprint<surface::BoundaryParticles>(board.get(keys::samples), print);
    g.check_writes(true);
}

uint32_t SceneRuntime::frame_substeps() const {
    return sim::frame_substeps(scene_.simulation.solver, body_, solver_->contact(), scene_.simulation.dt, k_max_sweeps);
}

core::Status SceneRuntime::build_graph() {
    graph_ = graph::FrameGraph();
    GraphAssembly h;
    import_resources(h);
    // Paused: nothing moves, so no simulation stage runs; the frame is drawn again as it was.
    if (!paused_) {
        add_frame_event_passes(h, has_timed_events());
        step_settings_ = scene_.simulation.solver;
        step_settings_.tuned_substeps = step_settings_.substeps;
        step_settings_.substeps = frame_substeps();
        add_simulation_passes(graph_, h.board, *solver_, step_settings_, scene_.simulation.dt);
    }
    add_surface_and_map_passes(h);
    if (renderer_) add_view_passes(h);
    if (options_.check_writes) fingerprint_resources(h);
    PBDSPLAT_TRY(graph_.compile());
    group_of_kept_pass_.clear();
    for (const graph::PassInfo& p : graph_.describe())
        if (!p.culled) group_of_kept_pass_.push_back(PassGroup(p.tag));
    return core::Status::success();
}

void SceneRuntime::add_frame_event_passes(GraphAssembly& h, bool has_events) {
    graph::FrameGraph& g = graph_;
    const SimulationDesc& sd = scene_.simulation;
    graph::import_into(g, h.board, keys::control, &control_);
    graph::import_into(g, h.board, keys::topology, topology_.get());
    EventPassOptions o;
    o.dt = sd.dt, o.interactive = options_.interactive, o.timeline = has_events;
    o.drags = h.drags;
    o.cut = sd.cut;
    o.tag = tag(PassGroup::events), o.topology_tag = tag(PassGroup::topology);
    add_event_passes(g, h.board, o);
    ChangePassOptions c;
    c.boundary = h.boundary, c.fine = fine_.has_value(), c.stretch = scene_.surface.stretch_scale, c.cut_faces = h.cut_faces_on;
    c.h = h_, c.seed = scene_.surface.seed, c.fade_frames = sd.fade_frames, c.edge_samples = scene_.surface.edge_samples;
    c.tag = tag(PassGroup::topology);
    add_change_passes(g, h.board, c);
}

void SceneRuntime::add_occluder_mesh_pass(GraphAssembly& h) {
    graph::FrameGraph& g = graph_;
    // The surface the splats stand for, as it is this frame, for the occluders' pass.
    auto mesh = g.import("occluder mesh", &occluder_mesh_);
    // The fine surface's embedding, made on the first frame it is drawn (absent, and not
    // declared, without a fine surface).
    auto embedding = h.board.get(keys::fine_embedding);
    BodyParts body = BodyParts::from(h.board);
    const auto cut_faces = h.board.get(keys::cut_faces);
    auto input = h.board.get(keys::occluder_input);
    const auto stillness = h.board.get(keys::stillness);
    const bool cut_faces_on = h.cut_faces_on;
    g.add_pass("occluder mesh", graph::PassKind::cpu, [&](graph::PassBuilder& b) {
        body.declare(b);
        b.read(stillness);
        mesh = b.write(mesh);
        if (fine_) embedding = b.write(embedding);
        if (cut_faces_on) b.read(cut_faces);
        input = b.write(input);
        const mesh::TriangleMesh* fine = fine_ ? &*fine_ : nullptr;  // the model's surface: fixed at load
        const FineCopies* copies = &fine_copies_;
        return [fine, copies, mesh, embedding, body, cut_faces, input, cut_faces_on, stillness](const graph::PassResources& r,
                                                                                        graph::ExecuteContext&) {
            // The body where it was: the mesh made from it then (whose spans the input keeps)
            // stands, unless the fine surface's simplification is still to come.
            if (r.read(stillness).still() && !(fine && r.write(mesh).whole.simplification_due())) return;
            const sim::SoftBody& bd = body.body(r);
            passes::OccluderInput& in = r.write(input);
            // A cut face hides what lies behind it as the shell does.
            const splat::CutFaces* faces = cut_faces_on ? &r.read(cut_faces) : nullptr;
            const std::vector<uint8_t> solid = solid_pieces(bd, faces);
            if (const Solids solids = which_solid(solid); !fine && !(faces && faces->faces() > 0) && solids != Solids::some) {
                // The body's own triangles as they are (not copied): all solid or none.
                in.positions = bd.particles.x;
                in.triangles = bd.triangles;
                in.one_sided = solids == Solids::all ? bd.triangles.size() : 0;
                return;
            }
            OccluderMesh& m = r.write(mesh);
            if (fine) {
                deformed_fine_surface(bd, *fine, *copies, r.write(embedding), m.x, m.triangles, &m.whole);
            } else {
                m.x = bd.particles.x;
                m.triangles = bd.triangles;
            }
            const SolidOrder order = order_solids_first(bd, solid, m.triangles, fine ? &*r.write(embedding) : nullptr);
            if (faces) faces->append_surface(bd.particles.x, m.x, m.triangles);
            in.positions = m.x;
            in.triangles = m.triangles;
            in.one_sided = order.one_sided(m.triangles.size());
        };
    }, tag(PassGroup::update));
    h.board.put(keys::occluder_input, input);
    h.board.put(keys::fine_embedding, embedding);
}

graph::Handle<graph::GpuImageRef> SceneRuntime::add_mesh_view_pass(GraphAssembly& h) {
    graph::FrameGraph& g = graph_;
    auto mesh_color = g.import("mesh colour", &mesh_color_);
    auto mesh_depth = g.import("mesh depth", &mesh_depth_);
    auto raster = g.import("mesh raster", mesh_raster_.get());
    auto splats = g.import("splat renderer", renderer_.get());
    BodyParts body = BodyParts::from(h.board);
    const auto view = h.board.get(keys::view);
    const auto appearance = h.board.get(keys::appearance);
    auto note = h.board.get(keys::note);
    g.add_pass("mesh", graph::PassKind::gpu, [&](graph::PassBuilder& b) {
        body.declare(b);
        b.read(view);
        b.read(appearance);
        b.read(splats);
        raster = b.write(raster);
        note = b.write(note);
        mesh_color = b.write(mesh_color, passes::to_graph(render::uses::color_attachment));
        b.write(mesh_depth, passes::to_graph(render::uses::depth_attachment));
        return [body, view, appearance, note, raster, splats](const graph::PassResources& r, graph::ExecuteContext& c) {
            render::MeshRaster& mesh = r.write(raster);
            const sim::SoftBody& bd = body.body(r);
            const uint32_t slot = r.read(splats).slot();
            if (const core::Status s = mesh.set_mesh(particles_with_models(bd), bd.triangles, bd.normals, slot, bd.colors); !s.ok())
                r.write(note) = "mesh view: " + s.error().to_string();  // drawn with the last mesh that fitted
            // Drawn in the body's own colours where it has them, as its splats are.
            const Vec3f albedo = bd.colors.empty() ? r.read(appearance).albedo : Vec3f::Ones();
            mesh.draw(c.cmd, r.read(view), render::MeshView::shaded, albedo, slot);
        };
    });
    h.board.put(keys::note, note);
    return mesh_color;
}

void SceneRuntime::add_view_passes(GraphAssembly& h) {
    graph::FrameGraph& g = graph_;
    if (renderer_->has_occluders()) add_occluder_mesh_pass(h);
    const auto status = g.import("upload status", &upload_status_, true);
    const auto drawn = passes::add_gpu_passes(g, *renderer_, gpu_resources_,
                                              {h.board.get(keys::view), h.board.get(keys::splats), h.board.get(keys::occluder_input)}, status, h.board.get(keys::sink), order_ == render::SplatOrder::gpu,
                                              tag(PassGroup::gpu_record));
    passes::PresentSources sources{drawn, {}, renderer_->width(), renderer_->height(),
                                   [renderer = renderer_.get()] { return renderer->slot(); }};
    if (mesh_raster_ && (view_ == DisplayView::mesh || view_ == DisplayView::side_by_side)) sources.mesh = add_mesh_view_pass(h);
    if (options_.presenter) options_.presenter->add_passes(g, sources);
}

} // namespace pbdsplat::scene
