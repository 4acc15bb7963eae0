#include "surface/edges.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "core/assert.h"

namespace pbdsplat::surface {

namespace {
// Samples along edge k of triangle t, on centred intervals: the corners (shared with the next
// edge) get none, so the spacing holds across corners as well.
void lay_along(std::span<const Vec3f> rest, const mesh::Triangle& tri, uint32_t t, int k, float step, BoundaryParticles& s) {
    const uint32_t a = tri[size_t(k)], b = tri[size_t((k + 1) % 3)];
    const float length = (rest[b] - rest[a]).norm();
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

// The arrays beside triangle and bary for samples [first, size()): positions and normals
// follow at the next update_boundary_particles, the embedding from older samples.
size_t finish_appended(size_t first, const EdgeOptions& o, BoundaryParticles& s) {
    if (s.size() == first) return 0;
    if (s.position.size() == first) {
        s.position.resize(s.size(), Vec3f::Zero());
        s.normal.resize(s.size(), Vec3f::UnitZ());
    }
    embed_appended(first, s);
    s.size_factor.resize(first, 1.0f);
    s.size_factor.resize(s.size(), o.size);
    return s.size() - first;
}
} // namespace

size_t relay_edge_samples(std::span<const Vec3f> rest, std::span<const mesh::Triangle> triangles, std::span<const uint32_t> region,
                          std::span<const uint8_t> boundary_edges, float h, const EdgeOptions& o, BoundaryParticles& s) {
    PBDSPLAT_ASSERT(region.size() == boundary_edges.size(), "relay_edge_samples: one boundary mask per region triangle");
    PBDSPLAT_ASSERT(std::is_sorted(region.begin(), region.end()), "relay_edge_samples: the region must be sorted");
    s.keep_if([&](size_t i) { return !s.on_edge(i) || !std::binary_search(region.begin(), region.end(), s.triangle[i]); });
    const size_t first = s.size();
    const float step = std::max(o.spacing, 0.01f) * h;
    for (size_t r = 0; r < region.size(); ++r)
        for (int k = 0; k < 3; ++k)
            if (boundary_edges[r] >> k & 1u) lay_along(rest, triangles[region[r]], region[r], k, step, s);
    return finish_appended(first, o, s);
}

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
        for (int k = 0; k < 3; ++k)
            if (uses[key(triangles[t][k], triangles[t][(k + 1) % 3])] == 1) lay_along(rest, triangles[t], t, k, step, s);
    return finish_appended(first, o, s);
}

} // namespace pbdsplat::surface
