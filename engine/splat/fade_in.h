#pragma once
// Splats created by a topology change fade in over a few frames instead of popping: their
// record's colour alpha (the shader's fade factor) rises from 0 to 1. Sparse: only splats
// still fading cost anything.
#include <cstdint>
#include <vector>

#include "splat/gaussian_record.h"

namespace pbdsplat::splat {

class FadeIn {
public:
    explicit FadeIn(uint32_t frames = 8) : frames_(frames < 1 ? 1 : frames) {}
    void add_particles(size_t first, size_t count) { add(false, first, count); }
    void add_samples(size_t first, size_t count) { add(true, first, count); }
    // Writes the fade of every splat still fading into `records` (the particles' records first,
    // `particle_count` of them, then the boundary particles'), then advances one frame.
    void apply(size_t particle_count, std::vector<GaussianRecord>& records);
    size_t fading() const { return items_.size(); }
    // Forgets the boundary particles still fading (their indices no longer hold: samples were
    // dropped); they show at once.
    void reset_samples() { std::erase_if(items_, [](const Item& i) { return i.sample; }); }

private:
    struct Item {
        bool sample;
        uint32_t index;
        uint32_t age;
    };
    void add(bool sample, size_t first, size_t count);
    uint32_t frames_;
    std::vector<Item> items_;
};

} // namespace pbdsplat::splat
