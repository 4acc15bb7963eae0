#pragma once
// The density control's trigger on the samples themselves. The triangle-based trigger
// (surface/density.h) sees a triangle stretch or shrink under its own samples; it cannot see
// the surface *between* two kept samples fold or shrink while neither sample's triangle does
// (a crumpled balloon's wrinkles bring samples two rings apart within half a spacing), nor the
// gap such a fold leaves behind when it opens again. Both show on the samples: a sample whose
// nearest neighbour on its own side of the surface came nearer than `crowd` h, and a triangle
// whose centre lies farther than `gap` h from every sample.
#include <cstdint>
#include <span>
#include <vector>

#include "core/math.h"
#include "mesh/triangle_mesh.h"
#include "surface/boundary_particles.h"
#include "surface/rows.h"

namespace pbdsplat::surface {

inline constexpr uint8_t k_shrank = 1, k_grew = 2;

struct CrowdingQuery {
    float h = 1.0f;
    float crowd = 0.7f;  // in h; a sample nearer than this to a kept one retires
    float gap = 1.25f;   // in h; a triangle centre farther than this from every sample is a gap; 0: no gap search
    bool anchors_drawn = false;  // the particles are splats: they are kept and count as samples
    float fade_step = 1.0f / 6.0f;  // a retired sample fades out by this per frame
    uint32_t max_retired = ~0u;     // at most this many retire in one call
    // Per triangle, how its shape changed since the last call (k_shrank, k_grew; empty: both,
    // everywhere). Only samples on shrunk triangles are tested (the others are kept), and only
    // grown triangles are searched for gaps: a surface that stays as it was needs neither, and an
    // inflating one crowds nowhere (the whole test on balloon_inflate's 19k samples, every 4
    // frames, for nothing).
    std::span<const uint8_t> changed;
    // The triangles around each particle (corner_rows), where the caller keeps them; built here if null.
    const Rows* ring = nullptr;
};

struct CrowdingResult {
    uint32_t retired = 0;
    std::vector<uint32_t> gaps;     // triangles whose centre no sample covers
};

// Keeps, greedily, the particles (where drawn) and the samples on triangles that did not
// shrink, then the settled samples on shrunk ones, then those still fading in (each in storage
// order, so the oldest stay), and starts the fade-out of every sample that has a kept one within
// `crowd` h on its own side (its triangle's face normals within 60 degrees: the two faces of a
// sharp fold are no neighbours). Edge samples take no part: they follow the boundary
// (surface/edges.h). Then lists the grown triangles whose centre nothing kept around them (on
// their own triangle or one sharing a vertex) covers. `x`: the particles (w ignored),
// `normals`: theirs; the samples' positions must be current.
CrowdingResult thin_crowds(std::span<const Vec4f> x, std::span<const Vec3f> normals, std::span<const mesh::Triangle> triangles,
                           const CrowdingQuery& query, BoundaryParticles& samples);

} // namespace pbdsplat::surface
