#pragma once
#include <array>

#include "gpu_types.h"
#include "render/frame_inputs.h"

namespace pbdsplat::render {

// The std140 block every pass reads, from the frame's camera, lights and splat style; `sh`: the
// environment map's irradiance (null: none bound, the environment terms are black).
gpu_types::FrameUniforms make_frame_uniforms(const FrameInputs& in, uint32_t width, uint32_t height,
                                             const std::array<Vec3f, 9>* sh = nullptr);

// The paper disc's half-size in s0 (kappa, or the closing default when kappa is 0).
float paper_kappa(const SplatStyle& style);
// How far any splat of this style reaches from its centre, in units of its scale s0 (the global
// multiplier included): a bound for culling. The Gaussian's reach is where an opaque splat's
// alpha falls below 1/255 (sqrt(2 ln 255) = 3.33 standard deviations).
float splat_reach_bound(const SplatStyle& style);

} // namespace pbdsplat::render
