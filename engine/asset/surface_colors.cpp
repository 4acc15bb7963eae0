#include "asset/surface_colors.h"

namespace pbdsplat::asset {

SurfaceColors::SurfaceColors(SurfaceLook look) : look_(std::move(look)), grid_(look_.positions, look_.triangles) {
    if (!look_.textures.empty()) charts_ = TextureCharts(look_);
}

Vec3f SurfaceColors::at(const Vec3f& p, std::vector<mesh::ClosestPoint>& scratch) const {
    const auto q = nearest(p, scratch);
    return q ? look_.color_at(q->triangle, q->bary) : Vec3f::Ones();
}

std::optional<mesh::ClosestPoint> SurfaceColors::nearest(const Vec3f& p, std::vector<mesh::ClosestPoint>& scratch) const {
    grid_.closest(p, 1.0f, 0.0f, scratch);
    if (scratch.empty()) return std::nullopt;
    return scratch.front();
}

std::optional<SurfaceColors::TexturePoint> SurfaceColors::texture_point(const Vec3f& p, float reach,
                                                                        std::vector<mesh::ClosestPoint>& scratch) const {
    if (look_.textures.empty()) return std::nullopt;
    const auto q = nearest(p, scratch);
    return q ? texture_point(*q, p, reach) : std::nullopt;
}

std::optional<SurfaceColors::TexturePoint> SurfaceColors::texture_point(const mesh::ClosestPoint& q, const Vec3f& p, float reach) const {
    if (look_.textures.empty()) return std::nullopt;
    const SurfaceLook::Parts parts = look_.parts_at(q.triangle, q.bary);
    if (parts.texture < 0) return std::nullopt;
    const auto gradient = uv_gradient(look_, q.triangle);
    if (!gradient || !parts.uv.allFinite()) return std::nullopt;
    return TexturePoint{parts.uv, *gradient, parts.texture, parts.tint.cwiseMax(0.0f), charts_.seam_distance(p, reach)};
}

} // namespace pbdsplat::asset
