#pragma once
// Where a textured look's texture coordinates run on without a break, so a splat may read the
// texture under each of its pixels by carrying the coordinates on from its centre (the
// coordinates' gradient): anywhere but near a seam, where the surface's two sides of an edge
// take their coordinates from different places of the texture (a chart's border in an atlas, a
// material's edge). There a splat reads its texture no farther from its centre than the seam.
#include <cstdint>
#include <optional>
#include <unordered_map>
#include <vector>

#include "asset/look.h"

namespace pbdsplat::asset {

class TextureCharts {
public:
    TextureCharts() = default;
    explicit TextureCharts(const SurfaceLook& look);

    // Whether any seam vertex lies within `reach` of p (the look's coordinates).
    bool near_seam(const Vec3f& p, float reach) const { return seam_distance(p, reach) < reach; }
    // The distance from p to the nearest seam (never more), or `reach` where none is nearer.
    float seam_distance(const Vec3f& p, float reach) const;
    size_t seam_vertices() const { return seam_count_; }  // the seams' corners, welded

private:
    float cell_ = 1.0f;
    float spacing_ = 0.0f;  // of the points along seam edges
    size_t seam_count_ = 0;
    std::unordered_map<uint64_t, std::vector<Vec3f>> cells_;
    uint64_t key(int x, int y, int z) const;
    void insert(const Vec3f& p);
};

// The world gradients of triangle t's texture coordinates u and v (in its plane: a step d along
// the surface changes them by du . d and dv . d); none where the triangle or its coordinates are
// degenerate.
struct UvGradient {
    Vec3f du, dv;
};
std::optional<UvGradient> uv_gradient(const SurfaceLook& look, uint32_t t);

} // namespace pbdsplat::asset
