#pragma once
// What follows a topology change downstream of the mesh (the topology pass hands it to
// TopologyStage as its Follow): after each change, the new particles' fade-in and the deformed
// shapes (mapping), the body's openness (culling), the cut faces told of a cut, the samples
// carried across the split; once
// after the frame's last change, the refill of every touched triangle and the stretch data.
#include <optional>
#include <span>
#include <vector>

#include "scene/stages/mapping_stage.h"
#include "scene/stages/surface_stage.h"
#include "scene/stages/topology_stage.h"

namespace pbdsplat::scene {

class ChangeFollowers {
public:
    struct Targets {
        surface::BoundaryParticles* samples = nullptr;  // null: a vertices-only scene
        // The model's vertices embedded in the body, made on first use (so read at each change).
        std::optional<surface::BoundaryParticles>* fine_vertices = nullptr;
        surface::DensityControl* density = nullptr;
        MappingStage* mapping = nullptr;
        MapSettings* map_settings = nullptr;
        splat::StretchScale* stretch = nullptr;  // empty unless the scene scales splats by stretch
        splat::CutFaces* cut_faces = nullptr;    // told of each cut (a tear's openings stay open)
        float h = 0.0f;
        uint32_t seed = 0;
        uint32_t fade_frames = 0;
        bool edge_samples = false;
    };
    explicit ChangeFollowers(const Targets& t) : t_(t) {}

    // The Follow that TopologyStage::run calls, for this body.
    TopologyStage::Follow follow(const sim::SoftBody& body);

private:
    core::Result<std::vector<uint32_t>> after_each(const sim::SoftBody& body, const topology::TopologyChange& change,
                                                   const topology::CutSurface* cut);
    core::Status settle(const sim::SoftBody& body, std::span<const uint32_t> touched, size_t seed_offset);
    SurfaceFollow surface_follow() const;
    Targets t_;
};

} // namespace pbdsplat::scene
