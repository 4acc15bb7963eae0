#include "scene/stages/surface_stage.h"

#include <algorithm>
#include <vector>

#include "mesh/topology.h"
#include "scene/stages/body_parts.h"
#include "scene/stages/frame_keys.h"
#include "scene/stages/stillness.h"
#include "surface/edges.h"
#include "surface/remap.h"
#include "surface/thin_parts.h"
#include "surface/thin_order.h"

namespace pbdsplat::scene {

core::Result<SurfaceSetup> setup_surface(const SurfaceDesc& desc, uint32_t fade_frames, const sim::SoftBody& body,
                                         const std::optional<mesh::TriangleMesh>& fine, surface::BoundaryParticles& samples,
                                         surface::EmbeddingStats& embedding, surface::DensityControl& density,
                                         core::ThreadPool* pool) {
    SurfaceSetup out;
    const mesh::TriangleMesh rest{body.rest_positions, body.triangles, {}, {}, {}};
    const bool boundary = desc.mode == SurfaceMode::boundary;
    // Boundary particles sample the model's own surface (h from its edges) and ride on the
    // simulation mesh; without a separate model surface they sample the simulation mesh. The
    // vertices-only mode keeps the same h, so its splats are as large as with boundary
    // particles and show the holes those close (the paper's Figure 14a against 14b).
    const mesh::TriangleMesh& sampled = boundary && fine ? *fine : rest;
    out.edge_h = surface::spacing(sampled, desc.eta);
    if (!(out.edge_h > 0.0f)) return core::make_error("the mesh has no edges to derive the sampling spacing from");
    // A closed part thinner than the edge's spacing would be sampled on one face only.
    out.eta_h = boundary ? std::min(out.edge_h, surface::spacing_for_thin_parts(sampled, out.edge_h)) : out.edge_h;
    // The budget holds only where samples are placed: in vertices mode the splats are the particles.
    out.h = boundary ? std::max(out.eta_h, surface::spacing_for_budget(sampled, desc.sample_budget)) : out.eta_h;
    // With an embedded surface the samples are the splats: the simulation particles sit on the
    // coarse mesh, off the model's surface wherever it curves, and after a cut the new ones
    // lie on the coarse cut line, away from the fine samples: drawn, they float as strays.
    out.particles_are_splats = !(boundary && fine);
    if (boundary && fine) {
        const auto points = surface::sample_points(*fine, {}, {out.h, desc.seed}, pool);
        surface::embed_points(points, body.rest_positions, body.triangles, body.normals, samples, &embedding, pool);
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

namespace {
// New samples (at load, refilled after a change, darted where the surface stretched) join the
// thinning order around the old ones, with their piece: pieces do not cover for each other once
// they part. Around removed samples the order is remade too.
void add_thin_order_pass(graph::FrameGraph& g, graph::Handle<sim::BodyStructure> body, graph::Handle<surface::BoundaryParticles>& samples,
                         const SurfacePassConfig& config) {
    g.add_pass(
        "thin order", graph::PassKind::cpu,
        [&](graph::PassBuilder& b) {
            b.read(body);
            samples = b.write(samples);
            return [config, body, samples](const graph::PassResources& r, graph::ExecuteContext&) {
                surface::BoundaryParticles& s = r.write(samples);
                if (s.thin_level.size() == s.size() && s.thin_gaps.empty()) return;
                const sim::BodyStructure& bd = r.read(body);
                std::vector<uint32_t> piece(s.size());
                for (size_t i = 0; i < s.size(); ++i) piece[i] = bd.piece_of_particle[bd.triangles[s.triangle[i]][0]];
                surface::place_in_thin_order(s.position, s.normal, piece, config.h, s.thin_level, s.thin_gaps);
                s.thin_gaps.clear();
            };
        },
        config.tag);
}

// The stretch-scaled splats' factors follow the triangles' stretch (where the body moved).
void add_stretch_pass(graph::FrameGraph& g, const BodyParts& body, graph::Handle<Stillness> stillness,
                      graph::Handle<splat::StretchScale>& stretch, uint32_t tag) {
    g.add_pass(
        "stretch", graph::PassKind::cpu,
        [&](graph::PassBuilder& b) {
            b.read(body.structure);
            b.read(body.state);
            b.read(stillness);
            stretch = b.write(stretch);
            return [body, stretch, stillness](const graph::PassResources& r, graph::ExecuteContext&) {
                if (r.read(stillness).still()) return;
                r.write(stretch).update(r.read(body.state).particles.x, r.read(body.structure).triangles);
            };
        },
        tag);
}
} // namespace

void add_surface_passes(graph::FrameGraph& g, graph::Blackboard& board, const SurfacePassConfig& config) {
    struct SurfaceHandles {
        BodyParts body;                                     // read
        graph::Handle<surface::BoundaryParticles> samples;  // written
        graph::Handle<surface::DensityControl> density;
        graph::Handle<surface::DensityStats> density_stats;
        graph::Handle<splat::StretchScale> stretch;         // written
        graph::Handle<Stillness> stillness;                 // read
    } h{BodyParts::from(board), board.get(keys::samples), board.get(keys::density), board.get(keys::density_stats),
        board.get(keys::stretch), board.get(keys::stillness)};
    g.add_pass(
        "boundary particles", graph::PassKind::cpu,
        [&](graph::PassBuilder& b) {
            h.body.declare(b);
            b.read(h.stillness);
            h.samples = b.write(h.samples);
            return [body = h.body, samples = h.samples, still = h.stillness, pool = config.pool](const graph::PassResources& r,
                                                                                                  graph::ExecuteContext&) {
                // Where the body has not moved the samples are where its last carry (or the
                // density control, for those it added since) put them.
                const Stillness& stillness = r.read(still);
                if (stillness.still()) return;
                surface::update_boundary_particles(r.read(body.structure).triangles, r.read(body.state).particles.x,
                                                   r.read(body.caches).normals, r.write(samples), 0, pool, stillness.moved_triangles());
            };
        },
        config.tag);
    // Also advances the fades of samples a cut or tear added.
    g.add_pass(
        k_density_pass, graph::PassKind::cpu,
        [&](graph::PassBuilder& b) {
            h.body.declare(b);
            h.density = b.write(h.density);  // its trigger state and fades advance
            h.samples = b.write(h.samples);
            h.density_stats = b.write(h.density_stats);
            return [config, body = h.body, samples = h.samples, density = h.density, stats = h.density_stats](
                       const graph::PassResources& r, graph::ExecuteContext&) {
                const sim::SoftBody& bd = body.body(r);
                surface::DensityStats& out = r.write(stats);
                surface::DensityControl& control = r.write(density);
                if (control.empty()) {
                    out = {};
                    out.removed = uint32_t(surface::advance_fades(r.write(samples), &out.fading));
                    return;
                }
                out = control.update(bd.particles.x, bd.normals, bd.triangles, config.particles_are_splats, config.h, config.seed,
                                     r.write(samples));
            };
        },
        config.tag);
    if (config.thin) add_thin_order_pass(g, h.body.structure, h.samples, config);
    add_stretch_pass(g, h.body, h.stillness, h.stretch, config.tag);
    board.put(keys::samples, h.samples);
    board.put(keys::stretch, h.stretch);
    board.put(keys::density_stats, h.density_stats);
}

namespace {
// Per triangle of `region`: bit k set when edge k is used by that triangle alone, found from the
// rings of its first corner (the body's rings are current after a change).
std::vector<uint8_t> boundary_edges(const sim::SoftBody& body, std::span<const uint32_t> region) {
    std::vector<uint8_t> mask(region.size(), 0);
    for (size_t r = 0; r < region.size(); ++r) {
        const mesh::Triangle& t = body.triangles[region[r]];
        for (int k = 0; k < 3; ++k) {
            if (sim::edge_on_boundary(body.rings, body.triangles, region[r], t[size_t(k)], t[size_t((k + 1) % 3)])) mask[r] |= uint8_t(1u << k);
        }
    }
    return mask;
}
} // namespace

bool opens_boundary(const sim::SoftBody& body, std::span<const uint32_t> triangles) {
    for (uint8_t mask : boundary_edges(body, triangles))
        if (mask) return true;
    return false;
}

std::vector<uint32_t> carry_samples_across(const SurfaceFollow& f, const sim::SoftBody& body, const topology::TopologyChange& change,
                                           const topology::CutSurface* cut) {
    surface::BoundaryParticles& samples = *f.samples;
    surface::remap_samples(change.splits, samples);
    if (f.fine_vertices) surface::remap_samples(change.splits, *f.fine_vertices);
    std::vector<uint32_t> emptied;
    if (cut && samples.embedded()) {
        const auto side = [cut](const Vec3f& p) {
            const float d = cut->distance(p);
            return cut->reaches(p - d * cut->normal) ? d : 0.0f;
        };
        surface::drop_across_cut(side, body.triangles, body.particles.x, samples, &emptied);
    }
    return emptied;
}

void refill_touched(const SurfaceFollow& f, const sim::SoftBody& body, std::span<const uint32_t> refill, size_t seed_offset) {
    surface::BoundaryParticles& samples = *f.samples;
    // Edge samples are laid afresh along the boundary edges of the refilled triangles (where the
    // boundary changed), after the refill; the others keep their place and fade.
    if (f.edge_samples)
        samples.keep_if([&](size_t i) { return !samples.on_edge(i) || !std::binary_search(refill.begin(), refill.end(), samples.triangle[i]); });
    const size_t before = samples.size();
    // Each triangle's piece, from the labels the topology stage keeps (no component count).
    std::vector<uint32_t> piece(body.triangles.size());
    for (size_t t = 0; t < piece.size(); ++t) piece[t] = body.piece_of_particle[body.triangles[t][0]];
    surface::fill_triangles(body.rest_positions, body.triangles, refill,
                            f.particles_are_splats ? std::span<const Vec3f>(body.rest_positions) : std::span<const Vec3f>(), piece,
                            {f.h, f.seed + uint32_t(seed_offset)}, samples);
    if (f.edge_samples) surface::relay_edge_samples(body.rest_positions, body.triangles, refill, boundary_edges(body, refill), f.h, {}, samples);
    // The new samples onto the deformed surface now; the others are current and this frame's
    // boundary pass moves them all.
    surface::update_boundary_particles(body.triangles, body.particles.x, body.normals, samples, before);
    surface::fade_in(samples, before, f.fade_frames);
    if (f.density && !f.density->empty()) f.density->topology_changed(body.rest_positions, body.triangles, refill);
}

} // namespace pbdsplat::scene
