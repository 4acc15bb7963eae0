#include "topology/cut_surface.h"

#include <algorithm>

#include <cmath>

namespace pbdsplat::topology {

core::Result<CutSurface> plane_cut(const Vec3f& point, const Vec3f& normal) {
    if (!point.allFinite() || !normal.allFinite()) return core::make_error("cut plane: point and normal must be finite");
    const float len = normal.norm();
    if (!(len > 1e-12f)) return core::make_error("cut plane: the normal must not be zero");
    CutSurface s;
    s.point = point;
    s.normal = normal / len;
    return s;
}

core::Result<CutSurface> screen_cut(const Mat4f& view_proj, const Vec3f& eye, const Vec2f& screen, const Vec2f& a,
                                    const Vec2f& b) {
    if (!view_proj.allFinite() || !eye.allFinite() || !a.allFinite() || !b.allFinite())
        return core::make_error("cut stroke: camera and stroke must be finite");
    if (!(screen.x() > 0.0f && screen.y() > 0.0f)) return core::make_error("cut stroke: the screen size must be positive");
    const Vec2f ab = b - a;
    if (ab.norm() < 1.0f) return core::make_error("cut stroke: the segment is shorter than a pixel");
    const Mat4f inverse = view_proj.inverse();
    auto ray = [&](const Vec2f& px) {
        const Vec2f ndc(2.0f * px.x() / screen.x() - 1.0f, 2.0f * px.y() / screen.y() - 1.0f);
        const Vec4f far_point = inverse * Vec4f(ndc.x(), ndc.y(), 1.0f, 1.0f);
        return Vec3f((far_point.head<3>() / far_point.w() - eye).normalized());
    };
    auto plane = plane_cut(eye, ray(a).cross(ray(b)));
    if (!plane.ok()) return core::make_error("cut stroke: its two ends look along the same ray");
    CutSurface s = std::move(plane).value();
    const float inv_len2 = 1.0f / ab.squaredNorm();
    s.inside = [view_proj, screen, a, ab, inv_len2](const Vec3f& x) {
        const Vec4f c = view_proj * Vec4f(x.x(), x.y(), x.z(), 1.0f);
        if (!(c.w() > 0.0f)) return false;  // behind the eye
        const Vec2f px((c.x() / c.w() * 0.5f + 0.5f) * screen.x(), (c.y() / c.w() * 0.5f + 0.5f) * screen.y());
        const float u = (px - a).dot(ab) * inv_len2;
        return u >= 0.0f && u <= 1.0f;
    };
    return s;
}

CutSurface local_cut(const Vec3f& point, const Vec3f& unit_normal, float radius) {
    CutSurface s;
    s.point = point;
    s.normal = unit_normal;
    const float r2 = radius * radius;
    s.inside = [point, r2](const Vec3f& x) { return (x - point).squaredNorm() <= r2; };
    return s;
}

CutSurface local_cut_on(const sim::SoftBody& b, uint32_t particle, const Vec3f& unit_normal, float radius) {
    const Vec3f centre = sim::xyz(b.particles.x[particle]);
    CutSurface s = local_cut(centre, unit_normal, radius);
    const float r2 = radius * radius;
    std::vector<uint32_t> inside{particle}, ring;
    std::vector<uint8_t> seen(b.particle_count(), 0);  // a memset: cheaper than a search per step
    seen[particle] = 1;
    for (size_t q = 0; q < inside.size(); ++q)
        for (const auto& pair : b.rings.ring.of(inside[q]))
            for (uint32_t w : pair) {
                if (seen[w]) continue;
                seen[w] = 1;
                if ((sim::xyz(b.particles.x[w]) - centre).squaredNorm() <= r2) inside.push_back(w);
                else ring.push_back(w);
            }
    s.particles = std::move(inside);
    s.particles.insert(s.particles.end(), ring.begin(), ring.end());
    std::sort(s.particles.begin(), s.particles.end());
    return s;
}

} // namespace pbdsplat::topology
