#include "sim/drag.h"

#include <algorithm>

#include "sim/contact.h"

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

DragConstraint grab_region(const SoftBody& body, uint32_t centre, float radius, float stiffness) {
    DragConstraint d;
    if (centre >= body.particle_count()) return d;
    const Vec3f grab = xyz(body.particles.x[centre]);
    d.target = grab;
    d.active = true;
    const uint32_t piece = centre < body.piece_of_particle.size() ? body.piece_of_particle[centre] : k_no_piece;
    // A piece pinned whole (a static body: a table, a bowl) stands as it is; dragged, the region
    // around the grab left it as a spike while the rest held.
    bool free = body.particles.w[centre] > 0.0f;
    for (uint32_t i = 0; i < body.particle_count() && !free; ++i) free = body.piece_of_particle[i] == piece && body.particles.w[i] > 0.0f;
    if (!free) return DragConstraint{};
    for (uint32_t i = 0; i < body.particle_count(); ++i) {
        if (i != centre && (radius <= 0.0f || body.piece_of_particle[i] != piece)) continue;
        const Vec3f offset = xyz(body.particles.x[i]) - grab;
        const float u = radius > 0.0f ? offset.norm() / radius : 0.0f;
        if (u >= 1.0f) continue;
        // Full weight to half the radius, then a smoothstep down to nothing at the rim.
        const float t = std::clamp(2.0f * (1.0f - u), 0.0f, 1.0f);
        d.particles.push_back(i);
        d.offsets.push_back(offset);
        d.weights.push_back(stiffness * t * t * (3.0f - 2.0f * t));
    }
    return d;
}

float default_grab_radius(const SoftBody& body) { return 2.0f * mean_rest_edge(body); }

} // namespace pbdsplat::sim
