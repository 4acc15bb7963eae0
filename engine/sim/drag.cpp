#include "sim/drag.h"

namespace pbdsplat::sim {

std::optional<uint32_t> pick_particle(const Particles& p, const Vec3f& origin, const Vec3f& direction, float radius) {
    std::optional<uint32_t> best;
    float best_t = 0.0f;
    const float r2 = radius * radius;
    for (uint32_t i = 0; i < p.size(); ++i) {
        const Vec3f d = xyz(p.x[i]) - origin;
        const float t = d.dot(direction);
        if (t <= 0.0f) continue;
        if ((d - t * direction).squaredNorm() > r2) continue;
        if (!best || t < best_t) best = i, best_t = t;
    }
    return best;
}

} // namespace pbdsplat::sim
