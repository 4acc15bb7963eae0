#include "scene/stages/mapping_stage.h"

#include "scene/stages/body_view.h"
#include "scene/stages/frame_keys.h"

namespace pbdsplat::scene {

MappingStage::MappingStage(const sim::SoftBody& body, uint32_t fade_frames, bool deformed, bool varying_normals)
    : varying_normals_(varying_normals), fade_(fade_frames) {
    if (deformed) deformed_ = splat::DeformedShapes(body.rest_positions, body.triangles);
}

void MappingStage::map(const Sources& s, const splat::Appearance& look) {
    const sim::SoftBody& body = *s.body;
    if (varying_normals_)
        normal_field_.update(body.particles.x, body.normals, body.triangles, s.particles, splat::curvature_limit(look.scale));
    splat::map_body(s.particles ? std::span<const Vec4f>(body.particles.x) : std::span<const Vec4f>(),
                    s.particles ? std::span<const Vec3f>(body.normals) : std::span<const Vec3f>(), body.colors, body.triangles,
                    s.samples, look, s.stretch, varying_normals_ ? &normal_field_ : nullptr, records_);
    if (!deformed_.empty()) {
        deformed_.update(body.particles.x, body.triangles);
        deformed_.map(s.particles ? body.particle_count() : 0, s.samples, records_, shapes_);
    }
    fade_.apply(records_);
    if (s.cut_faces) s.cut_faces->append_records(body.particles.x, body.colors, look, records_, deformed_.empty() ? nullptr : &shapes_);
}

void MappingStage::sort(const render::Camera& c) {
    splat::sort_far_to_near(records_, shapes_, math::look_at(c.eye, c.target, c.up), sort_scratch_);
}

void MappingStage::publish(passes::GpuFrameInput& input, bool moved) {
    input.records = records_;
    input.shapes = shapes_;
    if (moved) {
        input.changed.clear();  // everything
        previous_valid_ = false;
        return;
    }
    if (previous_valid_) passes::changed_ranges(previous_, records_, input.changed);
    else input.changed.clear();
    previous_ = records_;
    previous_valid_ = true;
}

void MappingStage::topology_changed(const sim::SoftBody& body, const topology::TopologyChange& change, bool particles) {
    if (particles) fade_.add_particles(change.particles_before, change.new_particles());
    if (!deformed_.empty()) deformed_ = splat::DeformedShapes(body.rest_positions, body.triangles);
}

namespace {
struct MapHandles {
    graph::Handle<sim::SoftBody> body;
    graph::Handle<surface::BoundaryParticles> samples;
    graph::Handle<splat::StretchScale> stretch;
    graph::Handle<splat::SortScratch> sort;
    graph::Handle<splat::Appearance> appearance;
    graph::Handle<MapSettings> settings;
    graph::Handle<MappingStage> mapping;
    graph::Handle<passes::GpuFrameInput> input;
    graph::Handle<splat::CutFaces> cut_faces;
};
} // namespace

void add_mapping_passes(graph::FrameGraph& g, graph::Blackboard& board, const MapPassOptions& o) {
    MapHandles h{board.get(keys::body),       board.get(keys::samples),      board.get(keys::stretch),
                 board.get(keys::sort),       board.get(keys::appearance),   board.get(keys::map_settings),
                 board.get(keys::mapping),    board.get(keys::input),        board.get(keys::cut_faces)};
    g.add_pass("map", graph::PassKind::cpu, [&](graph::PassBuilder& b) {
        b.read(h.body);
        if (o.boundary) b.read(h.samples);
        if (o.stretch) b.read(h.stretch);
        b.read(h.appearance);
        b.read(h.settings);
        h.mapping = b.write(h.mapping);
        h.input = b.write(h.input);
        if (o.cut_faces) h.cut_faces = b.write(h.cut_faces);
        if (o.keep_records) b.side_effect();
        return [o, hh = h](const graph::PassResources& r, graph::ExecuteContext&) {
            const sim::SoftBody& body = r.read(hh.body);
            const MapSettings& settings = r.read(hh.settings);
            const splat::Appearance& look = r.read(hh.appearance);
            MappingStage& mapping = r.write(hh.mapping);
            passes::GpuFrameInput& input = r.write(hh.input);
            MappingStage::Sources sources;
            sources.body = &body;
            sources.particles = settings.particles;
            sources.samples = o.boundary && settings.show_boundary ? &r.read(hh.samples) : nullptr;
            const splat::StretchScale* stretch = o.stretch ? &r.read(hh.stretch) : nullptr;
            sources.stretch = stretch && !stretch->empty() ? stretch : nullptr;
            if (o.cut_faces) {
                splat::CutFaces& faces = r.write(hh.cut_faces);
                faces.update(body);
                sources.cut_faces = &faces;
            }
            mapping.map(sources, look);
            BodyViewOptions view;
            view.cull_back = settings.cull_back;
            view.closed = settings.closed;
            view.opaque = input.frame.style.blend != render::Blend::additive && look.opacity_logit > math::logit(0.9f);
            view.draw_ground = settings.draw_ground;
            follow_body(body.particles.x, settings.ground, view, input.frame);
            if (!o.sorted) mapping.publish(input, o.moved);  // else the sort pass reorders them first
        };
    }, o.tag);
    g.add_pass("sort", graph::PassKind::cpu, [&](graph::PassBuilder& b) {
        b.read(h.sort);
        h.mapping = b.write(h.mapping);
        h.input = b.write(h.input);
        if (o.keep_records) b.side_effect();
        return [moved = o.moved, hh = h](const graph::PassResources& r, graph::ExecuteContext&) {
            MappingStage& mapping = r.write(hh.mapping);
            passes::GpuFrameInput& input = r.write(hh.input);
            mapping.sort(input.frame.camera);
            mapping.publish(input, moved);
        };
    }, o.tag);
    board.put(keys::input, h.input);
    board.put(keys::cut_faces, h.cut_faces);
}

} // namespace pbdsplat::scene
