#pragma once
// The colour of any point on or near a model's surface: the nearest point of its full-resolution
// triangles (found through a grid), and the look there. Samples are painted by where they lie
// at rest, so a sample added late (after a cut, by the density control) gets the colour of the
// spot it stands on, and decimating the simulation mesh never blurs the texture.
#include <memory>
#include <optional>
#include <vector>

#include "asset/look.h"
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

private:
    SurfaceLook look_;
    mesh::TriangleGrid grid_;
};

} // namespace pbdsplat::asset
