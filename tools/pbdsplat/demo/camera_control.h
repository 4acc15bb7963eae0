#pragma once
// Orbit, pan and zoom about the camera's target, as the mouse asks.
#include "render/frame_inputs.h"

namespace pbdsplat::demo {

inline constexpr float k_orbit_radians_per_pixel = 0.005f;  // how far a pixel of mouse travel turns

class CameraControl {
public:
    explicit CameraControl(const render::Camera& start);
    void orbit(Vec2f pixels);  // turn about the target (degrees per pixel fixed)
    void pan(Vec2f pixels, float view_height_pixels);
    void zoom(float steps);    // scroll steps, up = closer
    render::Camera camera() const;

private:
    render::Camera base_;
    Vec3f target_;
    float yaw_ = 0.0f, pitch_ = 0.0f, distance_ = 1.0f;  // radians, world units
};

} // namespace pbdsplat::demo
