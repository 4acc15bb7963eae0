#include "demo/camera_control.h"

#include <algorithm>
#include <cmath>

namespace pbdsplat::demo {

CameraControl::CameraControl(const render::Camera& start) : base_(start), target_(start.target) {
    const Vec3f d = start.eye - start.target;
    distance_ = std::max(1e-3f, d.norm());
    yaw_ = std::atan2(d.x(), d.z());
    pitch_ = std::asin(std::clamp(d.y() / distance_, -1.0f, 1.0f));
}

void CameraControl::orbit(Vec2f pixels) {
    constexpr float radians_per_pixel = k_orbit_radians_per_pixel;
    yaw_ -= pixels.x() * radians_per_pixel;
    pitch_ = std::clamp(pitch_ + pixels.y() * radians_per_pixel, -1.5f, 1.5f);  // never over the pole
}

void CameraControl::pan(Vec2f pixels, float view_height_pixels) {
    const render::Camera c = camera();
    const Vec3f forward = (c.target - c.eye).normalized();
    const Vec3f right = forward.cross(c.up).normalized();
    const Vec3f up = right.cross(forward);
    // One pixel at the target's distance.
    const float world_per_pixel = 2.0f * distance_ * std::tan(math::radians(c.fov_y_degrees) * 0.5f) / std::max(1.0f, view_height_pixels);
    target_ += (-pixels.x() * right + pixels.y() * up) * world_per_pixel;
}

void CameraControl::zoom(float steps) { distance_ = std::clamp(distance_ * std::pow(0.9f, steps), 1e-3f, 1e4f); }

render::Camera CameraControl::camera() const {
    render::Camera c = base_;
    c.target = target_;
    c.eye = target_ + distance_ * Vec3f(std::cos(pitch_) * std::sin(yaw_), std::sin(pitch_), std::cos(pitch_) * std::cos(yaw_));
    c.up = Vec3f::UnitY();
    return c;
}

} // namespace pbdsplat::demo
