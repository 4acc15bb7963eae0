#pragma once
// The render inputs that follow the body from frame to frame: whether the far side of a closed,
// opaque body may be skipped, the centre position-based environment lookups look out from, and
// the ground under the body with its contact shadow.
#include <cstddef>
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

// The particles, which piece each is in (`piece` may be empty: one piece) and which model
// (`model` may be empty: one model).
struct BodyPoints {
    std::span<const Vec4f> x;
    std::span<const uint32_t> piece;
    size_t pieces = 1;
    std::span<const uint32_t> model = {};
};

// Updates `frame`'s culling threshold, environment centre and ground from the body's particles.
void follow_body(const BodyPoints& body, const std::optional<sim::GroundPlane>& plane, const BodyViewOptions& o,
                 render::FrameInputs& frame);

// The ground disc under the body (whose centre is `centre`) and a contact shadow under each of
// its largest pieces: pieces cut apart or models set beside each other each darken the ground
// under themselves, where one shadow for the whole body darkened everything around them.
void fit_ground(const sim::GroundPlane& plane, const BodyPoints& body, const Vec3f& centre, render::Ground& g);

} // namespace pbdsplat::scene
