#pragma once
// From the body to the Gaussians: the paper's one-to-one mapping (eqs. 11-13) of the particles
// and the boundary particles, their deformed shapes where the scene asks, the fade-in of
// splats a cut added, the far-to-near CPU sort, and the hand-over to the GPU passes with the
// byte ranges that changed since the last frame.
#include <vector>

#include "render/frame_inputs.h"
#include "passes/gpu_passes.h"
#include "sim/soft_body.h"
#include "splat/deformed_shape.h"
#include "splat/fade_in.h"
#include "splat/mapping.h"
#include "splat/sort.h"
#include "surface/boundary_particles.h"
#include "topology/topology_change.h"

namespace pbdsplat::scene {

class MappingStage {
public:
    // `deformed`: each boundary particle a disc carried by its triangle (render.splat_shape).
    MappingStage(const sim::SoftBody& body, uint32_t fade_frames, bool deformed);

    struct Sources {
        const sim::SoftBody* body = nullptr;
        bool particles = true;  // the particles are splats (not under an embedded surface)
        const surface::BoundaryParticles* samples = nullptr;  // shown boundary particles, or null
        const splat::StretchScale* stretch = nullptr;         // stretch-scaled splats, or null
    };
    void map(const Sources& s, const splat::Appearance& look);
    void sort(const render::Camera& camera);
    // Hands the records (and shapes) to the GPU passes with what changed.
    void publish(passes::GpuFrameInput& input);
    // New particles fade in; the deformed shapes follow the new triangles.
    void topology_changed(const sim::SoftBody& body, const topology::TopologyChange& change, bool particles);

    const std::vector<splat::GaussianRecord>& records() const { return records_; }
    const std::vector<splat::GaussianShape>& shapes() const { return shapes_; }
    splat::SortScratch& sort_scratch() { return sort_scratch_; }

private:
    std::vector<splat::GaussianRecord> records_;
    std::vector<splat::GaussianRecord> previous_;  // what the GPU holds: for the changed ranges
    std::vector<splat::GaussianShape> shapes_;     // parallel to records_ with deformed shapes
    splat::DeformedShapes deformed_;
    splat::FadeIn fade_;
    splat::SortScratch sort_scratch_;
};

} // namespace pbdsplat::scene
