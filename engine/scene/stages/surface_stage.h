#pragma once
// The boundary particles' setup and their follow-up to topology changes.
//
// Setup: spacing h from the model's edges (eta) or, where that would place more samples than the
// scene's budget, from the budget; a maximal sample set on the model's own
// surface embedded in the simulation mesh (or on the simulation mesh itself), edge samples
// along open boundaries, the density control.
//
// After a cut or tear: samples on split triangles move to the
// children, the cut's far side is emptied, the re-triangulated and emptied triangles are
// refilled at spacing h (per piece), edge samples are laid afresh along the new boundary, and
// the new samples fade in. Only the triangles the change touched are resampled.
#include <cstdint>
#include <span>

#include <optional>

#include "core/result.h"
#include "graph/blackboard.h"
#include "graph/frame_graph.h"
#include "splat/mapping.h"
#include "mesh/triangle_mesh.h"
#include "scene/scene.h"
#include "sim/soft_body.h"
#include "surface/boundary_particles.h"
#include "surface/embedding.h"
#include "surface/density.h"
#include "topology/cut.h"
#include "topology/topology_change.h"

namespace pbdsplat::scene {

struct SurfaceSetup {
    float h = 0.0f;                    // sampling spacing
    float edge_h = 0.0f;               // eta times the edge
    float eta_h = 0.0f;                // edge_h, or less where a thin part needs it: h unless the sample budget raised it
    bool particles_are_splats = true;  // not with an embedded model surface
};

// `fine`: the model's full-resolution surface when the body simulates a decimated copy.
// Fills `samples` (boundary mode), `embedding` (with `fine`) and `density` (when the scene has it);
// `pool` (optional) shares the sampling and embedding of a fine surface, with the same result.
core::Result<SurfaceSetup> setup_surface(const SurfaceDesc& desc, uint32_t fade_frames, const sim::SoftBody& body,
                                         const std::optional<mesh::TriangleMesh>& fine, surface::BoundaryParticles& samples,
                                         surface::EmbeddingStats& embedding, surface::DensityControl& density,
                                         core::ThreadPool* pool = nullptr);

struct SurfaceFollow {
    surface::BoundaryParticles* samples = nullptr;
    surface::BoundaryParticles* fine_vertices = nullptr;  // the model's vertices, when embedded (or null)
    surface::DensityControl* density = nullptr;           // null or empty: no density control
    float h = 0.0f;
    uint32_t seed = 0;
    uint32_t fade_frames = 0;
    bool edge_samples = false;
    bool particles_are_splats = true;  // new samples keep their distance from the particles too
};

// The per-frame passes: the samples follow the deformed mesh ("boundary particles"), keep
// their density as it stretches and shrinks and advance their fades ("density"), and the
// stretch-scaled splats' factors follow ("stretch"). Each reaches its data through the handles;
// an absent one (vertices only, no stretch scaling) culls the passes that need it.
namespace keys {
inline constexpr graph::Key<surface::DensityStats> density_stats{"density stats"};
}
struct SurfacePassConfig {
    bool particles_are_splats = true;
    float h = 0.0f;
    uint32_t seed = 0;
    uint32_t tag = 0;  // the passes' group (scene/stages/pass_group.h)
    bool thin = false;  // the renderer thins small splats: the samples keep a thinning order
    core::ThreadPool* pool = nullptr;  // threads the samples' carry splits over, or null
};
// The density control's pass, by which `bench scene --passes` finds its time per sample.
inline constexpr const char* k_density_pass = "density";
// Reads the body, samples, density control, keys::density_stats and the stretch from `board`
// (an absent one culls the passes that need it) and puts back the samples, the stretch and the density stats.
void add_surface_passes(graph::FrameGraph& g, graph::Blackboard& board, const SurfacePassConfig& config);

// Whether any of `triangles` has an edge no other triangle uses (the body's rings current).
bool opens_boundary(const sim::SoftBody& body, std::span<const uint32_t> triangles);

// Right after each change: the samples carried onto the children of the split triangles and,
// for a cut (`cut`, null for a tear) through an embedded surface, dropped where they fell on
// the wrong side; returns the triangles so emptied (to refill with the rest).
std::vector<uint32_t> carry_samples_across(const SurfaceFollow& f, const sim::SoftBody& body, const topology::TopologyChange& change,
                                           const topology::CutSurface* cut);
// Once after the frame's changes: new samples on `refill` (sorted; every triangle the changes
// touched), edge samples along their new boundary, fades, density data. `seed_offset` is added
// to the seed.
void refill_touched(const SurfaceFollow& f, const sim::SoftBody& body, std::span<const uint32_t> refill, size_t seed_offset);

} // namespace pbdsplat::scene
