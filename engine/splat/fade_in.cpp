#include "splat/fade_in.h"

#include <algorithm>
#include <cmath>

namespace pbdsplat::splat {

void FadeIn::add(bool sample, size_t first, size_t count) {
    for (size_t k = 0; k < count; ++k) items_.push_back({sample, uint32_t(first + k), 0});
}

void FadeIn::apply(size_t particle_count, std::vector<GaussianRecord>& records) {
    for (Item& it : items_) {
        const size_t r = it.sample ? particle_count + it.index : it.index;
        if (r >= records.size()) continue;
        const float fade = float(it.age + 1) / float(frames_ + 1);
        records[r].color[3] = uint8_t(std::lround(std::clamp(fade, 0.0f, 1.0f) * 255.0f));
        ++it.age;
    }
    std::erase_if(items_, [this](const Item& it) { return it.age >= frames_; });
}

} // namespace pbdsplat::splat
