#include "render/screen_bounds.h"

#include <algorithm>
#include <cmath>

#include "render/frame_uniforms.h"

namespace pbdsplat::render {

SplatBounds splat_bounds(std::span<const splat::GaussianRecord> records) {
    SplatBounds b;
    for (const splat::GaussianRecord& r : records) {
        const Vec3f p(r.position[0], r.position[1], r.position[2]);
        if (!p.allFinite()) continue;  // clipped away: it draws nothing
        b.lo = b.lo.cwiseMin(p);
        b.hi = b.hi.cwiseMax(p);
        b.max_scale = std::max(b.max_scale, std::abs(splat::half_to_float(r.scale_half)));
    }
    return b;
}

PixelRect splat_screen_rect(const SplatBounds& bounds, const FrameInputs& inputs, uint32_t width, uint32_t height) {
    const PixelRect whole{0, 0, width, height};
    if (bounds.empty()) return {0, 0, 1, 1};
    // Half again the reach: a deformed or stretched splat's carrier, and the filter's pixel.
    const float reach = 1.5f * splat_reach_bound(inputs.style) * bounds.max_scale;
    if (!std::isfinite(reach) || !bounds.lo.allFinite() || !bounds.hi.allFinite()) return whole;
    const Camera& c = inputs.camera;
    const Mat4f clip = math::perspective(math::radians(c.fov_y_degrees), float(width) / float(height), c.z_near, c.z_far) *
                       math::look_at(c.eye, c.target, c.up);
    const Vec3f lo = bounds.lo - Vec3f::Constant(reach), hi = bounds.hi + Vec3f::Constant(reach);
    float x0 = 1e30f, y0 = 1e30f, x1 = -1e30f, y1 = -1e30f;
    for (int k = 0; k < 8; ++k) {
        const Vec4f p(k & 1 ? hi.x() : lo.x(), k & 2 ? hi.y() : lo.y(), k & 4 ? hi.z() : lo.z(), 1.0f);
        const Vec4f q = clip * p;
        if (!(q.w() > c.z_near)) return whole;  // a corner at or behind the eye: the projection wraps
        const float px = (q.x() / q.w() * 0.5f + 0.5f) * float(width), py = (q.y() / q.w() * 0.5f + 0.5f) * float(height);
        x0 = std::min(x0, px), x1 = std::max(x1, px), y0 = std::min(y0, py), y1 = std::max(y1, py);
    }
    const float margin = 2.0f;
    const auto clamp_to = [](float v, uint32_t size) { return uint32_t(std::clamp(v, 0.0f, float(size))); };
    const uint32_t ax = clamp_to(std::floor(x0 - margin), width), bx = clamp_to(std::ceil(x1 + margin), width);
    const uint32_t ay = clamp_to(std::floor(y0 - margin), height), by = clamp_to(std::ceil(y1 + margin), height);
    if (bx <= ax || by <= ay) return {std::min(ax, width - 1), std::min(ay, height - 1), 1, 1};  // off screen
    return {ax, ay, bx - ax, by - ay};
}

} // namespace pbdsplat::render
