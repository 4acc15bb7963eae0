#include "asset/surface_colors.h"

namespace pbdsplat::asset {

SurfaceColors::SurfaceColors(SurfaceLook look) : look_(std::move(look)), grid_(look_.positions, look_.triangles) {}

Vec3f SurfaceColors::at(const Vec3f& p, std::vector<mesh::ClosestPoint>& scratch) const {
    grid_.closest(p, 1.0f, 0.0f, scratch);
    if (scratch.empty()) return Vec3f::Ones();
    return look_.color_at(scratch.front().triangle, scratch.front().bary);
}

} // namespace pbdsplat::asset
