#include "surface/edges.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace pbdsplat::surface {

size_t lay_edge_samples(std::span<const Vec3f> rest, std::span<const mesh::Triangle> triangles, float h,
                        const EdgeOptions& o, BoundaryParticles& s) {
    s.keep_if([&](size_t i) { return !s.on_edge(i); });
    // An edge is on the boundary when only one triangle uses it.
    auto key = [](uint32_t a, uint32_t b) { return (uint64_t(std::min(a, b)) << 32) | std::max(a, b); };
    std::unordered_map<uint64_t, uint32_t> uses;
    uses.reserve(triangles.size() * 2);
    for (const mesh::Triangle& t : triangles)
        for (int k = 0; k < 3; ++k) ++uses[key(t[k], t[(k + 1) % 3])];
    const size_t first = s.size();
    const float step = std::max(o.spacing, 0.01f) * h;
    for (uint32_t t = 0; t < triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = triangles[t][k], b = triangles[t][(k + 1) % 3];
            if (uses[key(a, b)] != 1) continue;
            const float length = (rest[b] - rest[a]).norm();
            // Centred intervals: the corners (shared with the next edge) get none, so the
            // spacing holds across corners as well.
            const uint32_t n = std::max(1u, uint32_t(std::ceil(length / step)));
            for (uint32_t j = 0; j < n; ++j) {
                const float u = (float(j) + 0.5f) / float(n);
                float w[3] = {0.0f, 0.0f, 0.0f};
                w[k] = 1.0f - u;
                w[(k + 1) % 3] = u;
                s.triangle.push_back(t);
                s.bary.emplace_back(w[1], w[2]);
            }
        }
    if (s.size() == first) return 0;
    if (s.position.size() == first) {
        // Positions follow at the next update_boundary_particles; keep the arrays aligned.
        s.position.resize(s.size(), Vec3f::Zero());
        s.normal.resize(s.size(), Vec3f::UnitZ());
    }
    embed_appended(first, s);
    s.size_factor.resize(first, 1.0f);
    s.size_factor.resize(s.size(), o.size);
    return s.size() - first;
}

} // namespace pbdsplat::surface
