#include "mesh/subdivide.h"

#include <algorithm>
#include <unordered_map>

namespace pbdsplat::mesh {

void subdivide(TriangleMesh& m, const std::function<Vec3f(const Vec3f&, const Vec3f&)>& midpoint) {
    const bool colors = m.colors.size() == m.positions.size();
    m.normals.clear();
    m.uvs.clear();
    std::unordered_map<uint64_t, uint32_t> made;
    made.reserve(m.triangles.size() * 2);
    auto mid = [&](uint32_t a, uint32_t b) {
        const uint64_t key = (uint64_t(std::min(a, b)) << 32) | std::max(a, b);
        auto [it, inserted] = made.try_emplace(key, uint32_t(m.positions.size()));
        if (inserted) {
            m.positions.push_back(midpoint(m.positions[a], m.positions[b]));
            if (colors) m.colors.push_back(0.5f * (m.colors[a] + m.colors[b]));
        }
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

void subdivide_flat(TriangleMesh& mesh) {
    subdivide(mesh, [](const Vec3f& a, const Vec3f& b) { return Vec3f(0.5f * (a + b)); });
}

uint32_t refine_to(TriangleMesh& mesh, size_t min_vertices, uint32_t max_levels) {
    uint32_t levels = 0;
    while (mesh.vertex_count() < min_vertices && levels < max_levels && !mesh.triangles.empty()) {
        subdivide_flat(mesh);
        ++levels;
    }
    return levels;
}

} // namespace pbdsplat::mesh
