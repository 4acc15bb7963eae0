#include "scene/stages/mapping_stage.h"

#include "scene/stages/body_parts.h"
#include "scene/stages/body_view.h"
#include "scene/stages/frame_keys.h"
#include "scene/stages/solid_pieces.h"
#include "scene/stages/stillness.h"
#include "scene/stages/surface_stage.h"

namespace pbdsplat::scene {

MappingStage::MappingStage(const sim::SoftBody& body, uint32_t fade_frames, bool deformed, bool varying_normals, core::ThreadPool* pool)
    : varying_normals_(varying_normals), pool_(pool), fade_(fade_frames) {
    if (deformed) deformed_ = splat::DeformedShapes(body.rest_positions, body.triangles);
}

bool MappingStage::made_like(const Sources& s, const splat::Appearance& look) const {
    return made_.valid && made_.particles == s.particles && made_.samples == (s.samples != nullptr) &&
           made_.stretch == (s.stretch != nullptr) && made_.cut_faces == (s.cut_faces != nullptr) && made_.look == look;
}

bool MappingStage::stands(const Sources& s, const splat::Appearance& look, bool body_still, bool samples_still) const {
    return made_like(s, look) && body_still && (samples_still || !s.samples) && fade_.fading() == 0 &&
           (!s.cut_faces || !s.cut_faces->fading());
}

bool MappingStage::keeps(const Sources& s, const splat::Appearance& look, const Unmoved& unmoved) const {
    return s.samples && !unmoved.moved_triangles.empty() && unmoved.samples_same && made_like(s, look) &&
           made_.particle_count == (s.particles ? s.body->particle_count() : 0) && made_.sample_count == s.samples->size() &&
           unmoved.moved_triangles.size() == s.body->triangles.size();
}

namespace {
// Each record's model, whose centre its environment lookups look out from (gpu_types.h): a
// particle's own, a sample's that of its triangle's.
void mark_models(const sim::SoftBody& body, const MappingStage::Sources& s, std::span<const uint8_t> kept,
                 std::vector<splat::GaussianRecord>& records) {
    const size_t n = s.particles ? body.particle_count() : 0;
    for (size_t i = 0; i < n; ++i) splat::set_model(records[i], body.model_of_particle[i]);
    if (!s.samples) return;
    for (size_t k = 0; k < s.samples->size(); ++k)
        if (kept.empty() || !kept[k]) splat::set_model(records[n + k], body.model_of_particle[body.triangles[s.samples->triangle[k]][0]]);
}
} // namespace

void MappingStage::map(const Sources& s, const splat::Appearance& look) { map(s, look, Unmoved{}); }

void MappingStage::map(const Sources& s, const splat::Appearance& look, const Unmoved& unmoved) {
    const sim::SoftBody& body = *s.body;
    kept_.clear(), kept_count_ = 0;
    if (keeps(s, look, unmoved)) {
        const surface::BoundaryParticles& sm = *s.samples;
        kept_.resize(sm.size());
        for (size_t k = 0; k < sm.size(); ++k) {
            kept_[k] = !unmoved.moved_triangles[sm.triangle[k]] && !(k < sm.fade_step.size() && sm.fade_step[k] != 0.0f);
            kept_count_ += kept_[k];
        }
        if (kept_count_ == 0) kept_.clear();
    }
    made_ = {true, s.particles, s.samples != nullptr, s.stretch != nullptr, s.cut_faces != nullptr, look,
             s.particles ? body.particle_count() : 0, s.samples ? s.samples->size() : 0};
    if (varying_normals_)
        normal_field_.update(body.particles.x, body.normals, body.triangles, s.particles, splat::curvature_limit(look.scale));
    splat::map_body(s.particles ? std::span<const Vec4f>(body.particles.x) : std::span<const Vec4f>(),
                    s.particles ? std::span<const Vec3f>(body.normals) : std::span<const Vec3f>(), body.colors, body.triangles,
                    s.samples, look, s.stretch, varying_normals_ ? &normal_field_ : nullptr, records_, pool_, kept_);
    if (!deformed_.empty()) {
        deformed_.update(body.particles.x, body.triangles);
        deformed_.map(s.particles ? body.particle_count() : 0, s.samples, records_, shapes_);
    }
    fade_.apply(records_);
    const std::span<const uint32_t> models = body.model_count() > 1 ? std::span<const uint32_t>(body.model_of_particle) : std::span<const uint32_t>();
    if (!models.empty()) mark_models(body, s, kept_, records_);
    if (s.cut_faces) s.cut_faces->append_records(body.particles.x, body.colors, look, records_, deformed_.empty() ? nullptr : &shapes_, models);
    // Once a frame drew textured splats, every later one hands entries over too (untextured where
    // nothing is, as when the boundary splats are hidden): the renderer would read the last ones.
    static const surface::BoundaryParticles no_samples;
    const bool textured = (s.samples && !s.samples->texcoord.empty()) || (s.particles && !body.texcoords.empty());
    if (textured || !texcoords_.empty())
        splat::map_texcoords(body.rest_positions, body.particles.x, body.triangles, s.particles ? body.particle_count() : 0,
                             body.texcoords, s.samples ? *s.samples : no_samples, records_.size(), texcoords_, texcoord_scratch_);
}

void MappingStage::sort(const render::Camera& c) {
    splat::sort_far_to_near(records_, shapes_, math::look_at(c.eye, c.target, c.up), sort_scratch_);
    splat::reorder_like_last_sort(sort_scratch_, texcoords_);
}

void MappingStage::publish(passes::SplatStream& input, bool moved) {
    input.records = records_;
    input.shapes = shapes_;
    input.texcoords = texcoords_;
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

void MappingStage::publish_unchanged(passes::SplatStream& input) const {
    input.records = records_;
    input.shapes = shapes_;
    input.texcoords = texcoords_;
    input.changed.assign(1, gpu::ByteRange{0, 0});  // nothing: an empty range, not "everything"
}

void MappingStage::topology_changed(const sim::SoftBody& body, const topology::TopologyChange& change, bool particles) {
    if (particles) fade_.add_particles(change.particles_before, change.new_particles());
    if (!deformed_.empty()) deformed_ = splat::DeformedShapes(body.rest_positions, body.triangles);
}

namespace {
struct MapHandles {
    BodyParts body;
    graph::Handle<surface::BoundaryParticles> samples;
    graph::Handle<splat::StretchScale> stretch;
    graph::Handle<splat::SortScratch> sort;
    graph::Handle<splat::Appearance> appearance;
    graph::Handle<MapSettings> settings;
    graph::Handle<MappingStage> mapping;
    graph::Handle<render::FrameInputs> frame;
    graph::Handle<passes::SplatStream> splats;
    graph::Handle<splat::CutFaces> cut_faces;
    graph::Handle<Stillness> stillness;
    graph::Handle<surface::DensityStats> density_stats;
};

// Nothing the density control did this frame changed a sample's place, count or fade.
bool samples_quiet(const surface::DensityStats& s) {
    return s.resampled == 0 && s.inserted == 0 && s.retired == 0 && s.removed == 0 && s.fading == 0;
}

void map_frame(const MapPassOptions& o, const MapHandles& hh, const graph::PassResources& r) {
    const sim::SoftBody& body = hh.body.body(r);
    const MapSettings& settings = r.read(hh.settings);
    const splat::Appearance& look = r.read(hh.appearance);
    MappingStage& mapping = r.write(hh.mapping);
    render::FrameInputs& frame = r.write(hh.frame);
    MappingStage::Sources sources;
    sources.body = &body;
    sources.particles = settings.particles;
    sources.samples = o.boundary && settings.show_boundary ? &r.read(hh.samples) : nullptr;
    const splat::StretchScale* stretch = o.stretch ? &r.read(hh.stretch) : nullptr;
    sources.stretch = stretch && !stretch->empty() ? stretch : nullptr;
    splat::CutFaces* faces = o.cut_faces ? &r.write(hh.cut_faces) : nullptr;
    sources.cut_faces = faces;
    // A sorted frame sorts the records it makes: they are made again whatever stands.
    const bool body_still = o.stillness && r.read(hh.stillness).still();
    const bool quiet = o.stillness && o.boundary && samples_quiet(r.read(hh.density_stats));
    const bool stands = !o.sorted && mapping.stands(sources, look, body_still, quiet);
    if (!stands) {
        if (faces) faces->update(body);
        MappingStage::Unmoved unmoved;
        if (o.stillness && !o.sorted) {
            unmoved.moved_triangles = r.read(hh.stillness).moved_triangles();
            if (o.boundary) {
                const surface::DensityStats& d = r.read(hh.density_stats);
                unmoved.samples_same = d.inserted == 0 && d.removed == 0 && d.resampled == 0;
            }
        }
        mapping.map(sources, look, unmoved);
    }
    BodyViewOptions view;
    view.cull_back = settings.cull_back;
    // A cut opens the simulation mesh, but a body whose every piece is a solid closed by its
    // drawn cut faces (solid_pieces) still has a far side that cannot show, once those faces
    // stand opaque: while one fades in, the inside shows through it.
    view.closed = settings.closed || (faces && !faces->fading() && which_solid(solid_pieces(body, faces)) == Solids::all);
    view.opaque = frame.style.blend != render::Blend::additive && look.opacity_logit > math::logit(0.9f);
    view.draw_ground = settings.draw_ground;
    follow_body({body.particles.x, body.piece_of_particle, body.pieces, body.model_of_particle}, settings.ground, view, frame);
    if (o.sorted) return;  // the sort pass reorders them first
    if (stands) mapping.publish_unchanged(r.write(hh.splats));
    else mapping.publish(r.write(hh.splats), o.moved);
}
} // namespace

void add_mapping_passes(graph::FrameGraph& g, graph::Blackboard& board, const MapPassOptions& o) {
    MapHandles h{BodyParts::from(board),      board.get(keys::samples),      board.get(keys::stretch),
                 board.get(keys::sort),       board.get(keys::appearance),   board.get(keys::map_settings),
                 board.get(keys::mapping),    board.get(keys::view),         board.get(keys::splats),
                 board.get(keys::cut_faces),  board.get(keys::stillness),    board.get(keys::density_stats)};
    g.add_pass("map", graph::PassKind::cpu, [&](graph::PassBuilder& b) {
        h.body.declare(b);
        if (o.boundary) b.read(h.samples);
        if (o.stretch) b.read(h.stretch);
        if (o.stillness) b.read(h.stillness);
        if (o.stillness && o.boundary) b.read(h.density_stats);
        b.read(h.appearance);
        b.read(h.settings);
        h.mapping = b.write(h.mapping);
        h.frame = b.write(h.frame);  // the view follows the body
        if (!o.sorted) h.splats = b.write(h.splats);
        if (o.cut_faces) h.cut_faces = b.write(h.cut_faces);
        if (o.keep_records) b.side_effect();
        return [o, hh = h](const graph::PassResources& r, graph::ExecuteContext&) { map_frame(o, hh, r); };
    }, o.tag);
    g.add_pass("sort", graph::PassKind::cpu, [&](graph::PassBuilder& b) {
        b.read(h.sort);
        h.mapping = b.write(h.mapping);
        b.read(h.frame);
        h.splats = b.write(h.splats);
        if (o.keep_records) b.side_effect();
        return [moved = o.moved, hh = h](const graph::PassResources& r, graph::ExecuteContext&) {
            MappingStage& mapping = r.write(hh.mapping);
            mapping.sort(r.read(hh.frame).camera);
            mapping.publish(r.write(hh.splats), moved);
        };
    }, o.tag);
    board.put(keys::view, h.frame);
    board.put(keys::splats, h.splats);
    board.put(keys::cut_faces, h.cut_faces);
}

} // namespace pbdsplat::scene
