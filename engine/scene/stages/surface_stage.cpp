#include "scene/stages/surface_stage.h"

#include <algorithm>
#include <vector>

#include "mesh/topology.h"
#include "surface/edges.h"
#include "surface/remap.h"

namespace pbdsplat::scene {

core::Result<SurfaceSetup> setup_surface(const SurfaceDesc& desc, uint32_t fade_frames, const sim::SoftBody& body,
                                         const std::optional<mesh::TriangleMesh>& fine, surface::BoundaryParticles& samples,
                                         surface::EmbeddingStats& embedding, surface::DensityControl& density) {
    SurfaceSetup out;
    const mesh::TriangleMesh rest{body.rest_positions, body.triangles, {}, {}, {}};
    const bool boundary = desc.mode == SurfaceMode::boundary;
    // Boundary particles sample the model's own surface (h from its edges) and ride on the
    // simulation mesh; without a separate model surface they sample the simulation mesh. The
    // vertices-only mode keeps the same h, so its splats are as large as with boundary
    // particles and show the holes those close (the paper's Figure 14a against 14b).
    out.h = boundary && fine ? surface::spacing(*fine, desc.eta) : surface::spacing(rest, desc.eta);
    if (!(out.h > 0.0f)) return core::make_error("the mesh has no edges to derive the sampling spacing from");
    // With an embedded surface the samples are the splats: the simulation particles sit on the
    // coarse mesh, off the model's surface wherever it curves, and after a cut the new ones
    // lie on the coarse cut line, away from the fine samples: drawn, they float as strays.
    out.particles_are_splats = !(boundary && fine);
    if (boundary && fine) {
        const auto points = surface::sample_points(*fine, {}, {out.h, desc.seed});
        surface::embed_points(points, body.rest_positions, body.triangles, body.normals, samples, &embedding);
    } else if (boundary) {
        samples = surface::sample_surface(rest, {out.h, desc.seed});
    }
    if (boundary && desc.edge_samples) surface::lay_edge_samples(body.rest_positions, body.triangles, out.h, {}, samples);
    if (boundary && desc.density.enabled) {
        surface::DensityOptions o = desc.density;
        o.fade_frames = fade_frames;
        density = surface::DensityControl(body.rest_positions, body.triangles, o);
    }
    return out;
}

void add_surface_passes(graph::FrameGraph& g, SurfaceHandles& h, const SurfacePassConfig& config) {
    g.add_pass(
        "boundary particles", graph::PassKind::cpu,
        [&](graph::PassBuilder& b) {
            b.read(h.body);
            h.samples = b.write(h.samples);
            return [body = h.body, samples = h.samples](const graph::PassResources& r, graph::ExecuteContext&) {
                const sim::SoftBody& bd = r.get(body);
                surface::update_boundary_particles(bd.triangles, bd.particles.x, bd.normals, r.get(samples));
            };
        },
        config.tag);
    // Also advances the fades of samples a cut or tear added.
    g.add_pass(
        "density", graph::PassKind::cpu,
        [&](graph::PassBuilder& b) {
            b.read(h.body);
            b.read(h.density);
            h.samples = b.write(h.samples);
            h.density_stats = b.write(h.density_stats);
            return [config, body = h.body, samples = h.samples, density = h.density, stats = h.density_stats](
                       const graph::PassResources& r, graph::ExecuteContext&) {
                const sim::SoftBody& bd = r.get(body);
                surface::DensityStats& out = r.get(stats);
                surface::DensityControl& control = r.get(density);
                if (control.empty()) {
                    out = {};
                    out.removed = uint32_t(surface::advance_fades(r.get(samples), &out.fading));
                    return;
                }
                out = control.update(bd.particles.x, bd.normals, bd.triangles, config.particles_are_splats, config.h, config.seed,
                                     r.get(samples));
            };
        },
        config.tag);
    g.add_pass(
        "stretch", graph::PassKind::cpu,
        [&](graph::PassBuilder& b) {
            b.read(h.body);
            h.stretch = b.write(h.stretch);
            return [body = h.body, stretch = h.stretch](const graph::PassResources& r, graph::ExecuteContext&) {
                const sim::SoftBody& bd = r.get(body);
                r.get(stretch).update(bd.particles.x, bd.triangles);
            };
        },
        config.tag);
}

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
