#include "asset/surface_colors.h"

namespace pbdsplat::asset {

SurfaceColors::SurfaceColors(SurfaceLook look) : look_(std::move(look)), grid_(look_.positions, look_.triangles) {}

Vec3f SurfaceColors::at(const Vec3f& p, std::vector<mesh::ClosestPoint>& scratch) const {
    const auto q = nearest(p, scratch);
    return q ? look_.color_at(q->triangle, q->bary) : Vec3f::Ones();
}

std::optional<mesh::ClosestPoint> SurfaceColors::nearest(const Vec3f& p, std::vector<mesh::ClosestPoint>& scratch) const {
    grid_.closest(p, 1.0f, 0.0f, scratch);
    if (scratch.empty()) return std::nullopt;
    return scratch.front();
}

} // namespace pbdsplat::asset
