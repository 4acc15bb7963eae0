#include "mesh/procedural.h"

#include <cmath>
#include <unordered_map>

#include "core/assert.h"

namespace pbdsplat::mesh {

TriangleMesh icosphere(uint32_t level, float radius) {
    PBDSPLAT_ASSERT(level <= 8, "icosphere: level above 8 makes over 2.6 million triangles; lower it");
    TriangleMesh m;
    const float t = (1.0f + std::sqrt(5.0f)) * 0.5f;
    const float base[12][3] = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                               {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    for (const auto& p : base) m.positions.push_back(Vec3f(p[0], p[1], p[2]).normalized());
    m.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                   {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                   {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};

    for (uint32_t l = 0; l < level; ++l) {
        std::unordered_map<uint64_t, uint32_t> midpoint;
        auto mid = [&](uint32_t a, uint32_t b) {
            const uint64_t key = (uint64_t(std::min(a, b)) << 32) | std::max(a, b);
            auto [it, inserted] = midpoint.try_emplace(key, uint32_t(m.positions.size()));
            if (inserted) m.positions.push_back((m.positions[a] + m.positions[b]).normalized());
            return it->second;
        };
        std::vector<Triangle> next;
        next.reserve(m.triangles.size() * 4);
        for (const Triangle& tri : m.triangles) {
            const uint32_t a = mid(tri[0], tri[1]), b = mid(tri[1], tri[2]), c = mid(tri[2], tri[0]);
            next.push_back({tri[0], a, c});
            next.push_back({tri[1], b, a});
            next.push_back({tri[2], c, b});
            next.push_back({a, b, c});
        }
        m.triangles = std::move(next);
    }
    for (Vec3f& p : m.positions) p *= radius;
    return m;
}

} // namespace pbdsplat::mesh

namespace pbdsplat::mesh {
std::vector<Vec3f> fibonacci_sphere(uint32_t count, float radius) {
    std::vector<Vec3f> p(count);
    const double golden = k_pi * (3.0 - std::sqrt(5.0));
    for (uint32_t i = 0; i < count; ++i) {
        const double y = 1.0 - 2.0 * (double(i) + 0.5) / double(count);
        const double r = std::sqrt(std::max(0.0, 1.0 - y * y));
        const double t = golden * double(i);
        p[i] = Vec3f(float(r * std::cos(t)), float(y), float(r * std::sin(t))) * radius;
    }
    return p;
}
} // namespace pbdsplat::mesh
