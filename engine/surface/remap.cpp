#include "surface/remap.h"

#include <algorithm>
#include <cmath>
#include <limits>
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

size_t drop_across_cut(const std::function<float(const Vec3f&)>& side, std::span<const mesh::Triangle> all,
                       std::span<const Vec4f> x, BoundaryParticles& s, std::vector<uint32_t>* emptied) {
    if (emptied) emptied->clear();
    if (s.position.size() != s.size()) return 0;
    // Not only the touched triangles: a neighbour with a corner snapped onto the cut is not
    // re-triangulated, yet its samples can hang over the cut just the same. A sample is across
    // when it lies on a side of the cut where none of its triangle's corners lies: a snapped
    // cut runs through vertices, a little off the ideal surface, and triangles there may reach
    // over it by that much with their samples rightly on them. Triangle extents cached once.
    std::vector<Vec2f> extent(all.size(), Vec2f(1.0f, -1.0f));  // (lowest, highest) corner side
    const size_t dropped = s.keep_if([&](size_t i) {
        const float d = side(s.position[i]);
        if (d == 0.0f) return true;
        Vec2f& e = extent[s.triangle[i]];
        if (e.x() > e.y()) {
            const auto& tri = all[s.triangle[i]];
            e = Vec2f(1e30f, -1e30f);
            for (uint32_t v : tri) {
                const float c = side(x[v].head<3>());
                e = Vec2f(std::min(e.x(), c), std::max(e.y(), c));
            }
        }
        const bool keep = d > 0.0f ? e.y() > 0.0f : e.x() < 0.0f;
        if (!keep && emptied) emptied->push_back(s.triangle[i]);
        return keep;
    });
    if (emptied) {
        std::sort(emptied->begin(), emptied->end());
        emptied->erase(std::unique(emptied->begin(), emptied->end()), emptied->end());
    }
    return dropped;
}

} // namespace pbdsplat::surface
