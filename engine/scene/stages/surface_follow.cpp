#include "scene/stages/surface_follow.h"

#include <algorithm>
#include <vector>

#include "mesh/topology.h"
#include "surface/edges.h"
#include "surface/remap.h"

namespace pbdsplat::scene {

void follow_topology_change(const SurfaceFollow& f, const sim::SoftBody& body, const topology::TopologyChange& change,
                            const topology::CutSurface* cut, size_t seed_offset) {
    surface::BoundaryParticles& samples = *f.samples;
    surface::remap_samples(change.splits, samples);
    if (f.fine_vertices) surface::remap_samples(change.splits, *f.fine_vertices);
    std::vector<uint32_t> refill(change.touched_triangles.begin(), change.touched_triangles.end());
    if (cut && samples.embedded()) {
        const auto side = [cut](const Vec3f& p) {
            const float d = cut->distance(p);
            return cut->reaches(p - d * cut->normal) ? d : 0.0f;
        };
        std::vector<uint32_t> emptied;
        surface::drop_across_cut(side, body.triangles, body.particles.x, samples, &emptied);
        // Where samples were dropped beyond the re-triangulated ones, refill too.
        refill.insert(refill.end(), emptied.begin(), emptied.end());
        std::sort(refill.begin(), refill.end());
        refill.erase(std::unique(refill.begin(), refill.end()), refill.end());
    }
    // Edge samples are laid afresh along the new boundary, after the refill.
    if (f.edge_samples) samples.keep_if([&samples](size_t i) { return !samples.on_edge(i); });
    const size_t before = samples.size();
    std::vector<uint32_t> piece;
    mesh::vertex_components(body.triangles, body.particle_count(), piece);
    surface::fill_triangles(body.rest_positions, body.triangles, refill,
                            f.particles_are_splats ? std::span<const Vec3f>(body.rest_positions) : std::span<const Vec3f>(), piece,
                            {f.h, f.seed + uint32_t(seed_offset)}, samples);
    const size_t edges_first = samples.size();
    if (f.edge_samples) surface::lay_edge_samples(body.rest_positions, body.triangles, f.h, {}, samples);
    surface::update_boundary_particles(body.triangles, body.particles.x, body.normals, samples);
    surface::fade_in(samples, before, f.fade_frames);
    // Edge samples that were there before the change (on untouched triangles) stay shown.
    std::vector<bool> touched(body.triangles.size(), false);
    for (uint32_t t : refill) touched[t] = true;
    for (size_t i = edges_first; i < samples.size(); ++i)
        if (!touched[samples.triangle[i]]) samples.fade[i] = 1.0f, samples.fade_step[i] = 0.0f;
    if (f.density && !f.density->empty()) f.density->topology_changed(body.rest_positions, body.triangles, refill);
}

} // namespace pbdsplat::scene
