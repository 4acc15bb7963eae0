#pragma once
#include <array>

#include "gpu_types.h"
#include "render/frame_inputs.h"

namespace pbdsplat::render {

// The std140 block every pass reads, from the frame's camera, lights and splat style; `sh`: the
// environment map's irradiance (null: none bound, the environment terms are black).
gpu_types::FrameUniforms make_frame_uniforms(const FrameInputs& in, uint32_t width, uint32_t height,
                                             const std::array<Vec3f, 9>* sh = nullptr);

} // namespace pbdsplat::render
