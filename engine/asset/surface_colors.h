#pragma once
// The colour of any point on or near a model's surface: the nearest point of its full-resolution
// triangles (found through a grid), and the look there. Samples are painted by where they lie
// at rest, so a sample added late (after a cut, by the density control) gets the colour of the
// spot it stands on, and decimating the simulation mesh never blurs the texture.
#include <memory>
#include <optional>
#include <vector>

#include "asset/look.h"
#include "asset/texture_charts.h"
#include "mesh/closest_point.h"

namespace pbdsplat::asset {

class SurfaceColors {
public:
    explicit SurfaceColors(SurfaceLook look);
    SurfaceColors(const SurfaceColors&) = delete;  // the grid refers to the look's arrays
    SurfaceColors& operator=(const SurfaceColors&) = delete;

    // Linear RGB at the surface point nearest to p (in the look's coordinates). Threads may ask
    // at once, each with its own scratch.
    Vec3f at(const Vec3f& p, std::vector<mesh::ClosestPoint>& scratch) const;
    // The look's triangle nearest to p and the barycentrics there (none for an empty look).
    std::optional<mesh::ClosestPoint> nearest(const Vec3f& p, std::vector<mesh::ClosestPoint>& scratch) const;
    const SurfaceLook& look() const { return look_; }

    // The texture at the surface point nearest to p, for a splat reaching `reach` around it that
    // reads the texture per pixel: its coordinates there and their gradients, the texture (into
    // look().textures), the colour it multiplies, and how far along the surface the splat may read
    // from its centre before it would cross a seam (texture_charts.h): `reach` where no seam is
    // within it. None where that point has no texture.
    struct TexturePoint {
        Vec2f uv;
        UvGradient gradient;
        int32_t texture;
        Vec3f tint;
        float reach;
    };
    std::optional<TexturePoint> texture_point(const Vec3f& p, float reach, std::vector<mesh::ClosestPoint>& scratch) const;
    // The same at the nearest point already found (nearest(p)).
    std::optional<TexturePoint> texture_point(const mesh::ClosestPoint& q, const Vec3f& p, float reach) const;

private:
    SurfaceLook look_;
    mesh::TriangleGrid grid_;
    TextureCharts charts_;
};

} // namespace pbdsplat::asset
