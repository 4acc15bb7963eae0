#include "scene/stages/mapping_stage.h"

namespace pbdsplat::scene {

MappingStage::MappingStage(const sim::SoftBody& body, uint32_t fade_frames, bool deformed) : fade_(fade_frames) {
    if (deformed) deformed_ = splat::DeformedShapes(body.rest_positions, body.triangles);
}

void MappingStage::map(const Sources& s, const splat::Appearance& look) {
    const sim::SoftBody& body = *s.body;
    splat::map_body(s.particles ? std::span<const Vec4f>(body.particles.x) : std::span<const Vec4f>(),
                    s.particles ? std::span<const Vec3f>(body.normals) : std::span<const Vec3f>(), body.colors, body.triangles,
                    s.samples, look, s.stretch, records_);
    if (!deformed_.empty()) {
        deformed_.update(body.particles.x, body.triangles);
        deformed_.map(s.particles ? body.particle_count() : 0, s.samples, records_, shapes_);
    }
    fade_.apply(records_);
}

void MappingStage::sort(const render::Camera& c) {
    splat::sort_far_to_near(records_, shapes_, math::look_at(c.eye, c.target, c.up), sort_scratch_);
}

void MappingStage::publish(passes::GpuFrameInput& input) {
    input.records = records_;
    input.shapes = shapes_;
    passes::changed_ranges(previous_, records_, input.changed);
    previous_ = records_;
}

void MappingStage::topology_changed(const sim::SoftBody& body, const topology::TopologyChange& change, bool particles) {
    if (particles) fade_.add_particles(change.particles_before, change.new_particles());
    if (!deformed_.empty()) deformed_ = splat::DeformedShapes(body.rest_positions, body.triangles);
}

} // namespace pbdsplat::scene
