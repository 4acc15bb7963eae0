#pragma once
// Fingerprints of the frame's shared CPU resources, for FrameGraph::check_writes: a test (or a
// debugging session, RuntimeOptions::check_writes) runs a scene and learns of any pass that
// changed a part of the body, the drag, the appearance, the samples, the frame input, the map settings,
// the frame's topology changes or the note without declaring the write.
#include <cstdint>
#include <string>

#include "passes/gpu_passes.h"
#include "scene/stages/mapping_stage.h"
#include "scene/stages/topology_stage.h"
#include "sim/soft_body.h"
#include "splat/gaussian_record.h"
#include "surface/boundary_particles.h"

namespace pbdsplat::scene {

// The body's parts: the mesh and constraint counts, pieces and each volume constraint's target;
// positions and velocities; the normals.
uint64_t fingerprint(const sim::BodyStructure& structure);
uint64_t fingerprint(const sim::BodyState& state);
uint64_t fingerprint(const sim::BodyCaches& caches);
uint64_t fingerprint(const sim::DragConstraint& drag);
uint64_t fingerprint(const splat::Appearance& look);
// The samples' count, triangles, barycentric coordinates and fades.
uint64_t fingerprint(const surface::BoundaryParticles& samples);
// The camera; the records handed to the GPU passes.
uint64_t fingerprint(const render::FrameInputs& frame);
uint64_t fingerprint(const passes::SplatStream& splats);
uint64_t fingerprint(const std::string& text);
uint64_t fingerprint(const MapSettings& settings);
// The changes' count and particle counts, the refill list and the seed offset.
uint64_t fingerprint(const FrameChanges& changes);

} // namespace pbdsplat::scene
