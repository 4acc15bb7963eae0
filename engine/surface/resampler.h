#pragma once
// The density control's resampling of one frame's due triangles: new samples darted where a
// triangle stretched (kept insert_spacing h from every sample around it), fade-outs where one
// shrank (samples closer than retire_spacing h to a kept one). DensityControl decides which
// triangles are due (surface/density.h); one is made on the frame's first due triangle.
#include <cstdint>
#include <memory>
#include <span>

#include "core/math.h"
#include "mesh/triangle_mesh.h"
#include "surface/boundary_particles.h"
#include "surface/density.h"
#include "surface/rows.h"

namespace pbdsplat::surface {

class Resampler {
public:
    struct Inputs {
        std::span<const Vec4f> x;
        std::span<const Vec3f> normals;
        std::span<const mesh::Triangle> triangles;
        const Rows& ring;  // the triangles around each particle
        bool anchors_drawn;
        float h;
        uint32_t seed;
        uint64_t frame;
        size_t max_samples;
    };
    Resampler(const Inputs& in, const DensityOptions& o, BoundaryParticles& s, DensityStats& stats);
    ~Resampler();
    Resampler(const Resampler&) = delete;
    Resampler& operator=(const Resampler&) = delete;

    // New samples darted onto t where it has room (kept insert_spacing h from every sample
    // around it, the new ones fading in).
    void insert(uint32_t t);
    // t's samples closer than retire_spacing h to a kept one begin to fade out.
    void retire(uint32_t t);

private:
    class Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace pbdsplat::surface
