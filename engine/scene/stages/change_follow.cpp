#include "scene/stages/change_follow.h"


namespace pbdsplat::scene {

SurfaceFollow ChangeFollowers::surface_follow() const {
    SurfaceFollow f;
    f.samples = t_.samples;
    f.fine_vertices = t_.fine_vertices && *t_.fine_vertices ? &**t_.fine_vertices : nullptr;
    f.density = t_.density;
    f.h = t_.h;
    f.seed = t_.seed;
    f.fade_frames = t_.fade_frames;
    f.edge_samples = t_.edge_samples;
    f.particles_are_splats = t_.map_settings->particles;
    return f;
}

core::Result<std::vector<uint32_t>> ChangeFollowers::after_each(const sim::SoftBody& body, const topology::TopologyChange& change,
                                                                const topology::CutSurface* cut) {
    // Only a cut or tear can open the boundary, and only where it touched.
    MapSettings& view = *t_.map_settings;
    if (view.closed) view.closed = !opens_boundary(body, change.touched_triangles);
    if (cut && t_.cut_faces) t_.cut_faces->cut_made();
    t_.mapping->topology_changed(body, change, view.particles);
    if (!t_.samples) return std::vector<uint32_t>{};
    return carry_samples_across(surface_follow(), body, change, cut);
}

core::Status ChangeFollowers::settle(const sim::SoftBody& body, std::span<const uint32_t> touched, size_t seed_offset) {
    if (t_.samples) refill_touched(surface_follow(), body, touched, seed_offset);
    if (!t_.stretch->empty()) *t_.stretch = splat::StretchScale(body.rest_positions, body.triangles);
    return core::Status::success();
}

TopologyStage::Follow ChangeFollowers::follow(const sim::SoftBody& body) {
    TopologyStage::Follow f;
    f.each = [this, &body](const topology::TopologyChange& c, const topology::CutSurface* cut) { return after_each(body, c, cut); };
    f.settle = [this, &body](std::span<const uint32_t> touched, size_t seed_offset) { return settle(body, touched, seed_offset); };
    return f;
}

} // namespace pbdsplat::scene
