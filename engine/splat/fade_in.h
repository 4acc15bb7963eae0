#pragma once
// Particles created by a topology change fade in over a few frames instead of popping: their
// record's colour alpha (the shader's fade factor) rises from 0 to 1. Sparse: only splats
// still fading cost anything. (Boundary particles carry their own fade: surface/density.h.)
#include <cstdint>
#include <vector>

#include "splat/gaussian_record.h"

namespace pbdsplat::splat {

class FadeIn {
public:
    explicit FadeIn(uint32_t frames = 8) : frames_(frames < 1 ? 1 : frames) {}
    void add_particles(size_t first, size_t count);
    // Writes the fade of every particle still fading into `records` (the particles' records
    // first), then advances one frame.
    void apply(std::vector<GaussianRecord>& records);
    size_t fading() const { return items_.size(); }

private:
    struct Item {
        uint32_t index;
        uint32_t age;
    };
    uint32_t frames_;
    std::vector<Item> items_;
};

} // namespace pbdsplat::splat
