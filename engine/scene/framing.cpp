#include "scene/framing.h"

#include <algorithm>
#include <cmath>

#include "core/math.h"

namespace pbdsplat::scene {

render::Camera framing_camera(const mesh::Bounds& box, const render::Camera& lens, float aspect) {
    render::Camera c = lens;
    const float radius = std::max(0.5f * box.diagonal(), 1e-3f);
    const float half_y = 0.5f * math::radians(lens.fov_y_degrees);
    // The narrower of the two half-angles holds the sphere.
    const float half = std::min(half_y, std::atan(std::tan(half_y) * std::max(aspect, 1e-3f)));
    const float distance = radius / std::sin(half);
    c.target = box.center();
    c.eye = c.target + distance * Vec3f(0.0f, 0.3f, 1.0f).normalized();
    c.up = Vec3f(0.0f, 1.0f, 0.0f);
    // The depth range holds the whole sphere, whatever its size.
    c.z_near = std::min(lens.z_near, 0.5f * (distance - radius));
    c.z_far = std::max(lens.z_far, 4.0f * (distance + radius));
    return c;
}

bool camera_sees(const render::Camera& camera, std::span<const Vec3f> points, float aspect, float margin, float least_span) {
    const Mat4f view_projection = math::perspective(math::radians(camera.fov_y_degrees), aspect, camera.z_near, camera.z_far) *
                                  math::look_at(camera.eye, camera.target, camera.up);
    Vec2f lo = Vec2f::Constant(1.0f), hi = Vec2f::Constant(-1.0f);
    for (const Vec3f& p : points) {
        const Vec4f clip = view_projection * Vec4f(p.x(), p.y(), p.z(), 1.0f);
        if (!(clip.w() > camera.z_near)) return false;
        const Vec2f ndc(clip.x() / clip.w(), clip.y() / clip.w());
        if (std::abs(ndc.x()) > margin || std::abs(ndc.y()) > margin) return false;
        lo = lo.cwiseMin(ndc), hi = hi.cwiseMax(ndc);
    }
    return points.empty() || 0.5f * (hi - lo).maxCoeff() >= least_span;
}

} // namespace pbdsplat::scene
