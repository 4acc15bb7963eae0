#include "scene/stages/change_passes.h"

#include <algorithm>

#include "scene/stages/body_parts.h"
#include "scene/stages/frame_keys.h"
#include "scene/stages/mapping_stage.h"
#include "scene/stages/surface_stage.h"

namespace pbdsplat::scene {

namespace {

struct ChangeHandles {
    graph::Handle<FrameChanges> changes;
    graph::Handle<EventQueue> cuts;  // the marker: absent when no cut or tear can come
    BodyParts body;
    graph::Handle<surface::BoundaryParticles> samples;
    graph::Handle<std::optional<surface::BoundaryParticles>> fine;
    graph::Handle<surface::DensityControl> density;
    graph::Handle<MappingStage> mapping;
    graph::Handle<MapSettings> settings;
    graph::Handle<splat::CutFaces> cut_faces;
    graph::Handle<splat::StretchScale> stretch;
};

SurfaceFollow surface_follow(const ChangePassOptions& o, surface::BoundaryParticles& samples, surface::DensityControl* density,
                             std::optional<surface::BoundaryParticles>* fine, bool particles_are_splats) {
    SurfaceFollow f;
    f.samples = &samples;
    f.fine_vertices = fine && *fine ? &**fine : nullptr;
    f.density = density;
    f.h = o.h;
    f.seed = o.seed;
    f.fade_frames = o.fade_frames;
    f.edge_samples = o.edge_samples;
    f.particles_are_splats = particles_are_splats;
    return f;
}

void add_carry_pass(graph::FrameGraph& g, ChangeHandles& h, const ChangePassOptions& o) {
    g.add_pass("carry samples", graph::PassKind::cpu, [&](graph::PassBuilder& b) {
        b.read(h.cuts);
        h.body.declare(b);
        b.read(h.settings);
        h.changes = b.write(h.changes);  // the triangles it empties join the refill
        h.samples = b.write(h.samples);
        if (o.fine) h.fine = b.write(h.fine);
        return [o, hh = h](const graph::PassResources& r, graph::ExecuteContext&) {
            FrameChanges& changes = r.write(hh.changes);
            if (changes.empty()) return;
            const sim::SoftBody& body = hh.body.body(r);
            const SurfaceFollow f =
                surface_follow(o, r.write(hh.samples), nullptr, o.fine ? &r.write(hh.fine) : nullptr, r.read(hh.settings).particles);
            for (const FrameChanges::Change& c : changes.changes) {
                const std::vector<uint32_t> emptied = carry_samples_across(f, body, c.change, c.cut ? &*c.cut : nullptr);
                changes.refill.insert(changes.refill.end(), emptied.begin(), emptied.end());
            }
        };
    }, o.tag);
}

void add_refill_pass(graph::FrameGraph& g, ChangeHandles& h, const ChangePassOptions& o) {
    g.add_pass("refill", graph::PassKind::cpu, [&](graph::PassBuilder& b) {
        b.read(h.cuts);
        h.body.declare(b);
        b.read(h.settings);
        b.read(h.changes);
        h.samples = b.write(h.samples);
        h.density = b.write(h.density);
        return [o, hh = h](const graph::PassResources& r, graph::ExecuteContext&) {
            const FrameChanges& changes = r.read(hh.changes);
            if (changes.empty()) return;
            std::vector<uint32_t> refill = changes.refill;
            std::sort(refill.begin(), refill.end());
            refill.erase(std::unique(refill.begin(), refill.end()), refill.end());
            const SurfaceFollow f = surface_follow(o, r.write(hh.samples), &r.write(hh.density), nullptr, r.read(hh.settings).particles);
            refill_touched(f, hh.body.body(r), refill, changes.seed_offset);
        };
    }, o.tag);
}

void add_mapping_follow_pass(graph::FrameGraph& g, ChangeHandles& h, const ChangePassOptions& o) {
    g.add_pass("follow mapping", graph::PassKind::cpu, [&](graph::PassBuilder& b) {
        b.read(h.cuts);
        h.body.declare(b);
        b.read(h.changes);
        h.mapping = b.write(h.mapping);
        h.settings = b.write(h.settings);
        if (o.cut_faces) h.cut_faces = b.write(h.cut_faces);
        return [o, hh = h](const graph::PassResources& r, graph::ExecuteContext&) {
            const FrameChanges& changes = r.read(hh.changes);
            if (changes.empty()) return;
            const sim::SoftBody& body = hh.body.body(r);
            MapSettings& settings = r.write(hh.settings);
            MappingStage& mapping = r.write(hh.mapping);
            for (const FrameChanges::Change& c : changes.changes) {
                // Only a cut or tear can open the boundary, and only where it touched (the
                // triangles' indices stay valid through the changes after it).
                if (settings.closed) settings.closed = !opens_boundary(body, c.change.touched_triangles);
                if (c.cut && o.cut_faces) r.write(hh.cut_faces).cut_made();
                mapping.topology_changed(body, c.change, settings.particles);
            }
        };
    }, o.tag);
}

void add_stretch_follow_pass(graph::FrameGraph& g, ChangeHandles& h, const ChangePassOptions& o) {
    g.add_pass("stretch data", graph::PassKind::cpu, [&](graph::PassBuilder& b) {
        b.read(h.cuts);
        b.read(h.body.structure);  // the rest shape alone
        b.read(h.changes);
        h.stretch = b.write(h.stretch);
        return [hh = h](const graph::PassResources& r, graph::ExecuteContext&) {
            if (r.read(hh.changes).empty()) return;
            const sim::BodyStructure& body = r.read(hh.body.structure);
            r.write(hh.stretch) = splat::StretchScale(body.rest_positions, body.triangles);
        };
    }, o.tag);
}

} // namespace

void add_change_passes(graph::FrameGraph& g, graph::Blackboard& board, const ChangePassOptions& o) {
    ChangeHandles h{board.get(keys::changes),  board.get(keys::cuts),         BodyParts::from(board),
                    board.get(keys::samples),  board.get(keys::fine_embedding), board.get(keys::density),
                    board.get(keys::mapping),  board.get(keys::map_settings), board.get(keys::cut_faces),
                    board.get(keys::stretch)};
    if (o.boundary) {
        add_carry_pass(g, h, o);
        add_refill_pass(g, h, o);
    }
    add_mapping_follow_pass(g, h, o);
    if (o.stretch) add_stretch_follow_pass(g, h, o);
    board.put_all(std::pair{keys::changes, h.changes}, std::pair{keys::samples, h.samples}, std::pair{keys::fine_embedding, h.fine},
                  std::pair{keys::density, h.density}, std::pair{keys::mapping, h.mapping}, std::pair{keys::map_settings, h.settings},
                  std::pair{keys::cut_faces, h.cut_faces}, std::pair{keys::stretch, h.stretch});
}

} // namespace pbdsplat::scene
