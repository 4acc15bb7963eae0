#include "splat/fade_in.h"

#include <algorithm>
#include <cmath>

namespace pbdsplat::splat {

void FadeIn::add_particles(size_t first, size_t count) {
    for (size_t k = 0; k < count; ++k) items_.push_back({uint32_t(first + k), 0});
}

void FadeIn::apply(std::vector<GaussianRecord>& records) {
    for (Item& it : items_) {
        const size_t r = it.index;
        if (r >= records.size()) continue;
        const float fade = float(it.age + 1) / float(frames_ + 1);
        records[r].color[3] = uint8_t(std::lround(std::clamp(fade, 0.0f, 1.0f) * 255.0f));
        ++it.age;
    }
    std::erase_if(items_, [this](const Item& it) { return it.age >= frames_; });
}

} // namespace pbdsplat::splat
