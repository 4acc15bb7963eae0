#include "surface/remap.h"

#include <algorithm>
#include <unordered_map>

namespace pbdsplat::surface {

size_t remap_samples(std::span<const mesh::TriangleSplit> splits, BoundaryParticles& s) {
    if (splits.empty()) return 0;
    std::unordered_multimap<uint32_t, const mesh::TriangleSplit*> children;
    uint32_t top = 0;
    for (const mesh::TriangleSplit& c : splits) children.emplace(c.parent, &c), top = std::max(top, c.parent);
    std::vector<uint8_t> is_parent(size_t(top) + 1, 0);  // skips the hash lookup for most samples
    for (const mesh::TriangleSplit& c : splits) is_parent[c.parent] = 1;
    size_t moved = 0;
    for (size_t i = 0; i < s.size(); ++i) {
        if (s.triangle[i] > top || !is_parent[s.triangle[i]]) continue;
        const auto [first, last] = children.equal_range(s.triangle[i]);
        if (first == last) continue;
        const Vec3f p(1.0f - s.bary[i].x() - s.bary[i].y(), s.bary[i].x(), s.bary[i].y());
        // The child whose coordinates of p are least negative holds it (exactly one holds it up
        // to rounding; the test tolerates points on a shared child edge).
        float best_min = -1e30f;
        const mesh::TriangleSplit* best = nullptr;
        Vec3f best_lambda = Vec3f::Zero();
        for (auto it = first; it != last; ++it) {
            const auto& c = it->second->corners;
            Mat3f m;
            m.col(0) = c[0];
            m.col(1) = c[1];
            m.col(2) = c[2];
            const Vec3f lambda = m.colPivHouseholderQr().solve(p);
            const float lo = lambda.minCoeff();
            if (lo > best_min) best_min = lo, best = it->second, best_lambda = lambda;
        }
        const Vec3f l = best_lambda.cwiseMax(0.0f) / best_lambda.cwiseMax(0.0f).sum();
        s.triangle[i] = best->triangle;
        s.bary[i] = Vec2f(l.y(), l.z());
        ++moved;
    }
    return moved;
}

} // namespace pbdsplat::surface

namespace pbdsplat::surface {

size_t drop_across_cut(const std::function<float(const Vec3f&)>& side, std::span<const uint32_t> triangles,
                       std::span<const mesh::Triangle> all, std::span<const Vec4f> x, BoundaryParticles& s) {
    if (triangles.empty() || s.position.size() != s.size()) return 0;
    // The side of each touched triangle, by its centre (its corners lie on one side or on the cut).
    std::unordered_map<uint32_t, float> side_of;
    side_of.reserve(triangles.size());
    for (uint32_t t : triangles) {
        const auto& tri = all[t];
        side_of[t] = side(((x[tri[0]] + x[tri[1]] + x[tri[2]]) / 3.0f).head<3>());
    }
    return s.keep_if([&](size_t i) {
        const auto it = side_of.find(s.triangle[i]);
        if (it == side_of.end() || it->second == 0.0f) return true;
        const float d = side(s.position[i]);
        return d == 0.0f || (d > 0.0f) == (it->second > 0.0f);
    });
}

} // namespace pbdsplat::surface
