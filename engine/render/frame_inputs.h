#pragma once
// What the renderer needs from the scene each frame, besides the Gaussian records.
#include "core/math.h"

namespace pbdsplat::render {

struct Camera {
    Vec3f eye{0.0f, 0.0f, 3.0f};
    Vec3f target{0.0f, 0.0f, 0.0f};
    Vec3f up{0.0f, 1.0f, 0.0f};
    float fov_y_degrees = 45.0f;
    float z_near = 0.05f;
    float z_far = 100.0f;
};

struct Lighting {
    Vec3f direction{0.4f, 0.7f, 0.6f};  // from the surface towards the light; normalised on use
    Vec3f color{1.0f, 1.0f, 1.0f};
    float intensity = 1.0f;
    Vec3f ambient{0.18f, 0.18f, 0.2f};
    float specular = 0.35f;
    float shininess = 48.0f;
};

enum class Blend { over, additive };

struct SplatStyle {
    float kappa = 3.0f;       // quad half-size in standard deviations
    Vec2f sharpness{1.0f, 1.0f};
    float scale_multiplier = 1.0f;
    Blend blend = Blend::over;
    // "Over" blending without a sort: a depth-only pass first lays down each splat's core
    // (r^2 < core_r2), pushed back by depth_push standard deviations; the colour pass then
    // tests against it without writing, so neighbouring splats of one surface blend smoothly
    // and hidden ones stay hidden. Additive blending needs neither.
    float depth_push = 2.0f;
    float core_r2 = 0.25f;
};

struct FrameInputs {
    Camera camera;
    Lighting lighting;
    SplatStyle style;
    Vec4f background{0.06f, 0.06f, 0.08f, 1.0f};
};

} // namespace pbdsplat::render
