#include "asset/surface_colors.h"

namespace pbdsplat::asset {

SurfaceColors::SurfaceColors(SurfaceLook look) : look_(std::move(look)), grid_(look_.positions, look_.triangles) {}

Vec3f SurfaceColors::at(const Vec3f& p) const {
    grid_.closest(p, 1.0f, 0.0f, scratch_);
    if (scratch_.empty()) return Vec3f::Ones();
    return look_.color_at(scratch_.front().triangle, scratch_.front().bary);
}

} // namespace pbdsplat::asset
