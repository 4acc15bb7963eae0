#include <doctest/doctest.h>

#include <algorithm>
#include <random>

#include "mesh/closest_point.h"
#include "mesh/procedural.h"

using namespace pbdsplat;

namespace {
// What closest() promises, by testing every triangle: those within factor x the nearest
// distance + margin, nearest first, ties by index.
std::vector<mesh::ClosestPoint> every_triangle(const mesh::TriangleMesh& m, const Vec3f& p, float factor, float margin) {
    std::vector<mesh::ClosestPoint> all;
    float best = 1e30f;
    for (uint32_t t = 0; t < m.triangles.size(); ++t) {
        const Vec3f &a = m.positions[m.triangles[t][0]], &b = m.positions[m.triangles[t][1]], &c = m.positions[m.triangles[t][2]];
        const Vec2f w = mesh::closest_point_barycentric(p, a, b, c);
        const float d = (a + w.x() * (b - a) + w.y() * (c - a) - p).norm();
        all.push_back({d, t, w});
        best = std::min(best, d);
    }
    std::erase_if(all, [&](const mesh::ClosestPoint& c) { return c.distance > factor * best + margin; });
    std::sort(all.begin(), all.end(), [](const auto& x, const auto& y) {
        return x.distance != y.distance ? x.distance < y.distance : x.triangle < y.triangle;
    });
    return all;
}
} // namespace

TEST_SUITE("mesh/closest_point") {
    TEST_CASE("the grid's nearest triangles and their rivals are those a test of every triangle keeps") {
        // A bumpy ball, queried on it, just off it, inside it and far outside: the grid skips
        // triangles by their bounding spheres and starts from a small radius, and must still
        // return exactly the same list.
        mesh::TriangleMesh m = mesh::icosphere(3, 0.5f);
        std::mt19937 rng(3);
        std::uniform_real_distribution<float> bump(0.9f, 1.1f), u(-1.0f, 1.0f);
        for (Vec3f& p : m.positions) p *= bump(rng);
        const mesh::TriangleGrid grid(m.positions, m.triangles);
        for (int i = 0; i < 400; ++i) {
            Vec3f dir(u(rng), u(rng), u(rng));
            if (!(dir.norm() > 1e-3f)) continue;
            const float radius = i < 100 ? 0.5f : i < 200 ? 0.52f : i < 300 ? 0.2f : 3.0f;
            const Vec3f p = dir.normalized() * radius;
            for (const auto& [factor, margin] : {std::pair{1.5f, 0.25f * grid.cell_size()}, std::pair{1.0f, 0.0f}}) {
                std::vector<mesh::ClosestPoint> got;
                grid.closest(p, factor, margin, got);
                const auto want = every_triangle(m, p, factor, margin);
                REQUIRE(got.size() == want.size());
                for (size_t k = 0; k < got.size(); ++k) {
                    CHECK(got[k].triangle == want[k].triangle);
                    CHECK(got[k].distance == want[k].distance);
                }
            }
        }
    }
}
