#pragma once
// The model of a scene brought into the simulation: the repaired full-resolution surface, the
// simulation mesh decimated from it (or the model itself), and the body built on that.
#include <optional>
#include <string>
#include <vector>

#include "core/result.h"
#include "mesh/decimate.h"
#include "mesh/triangle_mesh.h"
#include "scene/scene.h"
#include "scene/stages/fine_surface.h"
#include "scene/stages/paint.h"
#include "sim/soft_body.h"

namespace pbdsplat::scene {

struct SceneModel {
    sim::SoftBody body;
    // The model's own surface, transformed into the scene, when the body is a decimated copy
    // of it; empty when the body simulates the model's vertices.
    std::optional<mesh::TriangleMesh> fine;
    FineCopies fine_copies;  // the models it holds only a copy of (simulated on their own vertices)
    mesh::DecimateReport decimation;  // summed over the models
    // With [[bodies]]: where each model's particles start ([model] first, then the bodies in
    // order), and the particle count last. Empty for one model.
    std::vector<uint32_t> part_start;
    // The models' looks (textures, materials, vertex colours); empty when every model is plain.
    SurfacePaint paint;
    // Substeps a frame: the scene's, raised where the file left them out and a solid is too
    // small to stand at them (docs/BENCHMARKS.md, "Solids that stand").
    uint32_t substeps = 1;
};

// The simulation size a scene asks for: 0 keeps the model's vertices.
uint32_t simulation_particles(const Scene& scene);

// Loads the mesh (next to the scene file first), applies the transform, decimates to the
// simulation size, builds the body with its pins.
core::Result<SceneModel> load_scene_model(const Scene& scene);

// A model as the scene file names it (model 0: [model], m: bodies[m - 1]), with its mesh.
std::string model_name(const Scene& scene, size_t m);

// The body only: for the tools that only simulate.
core::Result<sim::SoftBody> make_scene_body(const Scene& scene);

} // namespace pbdsplat::scene
