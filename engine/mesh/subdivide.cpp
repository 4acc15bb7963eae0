#include "mesh/subdivide.h"

#include <algorithm>
#include <unordered_map>

#include "mesh/topology.h"

namespace pbdsplat::mesh {

namespace {

// Splits the triangles whose `level` entry is at least `at` (all of them without `levels`), each
// child taking its parent's entry. Midpoints are shared along an edge, so a split part meets
// nothing unsplit: parts are what share no vertex.
void split(TriangleMesh& m, const std::function<Vec3f(const Vec3f&, const Vec3f&)>& midpoint, std::vector<uint8_t>* levels, uint8_t at) {
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
    std::vector<uint8_t> next_levels;
    next.reserve(m.triangles.size() * 4);
    for (size_t t = 0; t < m.triangles.size(); ++t) {
        const Triangle tri = m.triangles[t];
        const uint8_t level = levels ? (*levels)[t] : at;
        if (level < at) {
            next.push_back(tri);
            if (levels) next_levels.push_back(level);
            continue;
        }
        const uint32_t a = mid(tri[0], tri[1]), b = mid(tri[1], tri[2]), c = mid(tri[2], tri[0]);
        next.push_back({tri[0], a, c});
        next.push_back({tri[1], b, a});
        next.push_back({tri[2], c, b});
        next.push_back({a, b, c});
        if (levels) next_levels.insert(next_levels.end(), 4, level);
    }
    m.triangles = std::move(next);
    if (levels) *levels = std::move(next_levels);
}

Vec3f flat_midpoint(const Vec3f& a, const Vec3f& b) { return 0.5f * (a + b); }

} // namespace

void subdivide(TriangleMesh& m, const std::function<Vec3f(const Vec3f&, const Vec3f&)>& midpoint) { split(m, midpoint, nullptr, 0); }

void subdivide_flat(TriangleMesh& mesh) { subdivide(mesh, flat_midpoint); }

uint32_t refine_to(TriangleMesh& mesh, size_t min_vertices, uint32_t max_levels) {
    uint32_t levels = 0;
    while (mesh.vertex_count() < min_vertices && levels < max_levels && !mesh.triangles.empty()) {
        subdivide_flat(mesh);
        ++levels;
    }
    return levels;
}

uint32_t refine_coarse_parts(TriangleMesh& m, float edge_over_size, uint32_t max_levels, size_t max_triangles) {
    std::vector<uint32_t> part;
    const uint32_t parts = vertex_components(m.triangles, m.positions.size(), part);
    std::vector<Eigen::AlignedBox3f> box(parts);
    std::vector<float> longest(parts, 0.0f);
    std::vector<size_t> count(parts, 0);
    for (size_t t = 0; t < m.triangles.size(); ++t) {
        const Triangle& tri = m.triangles[t];
        const uint32_t c = part[t];
        ++count[c];
        for (int k = 0; k < 3; ++k) {
            box[c].extend(m.positions[tri[k]]);
            longest[c] = std::max(longest[c], (m.positions[tri[k]] - m.positions[tri[(k + 1) % 3]]).norm());
        }
    }
    std::vector<uint8_t> level(parts, 0);
    for (uint32_t c = 0; c < parts; ++c) {
        const float reach = edge_over_size * box[c].diagonal().norm();
        for (float edge = longest[c]; edge > reach && level[c] < max_levels; edge *= 0.5f) ++level[c];
    }
    // Within the budget: every part's levels lowered by one until the result fits.
    const auto total = [&] {
        size_t n = 0;
        for (uint32_t c = 0; c < parts; ++c) n += count[c] << (2 * level[c]);
        return n;
    };
    while (total() > std::max(max_triangles, m.triangles.size()))
        for (uint8_t& l : level) l = l > 0 ? uint8_t(l - 1) : l;
    const uint8_t most = parts ? *std::max_element(level.begin(), level.end()) : 0;
    if (most == 0) return 0;
    std::vector<uint8_t> levels(m.triangles.size());
    for (size_t t = 0; t < levels.size(); ++t) levels[t] = level[part[t]];
    for (uint8_t at = 1; at <= most; ++at) split(m, flat_midpoint, &levels, at);
    return most;
}

} // namespace pbdsplat::mesh
