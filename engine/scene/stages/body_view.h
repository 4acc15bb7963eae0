#pragma once
// The render inputs that follow the body from frame to frame: whether the far side of a closed,
// opaque body may be skipped, the centre position-based environment lookups look out from, and
// the ground under the body with its contact shadow.
#include <optional>
#include <span>

#include "render/frame_inputs.h"
#include "sim/colliders.h"

namespace pbdsplat::scene {

struct BodyViewOptions {
    bool cull_back = true;     // the scene allows skipping the far side
    bool closed = false;       // no open boundary now
    bool opaque = false;       // "over" blending at opacity above 0.9
    bool draw_ground = true;   // the scene draws its plane collider
};

// Updates `frame`'s culling threshold, environment centre and ground from the particles `x`.
void follow_body(std::span<const Vec4f> x, const std::optional<sim::GroundPlane>& plane, const BodyViewOptions& o,
                 render::FrameInputs& frame);

// The ground disc and contact shadow under a body whose particles are `x` (centre `centre`).
void fit_ground(const sim::GroundPlane& plane, std::span<const Vec4f> x, const Vec3f& centre, render::Ground& g);

} // namespace pbdsplat::scene
